//! A multi-CPU system's scans allocate nothing: the END exchange (own
//! information, auto refresh, shared-memory and module mirrors, out-of-group
//! I/O) copies spans resolved at load through a buffer sized at load. A
//! counting global allocator checks 200 scans of each CPU on both tiers.

use std::alloc::{GlobalAlloc, Layout, System as Heap};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use softplc_core::engine::{Clock, VirtualClock};
use softplc_core::system::System;
use softplc_core::tier::{apply, Exec};

struct Counting;
static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { Heap.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { Heap.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { Heap.realloc(p, l, n) }
    }
}

#[global_allocator]
static A: Counting = Counting;

/// Both CPUs' parameters: refresh of B and D, out-of-group inputs, a
/// Q64AD controlled by CPU 2 and a 16-point input module controlled by
/// CPU 1.
const PARAMS: &str = "[[program]]\nfile = \"main.il\"\n\
    [multi_cpu]\ncpus = 2\nout_of_group_input = true\n\
    [[multi_cpu.refresh]]\ndevice = \"B0\"\nwords = [2, 2]\n\
    [[multi_cpu.refresh]]\ndevice = \"D1000\"\nwords = [16, 16]\n\
    [[slot]]\ntype = \"input\"\npoints = 16\n\
    [[slot]]\ntype = \"intelligent\"\nmodule = \"Q64AD\"\ncontrol_cpu = 2\n";

const CPU1: &str = "LD SM400\nINC D1000\nMOV U3E1\\G2048 D0\nMOV U1\\G11 D1\nLD X0\nOUT B0\nEND\n";
const CPU2: &str = "LD SM400\n+ D1000 K1 D1016\nMOV U1\\G11 D2\nLD B0\nOUT B20\nEND\n";

#[test]
fn system_scans_do_not_allocate_on_either_tier() {
    for exec in [Exec::Interp, Exec::Jit] {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("system.toml"),
            "[[cpu]]\nproject = \"a\"\n[[cpu]]\nproject = \"b\"\n",
        )
        .unwrap();
        for (d, il) in [("a", CPU1), ("b", CPU2)] {
            let p = dir.path().join(d);
            std::fs::create_dir(&p).unwrap();
            std::fs::write(p.join("plc.toml"), PARAMS).unwrap();
            std::fs::write(p.join("main.il"), il).unwrap();
        }
        let clock = VirtualClock::new();
        let c = clock.clone();
        let mut sys = System::load(dir.path(), &mut || Box::new(c.clone()) as Box<dyn Clock>)
            .unwrap_or_else(|d| panic!("{d}"));
        for i in 0..2 {
            apply(sys.cpu_mut(i), exec).unwrap();
        }
        sys.schedule(Duration::from_millis(10), 0);
        sys.run_until(30_000, &clock);
        let before = ALLOCS.load(Ordering::Relaxed);
        for k in 1..=200u64 {
            sys.cpu_mut(0).set_input(0, k % 2 == 0);
            sys.run_until(30_000 + k * 10_000, &clock);
        }
        let allocs = ALLOCS.load(Ordering::Relaxed) - before;
        for i in 0..2 {
            assert!(sys.cpu(i).error().is_none(), "{:?}", sys.cpu(i).error());
            assert_eq!(sys.cpu(i).scans(), 203);
        }
        assert_eq!(
            allocs, 0,
            "allocations during 200 scans of each CPU ({exec:?})"
        );
        // The exchange ran: CPU 2 saw CPU 1's D1000 and B0 through the refresh.
        let d1000 = |i: usize| {
            sys.cpu(i)
                .memory()
                .get_word(softplc_core::device::DeviceKind::D, 1000)
        };
        assert_eq!(d1000(0).unwrap(), 203);
        assert_eq!(d1000(1).unwrap(), 203);
    }
}
