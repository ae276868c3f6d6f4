//! 000 §9.2 S.2PID L7735-8677 (spec §4.10): two-degree-of-freedom PID,
//! velocity form. As S.PID plus α (+64) and β (+66), both 0..1; past values
//! +102 Bn-1, +104 PVn, +106 PVn-1, +108 PVn-2, +110 DVn-1, +112 DVn-2, +114
//! Dn-1.
//!
//! `Bn = Bn-1 + c × [(DVn − 2DVn-1 + DVn-2) − (CT/TD)·Bn-1]` (derivative on
//! DV), `Cn = ±(PVn − PVn-1)`, `Dn = Dn-1 + c × [±(PVn − 2PVn-1 + PVn-2) −
//! (CT/TD)·Dn-1]` (derivative on PV), c = MD·TD/(MD·CT + TD), + for PN = 1;
//! `ΔMV = KP × {(1−α)(DVn − DVn-1) + α·Cn + (CT/TI)·DVn + (1−β)·Bn + β·Dn}`.
//! Bn = Dn = 0 when TD = 0 or MODE ∈ {MAN, LCM, CMV}. With α = 0, β = 1 this
//! is S.PID, bit for bit. Processing numbers: 5 Bn/Cn, 6 Dn, 7 ΔMV.

use softplc_ir::device::DeviceMemory;

use super::basic::shift_pv;
use super::front::{derivative, Areas, Front, PidPast};
use super::{gains, Input};
use crate::process::common::{result, PcError};
use crate::process::tag::LoopTag;

/// α or β: negative is detail 2, above 1 detail 3.
fn unit(m: &DeviceMemory, a: &Areas, f: softplc_ir::layout::At<f32>) -> Result<f32, PcError> {
    let v = super::front::tag_pos(m, a.d2, f, 7)?;
    if v > 1.0 {
        return Err(PcError::range(7));
    }
    Ok(v)
}

/// ΔMV of S.2PID (processing No. 5-7).
pub fn law(f: &Front, m: &mut DeviceMemory, a: &Areas, i: &Input) -> Result<f32, PcError> {
    let (md, td, ti) = gains(m, a, 5)?;
    let d2 = a.d2;
    let dv1 = d2.real(m, PidPast::dv1, 5)?;
    let dv2 = d2.real(m, PidPast::dv2, 5)?;
    let b1 = d2.real(m, PidPast::b1, 5)?;
    let off = td == 0.0 || f.mode.no_derivative(i.mode);
    let bn = if off {
        0.0
    } else {
        let x = result(i.dv - 2.0 * dv1 + dv2, 5)?;
        derivative(md, td, i.ct, x, b1, 5)?
    };
    let d1 = d2.real(m, PidPast::d1, 6)?;
    let (x, pv1) = shift_pv(m, a, i, 6)?;
    let cn = result(i.e1 - pv1, 5)?;
    let cn = if i.forward { cn } else { -cn };
    let dn = if off {
        0.0
    } else {
        derivative(md, td, i.ct, x, d1, 6)?
    };
    let alpha = unit(m, a, LoopTag::alpha)?;
    let beta = unit(m, a, LoopTag::beta)?;
    let inc = f.integral(m, d2, i.ct, ti, i.dv, 7)?;
    d2.set(m, PidPast::dv2, dv1);
    d2.set(m, PidPast::dv1, i.dv);
    d2.set(m, PidPast::b1, bn);
    d2.set(m, PidPast::d1, dn);
    let sum = (1.0 - alpha) * (i.dv - dv1) + alpha * cn + inc + (1.0 - beta) * bn + beta * dn;
    result(i.kp * sum, 7)
}
