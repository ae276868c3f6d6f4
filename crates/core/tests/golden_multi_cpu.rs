//! Multi-CPU systems (004 ch. 13-19, contract §6): one time for all CPUs,
//! CPU shared memory and its auto refresh at END, the parameter checks of
//! power-on and the propagation of stop errors. Values worked out by hand
//! from the manual's rules and its examples.

use softplc_core::access::Value;
use softplc_core::engine::{CpuState, VirtualClock};
use softplc_core::names::DevName;
use softplc_core::system::System;
use std::time::Duration;

/// A system in a temporary directory: `cpus` are (plc.toml, main.il) of
/// CPU 1, 2, …
struct Sys {
    _dir: tempfile::TempDir,
    sys: System,
    clock: VirtualClock,
}

fn system(cpus: &[(&str, &str)]) -> Sys {
    let dir = tempfile::tempdir().unwrap();
    let mut manifest = String::new();
    for (i, (toml, il)) in cpus.iter().enumerate() {
        let d = dir.path().join(format!("cpu{}", i + 1));
        std::fs::create_dir(&d).unwrap();
        let toml = format!("[[program]]\nfile = \"main.il\"\n{toml}");
        std::fs::write(d.join("plc.toml"), toml).unwrap();
        std::fs::write(d.join("main.il"), il).unwrap();
        manifest += &format!("[[cpu]]\nproject = \"cpu{}\"\n", i + 1);
    }
    std::fs::write(dir.path().join("system.toml"), manifest).unwrap();
    let clock = VirtualClock::new();
    let c = clock.clone();
    let mut sys = System::load(dir.path(), &mut || Box::new(c.clone())).unwrap_or_else(|d| {
        panic!("{d}");
    });
    sys.schedule(Duration::from_millis(10), 0);
    Sys {
        _dir: dir,
        sys,
        clock,
    }
}

impl Sys {
    /// Runs to `ms` of system time.
    fn run_ms(&mut self, ms: u64) {
        self.sys.run_until(ms * 1000, &self.clock);
    }

    fn int(&self, cpu: usize, name: &str) -> i64 {
        let c = self.sys.cpu(cpu);
        let n = DevName::parse_for(name, c).unwrap();
        match n.read(c).unwrap() {
            Value::Int(i) => i,
            Value::Bool(b) => b as i64,
            v => panic!("{name}: {v:?}"),
        }
    }

    fn bit(&self, cpu: usize, name: &str) -> bool {
        self.int(cpu, name) != 0
    }

    fn error(&self, cpu: usize) -> Option<u16> {
        self.sys.cpu(cpu).error().map(|e| e.code.0)
    }
}

const TWO: &str = "[multi_cpu]\ncpus = 2\n";
const IDLE: &str = "LD SM400\nOUT M0\nEND\n";

/// SD395 is the own CPU number (004 L10426); the CPUs scan on their own
/// constant scans in one time: 10 ms and 20 ms over 100 ms are 10 and 5
/// scans.
#[test]
fn cpu_numbers_and_one_time() {
    let cpu2 = format!("{TWO}[ras]\nconstant_scan = \"20ms\"\n");
    let mut s = system(&[(TWO, IDLE), (&cpu2, IDLE)]);
    s.run_ms(100);
    assert_eq!(s.int(0, "SD395"), 1);
    assert_eq!(s.int(1, "SD395"), 2);
    assert_eq!(s.sys.cpu(0).scans(), 10);
    assert_eq!(s.sys.cpu(1).scans(), 5);
    assert_eq!(s.error(0), None);
    assert_eq!(s.error(1), None);
}

