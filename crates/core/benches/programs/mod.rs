//! The benchmark programs, one definition for the criterion benches
//! (`benches/scan.rs`) and the generator `examples/bench_programs.rs` that
//! writes them as `.il` files for timing `softplc run` (docs/performance.md).
#![allow(dead_code)]

/// 50,000 contact/coil instructions: 10,000 rungs of LD, AND, OR, ANI, OUT.
pub fn contacts() -> (String, u64) {
    let mut s = String::new();
    for i in 0..10_000u32 {
        let x = i % 4096;
        s += &format!(
            "LD X{x:X}\nAND M{}\nOR M{}\nANI X{:X}\nOUT M{}\n",
            (i * 7) % 8000,
            (i * 13) % 8000,
            (x + 1) % 4096,
            i % 8000
        );
    }
    s += "END\n";
    (s, 50_000)
}

/// 20,000 MOV instructions (half constant to word, half word to word) on one
/// rung, with its LD: 20,001 instructions.
pub fn movs() -> (String, u64) {
    let mut s = String::from("LD SM400\n");
    for i in 0..20_000u32 {
        if i % 2 == 0 {
            s += &format!("MOV K{} D{}\n", i % 30000, i % 12000);
        } else {
            s += &format!("MOV D{} D{}\n", (i * 7) % 12000, i % 12000);
        }
    }
    s += "END\n";
    (s, 20_001)
}

/// A dependent MOV chain: INC D0, then 12,000 `MOV D(i) D(i+1)`, each
/// reading the previous one's result (12,002 instructions with the LD).
pub fn mov_chain() -> (String, u64) {
    let mut s = String::from("LD SM400\nINC D0\n");
    for i in 0..12_000u32 {
        s += &format!("MOV D{i} D{}\n", i + 1);
    }
    s += "END\n";
    (s, 12_002)
}

/// 1,000 groups of a 100 ms timer, a counter on its contact and a
/// comparison of the count driving a coil (6,000 instructions).
pub fn timer_counter_compare_groups() -> (String, u64) {
    let mut s = String::new();
    for i in 0..1000u32 {
        s += &format!(
            "LD X{:X}\nOUT T{i} K10\nLD T{i}\nOUT C{i} K100\nLD> CN{i} K50\nOUT M{i}\n",
            i % 16
        );
    }
    s += "END\n";
    (s, 6_000)
}

/// Timers, counters and comparisons, 2,000 rungs: a timer driven by a
/// contact, a counter on the timer's contact, a comparison of the current
/// value driving a coil, and a 32-bit comparison with a SET.
pub fn timers_counters_compare() -> (String, u64) {
    let mut s = String::new();
    let mut n = 0u64;
    for i in 0..2000u32 {
        let rung = match i % 4 {
            0 => format!(
                "LD X{:X}\nANI M{}\nOUT T{} K50\n",
                i % 256,
                i % 4000,
                i % 2048
            ),
            1 => format!("LD T{}\nOUT C{} K100\n", (i - 1) % 2048, i % 1024),
            2 => format!(
                "LD>= TN{} K20\nAND X{:X}\nOUT M{}\n",
                (i - 2) % 2048,
                i % 256,
                i % 4000
            ),
            _ => format!(
                "LDD< D{} K100000\nOR M{}\nSET M{}\n",
                (2 * i) % 12000,
                i % 4000,
                4000 + i % 4000
            ),
        };
        n += rung.lines().count() as u64;
        s += &rung;
    }
    s += "END\n";
    (s, n + 1)
}

/// A realistic mixed program: interlocks, timers, counters, comparisons, BIN,
/// BCD and real arithmetic, conversions and block moves, 1,000 rungs.
pub fn mixed() -> (String, u64) {
    let mut s = String::new();
    let mut n = 0u64;
    for i in 0..1000u32 {
        let (d, m) = (10 * (i % 1000), i % 4000);
        let rung = match i % 10 {
            0 => format!(
                "LD X{:X}\nOR M{m}\nANI X{:X}\nOUT M{m}\n",
                i % 256,
                (i + 1) % 256
            ),
            1 => format!("LD M{m}\nOUT T{} K50\n", i % 2000),
            2 => format!("LD X{:X}\nOUT C{} K100\n", i % 256, i % 1000),
            3 => format!("LD> D{d} K100\nAND M{m}\nMOV D{d} D{}\n", d + 1),
            4 => format!("LD SM400\n+ D{d} K1 D{}\n* D{d} K3 D{}\n", d + 2, d + 4),
            5 => format!("LD SM400\nBCD D{d} D{}\nBIN D{} D{}\n", d + 6, d + 6, d + 7),
            6 => format!("LD M{m}\nDMOV K100000 D{}\nINC D{d}\n", d + 8),
            7 => format!(
                "LD SM400\nE+ E1.5 E2.5 D{}\nINT D{} D{}\n",
                d + 2,
                d + 2,
                d + 4
            ),
            8 => format!("LDP X{:X}\nMOV K{} D{d}\n", i % 256, i),
            _ => format!(
                "LD SM400\nMPS\nAND M{m}\nOUT Y{:X}\nMPP\nANI M{m}\nOUT Y{:X}\n",
                i % 512,
                512 + i % 512
            ),
        };
        n += rung.lines().count() as u64;
        s += &rung;
    }
    s += "END\n";
    (s, n + 1)
}
