//! Remote operations (004 §7.6): the RUN-PAUSE contacts, remote RUN/STOP/
//! PAUSE from clients, STOP's priority across sources and the remote RESET
//! permission. Expected values are worked out scan by scan from the manual.

mod common;

use common::Plc;
use softplc_core::engine::{CpuState, Hold, Refusal};

/// D0 counts the scans that ran the program; Y1 follows SM204 (the PAUSE
/// status contact), the manual's interlock for the outputs held in PAUSE
/// (§7.6.2 (3)); SM206 (PAUSE enable) follows M6.
const MAIN: &str = "LD SM400\nINC D0\nLD SM204\nOUT Y1\nLD M6\nOUT SM206\nEND\n";

const CONTACTS: &str =
    "[[program]]\nfile = \"main.il\"\n[ras]\nrun_contact = \"X10\"\npause_contact = \"X11\"\n";

fn contacts() -> Plc {
    Plc::project(CONTACTS, &[("main.il", MAIN)])
}

fn plain() -> Plc {
    Plc::project("[[program]]\nfile = \"main.il\"\n", &[("main.il", MAIN)])
}

/// SD203 b0-b3: 0 RUN, 1 STOP, 2 PAUSE.
fn sd203(p: &Plc) -> i64 {
    p.int("SD203") & 0xF
}

#[test]
fn pause_contact_with_sm206_shows_sm204_one_end_before_pause() {
    // §7.6.2 (2) (a), figure 7.6: contact and SM206 ON → SM204 ON at the END
    // of that scan; PAUSE at the END of the next; contact OFF → RUN again.
    let mut p = contacts();
    p.set("M6", "1").scan();
    assert_eq!(p.int("D0"), 1);
    p.cpu.set_input(0x11, true);
    // Scan 2: the program runs; its END sees the contact: SM204 ON.
    p.scan();
    assert_eq!((p.int("D0"), p.bit("SM204"), p.bit("Y1")), (2, true, false));
    assert_eq!(p.state(), CpuState::Run);
    // Scan 3: the program sees SM204 ON (Y1 ON); its END enters PAUSE.
    p.scan();
    assert_eq!((p.int("D0"), p.bit("Y1")), (3, true));
    assert_eq!((p.state(), sd203(&p)), (CpuState::Pause, 2));
    // In PAUSE the program stands still and Y1 is held.
    p.scans(3);
    assert_eq!((p.int("D0"), p.bit("Y1"), p.bit("SM204")), (3, true, true));
    // Contact OFF: PAUSE ends at the next END, the program runs from step 0.
    p.cpu.set_input(0x11, false);
    p.scan();
    assert_eq!((p.state(), p.bit("SM204")), (CpuState::Run, false));
    p.scan();
    assert_eq!((p.int("D0"), p.bit("Y1")), (4, false));
}

#[test]
fn pause_contact_without_sm206_does_nothing() {
    // PAUSE needs SM206 ON as well (§7.6.5 *2).
    let mut p = contacts();
    p.cpu.set_input(0x11, true);
    p.scans(4);
    assert_eq!(
        (p.state(), p.int("D0"), p.bit("SM204")),
        (CpuState::Run, 4, false)
    );
    // SM206 turned OFF while paused ends the PAUSE as the contact would.
    p.set("M6", "1").scans(2);
    assert_eq!(p.state(), CpuState::Pause);
    p.set("M6", "0").scan();
    // PAUSE: the program does not run, so SM206 stays ON until it runs again.
    p.set("SM206", "0").scan();
    assert_eq!(p.state(), CpuState::Run);
}

