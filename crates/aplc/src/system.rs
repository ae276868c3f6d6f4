//! APLC-TCP system devices through the engine's [`System`] seam (spec
//! aplc.md §7.1-§7.2, §1.9, decision D14): SM0/SM1/SM2, the clocks SM10-SM15,
//! the scan times SD30-SD32, the run-error flags SM20-SM22 and the SD20-SD24
//! history, the pulse catch SM90-SM97, the positioning parameters'
//! initial values SD84-SD89; error numbering of Appendix 6 (L11239-11289);
//! D6000-D6999 loaded from the EEPROM at power-on and STOP→RUN.

use softplc_ir::device::{DeviceKind, DeviceMemory};
use softplc_ir::fault::{ErrorCode, Fault};
use softplc_ir::system::{End, EndCtx, ErrorReport, ScanStart, Severity, System};

use crate::comm::{mailbox, PortConfig, Regs, IDLE};
use crate::devices::{EEPROM_FIRST, EEPROM_WORDS, INPUT_EDGES};

/// The APLC-TCP's system devices, with the system block's times.
#[derive(Debug, Default)]
pub struct Aplc {
    /// SD34: the watchdog in effect (100-1000 ms, D4).
    pub watchdog_ms: u16,
    /// SD33: the constant scan (0 = off; SM8 ON otherwise).
    pub constant_scan_ms: u16,
    /// The run input (SM9 ON, SD9 its index 0-15: X0 is 0, X10 is 8; 002
    /// L1113-1121, L1231-1237); the engine's `CpuConfig::run_input` waits
    /// for it.
    pub run_input: Option<u8>,
    /// PORT1/PORT2 settings (SD120-SD124, SD135-SD137, SD140-SD142,
    /// SD150-SD154 and the mailboxes' protocol words).
    pub ports: Vec<PortConfig>,
}

/// softplc's BATTERY ERROR (a damaged state directory), as on MELSEC CPUs:
/// Appendix 6 has no number for it.
const BATTERY: ErrorCode = ErrorCode(1600);

fn sm(mem: &mut DeviceMemory, n: i64, v: bool) {
    let _ = mem.set_bit(DeviceKind::SM, n, v);
}

fn sd(mem: &mut DeviceMemory, n: i64, v: u16) {
    let _ = mem.set_word(DeviceKind::SD, n, v);
}

fn ms(us: u64) -> u16 {
    (us / 1000).min(u16::MAX as u64) as u16
}

/// Each word of D6000-D6999 that EROMWR saved comes from the EEPROM image
/// (ZR0-ZR999, marked in ZR1000-ZR1999), which power-on keeps: EEPROM data
/// outranks the data block and the device values on power-on and STOP→RUN
/// (table 2-2 L971-979); everything else starts cleared (L983, decision D5).
fn load_eeprom(mem: &mut DeviceMemory) {
    let n = EEPROM_WORDS as usize;
    let zr = mem.map.base(DeviceKind::ZR) as usize;
    let d = (mem.map.base(DeviceKind::D) + EEPROM_FIRST) as usize;
    if (mem.map.points(DeviceKind::ZR) as usize) < 2 * n {
        return;
    }
    for k in 0..n {
        if mem.words[zr + n + k] != 0 {
            mem.words[d + k] = mem.words[zr + k];
        }
    }
}

impl Aplc {
    /// The system block's port settings into SD (re-applied at STOP→RUN,
    /// §7.1-§7.2), the ports idle (SM114, SM124, SM134), every mailbox
    /// empty (a request of the previous RUN is dropped, L10361 "only in
    /// RUN").
    fn init_ports(&self, mem: &mut DeviceMemory) {
        let sw = mem.map.base(DeviceKind::SW) as usize;
        let n = mem.map.points(DeviceKind::SW) as usize;
        mem.words[sw..sw + n].fill(0);
        for sm_n in [114, Regs::of(1).sm_free + IDLE, Regs::of(2).sm_free + IDLE] {
            sm(mem, sm_n as i64, true);
        }
        for p in &self.ports {
            for (n, v) in p.registers() {
                sd(mem, n as i64, v);
            }
            let _ = mem.set_word(
                DeviceKind::SW,
                (mailbox::base(p.port) + mailbox::PROTOCOL) as i64,
                p.protocol_code(),
            );
        }
    }
}

/// SD1: the firmware version as Appendix 2 writes it (100 for 1.00):
/// softplc's own version.
fn firmware_version() -> u16 {
    let n = |s: &str| s.parse::<u16>().unwrap_or(0);
    n(env!("CARGO_PKG_VERSION_MAJOR")) * 100 + n(env!("CARGO_PKG_VERSION_MINOR")).min(99)
}

