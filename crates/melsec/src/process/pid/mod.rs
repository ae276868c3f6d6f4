//! Control instructions with the common PID front end (000 ch. 9: §9.1-§9.7,
//! §9.20-§9.21; spec §4.8-§4.15, §4.24): S.PID, S.2PID, S.PIDP, S.SPI,
//! S.IPD, S.BPI, S.R, S.ONF2, S.ONF3. `front` is the shared front end; the
//! velocity forms (S.PID, S.2PID, S.IPD, S.BPI) share one flow here and
//! differ in their law (one file each); S.PIDP, S.SPI, S.R and S.ONF2/3 have
//! their own flows.
//!
//! Operands `S1 D1 S2 D2 S3`: S1 +0 E1 (PV, %); D1 +0 BW, +2 BB (S.R: BW
//! only); S2 the operation constants; D2 the 128-word loop memory
//! ([`crate::process::tag::LoopTag`]); S3 +0 E2, the set value from the
//! upper loop (%), or a dummy (SD1506) when SVPTN says E2 is unused.

pub mod basic;
pub mod bpi;
pub mod front;
pub mod ipd;
pub mod onoff;
pub mod pidp;
pub mod ratio;
pub mod spi;
pub mod twodof;

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_lang::isa::{Def, Doc};

use softplc_ir::layout::At;

use self::front::{run, Areas, Front, Halt, Operands, Pattern, PatternFields};
use crate::process::common::{self, def, BlockMemory, PcError};
use crate::process::tag::{alm, bb, LoopTag, LOOP_TAG};
use crate::{Args, ExecCtx, Instr};

static PID: Doc = Doc {
    family: "process control: PID",
    cite: "000 §9.1 L6777-7734",
    notes: "velocity form, incomplete derivative on PV; CT counter per DEC-1..4; cascade SV \
            (DEC-14); anti-windup on MHA2/MLA2 or, firmware ≤ 07031, MHA/MLA (DEC-15)",
};
static TWO_DOF: Doc = Doc {
    family: "process control: PID",
    cite: "000 §9.2 L7735-8677",
    notes: "two degrees of freedom (α +64, β +66); α = 0, β = 1 is S.PID",
};
static PIDP: Doc = Doc {
    family: "process control: PID",
    cite: "000 §9.3 L8678-9749",
    notes: "position form with its own output stage (rate/high/low limiter, MV, ALM2); \
            NMAX/NMIN at S2+7/+9; SD1508 b0 integral hold while TRKF (firmware ≥ 07032)",
};
static SPI: Doc = Doc {
    family: "process control: PID",
    cite: "000 §9.4 L9750-10583",
    notes: "sampled PI: operate int(ST/ΔT) of every int(STHT/ΔT) executions, BT = ΔT",
};
static IPD: Doc = Doc {
    family: "process control: PID",
    cite: "000 §9.5 L10602-11483",
    notes: "I-PD: only the integral term sees SV",
};
static BPI: Doc = Doc {
    family: "process control: PID",
    cite: "000 §9.6 L11484-12241",
    notes: "blend PI, reconstructed form KP × (DVn + (CT/TI)·ΣDV) (DEC-16)",
};
static RATIO: Doc = Doc {
    family: "process control: ratio",
    cite: "000 §9.7 L12242-12746",
    notes: "BW = E1 × (Rn − RMIN)/(RMAX − RMIN) + BIAS (DEC-17), Rn rate-limited by DR",
};
static ONF: Doc = Doc {
    family: "process control: ON/OFF",
    cite: "000 §9.20 L15929-16516, §9.21 L16517-17151",
    notes: "2- and 3-position ON/OFF with hysteresis HS0 (+18) / HS1 (+20) on the CT counter",
};

pub static DEFS: &[Def] = &[
    def("S.PID", 5, &PID, Velocity::compile_pid).loop_memory(3, &LOOP_TAG),
    def("S.2PID", 5, &TWO_DOF, Velocity::compile_2pid).loop_memory(3, &LOOP_TAG),
    def("S.PIDP", 5, &PIDP, pidp::Pidp::compile).loop_memory(3, &LOOP_TAG),
    def("S.SPI", 5, &SPI, spi::Spi::compile).loop_memory(3, &LOOP_TAG),
    def("S.IPD", 5, &IPD, Velocity::compile_ipd).loop_memory(3, &LOOP_TAG),
    def("S.BPI", 5, &BPI, Velocity::compile_bpi).loop_memory(3, &LOOP_TAG),
    def("S.R", 5, &RATIO, ratio::Ratio::compile).loop_memory(3, &LOOP_TAG),
    def("S.ONF2", 5, &ONF, onoff::OnOff::compile_2).loop_memory(3, &LOOP_TAG),
    def("S.ONF3", 5, &ONF, onoff::OnOff::compile_3).loop_memory(3, &LOOP_TAG),
];