/// The manual's example (L8780-8830, L8873-8876): setting 1, CPU 1 and
/// CPU 2 send 2 words each from B0: CPU 1's B0-B1F, CPU 2's B20-B3F, in
/// shared memory 800H-801H of each. Setting 2, W, 16 words each: 802H-811H.
#[test]
fn auto_refresh_of_the_manuals_example() {
    let params = "[multi_cpu]\ncpus = 2\n\
        [[multi_cpu.refresh]]\ndevice = \"B0\"\nwords = [2, 2]\n\
        [[multi_cpu.refresh]]\ndevice = \"W100\"\nwords = [16, 16]\n";
    let cpu1 = "LD SM400\nDMOV H12345678 K8B0\nMOV K111 W100\nMOV K126 W10F\nEND\n";
    let cpu2 = "LD SM400\nMOV K-2 K4B20\nMOV K222 W110\nEND\n";
    let mut s = system(&[(params, cpu1), (params, cpu2)]);
    s.run_ms(10);
    // CPU 1's END published B0-B1F and W100-W10F into its 800H-811H …
    assert_eq!(s.int(0, "U3E0\\G2048"), 0x5678);
    assert_eq!(s.int(0, "U3E0\\G2049"), 0x1234);
    assert_eq!(s.int(0, "U3E0\\G2050"), 111);
    assert_eq!(s.int(0, "U3E0\\G2065"), 126);
    // … and CPU 2's END (same time, after CPU 1's) took them into its devices.
    assert_eq!(s.int(1, "K8B0"), 0x12345678);
    assert_eq!(s.int(1, "W100"), 111);
    assert_eq!(s.int(1, "W10F"), 126);
    assert_eq!(s.int(1, "U3E1\\G2048"), -2);
    assert_eq!(s.int(1, "U3E1\\G2050"), 222);
    // CPU 1 receives CPU 2's words at its next END.
    assert_eq!(s.int(0, "K4B20"), 0);
    s.run_ms(20);
    assert_eq!(s.int(0, "K4B20"), -2);
    assert_eq!(s.int(0, "W110"), 222);
    // B40 onward is no one's: untouched.
    assert_eq!(s.int(1, "K4B40"), 0);
}

/// (Buffer-memory addresses in names are decimal: 800H is `G2048`.)
///
/// Each CPU may refresh into its own device (L8878-8879): CPU 2 takes the
/// same words into D500.
#[test]
fn refresh_devices_may_differ_per_cpu() {
    let cpu1 = "[multi_cpu]\ncpus = 2\n[[multi_cpu.refresh]]\ndevice = \"D0\"\nwords = [2, 0]\n";
    let cpu2 = "[multi_cpu]\ncpus = 2\n[[multi_cpu.refresh]]\ndevice = \"D500\"\nwords = [2, 0]\n";
    let mut s = system(&[
        (cpu1, "LD SM400\nMOV K7 D0\nMOV K8 D1\nEND\n"),
        (cpu2, IDLE),
    ]);
    s.run_ms(10);
    assert_eq!(s.int(1, "D500"), 7);
    assert_eq!(s.int(1, "D501"), 8);
}

/// A stop error of CPU 2 with the default operation mode stops every CPU
/// with MULTI CPU DOWN 7000; CPU 2 keeps its own code; SM244/SM245 show
/// both stop errors in both CPUs (L8521-8598, L9577-9590).
#[test]
fn a_stop_error_of_cpu2_stops_all() {
    let cpu2 = format!("{TWO}[ras]\noperation_error = \"stop\"\n");
    let mut s = system(&[
        (TWO, IDLE),
        (&cpu2, "LD SM400\nMOV K0 D1\n/ K10 D1 D2\nEND\n"),
    ]);
    s.run_ms(10);
    assert_eq!(s.error(1), Some(4100));
    assert_eq!(s.error(0), Some(7000));
    assert_eq!(s.sys.cpu(0).state(), CpuState::Stop);
    // CPU 1's 7000 is a stop error too: SM244 and SM245 are ON in both.
    for cpu in 0..2 {
        assert!(s.bit(cpu, "SM244"));
        assert!(s.bit(cpu, "SM245"));
        assert!(!s.bit(cpu, "SM246"));
    }
    assert!(s.sys.all_stopped());
}

/// With "the others go on" for CPU 2, CPU 1 records MULTI EXE. ERROR 7010
/// and keeps running.
#[test]
fn a_stop_error_of_cpu2_may_let_cpu1_go_on() {
    let params = "[multi_cpu]\ncpus = 2\nstop_all = { 2 = false }\n";
    let cpu2 = format!("{params}[ras]\noperation_error = \"stop\"\n");
    let mut s = system(&[
        (params, "LD SM400\nINC D0\nEND\n"),
        (&cpu2, "LD SM400\nMOV K0 D1\n/ K10 D1 D2\nEND\n"),
    ]);
    s.run_ms(30);
    assert_eq!(s.error(1), Some(4100));
    assert_eq!(s.error(0), Some(7010));
    assert_eq!(s.sys.cpu(0).state(), CpuState::Run);
    assert_eq!(s.int(0, "D0"), 3);
    assert!(s.bit(0, "SM245"));
}

