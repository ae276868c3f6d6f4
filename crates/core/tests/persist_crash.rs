//! Crash consistency of `persist::Store` (issue 4, item 4): the state must survive
//! kill -9 at any instant, and a reopen must see exactly one complete commit.
//!
//! The child is this test binary re-executed with `SOFTPLC_PERSIST_CHILD_DIR` set,
//! running only the `persist_child` test: it increments a set of counters spread
//! over three regions (and every fourth commit rewrites a whole 256 KiB region,
//! so some frames are large enough to be torn by the kill) and commits, in a loop,
//! reporting each finished commit on stdout. The parent kills it with SIGKILL (`Child::kill`) after a random delay,
//! reopens the store and checks that all counters are equal (one commit, not a
//! mix), never go backwards, and are at least the last commit the child reported
//! as finished.
//!
//! Knobs (environment): `SOFTPLC_PERSIST_KILLS` (default 250),
//! `SOFTPLC_PERSIST_SEED` (default fixed).

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use softplc_core::persist::{Region, Store, StoreOptions};

const CHILD_ENV: &str = "SOFTPLC_PERSIST_CHILD_DIR";
const THRESHOLD_ENV: &str = "SOFTPLC_PERSIST_CHILD_THRESHOLD";

fn layout() -> Vec<Region> {
    vec![
        // 64 counters 512 bytes apart: 64 separate chunk records per commit.
        Region::new("latch:D", 64 * 512),
        Region::new("zr", 256 * 1024),
        Region::new("history", 1024),
    ]
}

/// (region, byte offset) of every counter; all hold the same value after a commit.
fn counters() -> Vec<(usize, usize)> {
    let mut v: Vec<(usize, usize)> = (0..64).map(|i| (0, i * 512 + (i % 4) * 4)).collect();
    v.extend([(1, 0), (1, 70_000), (1, 131_072), (1, 256 * 1024 - 4)]);
    v.push((2, 1020));
    v
}

fn read_counters(regions: &[Vec<u8>]) -> Vec<u32> {
    counters()
        .into_iter()
        .map(|(r, o)| u32::from_le_bytes(regions[r][o..o + 4].try_into().unwrap()))
        .collect()
}

/// The byte that fills "zr" (outside the counters) once commit `value` is done:
/// every fourth commit (1, 5, 9 …) rewrites the whole region, so its frame is large
/// (~256 KiB) and a kill can tear it in the middle of `write`.
fn filler(value: u32) -> u8 {
    match value {
        0 => 0,
        v => (v - (v - 1) % 4) as u8,
    }
}

/// Applies commit `value` to the regions.
fn step(regions: &mut [Vec<u8>], value: u32) {
    if value % 4 == 1 {
        regions[1].fill(filler(value));
    }
    for (r, o) in counters() {
        regions[r][o..o + 4].copy_from_slice(&value.to_le_bytes());
    }
}

/// The single value all counters share, or a description of the mix.
fn common_value(regions: &[Vec<u8>]) -> Result<u32, String> {
    let c = read_counters(regions);
    if !c.iter().all(|&x| x == c[0]) {
        let mut distinct = c.clone();
        distinct.sort_unstable();
        distinct.dedup();
        return Err(format!("counters differ (a mix of commits): {distinct:?}"));
    }
    let mut expect = regions.to_vec();
    expect[1].fill(filler(c[0]));
    step(&mut expect, c[0]);
    if let Some(at) = (0..expect[1].len()).find(|&i| expect[1][i] != regions[1][i]) {
        return Err(format!(
            "counters say commit {}, but zr[{at}] is {} instead of {} (a mix of commits)",
            c[0], regions[1][at], expect[1][at]
        ));
    }
    Ok(c[0])
}

fn open(dir: &Path, threshold: Option<u64>) -> (Store, Vec<Vec<u8>>) {
    let l = layout();
    let (store, got) = Store::open_with(
        dir,
        &l,
        StoreOptions {
            checkpoint_threshold: threshold,
            ..StoreOptions::default()
        },
    )
    .unwrap_or_else(|e| panic!("open {}: {e}", dir.display()));
    let regions = got
        .into_iter()
        .zip(&l)
        .map(|(g, r)| g.unwrap_or_else(|| vec![0; r.len]))
        .collect();
    (store, regions)
}