#[test]
fn remote_pause_shows_sm204_at_the_next_end_and_pauses_one_end_later() {
    // §7.6.2 (2) (b), figure 7.7: SM204 ON at the END of the scan that
    // received the request; PAUSE at the END after; remote RUN from step 0.
    let mut p = plain();
    p.scan();
    p.cpu.remote_pause(1, false).unwrap();
    assert_eq!((p.state(), p.bit("SM204")), (CpuState::Run, false));
    p.scan();
    assert_eq!(
        (p.int("D0"), p.bit("SM204"), p.state()),
        (2, true, CpuState::Run)
    );
    p.scan();
    assert_eq!(
        (p.int("D0"), p.bit("Y1"), p.state()),
        (3, true, CpuState::Pause)
    );
    p.scans(2);
    assert_eq!(p.int("D0"), 3);
    p.cpu.remote_run(1, false).unwrap();
    assert_eq!((p.state(), p.bit("SM204")), (CpuState::Run, false));
    p.scan();
    assert_eq!((p.int("D0"), p.bit("Y1")), (4, false));
    // PAUSE only from RUN.
    p.cpu.remote_stop(1, false).unwrap();
    assert_eq!(p.cpu.remote_pause(1, false), Err(Refusal::Stopped));
}

#[test]
fn run_contact_stops_at_end_and_shows_sm203() {
    // §7.6.1 (2) (a), figure 7.4: contact ON → STOP, OFF → RUN; SM203 ON
    // while stopped by the contact (App. 1).
    let mut p = contacts();
    p.scan();
    p.cpu.set_input(0x10, true);
    p.scan();
    assert_eq!(p.int("D0"), 2, "the scan runs to END, then STOP");
    assert_eq!(
        (p.state(), sd203(&p), p.bit("SM203")),
        (CpuState::Stop, 1, true)
    );
    p.scans(2);
    assert_eq!(p.int("D0"), 2);
    p.cpu.set_input(0x10, false);
    p.scan();
    assert_eq!((p.state(), p.bit("SM203")), (CpuState::Run, false));
    p.scan();
    assert_eq!(p.int("D0"), 3);
}

#[test]
fn stop_has_priority_every_source_must_say_run() {
    // §7.6.1 (3): any STOP source stops the CPU; all of them must say RUN.
    let mut p = contacts();
    p.scan();
    // The RUN contact and a remote STOP of client 1.
    p.cpu.set_input(0x10, true);
    p.scan();
    p.cpu.remote_stop(1, false).unwrap();
    p.cpu.set_input(0x10, false);
    p.scan();
    assert_eq!((p.state(), p.bit("SM203")), (CpuState::Stop, false));
    // The key switch to RUN does not cancel the remote STOP.
    assert!(p.cpu.set_run().is_err());
    assert_eq!(p.state(), CpuState::Stop);
    p.cpu.remote_run(1, false).unwrap();
    assert_eq!(p.state(), CpuState::Run);
    // The key switch at STOP: a remote RUN leaves the CPU stopped (§7.6.5 table).
    p.cpu.set_stop();
    assert!(matches!(
        p.cpu.remote_run(1, false),
        Err(Refusal::StopHeld(_))
    ));
    assert_eq!(p.state(), CpuState::Stop);
    // The RUN contact ON while the switch is at STOP; the switch to RUN
    // still leaves the contact's STOP.
    p.cpu.set_input(0x10, true);
    p.scan();
    assert!(p.cpu.set_run().is_err());
    p.cpu.set_input(0x10, false);
    p.scan();
    assert_eq!(p.state(), CpuState::Run, "the last STOP source released");
}

#[test]
fn another_clients_hold_blocks_until_it_runs() {
    // §7.6.5 (3): a PAUSE held by one client blocks another's STOP and RUN
    // until the first cancels it with a remote RUN; the same client's last
    // operation wins (§7.6.5 (2)).
    let mut p = plain();
    p.cpu.remote_pause(1, false).unwrap();
    p.scans(2);
    assert_eq!(p.state(), CpuState::Pause);
    let held = Err(Refusal::Held {
        by: 1,
        hold: Hold::Pause,
    });
    assert_eq!(p.cpu.remote_stop(2, false), held);
    assert_eq!(p.cpu.remote_run(2, false), held);
    assert_eq!(p.state(), CpuState::Pause);
    // The same client: STOP replaces its PAUSE.
    p.cpu.remote_stop(1, false).unwrap();
    assert_eq!(p.state(), CpuState::Stop);
    assert_eq!(p.cpu.remote_hold(), Some((1, Hold::Stop)));
    // Forced execution (MC mode 0003) overrides the hold.
    p.cpu.remote_run(2, true).unwrap();
    assert_eq!((p.state(), p.cpu.remote_hold()), (CpuState::Run, None));
}