/// A stop error of CPU 1 always stops the others (7000).
#[test]
fn a_stop_error_of_cpu1_stops_all() {
    let params = "[multi_cpu]\ncpus = 2\nstop_all = { 2 = false }\n";
    let cpu1 = format!("{params}[ras]\noperation_error = \"stop\"\n");
    let mut s = system(&[
        (&cpu1, "LD SM400\nMOV K0 D1\n/ K10 D1 D2\nEND\n"),
        (params, IDLE),
    ]);
    s.run_ms(10);
    assert_eq!(s.error(0), Some(4100));
    assert_eq!(s.error(1), Some(7000));
    assert!(s.bit(1, "SM244"));
}

/// Parameters that differ from CPU 1's stop that CPU with PARAMETER ERROR
/// 3012 at power-on, which stops the others as any stop error (L8481,
/// L8500-8512).
#[test]
fn inconsistent_parameters_are_3012() {
    let other = "[multi_cpu]\ncpus = 2\nout_of_group_input = true\n";
    let s = system(&[(TWO, IDLE), (other, IDLE)]);
    assert_eq!(s.error(1), Some(3012));
    assert_eq!(s.error(0), Some(7000));
    // Other refresh word counts too (the devices may differ, not the counts).
    let r = |w: &str| format!("{TWO}[[multi_cpu.refresh]]\ndevice = \"D0\"\nwords = {w}\n");
    let s = system(&[(&r("[2, 2]"), IDLE), (&r("[4, 2]"), IDLE)]);
    assert_eq!(s.error(1), Some(3012));
    assert_eq!(s.error(0), Some(7000));
    // No [multi_cpu] at all is inconsistent too.
    let s = system(&[(TWO, IDLE), ("", IDLE)]);
    assert_eq!(s.error(1), Some(3010));
}

/// A number of CPUs other than the CPUs installed is 3010 in every CPU.
#[test]
fn a_wrong_number_of_cpus_is_3010() {
    let three = "[multi_cpu]\ncpus = 3\n";
    let s = system(&[(three, IDLE), (three, IDLE)]);
    assert_eq!(s.error(0), Some(3010));
    assert_eq!(s.error(1), Some(3010));
}

/// RESET of CPU 1 resets the system; RESET of CPU 2 alone brings every
/// CPU down with 7000 (L8521-8560).
#[test]
fn reset_rules() {
    let cpu2 = format!("{TWO}[ras]\noperation_error = \"stop\"\n");
    let mut s = system(&[
        (TWO, "LD SM400\nINC D0\nEND\n"),
        (&cpu2, "LD X0\nMOV K0 D1\n/ K10 D1 D2\nEND\n"),
    ]);
    s.sys.cpu_mut(1).set_input(0, true);
    s.run_ms(10);
    assert_eq!(s.error(0), Some(7000));
    s.sys.cpu_mut(1).set_input(0, false);
    s.sys.reset(0).unwrap();
    assert_eq!(s.error(0), None);
    assert_eq!(s.error(1), None);
    assert_eq!(s.sys.cpu(1).state(), CpuState::Run);
    s.run_ms(20);
    assert_eq!(s.int(0, "D0"), 1);
    s.sys.cpu_mut(1).set_stop();
    s.sys.reset(1).unwrap();
    assert_eq!(s.error(0), Some(7000));
    assert_eq!(s.error(1), Some(7000));
    assert!(s.sys.all_stopped());
}

/// The own-operation information area (table 16.1): 0H valid, 1H the
/// error code (SD0), 1FH the operating status; another CPU reads it.
#[test]
fn own_operation_information() {
    let params = "[multi_cpu]\ncpus = 2\nstop_all = { 2 = false }\n";
    let cpu2 = format!("{params}[ras]\noperation_error = \"stop\"\n");
    let mut s = system(&[
        (params, IDLE),
        (&cpu2, "LD SM400\nMOV K0 D1\n/ K10 D1 D2\nEND\n"),
    ]);
    s.run_ms(10);
    assert_eq!(s.int(1, "U3E1\\G0"), 1);
    assert_eq!(s.int(0, "U3E0\\G0"), 1);
    // CPU 2's error, as CPU 1 reads it in CPU 2's area.
    assert_eq!(s.int(0, "U3E1\\G1"), 4100);
    // Status (SD203): STOP is 1 in its low digit.
    assert_eq!(s.int(0, "U3E1\\G31") & 0xF, 1);
    // CPU 1's error 7010 reaches its area at its next END.
    assert_eq!(s.int(1, "U3E0\\G1"), 0);
    s.run_ms(20);
    assert_eq!(s.int(1, "U3E0\\G1"), 7010);
}

