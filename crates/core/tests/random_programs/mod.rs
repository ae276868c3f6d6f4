//! Random well-formed MELSEC programs for property tests: contacts,
//! ANB/ORB blocks, MPS, coils, timers (low-speed, high-speed, retentive)
//! and counters with constant or word set values (a negative one faults),
//! RST of both, MOV/arithmetic/logic/BSET/compare, forward jumps, FOR/NEXT,
//! master control, pulse forms and index modification that may go out of
//! range. `body(depth)` makes the parts, `render` the program text.
#![allow(dead_code)]

use proptest::prelude::*;

fn bit() -> impl Strategy<Value = String> {
    prop_oneof![
        (0..8u32).prop_map(|n| format!("X{n}")),
        (0..16u32).prop_map(|n| format!("M{n}")),
        (0..8u32).prop_map(|n| format!("Y{n}")),
        (0..16u32).prop_map(|n| format!("D0.{n:X}")),
        Just("SM400".to_string()),
        (0..4u32).prop_map(|n| format!("T{n}")),
        (0..4u32).prop_map(|n| format!("C{n}")),
        (0..2u32).prop_map(|n| format!("ST{n}")),
        // The last bits of memory (FY is last): native code reads a bit with
        // the three bytes after it only where they are still memory.
        (12..16u32).prop_map(|n| format!("FY{n:X}")),
        // Index-modified: Z0 may point past the end of M (4101).
        (0..4u32).prop_map(|n| format!("M{n}Z0")),
    ]
}

fn dest_bit() -> impl Strategy<Value = String> {
    prop_oneof![
        (0..16u32).prop_map(|n| format!("M{n}")),
        (0..8u32).prop_map(|n| format!("Y{n}")),
        (12..16u32).prop_map(|n| format!("FY{n:X}")),
        (0..4u32).prop_map(|n| format!("M{}Z0", 20 + n)),
    ]
}

fn word() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (0..8u32).prop_map(|n| format!("D{n}")),
        1 => (0..4u32).prop_map(|n| format!("D{n}Z0")),
    ]
}

fn operand() -> impl Strategy<Value = String> {
    prop_oneof![
        word(),
        (-3i32..40).prop_map(|k| format!("K{k}")),
        Just("K32767".to_string()),
        (0..4u32).prop_map(|n| format!("TN{n}")),
        (0..4u32).prop_map(|n| format!("CN{n}")),
    ]
}

/// A 32-bit operand: a word pair or a constant.
fn operand32() -> impl Strategy<Value = String> {
    prop_oneof![
        (0..8u32).prop_map(|n| format!("D{}", 2 * n)),
        (-70000i64..70000).prop_map(|k| format!("K{k}")),
        Just("K2147483647".to_string()),
    ]
}

/// A timer's or counter's set value: small constants (0 included) or a
/// word, which may hold a negative value (4100 where the CPU faults).
fn set_value() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => (0..6u32).prop_map(|k| format!("K{k}")),
        1 => (0..16u32).prop_map(|n| format!("D{n}")),
    ]
}

/// Timers, counters and their resets.
fn timer_counter() -> impl Strategy<Value = String> {
    prop_oneof![
        2 => (prop_oneof![Just("OUT"), Just("OUTH")], 0..4u32, set_value())
            .prop_map(|(o, n, k)| format!("{o} T{n} {k}\n")),
        1 => (0..2u32, set_value()).prop_map(|(n, k)| format!("OUT ST{n} {k}\n")),
        2 => (0..4u32, set_value()).prop_map(|(n, k)| format!("OUT C{n} {k}\n")),
        1 => (prop_oneof![Just("T"), Just("C"), Just("ST")], 0..2u32)
            .prop_map(|(d, n)| format!("RST {d}{n}\n")),
    ]
}

