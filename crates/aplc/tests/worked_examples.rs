//! The audit of spec aplc.md §8 (the manual's worked examples): every example
//! names the golden test that runs it with the manual's values, and that
//! test's doc comment cites the example (`#N`, or a range `#N-M`; for tests
//! of other crates, the test must exist).
//!
//! The table is literal, so the coverage check depends only on the
//! repository. Comparing the table with the spec's own §8 (an example added
//! there must get a row and a test) needs the maintainers' copy of the spec,
//! which is not in the repository: that check is `#[ignore]`d and runs only
//! when asked, with `APLC_SPEC=path/to/aplc.md cargo test -p softplc-aplc
//! --test worked_examples -- --ignored`, failing without the file.

use std::collections::BTreeSet;
use std::path::PathBuf;

/// What covers an example.
enum Cover {
    /// Golden tests: (file under crates/, test function).
    Tests(&'static [(&'static str, &'static str)]),
}
use Cover::*;

const LOGIC: &str = "aplc/tests/golden_logic.rs";
const DATA: &str = "aplc/tests/golden_data.rs";
const MORE: &str = "aplc/tests/golden_more.rs";
const VALUES: &str = "aplc/tests/golden_values.rs";
const MANUAL: &str = "aplc/tests/golden_manual.rs";
const CALL: &str = "aplc/tests/golden_call.rs";
const INT: &str = "aplc/tests/golden_interrupt.rs";

/// (§8 id, its "Line" column, what covers it).
static EXAMPLES: &[(u32, &str, Cover)] = &[
    (1, "L2642", Tests(&[(MANUAL, "ld_and_out")])),
    (2, "L2670, L2698, L2726", Tests(&[(MANUAL, "ani_or_ori")])),
    (3, "L2798", Tests(&[(LOGIC, "orb")])),
    (4, "L2774", Tests(&[(LOGIC, "anb_and_negations")])),
    (5, "L2185-2208", Tests(&[(LOGIC, "mps_mrd_mpp_listing")])),
    (6, "L2872-2876", Tests(&[(LOGIC, "eu_ed")])),
    (7, "L3006", Tests(&[(LOGIC, "master_control")])),
    (8, "L3161-3169", Tests(&[(LOGIC, "tonr_accumulates")])),
    (9, "L3227-3235", Tests(&[(LOGIC, "tmon_one_shot")])),
    (10, "L3655-3666", Tests(&[(LOGIC, "cj_and_cfend")])),
    (11, "L3682-3687", Tests(&[(LOGIC, "cfend_stops_the_blink")])),
    (12, "L3568", Tests(&[(LOGIC, "for_next")])),
    (
        13,
        "L2465-2473",
        Tests(&[(CALL, "manual_subroutine_example")]),
    ),
    (14, "L2013-2030", Tests(&[(DATA, "bit_groups_and_index")])),
    (15, "L1984-1989", Tests(&[(DATA, "bit_groups_and_index")])),
    (16, "L1991-1998", Tests(&[(MORE, "bit_functions")])),
    (17, "L3830", Tests(&[(DATA, "mov_dmov_rmov")])),
    (18, "L3860", Tests(&[(DATA, "mov_dmov_rmov")])),
    (19, "L3885", Tests(&[(DATA, "mov_dmov_rmov")])),
    (20, "L3913", Tests(&[(DATA, "block_transfer_examples")])),
    (21, "L3947", Tests(&[(DATA, "block_transfer_examples")])),
    (22, "L3981", Tests(&[(DATA, "block_transfer_examples")])),
    (23, "L4008", Tests(&[(DATA, "block_transfer_examples")])),
    (24, "L4044", Tests(&[(DATA, "block_transfer_examples")])),
    (25, "L4078", Tests(&[(DATA, "block_transfer_examples")])),
    (26, "L4113-4115", Tests(&[(MORE, "push_fifo_lifo")])),
    (27, "L4150-4152", Tests(&[(MORE, "push_fifo_lifo")])),
    (28, "L4189-4191", Tests(&[(MORE, "push_fifo_lifo")])),
    (29, "L4219-4231", Tests(&[(MORE, "string_shifts")])),
    (30, "L4259-4271", Tests(&[(MORE, "string_shifts")])),
    (31, "L4300", Tests(&[(DATA, "arithmetic_examples")])),
    (32, "L4329", Tests(&[(DATA, "arithmetic_examples")])),
    (33, "L4356", Tests(&[(DATA, "arithmetic_examples")])),
    (34, "L4390", Tests(&[(DATA, "arithmetic_examples")])),
    (35, "L4420", Tests(&[(VALUES, "conversions_and_functions")])),
    (36, "L4446", Tests(&[(DATA, "arithmetic_examples")])),
    (37, "L4472", Tests(&[(DATA, "arithmetic_examples")])),
    (38, "L4501", Tests(&[(VALUES, "conversions_and_functions")])),
    (39, "L4530", Tests(&[(VALUES, "conversions_and_functions")])),
    (40, "L4559", Tests(&[(DATA, "arithmetic_examples")])),
    (41, "L4588", Tests(&[(DATA, "arithmetic_examples")])),
    (42, "L4620", Tests(&[(DATA, "arithmetic_examples")])),
    (43, "L4652", Tests(&[(DATA, "arithmetic_examples")])),
    (44, "L4682", Tests(&[(VALUES, "conversions_and_functions")])),
    (45, "L4709", Tests(&[(DATA, "arithmetic_examples")])),
    (46, "L4735", Tests(&[(DATA, "arithmetic_examples")])),
    (47, "L4764", Tests(&[(VALUES, "conversions_and_functions")])),
    (48, "L4793", Tests(&[(VALUES, "conversions_and_functions")])),
    (49, "L4823", Tests(&[(MORE, "sums")])),
    (50, "L4861", Tests(&[(MORE, "sums")])),
    (51, "L4892-5239", Tests(&[(VALUES, "real_arithmetic")])),
    (52, "L5275", Tests(&[(VALUES, "conversions_and_functions")])),
    (53, "L5300", Tests(&[(VALUES, "conversions_and_functions")])),
    (54, "L5325", Tests(&[(VALUES, "conversions_and_functions")])),
    (55, "L5350", Tests(&[(VALUES, "conversions_and_functions")])),
    (56, "L5380", Tests(&[(VALUES, "conversions_and_functions")])),
    (57, "L5410", Tests(&[(VALUES, "conversions_and_functions")])),
    (
        58,
        "L5439-5656",
        Tests(&[(VALUES, "conversions_and_functions")]),
    ),
    (59, "L5690-5771", Tests(&[(MORE, "ita_ati"), (MORE, "asc")])),
    (60, "L5801-5989", Tests(&[(VALUES, "word_logic")])),
    (
        61,
        "L6023-6384",
        Tests(&[
            (VALUES, "shifts_and_rotations"),
            (MANUAL, "rotations_through_carry"),
        ]),
    ),
    (62, "L6423-6463", Tests(&[(MORE, "string_shifts")])),
    (
        63,
        "L6749-6811",
        Tests(&[(MANUAL, "clock_examples_are_load_errors")]),
    ),
    (
        64,
        "L6892-6907",
        Tests(&[(MANUAL, "clock_examples_are_load_errors")]),
    ),
    (
        65,
        "L7153-7158",
        Tests(&[(MANUAL, "high_speed_example_is_a_load_error")]),
    ),
    (66, "L8699, L8724", Tests(&[(DATA, "zrst_zset")])),
    (67, "L8754", Tests(&[(MORE, "bit_functions")])),
    (68, "L8785", Tests(&[(MORE, "bit_functions")])),
    (69, "L8808", Tests(&[(MORE, "bit_functions")])),
    (70, "L8831", Tests(&[(MORE, "bit_functions")])),
    (71, "L8858-9001", Tests(&[(MORE, "word_bits")])),
    (72, "L9026, L9051, L9076", Tests(&[(MORE, "word_bits")])),
    (
        73,
        "L7888, L7973, L8048",
        Tests(&[
            (MORE, "ramps"),
            (MANUAL, "hackle_and_triangle_manual_operands"),
        ]),
    ),
    (74, "L8652-8667", Tests(&[(MORE, "checksums")])),
    (
        75,
        "L10533-10596, L11636-11721",
        Tests(&[("modbus/tests/aplc.rs", "seed_002_worked_examples")]),
    ),
    (
        76,
        "L10403-10422",
        Tests(&[("ports/tests/virtual_ports.rs", "manual_free_port_example")]),
    ),
    (
        77,
        "L8108-8121",
        Tests(&[("ports/tests/virtual_ports.rs", "manual_modbus_example")]),
    ),
    (
        78,
        "L10209-10219",
        Tests(&[(INT, "timed_interrupt_every_second")]),
    ),
    (79, "", Tests(&[(INT, "queue_overflow_is_error_67")])),
];

fn crates_dir() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

/// The example ids a doc comment cites: `#N` and `#N-M` ranges.
fn cited(doc: &str) -> BTreeSet<u32> {
    let mut out = BTreeSet::new();
    let b = doc.as_bytes();
    let num = |i: &mut usize| {
        let s = *i;
        while *i < b.len() && b[*i].is_ascii_digit() {
            *i += 1;
        }
        doc[s..*i].parse::<u32>().ok()
    };
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'#' {
            i += 1;
            if let Some(a) = num(&mut i) {
                let mut hi = a;
                if i + 1 < b.len() && b[i] == b'-' && b[i + 1].is_ascii_digit() {
                    i += 1;
                    hi = num(&mut i).unwrap_or(a);
                }
                out.extend(a..=hi.max(a));
            }
        } else {
            i += 1;
        }
    }
    out
}