#[test]
fn remote_reset_only_in_stop_and_only_when_allowed() {
    // §7.6.3 (3): not allowed by default; never in RUN.
    let mut p = plain();
    assert_eq!(p.cpu.remote_reset(), Err(Refusal::NotStopped));
    p.cpu.remote_stop(1, false).unwrap();
    assert_eq!(p.cpu.remote_reset(), Err(Refusal::ResetDisabled));
    assert_eq!(p.state(), CpuState::Stop);
    let toml =
        "[[program]]\nfile = \"main.il\"\n[ras]\nremote_reset = true\nrun_contact = \"X10\"\n";
    let mut p = Plc::project(toml, &[("main.il", MAIN)]);
    p.scans(3);
    p.cpu.remote_stop(1, false).unwrap();
    p.cpu.remote_reset().unwrap();
    // Power-on processing: D0 cleared, RUN (the switch at RUN, §7.6.3 (3) (c)).
    assert_eq!(
        (p.state(), p.int("D0"), p.cpu.remote_hold()),
        (CpuState::Run, 0, None)
    );
    // With the RUN contact ON the CPU comes out of RESET in STOP.
    p.cpu.set_input(0x10, true);
    p.scan();
    p.cpu.remote_reset().unwrap();
    assert_eq!((p.state(), p.bit("SM203")), (CpuState::Stop, true));
}

#[test]
fn contact_parameters_are_checked() {
    let load = |ras: &str| {
        Plc::try_project(
            &format!("[[program]]\nfile = \"main.il\"\n[ras]\n{ras}\n"),
            &[("main.il", MAIN)],
        )
        .err()
        .unwrap_or_default()
    };
    assert!(load("run_contact = \"Y10\"").contains("must be an input X0-X1FFF"));
    assert!(load("run_contact = \"X2000\"").contains("must be an input X0-X1FFF"));
    assert!(load("pause_contact = \"X11\"").contains("pause_contact needs run_contact"));
    assert!(load("remote_reset = 1").contains("true or false"));
    assert_eq!(load("run_contact = \"x1fff\"\npause_contact = \"X0\""), "");
}

/// A converted A-series program enables PAUSE with M9040 (SM1040 = SM206,
/// QCPU App. 1) and reads the contacts as M9041/M9042 (SM1041 = SM204,
/// SM1042 = SM203). The A-series compatibility area is on by default.
#[test]
fn a_series_pause_enable_and_contacts_sm1040_to_sm1042() {
    const A_MAIN: &str = "LD SM400\nINC D0\nLD M6\nOUT SM1040\nEND\n";
    let mut p = Plc::project(CONTACTS, &[("main.il", A_MAIN)]);
    // SM1040 ON, the PAUSE contact ON: SM204 and SM1041 at the END of
    // the scan that sees the contact, PAUSE at the next END.
    p.set("M6", "1").scan();
    p.cpu.set_input(0x11, true);
    p.scan();
    assert_eq!((p.bit("SM204"), p.bit("SM1041")), (true, true));
    p.scan();
    assert_eq!(p.state(), CpuState::Pause);
    // Without SM1040 (nor SM206) the contact does nothing.
    let mut q = Plc::project(CONTACTS, &[("main.il", A_MAIN)]);
    q.cpu.set_input(0x11, true);
    q.scans(3);
    assert_eq!((q.state(), q.bit("SM1041")), (CpuState::Run, false));
    // The RUN contact holds the CPU in STOP: SM203 and SM1042 ON.
    q.cpu.set_input(0x10, true);
    q.scans(2);
    assert_eq!(
        (q.state(), q.bit("SM203"), q.bit("SM1042")),
        (CpuState::Stop, true, true)
    );
    // With the area off, SM1040 enables nothing.
    let off = format!("{CONTACTS}[cpu]\na_compatibility = false\n");
    let mut r = Plc::project(&off, &[("main.il", A_MAIN)]);
    r.set("M6", "1").scan();
    r.cpu.set_input(0x11, true);
    r.scans(3);
    assert_eq!(r.state(), CpuState::Run);
}