/// Two slots controlled by CPU 1 (16 inputs X0-XF, 16 outputs Y10-Y1F) and
/// a generic module controlled by CPU 2 at X/Y20 (unit 2).
const CONTROL: &str = "[[slot]]\ntype = \"input\"\npoints = 16\n\
    [[slot]]\ntype = \"output\"\npoints = 16\n\
    [[slot]]\ntype = \"intelligent\"\nmodule = \"generic\"\ncontrol_cpu = 2\n";

/// Buffer memory of a module another CPU controls is read (L9199-9205):
/// CPU 1 reads what CPU 2 wrote to its module, as of CPU 2's last END.
#[test]
fn another_cpus_module_is_read() {
    let params = format!("{TWO}{CONTROL}");
    let mut s = system(&[
        (&params, "LD SM400\nMOV U2\\G0 D0\nEND\n"),
        (&params, "LD SM400\nINC U2\\G0\nEND\n"),
    ]);
    s.run_ms(30);
    assert_eq!(s.int(1, "U2\\G0"), 3);
    // CPU 1 scans before CPU 2 at the same time: it read CPU 2's value of
    // the scan before.
    assert_eq!(s.int(0, "D0"), 2);
    assert_eq!(s.int(0, "U2\\G0"), 3);
}

/// Inputs and outputs of modules another CPU controls (L9119-9215): with
/// the out-of-group settings CPU 2 loads CPU 1's X0 and Y10; without them
/// they stay OFF; a Y a CPU writes to a module it does not control changes
/// only its own device memory.
#[test]
fn out_of_group_inputs_and_outputs() {
    let program2 = "LD X0\nOUT M0\nLD Y10\nOUT M1\nLD SM400\nOUT Y11\nEND\n";
    for load in [false, true] {
        let params =
            format!("{TWO}out_of_group_input = {load}\nout_of_group_output = {load}\n{CONTROL}");
        let mut s = system(&[(&params, "LD X0\nOUT Y10\nEND\n"), (&params, program2)]);
        s.sys.cpu_mut(0).set_input(0, true);
        s.run_ms(20);
        assert!(s.bit(0, "Y10"));
        assert_eq!(s.bit(1, "X0"), load, "load = {load}");
        assert_eq!(s.bit(1, "M0"), load, "load = {load}");
        assert_eq!(s.bit(1, "M1"), load, "load = {load}");
        // CPU 2's Y11 is its own memory only: CPU 1's Y11 (the module's) stays OFF.
        assert!(s.bit(1, "Y11"));
        assert!(!s.bit(0, "Y11"));
    }
}

/// The I/O assignment is part of the consistency check: a different
/// control CPU in CPU 2's parameters is 3012.
#[test]
fn a_different_io_assignment_is_3012() {
    let p1 = format!("{TWO}{CONTROL}");
    let p2 = format!(
        "{TWO}{}",
        CONTROL.replace("control_cpu = 2", "control_cpu = 1")
    );
    let s = system(&[(&p1, IDLE), (&p2, IDLE)]);
    assert_eq!(s.error(1), Some(3012));
}

/// S.TO writes the own user area, which starts after the refresh area
/// (004 L9049-9111): with 2 refresh words a CPU, CPU 1's user area starts at
/// 802H. CPU 2 reads it with `U3E0\G` and FROM after CPU 1's END; S.TO into
/// the refresh area (800H) is 4101.
#[test]
fn s_to_reaches_the_other_cpu() {
    let params = "[multi_cpu]\ncpus = 2\n\
        [[multi_cpu.refresh]]\ndevice = \"D100\"\nwords = [2, 2]\n";
    let cpu1 = "LD SM400\nMOV K4321 D0\nS.TO H3E0 H802 D0 K1 M10\nEND\n";
    let cpu2 = "LD SM400\nMOV U3E0\\G2050 D0\nFROM H3E0 H802 D1 K1\nEND\n";
    let mut s = system(&[(params, cpu1), (params, cpu2)]);
    s.run_ms(10);
    assert_eq!(s.error(0), None);
    assert_eq!(s.int(0, "U3E0\\G2050"), 4321);
    // CPU 2 scanned after CPU 1's END at the same time.
    assert_eq!(s.int(1, "D0"), 4321);
    assert_eq!(s.int(1, "D1"), 4321);
    // The completion device is ON from the END of the S.TO's scan.
    assert!(s.bit(0, "M10"));
    assert!(!s.bit(0, "M11"));
    let cpu1 = "LD SM400\nS.TO H3E0 H800 D0 K1 M10\nEND\n";
    let mut s = system(&[(params, cpu1), (params, IDLE)]);
    s.run_ms(10);
    assert_eq!(s.error(0), Some(4101));
}