/// The doc comment (`///` lines) right above `#[test] fn name(` in `text`.
fn test_doc(text: &str, name: &str) -> Option<String> {
    let lines: Vec<&str> = text.lines().collect();
    let at = lines
        .iter()
        .position(|l| l.trim_start().starts_with(&format!("fn {name}(")))?;
    if at == 0 || lines[at - 1].trim() != "#[test]" {
        return None;
    }
    let doc: Vec<&str> = lines[..at - 1]
        .iter()
        .rev()
        .take_while(|l| l.trim_start().starts_with("///"))
        .copied()
        .collect();
    Some(doc.into_iter().rev().collect::<Vec<_>>().join("\n"))
}

#[test]
fn every_example_has_a_golden_test_that_cites_it() {
    let ids: Vec<u32> = EXAMPLES.iter().map(|e| e.0).collect();
    assert_eq!(
        ids,
        (1..=79).collect::<Vec<_>>(),
        "one row per example, in order"
    );
    let mut problems = Vec::new();
    for (id, line, cover) in EXAMPLES {
        match cover {
            Tests(tests) => {
                for (file, name) in *tests {
                    let path = crates_dir().join(file);
                    let text = std::fs::read_to_string(&path).unwrap_or_default();
                    match test_doc(&text, name) {
                        None => {
                            problems.push(format!("#{id} ({line}): no #[test] fn {name} in {file}"))
                        }
                        // Files of other crates are named, not edited here.
                        Some(doc) if file.starts_with("aplc/") && !cited(&doc).contains(id) => {
                            problems.push(format!(
                            "#{id} ({line}): the doc comment of {file}::{name} does not cite #{id}"
                        ))
                        }
                        Some(_) => {}
                    }
                }
            }
        }
    }
    assert!(problems.is_empty(), "§8 coverage:\n{}", problems.join("\n"));
}

