//! I/O control instructions (000 ch. 8): S.IN, S.OUT1, S.OUT2, S.MOUT,
//! S.DUTY, S.BC, S.PSUM. `stage` holds the output stage that S.OUT1/S.OUT2/
//! S.DUTY share (and S.SEL's limiter): the mode judgment, the velocity input
//! addition with TRKF, the change-rate and high/low limiter with
//! MHA/MLA/DMLA and ALM2, the reset windup.

mod bc;
mod duty;
mod input;
mod mout;
mod out;
mod psum;
pub(crate) mod stage;

use softplc_lang::isa::{Def, Doc};

use super::common::def;
use super::tag::LOOP_TAG;

static IN: Doc = Doc {
    family: "process control: I/O",
    cite: "000 §8.1 L3306-3893",
    notes: "f32; range check with hysteresis, SEA = BB2 ∨ BB3 (DEC-9), SM1500 hold, \
            limiter, inverse conversion, digital filter on the previous BW (DEC-8)",
};

static OUT1: Doc = Doc {
    family: "process control: I/O",
    cite: "000 §8.2 L3894-4506",
    notes: "velocity input into MVP, TRKF bumpless, change-rate and MH/ML limiter with \
            ALM2, skipped when T = MV (DEC-10), first-order reset windup (DEC-11), SM1501 hold",
};

static OUT2: Doc = Doc {
    family: "process control: I/O",
    cite: "000 §8.3 L4507-5017",
    notes: "positional input; change-rate and MH/ML limiter skipped when E1 = MV (DEC-10)",
};

static MOUT: Doc = Doc {
    family: "process control: I/O",
    cite: "000 §8.4 L5018-5288",
    notes: "BW from the operator's MV in the manual modes, held otherwise",
};

static DUTY: Doc = Doc {
    family: "process control: I/O",
    cite: "000 §8.5 L5307-5996",
    notes: "S.OUT1's stage, then ON count round(MV/100·N) at each CTDUTY period \
            (DEC-1, DEC-12; the first period after clearing is OFF)",
};

static BC: Doc = Doc {
    family: "process control: I/O",
    cite: "000 §8.6 L5997-6423",
    notes: "BIN32; high alarm, change-rate window of m = int(CTIM/ΔT) (DEC-18), SV1/SV2 outputs",
};

static PSUM: Doc = Doc {
    family: "process control: I/O",
    cite: "000 §8.7 L6424-6774",
    notes: "BIN32 pulse increments modulo 2^32/2^24/2^16 (DEC-13), weight/unit, HILMT wrap or hold",
};

pub static DEFS: &[Def] = &[
    def("S.IN", 4, &IN, input::In::compile).loop_memory(3, &LOOP_TAG),
    def("S.OUT1", 4, &OUT1, out::Out::compile_out1).loop_memory(3, &LOOP_TAG),
    def("S.OUT2", 4, &OUT2, out::Out::compile_out2).loop_memory(3, &LOOP_TAG),
    def("S.MOUT", 4, &MOUT, mout::Mout::compile).loop_memory(3, &LOOP_TAG),
    def("S.DUTY", 4, &DUTY, duty::Duty::compile).loop_memory(3, &LOOP_TAG),
    def("S.BC", 4, &BC, bc::Bc::compile).loop_memory(3, &bc::BC_TAG),
    def("S.PSUM", 4, &PSUM, psum::Psum::compile).loop_memory(3, &psum::PSUM_TAG),
];
