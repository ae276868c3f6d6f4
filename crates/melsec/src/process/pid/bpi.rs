//! 000 §9.6 S.BPI L11484-12241 (spec §4.14): blend PI, velocity form, in the
//! reconstructed form of DEC-16 (the manual's formula is lost; its legend
//! names BT, the execution cycle, which could not be placed):
//! `ΔMV = KP × (DVn + (CT/TI)·DVI)` with DVI the accumulated deviation, SDV
//! = ΣDV at +56 and (CT/TI)·DVI at +98/99. S2 +0 DVLS, +2 PN, +3 TRK, +4
//! SVPTN.
//!
//! Normally ΣDV := ΣDV + DVn and (CT/TI)·DVI := (CT/TI) × ΣDV. When TI = 0 or
//! ALM.MHA/MLA = 1 (the BPI page gives the alarm bits of ALM, not ALM2, and
//! no firmware split, L12156-12187) both are held at their previous values.

use softplc_ir::device::DeviceMemory;
use softplc_ir::layout::At;

use super::front::{tag_pos, Areas};
use super::Input;
use crate::process::common::{result, PcError};
use crate::process::tag::{alm, LoopTag};

/// ΣDV, S.BPI's +56 (000 §9.6 L11940-11950).
const SDV: At<f32> = LoopTag::d;

softplc_ir::layout! {
    /// The past values of S.BPI in the loop tag (000 §9.6 L11940-11950).
    pub struct BpiPast[128] {
        /// (CT/TI)·DVI: the integral term.
        ip: f32 @ 98,
    }
}

/// ΔMV of S.BPI (processing No. 5).
pub fn law(m: &mut DeviceMemory, a: &Areas, i: &Input) -> Result<f32, PcError> {
    let d2 = a.d2;
    let ti = tag_pos(m, d2, LoopTag::i, 5)?;
    let frozen = ti == 0.0 || d2.get(m, LoopTag::alm) & (alm::MHA | alm::MLA) != 0;
    let ip = if frozen {
        d2.real(m, BpiPast::ip, 5)?
    } else {
        let sdv = result(d2.real(m, SDV, 5)? + i.dv, 5)?;
        let ip = result(i.ct / ti * sdv, 5)?;
        d2.set(m, SDV, sdv);
        d2.set(m, BpiPast::ip, ip);
        ip
    };
    result(i.kp * (i.dv + ip), 5)
}