/// Child mode: commit forever. Does nothing in a normal test run.
#[test]
fn persist_child() {
    let Some(dir) = std::env::var_os(CHILD_ENV) else {
        return;
    };
    let threshold = std::env::var(THRESHOLD_ENV)
        .ok()
        .and_then(|s| s.parse().ok());
    let (mut store, mut regions) = open(Path::new(&dir), threshold);
    let mut value = common_value(&regions).unwrap();
    let mut out = std::io::stdout().lock();
    // Markers start their own line: libtest may have printed "test … " before.
    let _ = writeln!(out, "\n@@READY {value}");
    let _ = out.flush();
    loop {
        value += 1;
        step(&mut regions, value);
        let refs: Vec<&[u8]> = regions.iter().map(Vec::as_slice).collect();
        store.commit(&refs).unwrap();
        let _ = writeln!(out, "@@C {value}");
        let _ = out.flush();
    }
}

/// xorshift64: deterministic delays without a `rand` dependency.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

#[derive(Default)]
struct ChildReport {
    ready: Option<u32>,
    last_commit: Option<u32>,
}

#[test]
fn kill_9_at_random_instants_never_loses_or_mixes_commits() {
    if std::env::var_os(CHILD_ENV).is_some() {
        return;
    }
    let kills = env_u64("SOFTPLC_PERSIST_KILLS", 250);
    let seed = env_u64("SOFTPLC_PERSIST_SEED", 0x5eed_2024_0404_0001).max(1);
    let mut rng = Rng(seed);
    let dir: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("persist_crash-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let exe = std::env::current_exe().unwrap();

    let started = Instant::now();
    let mut seen = 0u32; // the value found by the last reopen
    let mut max_commits_per_life = 0u32;
    let mut torn_tails = 0;
    let mut killed_in_checkpoint = 0;
    let mut early_kills = 0;
    for round in 0..kills {
        // Commits append ~5 KiB, every fourth ~260 KiB: checkpoint every few
        // commits, every ~15, or at the default threshold (8 MiB, every ~120).
        let threshold = match rng.below(3) {
            0 => 128 << 10,
            1 => 1 << 20,
            _ => 8 << 20,
        };
        let mut child = Command::new(&exe)
            .args([
                "persist_child",
                "--exact",
                "--nocapture",
                "--test-threads=1",
            ])
            .env(CHILD_ENV, &dir)
            .env(THRESHOLD_ENV, threshold.to_string())
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawn child");
        let stdout = child.stdout.take().unwrap();
        let (ready_tx, ready_rx) = mpsc::channel();
        let reader = std::thread::spawn(move || {
            let mut report = ChildReport::default();
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if let Some(v) = line.strip_prefix("@@READY ") {
                    report.ready = v.trim().parse().ok();
                    let _ = ready_tx.send(());
                } else if let Some(v) = line.strip_prefix("@@C ") {
                    // A kill can cut the last line short: only whole lines count.
                    if let Ok(v) = v.parse() {
                        report.last_commit = Some(v);
                    }
                }
            }
            report
        });

        // One round in eight kills early, possibly during startup or recovery.
        let early = rng.below(8) == 0;
        if early {
            early_kills += 1;
            std::thread::sleep(Duration::from_micros(rng.below(15_000)));
        } else {
            if ready_rx.recv_timeout(Duration::from_secs(20)).is_err() {
                let _ = child.kill();
                let out = child.wait_with_output().unwrap();
                panic!(
                    "round {round}: child never got ready; stderr:\n{}",
                    String::from_utf8_lossy(&out.stderr)
                );
            }
            std::thread::sleep(Duration::from_micros(rng.below(30_000)));
        }
        if let Ok(Some(status)) = child.try_wait() {
            let out = child.wait_with_output().unwrap();
            panic!(
                "round {round}: child exited by itself ({status}); stderr:\n{}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        child.kill().expect("SIGKILL child");
        child.wait().unwrap();
        let report = reader.join().unwrap();

        if dir.join("image.bin.tmp").exists() {
            killed_in_checkpoint += 1;
        }
        let (store, regions) = open(&dir, None);
        if !store.warnings().is_empty() {
            torn_tails += 1;
        }
        let value = common_value(&regions)
            .unwrap_or_else(|e| panic!("round {round}: {e}; warnings: {:?}", store.warnings()));
        drop(store);
        if let Some(ready) = report.ready {
            assert_eq!(
                ready, seen,
                "round {round}: the child recovered {ready}, the parent's last reopen {seen}"
            );
        }
        assert!(
            value >= seen,
            "round {round}: counters went back from {seen} to {value}"
        );
        if let Some(last) = report.last_commit {
            assert!(
                value >= last,
                "round {round}: commit {last} finished in the child but reopen found {value}"
            );
            // Commits may be in flight, never more than one.
            assert!(
                value <= last + 1,
                "round {round}: reopen found {value}, child finished {last}"
            );
        }
        max_commits_per_life = max_commits_per_life.max(value - seen);
        seen = value;
    }
    let elapsed = started.elapsed();
    println!(
        "persist crash test: {kills} kills ({early_kills} early) in {:.1} s, final counter {seen}, \
         most commits in one life {max_commits_per_life}, {torn_tails} reopens with a torn/cut \
         journal tail, {killed_in_checkpoint} kills during a checkpoint (temp image left)",
        elapsed.as_secs_f64()
    );
    assert!(seen > 0, "no commit ever survived");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Cost of a typical END-processing commit: a 1 MiB file register area plus
/// 16 KiB of latched devices, a handful of words changed per scan. Prints, does
/// not assert (timings depend on the machine and the build profile).
#[test]
fn commit_cost_with_few_changed_words() {
    if std::env::var_os(CHILD_ENV).is_some() {
        return;
    }
    let dir =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("persist_cost-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let l = vec![Region::new("zr", 1 << 20), Region::new("latch", 16 << 10)];
    let (mut store, _) = Store::open(&dir, &l).unwrap();
    let mut zr = vec![0u8; 1 << 20];
    let mut latch = vec![0u8; 16 << 10];
    store.commit(&[&zr, &latch]).unwrap();
    let mut rng = Rng(12345);

    let mut measure = |store: &mut Store, n: usize| {
        let mut times = Vec::with_capacity(n);
        let mut bytes = 0;
        for i in 0..n {
            // 4 words in ZR, 2 in the latch area, at random places.
            for _ in 0..4 {
                let at = rng.below((1 << 20) / 2) as usize * 2;
                zr[at] = zr[at].wrapping_add(1);
            }
            for _ in 0..2 {
                let at = rng.below((16 << 10) / 2) as usize * 2;
                latch[at] = latch[at].wrapping_add(i as u8 | 1);
            }
            let t = Instant::now();
            let s = store.commit(&[&zr, &latch]).unwrap();
            times.push(t.elapsed());
            bytes += s.bytes_written;
        }
        times.sort();
        let mean = times.iter().sum::<Duration>() / n as u32;
        (
            mean,
            times[n / 2],
            times[n * 99 / 100],
            times[n - 1],
            bytes / n,
        )
    };
    let (mean, p50, p99, max, bytes) = measure(&mut store, 2000);
    println!(
        "commit, 1 MiB + 16 KiB, 6 words changed, no sync: mean {mean:?} p50 {p50:?} p99 {p99:?} \
         max {max:?}, {bytes} bytes/commit"
    );
    store.set_sync(true);
    let (mean, p50, p99, max, _) = measure(&mut store, 200);
    println!("commit, same, fdatasync each: mean {mean:?} p50 {p50:?} p99 {p99:?} max {max:?}");
    store.set_sync(false);
    let t = Instant::now();
    store.checkpoint().unwrap();
    println!("checkpoint (1 MiB image write + fsyncs): {:?}", t.elapsed());
    let mut times: Vec<Duration> = (0..500)
        .map(|_| {
            let t = Instant::now();
            let s = store.commit(&[&zr, &latch]).unwrap();
            assert_eq!(s.bytes_written, 0);
            t.elapsed()
        })
        .collect();
    times.sort();
    println!(
        "commit with nothing changed (the comparison alone): p50 {:?} max {:?}",
        times[250], times[499]
    );
    drop(store);
    let t = Instant::now();
    let (_, _) = Store::open(&dir, &l).unwrap();
    println!("open (image only): {:?}", t.elapsed());
    let _ = std::fs::remove_dir_all(&dir);
}