/// SD2: the user program capacity in k steps (12k steps, L655-656).
const CAPACITY_K_STEPS: u16 = 12;

/// SD10: the main module's I/O points, inputs in the high byte and outputs in
/// the low byte: 10 inputs and 6 outputs (L644, L714-718).
const MAIN_IO_POINTS: u16 = 10 << 8 | 6;

/// 002 App. 1 SM90-SM97 (L10783-10797), pulse catch: each rising edge of
/// X0-X7 sets its relay, which stays ON until the program (R/W) or STOP→RUN
/// clears it. softplc's inputs change between scans, so an edge is any
/// OFF→ON change of the input image since the previous scan start — also
/// one turned OFF again before the scan, which X itself never shows. The
/// exceptions (a port used by HCNT or SPD) cannot occur: APLC-TCP has no
/// high-speed I/O (both are rejected at load).
fn catch_pulses(mem: &mut DeviceMemory, rises: u64) {
    for k in 0..8 {
        if rises >> k & 1 != 0 {
            sm(mem, 90 + k, true);
        }
    }
}

/// SD84-SD89, the positioning parameters' initial values (App. 2
/// L11065-11070): base speed 0, top speed 100000 (SD85 high word, SD86 low),
/// acceleration time 100 ms, envelope rise and fall 100 ms. Only the
/// positioning instructions, which APLC-TCP does not have, read them.
const POSITIONING: [(i64, u16); 6] = [
    (84, 0),
    (85, (100_000u32 >> 16) as u16),
    (86, 100_000u32 as u16),
    (87, 100),
    (88, 100),
    (89, 100),
];

/// SD50-SD55 keep their values at STOP→RUN (Appendix 2, L10984).
const SD_KEPT: std::ops::RangeInclusive<i64> = 50..=55;

impl System for Aplc {
    /// Appendix 2's working-state rows: SD0 0 (the manual gives a type code
    /// for the AT100 only), SD1 the version, SD2 the capacity, SD7/SD8 and
    /// SD11/SD12 0 (no expansion, special or analog modules), SD10 the main
    /// module's I/O; SM3 OFF and SD3 0 (softplc detects no system error);
    /// SM9/SD9 the run input; SM196, SD25/SD26, SD33/SD34, SM8 below.
    fn power_on(&self, mem: &mut DeviceMemory) {
        sd(mem, 1, firmware_version());
        sd(mem, 2, CAPACITY_K_STEPS);
        sd(mem, 10, MAIN_IO_POINTS);
        sm(mem, 9, self.run_input.is_some());
        sd(mem, 9, self.run_input.map_or(0, u16::from));
        // SM196: EEPROM write idle; SD25/SD26 initial 255 (Appendix 2).
        sm(mem, 196, true);
        sd(mem, 25, 255);
        sd(mem, 26, 255);
        sd(mem, 33, self.constant_scan_ms);
        sd(mem, 34, self.watchdog_ms);
        sm(mem, 8, self.constant_scan_ms > 0);
        for (n, v) in POSITIONING {
            sd(mem, n, v);
        }
    }

    /// STOP→RUN: every SM (Appendix 1, L10698) and every SD but SD50-SD55
    /// (Appendix 2, L10984) back to its power-on value, whether or not the
    /// device values are kept; the ports follow in [`Self::initialised`].
    fn stop_to_run(&self, mem: &mut DeviceMemory) {
        let sm_base = mem.map.base(DeviceKind::SM) as usize;
        let sm_n = mem.map.points(DeviceKind::SM) as usize;
        mem.bits[sm_base..sm_base + sm_n].fill(false);
        let sd_n = mem.map.points(DeviceKind::SD) as i64;
        for n in (0..sd_n).filter(|n| !SD_KEPT.contains(n)) {
            sd(mem, n, 0);
        }
        self.power_on(mem);
    }

    /// After the initial values (`[initial]`, the data block's place): the
    /// words EROMWR saved (decision D5), also after a state directory brought
    /// the EEPROM back.
    fn initialised(&self, mem: &mut DeviceMemory) {
        load_eeprom(mem);
        self.init_ports(mem);
    }