softplc_ir::layout! {
    /// The operation constants (S2) of S.PID, S.2PID and S.IPD (and the
    /// first seven words of S.PIDP's, [`pidp::PidpConsts`]).
    pub struct PidConsts[7] {
        /// MTD: the derivative gain (8.0).
        mtd: f32 @ 0,
        /// DVLS: the deviation alarm hysteresis (2.0).
        dvls: f32 @ 2,
        /// PN: 0 reverse, 1 forward action.
        pn: u16 @ 4,
        /// TRK: 1 tracking.
        trk: u16 @ 5,
        /// SVPTN: b0 = 1 E2 not used, b1 = 0 E2 is the upper loop's MV.
        svptn: u16 @ 6,
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of S.SPI and S.BPI.
    pub struct PiConsts[5] {
        /// DVLS: the deviation alarm hysteresis (2.0).
        dvls: f32 @ 0,
        /// PN: 0 reverse, 1 forward action.
        pn: u16 @ 2,
        /// TRK: 1 tracking.
        trk: u16 @ 3,
        /// SVPTN: b0 = 1 E2 not used, b1 = 0 E2 is the upper loop's MV.
        svptn: u16 @ 4,
    }
}

/// PN, TRK and SVPTN of [`PidConsts`].
pub const PID_PATTERN: PatternFields = PatternFields {
    pn: Some(PidConsts::pn),
    trk: PidConsts::trk,
    svptn: PidConsts::svptn,
};

/// PN, TRK and SVPTN of [`PiConsts`].
pub const PI_PATTERN: PatternFields = PatternFields {
    pn: Some(PiConsts::pn),
    trk: PiConsts::trk,
    svptn: PiConsts::svptn,
};

/// Which velocity-form law an instruction computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Law {
    Pid,
    TwoDof,
    Ipd,
    Bpi,
}

/// What the front end hands a law.
#[derive(Clone, Copy, Debug)]
pub struct Input {
    /// E1 = PVn (%).
    pub e1: f32,
    pub dv: f32,
    pub kp: f32,
    pub ct: f32,
    pub mode: u16,
    pub forward: bool,
}

/// A velocity-form control instruction (S.PID, S.2PID, S.IPD, S.BPI):
/// loop stop (BW := 0, DVLA := 0, MODE := MAN, BB1 := 0) → control-cycle
/// judgment (not reached: BW := 0 and end, 000 §9.1 (7)) → SV setting →
/// tracking → gain → the law → deviation check (DVLA, BB1).
#[derive(Debug)]
pub struct Velocity {
    law: Law,
    f: Front,
    ops: Operands,
}

impl Velocity {
    fn compile(a: &mut Args<'_, '_>, law: Law) -> Option<Box<dyn Instr>> {
        let s2 = if law == Law::Bpi { 5 } else { 7 };
        let ops = Operands::compile(a, 2, 3, s2)?;
        let f = Front::new(a)?;
        if law == Law::Bpi && !f.s.bpi_reconstructed {
            a.error(
                0,
                "S.BPI: bpi_reconstructed = false asks for a form of the blend PI the manual's \
                 text does not give (its formula is lost, Process Control Instructions manual \
                 §9.6); only the reconstructed form is implemented",
            );
            return None;
        }
        Some(Box::new(Velocity { law, f, ops }))
    }

    fn compile_pid(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Velocity::compile(a, Law::Pid)
    }

    fn compile_2pid(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Velocity::compile(a, Law::TwoDof)
    }

    fn compile_ipd(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Velocity::compile(a, Law::Ipd)
    }

    fn compile_bpi(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Velocity::compile(a, Law::Bpi)
    }

    fn body(&self, m: &mut DeviceMemory, a: &Areas) -> Result<(), Halt> {
        let f = &self.f;
        if f.stopped(m, a.d2) {
            a.d1.set(m, BlockMemory::bw, 0.0);
            a.d1.set_bits(m, BlockMemory::bb, bb::BB1, false);
            f.stop(m, a.d2, alm::DVLA, Some(LoopTag::ct))?;
            return Ok(());
        }
        if !f.cycle(m, a.d2, LoopTag::ct)?.reached {
            a.d1.set(m, BlockMemory::bw, 0.0);
            return Ok(());
        }
        let (dvls_at, fields): (At<f32>, _) = if self.law == Law::Bpi {
            (PiConsts::dvls, PI_PATTERN)
        } else {
            (PidConsts::dvls, PID_PATTERN)
        };
        let pat = Pattern::read(m, a.s2, fields, 4)?;
        let mode = a.d2.get(m, LoopTag::mode);
        let svn = f.sv(m, a, pat, mode)?;
        let sv1 = f.track(m, a, pat, mode, svn)?;
        let (dv, kp) = f.gain(m, a, pat, sv1)?;
        let input = Input {
            e1: a.s1.real(m, common::Input::e1, 4)?,
            dv,
            kp,
            ct: a.d2.real(m, LoopTag::ct, 5)?,
            mode,
            forward: pat.forward,
        };
        let (bw, check) = match self.law {
            Law::Pid => (basic::law(f, m, a, &input)?, 6),
            Law::TwoDof => (twodof::law(f, m, a, &input)?, 8),
            Law::Ipd => (ipd::law(f, m, a, &input)?, 6),
            Law::Bpi => (bpi::law(m, a, &input)?, 6),
        };
        a.d1.set(m, BlockMemory::bw, bw);
        let dvls = a.s2.real(m, dvls_at, check)?;
        f.check(m, a, dv, dvls, bb::BB1, check)?;
        Ok(())
    }
}

impl Instr for Velocity {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let a = self.ops.resolve(cx.mem)?;
        run(&self.f.sys, cx.mem, |m| self.body(m, &a))
    }
}

/// MTD (S2, [`PidConsts`]) and TD, TI of the loop tag, checked at `step`.
pub(crate) fn gains(m: &DeviceMemory, a: &Areas, step: u16) -> Result<(f32, f32, f32), PcError> {
    let md = front::positive(a.s2.real(m, PidConsts::mtd, step)?, step)?;
    let td = front::tag_pos(m, a.d2, LoopTag::d, step)?;
    let ti = front::tag_pos(m, a.d2, LoopTag::i, step)?;
    Ok((md, td, ti))
}
