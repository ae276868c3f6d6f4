//! A multi-CPU system on the real-time engine (contract §6): each CPU scans
//! at its own constant scan on one monotonic time, requests address one CPU,
//! and an acknowledged write is in that CPU's state directory.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use softplc_core::device::DeviceKind;
use softplc_core::engine::{Clock, MonotonicClock};
use softplc_core::persist::Battery;
use softplc_core::system::System;
use softplc_serve::{EngineConfig, ServeState};

/// CPU 1 at 10 ms, CPU 2 at 20 ms; each counts its scans in D0 and latches
/// D1000-D1009.
fn write_system(dir: &Path) {
    for (i, scan) in [(1, "10ms"), (2, "20ms")] {
        let d = dir.join(format!("cpu{i}"));
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(
            d.join("plc.toml"),
            format!(
                "[[program]]\nfile = \"main.il\"\n[ras]\nconstant_scan = \"{scan}\"\n\
                 [latch]\nlatch1 = [\"D1000-D1009\"]\n[multi_cpu]\ncpus = 2\n"
            ),
        )
        .unwrap();
        std::fs::write(d.join("main.il"), "LD SM400\nINC D0\nEND\n").unwrap();
    }
    std::fs::write(
        dir.join("system.toml"),
        "[[cpu]]\nproject = \"cpu1\"\n[[cpu]]\nproject = \"cpu2\"\n",
    )
    .unwrap();
}

fn system(dir: &Path) -> System {
    let time = MonotonicClock::default();
    let mut clock = || -> Box<dyn Clock> { Box::new(time.clone()) };
    System::load(dir, &mut clock).unwrap()
}

/// The system with each CPU's state directory.
fn load(dir: &Path) -> ServeState {
    let mut sys = system(dir);
    let batteries = sys
        .members_mut()
        .iter_mut()
        .map(|m| Some(Battery::attach(&m.project.state_dir.clone(), &mut m.cpu, true).unwrap()))
        .collect();
    ServeState::system(sys, batteries)
}

fn config() -> EngineConfig {
    EngineConfig {
        period: Duration::from_millis(10),
        end_budget: Duration::from_millis(2),
        queue: 64,
        battery: None,
        log_every: None,
        realtime: softplc_serve::RealTime::none(),
        ack_after_commit: true,
    }
}

#[test]
fn each_cpu_scans_at_its_own_period() {
    let dir = tempfile::tempdir().unwrap();
    write_system(dir.path());
    let stop = Arc::new(AtomicBool::new(false));
    // No state directories: a slow disk's commits would set the pace.
    let state = ServeState::system(system(dir.path()), Vec::new());
    let (handle, join) = softplc_serve::engine::spawn(state, config(), stop.clone());
    std::thread::sleep(Duration::from_millis(600));
    let (one, two, count) = handle
        .call(|s| (s.cpu_at(0).scans(), s.cpu_at(1).scans(), s.cpu_count()))
        .unwrap();
    assert_eq!(count, 2);
    // About 60 and 30 scans; CPU 2 at half CPU 1's rate, whatever the load.
    assert!(one >= 10 && two >= 5, "{one} {two}");
    let ratio = one as f64 / two as f64;
    assert!((1.4..=2.8).contains(&ratio), "{one} {two}");
    stop.store(true, Ordering::Relaxed);
    let s = join.join().unwrap();
    assert_eq!(s.stats.cpus.len(), 2);
    assert!(s.stats.cpus.iter().all(|c| c.exec_max_us > 0));
}

#[test]
fn each_cpu_keeps_its_latched_devices_in_its_own_state_directory() {
    let dir = tempfile::tempdir().unwrap();
    write_system(dir.path());
    let stop = Arc::new(AtomicBool::new(false));
    let (handle, join) = softplc_serve::engine::spawn(load(dir.path()), config(), stop.clone());
    handle
        .call(|s| {
            s.cpu_mut_at(1).set_word(DeviceKind::D, 1000, 4242).unwrap();
            s.mark_wrote(1);
        })
        .unwrap();
    stop.store(true, Ordering::Relaxed);
    drop(join.join().unwrap());
    // A new power-on of the system restores each CPU's own D1000.
    let again = load(dir.path());
    let d1000 = |i| again.cpu_at(i).memory().get_word(DeviceKind::D, 1000);
    assert_eq!(d1000(1), Ok(4242));
    assert_eq!(d1000(0), Ok(0));
}