/// The §8 rows of the spec: (id, Line column).
fn spec_rows(text: &str) -> Vec<(u32, String)> {
    let Some(start) = text.find("\n## 8.") else {
        return Vec::new();
    };
    let body = &text[start + 1..];
    let end = body[1..].find("\n## ").map_or(body.len(), |e| e + 1);
    body[..end]
        .lines()
        .filter_map(|l| {
            let cells: Vec<&str> = l
                .trim()
                .trim_matches('|')
                .split('|')
                .map(str::trim)
                .collect();
            let id = cells.first()?.parse::<u32>().ok()?;
            Some((id, cells.last()?.to_string()))
        })
        .collect()
}

#[test]
#[ignore = "maintainers' check against the spec outside the repository: \
            APLC_SPEC=path/to/aplc.md cargo test -p softplc-aplc --test worked_examples -- --ignored"]
fn table_matches_the_spec() {
    let Some(path) = std::env::var_os("APLC_SPEC").map(PathBuf::from) else {
        panic!("set APLC_SPEC to the spec's aplc.md to compare the table with its §8");
    };
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("APLC_SPEC={}: {e}", path.display()));
    let rows = spec_rows(&text);
    let table: Vec<(u32, String)> = EXAMPLES.iter().map(|e| (e.0, e.1.to_string())).collect();
    assert_eq!(rows, table, "spec aplc.md §8 and this table differ");
}

#[test]
fn citations_are_parsed() {
    assert_eq!(
        cited("/// §8.3 #31-33, #40 and #7"),
        BTreeSet::from([7, 31, 32, 33, 40])
    );
    assert!(cited("/// Example 2 (L2798)").is_empty());
}