/// Word instructions: INC/DEC, 32-bit +/-, word logic, BSET/BRST.
fn word_instruction() -> impl Strategy<Value = String> {
    prop_oneof![
        (prop_oneof![Just("INC"), Just("DEC")], word()).prop_map(|(i, d)| format!("{i} {d}\n")),
        (prop_oneof![Just("DINC"), Just("DDEC")], 0..8u32)
            .prop_map(|(i, d)| format!("{i} D{}\n", 2 * d)),
        (
            prop_oneof![Just("D+"), Just("D-")],
            operand32(),
            operand32(),
            0..8u32
        )
            .prop_map(|(i, a, b, d)| format!("{i} {a} {b} D{}\n", 2 * d)),
        (prop_oneof![Just("+"), Just("-")], operand(), word())
            .prop_map(|(i, s, d)| format!("{i} {s} {d}\n")),
        (
            prop_oneof![Just("WAND"), Just("WOR"), Just("WXOR")],
            operand(),
            operand(),
            word()
        )
            .prop_map(|(i, a, b, d)| format!("{i} {a} {b} {d}\n")),
        (prop_oneof![Just("WAND"), Just("WOR")], operand(), word())
            .prop_map(|(i, s, d)| format!("{i} {s} {d}\n")),
        (prop_oneof![Just("DAND"), Just("DOR")], operand32(), 0..8u32)
            .prop_map(|(i, s, d)| format!("{i} {s} D{}\n", 2 * d)),
        (
            prop_oneof![Just("BSET"), Just("BRST")],
            word(),
            prop_oneof![(0..20u32).prop_map(|k| format!("K{k}")), word(),]
        )
            .prop_map(|(i, d, n)| format!("{i} {d} {n}\n")),
    ]
}

fn contact_chain() -> impl Strategy<Value = String> {
    (
        prop_oneof![4 => Just("LD"), 2 => Just("LDI"), 1 => Just("LDP"), 1 => Just("LDF")],
        bit(),
        prop::collection::vec(
            prop_oneof![
                8 => (
                    prop_oneof![Just("AND"), Just("ANI"), Just("OR"), Just("ORI")],
                    bit(),
                )
                    .prop_map(|(m, b)| format!("{m} {b}\n")),
                2 => (
                    prop_oneof![Just("ANDP"), Just("ANDF"), Just("ORP"), Just("ORF")],
                    bit(),
                )
                    .prop_map(|(m, b)| format!("{m} {b}\n")),
                // Edges of the operation result so far.
                1 => prop_oneof![Just("MEP\n".to_string()), Just("MEF\n".to_string())],
            ],
            0..4,
        ),
    )
        .prop_map(|(first, b, rest)| format!("{first} {b}\n{}", rest.concat()))
}

fn coil() -> impl Strategy<Value = String> {
    (
        prop_oneof![
            Just("OUT"),
            Just("SET"),
            Just("RST"),
            Just("PLS"),
            Just("PLF")
        ],
        dest_bit(),
    )
        .prop_map(|(c, d)| format!("{c} {d}\n"))
}

fn compare() -> impl Strategy<Value = String> {
    (
        prop_oneof![Just("LD"), Just("AND"), Just("OR")],
        prop_oneof![Just(""), Just("D")],
        prop_oneof![
            Just("="),
            Just("<>"),
            Just(">"),
            Just("<="),
            Just("<"),
            Just(">=")
        ],
        word(),
        operand(),
    )
        .prop_map(|(j, d, op, a, b)| format!("{j}{d}{op} {a} {b}\n"))
}

/// A comparison contact as the start of a rung or block (`AND=` → `LD=`).
fn lead(c: &str) -> String {
    match c.strip_prefix("AND").or_else(|| c.strip_prefix("OR")) {
        Some(rest) => format!("LD{rest}"),
        None => c.to_string(),
    }
}

/// The condition part of a rung: contacts, a comparison, a block or MPS-free
/// contact logic.
fn condition() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => contact_chain(),
        1 => compare().prop_map(|c| lead(&c)),
        1 => (contact_chain(), contact_chain(), compare(), prop_oneof![Just("ANB"), Just("ORB")])
            .prop_map(|(a, b, c, j)| {
                // LD … opens a block.
                format!("{a}{b}{j}\n{}ANB\n", lead(&c))
            }),
    ]
}

