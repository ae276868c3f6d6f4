//! The control instructions (S.PID … S.ONF3, S.AT1) allocate nothing in the
//! scan: a counting global allocator around 200 scans of a program running
//! all of them in AUT (and S.AT1 in MAN), loops stopped and running.

mod common;
#[path = "common/process_loop.rs"]
mod lp;

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(p, l, n) }
    }
}

#[global_allocator]
static A: Counting = Counting;

#[test]
fn control_instructions_do_not_allocate_in_the_scan() {
    let mnemonics = [
        "S.PID", "S.2PID", "S.PIDP", "S.SPI", "S.IPD", "S.BPI", "S.R", "S.ONF2", "S.ONF3",
    ];
    let mut src = String::from("LD SM400\n");
    for (k, m) in mnemonics.iter().enumerate() {
        // One loop per instruction at D2000 + 200·k; S3 (E2) and the upper
        // INH at its −8 inside D300..D399.
        let s2 = match *m {
            "S.SPI" | "S.BPI" => 240,
            "S.R" => 246,
            "S.ONF2" | "S.ONF3" => 248,
            _ => 200,
        };
        src += &format!(
            "{m} D0 D{} D{s2} D{} D{}\n",
            100 + 4 * k,
            2000 + 200 * k,
            310 + 10 * k
        );
    }
    src += "S.AT1 D0 D180 D251 D1000 D400\nEND\n";
    let mut p = common::Plc::process(&src);
    lp::defaults(&mut p);
    lp::constants(&mut p, "S.PID");
    p.set("D205", "1").set("D206", "0");
    lp::setf(&mut p, "D240", 2.0);
    for (d, v) in [
        (242, 0),
        (243, 0),
        (244, 3),
        (246, 0),
        (247, 3),
        (248, 0),
        (249, 0),
        (250, 3),
    ] {
        p.set(&format!("D{d}"), &v.to_string());
    }
    lp::tf(&mut p, 14, 50.0);
    lp::tf(&mut p, 56, 3.0);
    lp::tw(&mut p, 1, lp::MAN);
    lp::tf(&mut p, 70, 5.0);
    p.set("D2", "1");
    for k in 0..mnemonics.len() as u32 {
        for w in 0..96 {
            let v = p.int(&format!("D{}:u16", 1000 + w));
            p.set(&format!("D{}:u16", 2000 + 200 * k + w), &v.to_string());
        }
        lp::tw(&mut p, 1000 + 200 * k + 1, lp::AUT);
    }
    p.scans(3);
    let before = ALLOCS.load(Ordering::Relaxed);
    for k in 0..200u32 {
        // PV moves; every 50 scans the first loop stops for a scan.
        p.cpu
            .set_word(
                softplc_core::device::DeviceKind::D,
                1,
                0x4200 + (k % 64) as u16,
            )
            .unwrap();
        let alm = if k % 50 == 49 { 0x4000 } else { 0 };
        p.cpu
            .set_word(softplc_core::device::DeviceKind::D, 2003, alm)
            .unwrap();
        p.scan();
    }
    let allocs = ALLOCS.load(Ordering::Relaxed) - before;
    assert_eq!(p.error(), None);
    assert_eq!(allocs, 0, "allocations during 200 scans");
    assert!(lp::getf(&p, "D100") != 0.0 || lp::getf(&p, "D104") != 0.0);
}
