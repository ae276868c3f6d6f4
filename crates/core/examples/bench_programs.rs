//! Writes the benchmark programs as `.il` files for timing `softplc run`
//! (docs/performance.md, "Tiers"):
//!
//! ```sh
//! cargo run --release -p softplc-core --example bench_programs -- DIR
//! ```
//!
//! `DIR/bits_50k.il` (50,000 LD/AND/OR/ANI/OUT), `DIR/mov_20k.il` (20,000 MOV
//! on one rung), `DIR/tcc_mix.il` (timers, counters, comparisons) and
//! `DIR/mixed.il` (1,000 rungs of interlocks, timers, counters, arithmetic,
//! conversions and moves).

#[path = "../benches/programs/mod.rs"]
mod programs;

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let Some(dir) = std::env::args_os().nth(1).map(PathBuf::from) else {
        eprintln!("usage: bench_programs DIR");
        return ExitCode::from(2);
    };
    let files = [
        ("bits_50k.il", programs::contacts()),
        ("mov_20k.il", programs::movs()),
        ("tcc_mix.il", programs::timers_counters_compare()),
        ("mov_chain_12k.il", programs::mov_chain()),
        ("tcc_groups.il", programs::timer_counter_compare_groups()),
        ("mixed.il", programs::mixed()),
    ];
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("{}: {e}", dir.display());
        return ExitCode::from(1);
    }
    for (name, (src, n)) in files {
        let path = dir.join(name);
        if let Err(e) = std::fs::write(&path, src) {
            eprintln!("{}: {e}", path.display());
            return ExitCode::from(1);
        }
        println!("{} {n}", path.display());
    }
    ExitCode::SUCCESS
}