fn action() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => coil(),
        2 => (word(), operand()).prop_map(|(d, s)| format!("MOV {s} {d}\n")),
        1 => (0..8u32, -70000i64..70000).prop_map(|(d, k)| format!("DMOV K{k} D{}\n", 2 * d)),
        1 => (prop_oneof![Just("+"), Just("-"), Just("*"), Just("/")], word(), operand(), word())
            .prop_map(|(op, a, b, d)| format!("{op} {a} {b} {d}\n")),
        // Instructions interpreted from native code only while their
        // condition is ON (BCD faults above 9999).
        1 => (prop_oneof![Just("BCD"), Just("BIN")], word(), word())
            .prop_map(|(op, s, d)| format!("{op} {s} {d}\n")),
        1 => word().prop_map(|d| format!("INCP {d}\n")),
        2 => timer_counter(),
        2 => word_instruction(),
        1 => (word(), word()).prop_map(|(s, d)| format!("MOVP {s} {d}\n")),
        // Z0 inside M/D, near their ends, or past them.
        1 => prop_oneof![0..12i32, 8185..8200i32, 12280..12290i32, Just(20000)]
            .prop_map(|z| format!("MOV K{z} Z0\n")),
    ]
}

/// A word read, written under a condition, and read again: native code
/// holds it in a register across the condition.
fn read_write_read() -> impl Strategy<Value = String> {
    (
        0..8u32,
        condition(),
        prop_oneof![
            Just("MOV K3 D#"),
            Just("INC D#"),
            Just("BSET D# K1"),
            Just("+ D# K3 D#"),
            Just("WAND H0F D#"),
            Just("DMOV K70000 D#"),
        ],
        0..16u32,
    )
        .prop_map(|(n, c, w, m)| {
            format!(
                "LD= D{n} K0\nOUT M{m}\n{c}{}\nLD SM400\nMOV D{n} D{}\n",
                w.replace('#', &n.to_string()),
                n + 8
            )
        })
}

/// A rung: a condition, then one to three outputs (MPS branches when more).
fn rung() -> impl Strategy<Value = String> {
    prop_oneof![
        1 => read_write_read(),
        3 => (condition(), action()).prop_map(|(c, a)| c + &a),
        1 => (condition(), action(), contact_chain(), action(), action()).prop_map(
            |(c, a1, b, a2, a3)| {
                let b = b.replacen("LDI", "ANI", 1).replacen("LD", "AND", 1);
                format!("{c}MPS\n{b}{a1}MRD\n{a2}MPP\n{a3}")
            }
        ),
    ]
}

/// A program: rungs, forward jumps over rungs, FOR/NEXT and MC blocks.
pub fn body(depth: u32) -> BoxedStrategy<Vec<String>> {
    let leaf = prop::collection::vec(rung(), 1..6);
    if depth == 0 {
        return leaf.boxed();
    }
    let inner = body(depth - 1);
    prop::collection::vec(
        prop_oneof![
            4 => rung().prop_map(|r| vec![r]),
            1 => (condition(), inner.clone()).prop_map(|(c, rs)| {
                let mut v = vec![format!("{c}CJ P@\n")];
                v.extend(rs);
                v.push("P@\n".into());
                v
            }),
            1 => (1..4u32, inner.clone()).prop_map(|(n, rs)| {
                let mut v = vec![format!("FOR K{n}\n")];
                v.extend(rs);
                v.push("NEXT\n".into());
                v
            }),
            1 => (contact_chain(), inner).prop_map(|(c, rs)| {
                let mut v = vec![format!("{c}MC N# M{}\n", 300)];
                v.extend(rs);
                v.push("MCR N#\n".into());
                v
            }),
        ],
        1..6,
    )
    .prop_map(|vs| vs.into_iter().flatten().collect())
    .boxed()
}

/// Numbers the labels (`P@` pairs, innermost first is not needed: each CJ
/// opens one and its closing `P@` is the next unmatched one) and MC levels.
pub fn render(parts: &[String]) -> String {
    let mut out = String::new();
    let mut labels: Vec<u32> = Vec::new();
    let mut next_label = 0;
    let mut mc_level = 0;
    for p in parts {
        if p.contains("CJ P@") {
            labels.push(next_label);
            out += &p.replace("P@", &format!("P{next_label}"));
            next_label += 1;
        } else if p == "P@\n" {
            out += &format!("P{}\n", labels.pop().unwrap_or(0));
        } else if p.contains("MC N#") {
            // Nesting levels ascend inward (N0 outermost).
            out += &p
                .replace("N#", &format!("N{}", mc_level.min(14)))
                .replace("M300", &format!("M{}", 300 + mc_level));
            mc_level += 1;
        } else if p == "MCR N#\n" {
            mc_level -= 1;
            out += &format!("MCR N{}\n", mc_level.min(14));
        } else {
            out += p;
        }
    }
    out + "END\n"
}
