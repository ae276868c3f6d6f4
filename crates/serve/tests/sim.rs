//! A multi-CPU system in virtual time (contract §7 with §6): an advance
//! counts scans of CPU 1 and runs every CPU due up to CPU 1's last scan, in
//! virtual-time order; at `max` speed the CPUs keep their periods' ratio
//! exactly.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use softplc_core::device::DeviceKind;
use softplc_core::engine::{Clock, VirtualClock};
use softplc_core::system::System;
use softplc_serve::{Advance, AdvanceRefused, Advanced, EngineConfig, ServeState};
use softplc_serve::{TimeScale, VirtualTime};

/// CPU 1 at 10 ms, CPU 2 at 20 ms; each counts its scans in D0.
fn write_system(dir: &Path) {
    for (i, scan) in [(1, "10ms"), (2, "20ms")] {
        let d = dir.join(format!("cpu{i}"));
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(
            d.join("plc.toml"),
            format!(
                "[[program]]\nfile = \"main.il\"\n[ras]\nconstant_scan = \"{scan}\"\n\
                 [multi_cpu]\ncpus = 2\n"
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

/// The system on one virtual clock at `scale`.
fn start(
    dir: &Path,
    scale: TimeScale,
    lockstep: bool,
) -> (
    softplc_serve::EngineHandle,
    Arc<AtomicBool>,
    std::thread::JoinHandle<ServeState>,
) {
    write_system(dir);
    let time = VirtualClock::new();
    let mut clock = || -> Box<dyn Clock> { Box::new(time.clone()) };
    let sys = System::load(dir, &mut clock).unwrap();
    let mut state = ServeState::system(sys, Vec::new());
    state.set_virtual_time(VirtualTime {
        clock: time.clone(),
        scale,
        lockstep,
    });
    let cfg = EngineConfig {
        period: Duration::from_millis(10),
        end_budget: Duration::from_millis(2),
        queue: 64,
        battery: None,
        log_every: None,
        realtime: softplc_serve::RealTime::none(),
        ack_after_commit: true,
    };
    let stop = Arc::new(AtomicBool::new(false));
    let (handle, join) = softplc_serve::engine::spawn(state, cfg, stop.clone());
    (handle, stop, join)
}

/// Each CPU's executed scans and D0.
fn counts(h: &softplc_serve::EngineHandle) -> [(u64, u16); 2] {
    h.call(|s| {
        [0, 1].map(|i| {
            let c = s.cpu_at(i);
            (c.scans(), c.memory().get_word(DeviceKind::D, 0).unwrap())
        })
    })
    .unwrap()
}

fn advance(h: &softplc_serve::EngineHandle, a: Advance) -> Advanced {
    let rx = h.call(move |s| s.advance(a)).unwrap().unwrap();
    rx.blocking_recv().unwrap()
}

#[test]
fn a_system_advances_by_scans_of_cpu_1_in_virtual_time_order() {
    let dir = tempfile::tempdir().unwrap();
    let (h, stop, join) = start(dir.path(), TimeScale::Max, true);
    // Held at power-on.
    assert_eq!(counts(&h), [(0, 0), (0, 0)]);
    // CPU 1 scans at 10, 20, … 100 ms; CPU 2 at 20, 40, … 100 ms, the one
    // due with CPU 1's last scan included.
    assert_eq!(
        advance(&h, Advance::Scans(10)),
        Advanced {
            scan: 10,
            time_us: 100_000
        }
    );
    assert_eq!(counts(&h), [(10, 10), (5, 5)]);
    // 25 ms: 3 scans of CPU 1 (110, 120, 130 ms), CPU 2's at 120 ms.
    assert_eq!(
        advance(&h, Advance::Us(25_000)),
        Advanced {
            scan: 13,
            time_us: 130_000
        }
    );
    assert_eq!(counts(&h), [(13, 13), (6, 6)]);
    let refused = h.call(|s| s.advance(Advance::Scans(0)).err()).unwrap();
    assert_eq!(refused, Some(AdvanceRefused::Scans(0)));
    stop.store(true, Ordering::Relaxed);
    join.join().unwrap();
}

#[test]
fn at_max_speed_a_system_keeps_its_order_in_virtual_time() {
    let dir = tempfile::tempdir().unwrap();
    let (h, stop, join) = start(dir.path(), TimeScale::Max, false);
    let refused = h.call(|s| s.advance(Advance::Scans(1)).err()).unwrap();
    assert_eq!(refused, Some(AdvanceRefused::NotLockstep));
    for _ in 0..20 {
        std::thread::sleep(Duration::from_millis(10));
        let [(one, _), (two, _)] = counts(&h);
        // CPU 2 has scanned at every 20 ms up to CPU 1's last scan, except
        // at an END of CPU 1 whose time CPU 2 shares and has yet to scan.
        let due = one / 2;
        assert!(
            two == due || (one % 2 == 0 && two + 1 == due),
            "CPU 1 {one} scans, CPU 2 {two}"
        );
    }
    assert!(counts(&h)[0].0 > 100);
    stop.store(true, Ordering::Relaxed);
    join.join().unwrap();
}