    /// SM0 ON in RUN, SM1 the first scan, SM2 until one scan completed;
    /// SM10-SM14 toggle every half period from RUN (first half 0); SM15
    /// toggles every scan, 0 on the first (L10696-10760).
    fn scan_start(&self, mem: &mut DeviceMemory, start: ScanStart) {
        let (t, first_scan) = (start.since_run_us, start.first_scan);
        sm(mem, 0, true);
        sm(mem, 1, first_scan);
        sm(mem, 2, first_scan);
        let half = |us: u64| (t / us) & 1 == 1;
        sm(mem, 10, half(5_000));
        sm(mem, 11, half(50_000));
        sm(mem, 12, half(500_000));
        sm(mem, 13, half(30_000_000));
        sm(mem, 14, half(1_800_000_000));
        let toggle = !first_scan && !mem.get_bit(DeviceKind::SM, 15).unwrap_or(true);
        sm(mem, 15, toggle);
        catch_pulses(mem, start.input_rises);
        let edges = (start.input_rises & 0xFF) as u16 | ((start.input_falls & 0xFF) as u16) << 8;
        let _ = mem.set_word(DeviceKind::SW, INPUT_EDGES as i64, edges);
    }

    /// Housekeeping: the timers (D21); SD30/SD31/SD32: current, minimum,
    /// maximum scan time in ms. The APLC has no initial programs: the END
    /// of an initial scan changes nothing.
    fn end(&self, cx: &mut EndCtx<'_>, end: End) {
        if end.initial {
            return;
        }
        let (mem, t) = (&mut *cx.mem, end.times);
        crate::timers::housekeeping(mem, t.current_us);
        sd(mem, 30, ms(t.current_us));
        sd(mem, 31, ms(t.min_us));
        sd(mem, 32, ms(t.max_us));
    }

    /// Faults in Appendix 6 numbers; a scan longer than the constant scan
    /// is no error (L950) and there are no annunciators or common pointers. Conditions without
    /// an Appendix 6 number keep softplc's (BATTERY ERROR 1600) or take the
    /// nearest (IRET errors 68, a missing program 72).
    fn code(&self, fault: Fault) -> Option<ErrorCode> {
        Some(ErrorCode(match fault {
            Fault::Operation => 64,
            Fault::Range => 65,
            // The APLC has no rack: its programs cannot name a module.
            Fault::NoModule { .. } => 65,
            Fault::Watchdog => 61,
            Fault::ScanOverrun
            | Fault::LowSpeedOverrun
            | Fault::Annunciator
            | Fault::PointerTwice => return None,
            // The APLC is never part of a multi-CPU system (a project refuses it).
            Fault::OwnSharedMemory { .. }
            | Fault::OtherSharedMemory { .. }
            | Fault::NotControlled { .. }
            | Fault::TooManyPending
            | Fault::MultiCpuDown
            | Fault::MultiCpuError
            | Fault::CpuCount
            | Fault::MultiCpuParameter => return None,
            Fault::ForWithoutNext
            | Fault::NextWithoutFor
            | Fault::ForNesting
            | Fault::BreakWithoutFor
            | Fault::NoRet
            | Fault::RetInMain
            | Fault::NoIret
            | Fault::IretInMain => 68,
            Fault::CallNesting => 66,
            Fault::NoProgram => 72,
            Fault::Battery => BATTERY.0,
            Fault::Family(c) => c.0,
        }))
    }

    /// Appendix 6's messages (L11266-11289).
    fn message(&self, code: ErrorCode) -> &'static str {
        match code.0 {
            60 => "program compile error",
            61 => "user program timeout (watchdog)",
            62 => "illegal instruction",
            63 => "illegal operand device type",
            64 => "illegal operand value",
            65 => "operand device number out of range",
            66 => "subroutine stack overflow",
            67 => "interrupt request queue overflow",
            68 => "illegal jump label or subroutine call",
            69 => "divide by zero",
            70 => "illegal stack definition",
            72 => "undefined subroutine or interrupt routine",
            73 => "special module address invalid",
            74 => "special module access error",
            75 => "I/O immediate refresh error",
            1600 => "BATTERY ERROR: battery-backed data lost (damaged state file)",
            _ => "error",
        }
    }

    /// SM20 and the SD20-SD24 history (newest in SD20, pushed only when it
    /// differs, L1313-1316); SM21 for 65, SM22 for 64 (L10732-10733).
    fn report_error(&self, mem: &mut DeviceMemory, report: &ErrorReport<'_>) {
        let code = report.code;
        sm(mem, 20, true);
        match code.0 {
            65 => sm(mem, 21, true),
            64 => sm(mem, 22, true),
            _ => {}
        }
        let cur = mem.get_word(DeviceKind::SD, 20).unwrap_or(0);
        if cur != code.0 {
            for n in (21..=24).rev() {
                let v = mem.get_word(DeviceKind::SD, n - 1).unwrap_or(0);
                sd(mem, n, v);
            }
            sd(mem, 20, code.0);
        }
    }

    /// 64-80 keep the CPU running; 60-63 and everything else stop it (D14).
    fn severity(&self, code: ErrorCode) -> Severity {
        if (64..=80).contains(&code.0) {
            Severity::Continue
        } else {
            Severity::Stop
        }
    }
}