/// The auto refresh runs at END in RUN, STOP and PAUSE, and not after a
/// stop error: the others keep the last data (L8759-8766). CPU 2 writes its
/// D2 from outside while stopped or paused; CPU 1 keeps receiving it.
#[test]
fn refresh_in_stop_and_pause_not_after_a_stop_error() {
    let params = "[multi_cpu]\ncpus = 2\nstop_all = { 2 = false }\n\
        [[multi_cpu.refresh]]\ndevice = \"D0\"\nwords = [2, 2]\n";
    let cpu2 = format!("{params}[ras]\noperation_error = \"stop\"\n");
    let mut s = system(&[
        (params, IDLE),
        (&cpu2, "LD X0\nMOV K0 D10\n/ K10 D10 D11\nEND\n"),
    ]);
    let set_d2 = |s: &mut Sys, v: u16| {
        s.sys
            .cpu_mut(1)
            .set_word(softplc_core::device::DeviceKind::D, 2, v)
            .unwrap()
    };
    s.sys.cpu_mut(1).set_stop();
    set_d2(&mut s, 11);
    s.run_ms(20);
    assert_eq!(s.int(0, "D2"), 11, "STOP");
    s.sys.cpu_mut(1).set_run().unwrap();
    s.sys.cpu_mut(1).set_pause().unwrap();
    set_d2(&mut s, 22);
    s.run_ms(40);
    assert_eq!(s.int(0, "D2"), 22, "PAUSE");
    s.sys.cpu_mut(1).set_run().unwrap();
    // The stop error: CPU 1 goes on (7010) with the last data CPU 2 sent.
    s.sys.cpu_mut(1).set_input(0, true);
    s.run_ms(50);
    assert_eq!(s.error(1), Some(4100));
    assert_eq!(s.error(0), Some(7010));
    set_d2(&mut s, 33);
    s.run_ms(80);
    assert_eq!(s.int(0, "D2"), 22, "after the stop error");
}

/// A PARAMETER ERROR carries the parameter file as common information
/// (App. 2 SD4 = 2, L10182-10230): SD5 drive 0, SD6-SD9 "PARAM   ", SD10/
/// SD11 ".QPA", two ASCII characters a word, the first in the low byte.
#[test]
fn a_parameter_error_names_the_parameter_file() {
    let three = "[multi_cpu]\ncpus = 3\n";
    let s = system(&[(three, IDLE), (three, IDLE)]);
    assert_eq!(s.error(0), Some(3010));
    let sd: Vec<i64> = (4..=11).map(|n| s.int(0, &format!("SD{n}"))).collect();
    assert_eq!(sd, [2, 0, 0x4150, 0x4152, 0x204D, 0x2020, 0x512E, 0x4150]);
    assert!(s.bit(0, "SM5"));
    assert!(!s.bit(0, "SM16"));
}

/// MULTI CPU DOWN names the CPU whose stop error caused it (App. 2 SD4 = 1,
/// SD5 *1: the PLC number; SD6 its I/O number, CPU 2 = 3E10H).
#[test]
fn multi_cpu_down_names_the_cpu_that_stopped() {
    let cpu2 = format!("{TWO}[ras]\noperation_error = \"stop\"\n");
    let mut s = system(&[(TWO, IDLE), (&cpu2, "LD SM400\n/ K1 K0 D0\nEND\n")]);
    s.run_ms(20);
    assert_eq!(s.error(1), Some(4100));
    assert_eq!(s.error(0), Some(7000));
    let sd: Vec<i64> = (4..=6).map(|n| s.int(0, &format!("SD{n}"))).collect();
    assert_eq!(sd, [1, 2, 0x3E10]);
    assert!(s.bit(0, "SM5"));
}
