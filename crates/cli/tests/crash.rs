//! Crash consistency of latched data (issue 4): `softplc run` increments latched
//! devices every scan and is killed with SIGKILL at random moments; after each
//! restart every latched value must be one it had at some END (all counters
//! agree) and nothing may go backwards.

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn softplc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
}

/// xorshift: reproducible random delays without a dependency.
fn next(seed: &mut u64) -> u64 {
    *seed ^= *seed << 13;
    *seed ^= *seed >> 7;
    *seed ^= *seed << 17;
    *seed
}

#[test]
fn kill_9_never_loses_or_mixes_latched_data() {
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("count.il");
    // R (file registers) and L (latch relays) are retained; every scan adds 1 to
    // R0, to L0-L15 as a 16-bit number and to R10/R11 as a 32-bit number.
    std::fs::write(&prog, "LD SM400\nINC R0\nINC K4L0\nDINC R10\nEND\n").unwrap();
    let state = dir.path().join("state");
    let kills: u32 = std::env::var("SOFTPLC_CRASH_KILLS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(200);
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    let mut last = 0u64;
    let started = Instant::now();
    for k in 0..kills {
        let mut child = softplc()
            .arg("run")
            .arg(&prog)
            .args([
                "--state",
                state.to_str().unwrap(),
                "--scans",
                "1000000000",
                "--scan-time",
                "1ms",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_micros(10_000 + next(&mut seed) % 100_000));
        child.kill().unwrap();
        child.wait().unwrap();
        let out = softplc()
            .arg("run")
            .arg(&prog)
            .args(["--state", state.to_str().unwrap(), "--scans", "0", "--json"])
            .args([
                "--show", "R0:u16", "--show", "K4L0:u16", "--show", "R10:u32",
            ])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "restart {k}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let r0 = v["devices"]["R0:u16"].as_u64().unwrap();
        let l = v["devices"]["K4L0:u16"].as_u64().unwrap();
        let r10 = v["devices"]["R10:u32"].as_u64().unwrap();
        assert_eq!(
            (r0, l),
            (r10 & 0xFFFF, r10 & 0xFFFF),
            "kill {k}: values from different ENDs"
        );
        assert!(r10 >= last, "kill {k}: went back from {last} to {r10}");
        last = r10;
    }
    eprintln!(
        "{kills} kills in {:.1} s, final count {last} scans",
        started.elapsed().as_secs_f64()
    );
    assert!(last > 0, "the program never committed");
}
