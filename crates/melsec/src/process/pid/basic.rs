//! 000 §9.1 S.PID L6777-7734 (spec §4.9): basic PID, velocity form, the
//! incomplete derivative on the measured value. S2 +0 MTD (8.0), +2 DVLS
//! (2.0), +4 PN, +5 TRK, +6 SVPTN; past values +102 Bn-1, +104 PVn, +106
//! PVn-1, +108 PVn-2, +110 DVn-1.
//!
//! `Bn = Bn-1 + MD·TD/(MD·CT + TD) × [±(PVn − 2PVn-1 + PVn-2) − (CT/TD)·Bn-1]`
//! (+ for PN = 1), `ΔMV = KP × {(DVn − DVn-1) + (CT/TI)·DVn + Bn}`; Bn = 0
//! when TD = 0 or MODE ∈ {MAN, LCM, CMV} (the past values still move); the
//! integral increment after the freeze rules of [`Front::integral`].

use softplc_ir::device::DeviceMemory;

use super::front::{derivative, Areas, Front, PidPast};
use super::{gains, Input};
use crate::process::common::{result, PcError};

/// The second difference of PV after shifting the PV history (+104 → +106
/// → +108, E1 → +104), signed by PN; returns (x, PVn-1).
pub(crate) fn shift_pv(
    m: &mut DeviceMemory,
    a: &Areas,
    i: &Input,
    step: u16,
) -> Result<(f32, f32), PcError> {
    let pv1 = a.d2.real(m, PidPast::pv, step)?;
    let pv2 = a.d2.real(m, PidPast::pv1, step)?;
    a.d2.set(m, PidPast::pv2, pv2);
    a.d2.set(m, PidPast::pv1, pv1);
    a.d2.set(m, PidPast::pv, i.e1);
    let x = result(i.e1 - 2.0 * pv1 + pv2, step)?;
    Ok((if i.forward { x } else { -x }, pv1))
}

/// Bn of S.PID and S.IPD (processing No. 5), stored at +102.
pub(crate) fn bn(
    f: &Front,
    m: &mut DeviceMemory,
    a: &Areas,
    i: &Input,
    x: f32,
) -> Result<f32, PcError> {
    let (md, td, _) = gains(m, a, 5)?;
    let b1 = a.d2.real(m, PidPast::b1, 5)?;
    let bn = if td == 0.0 || f.mode.no_derivative(i.mode) {
        0.0
    } else {
        derivative(md, td, i.ct, x, b1, 5)?
    };
    a.d2.set(m, PidPast::b1, bn);
    Ok(bn)
}

/// ΔMV of S.PID (processing No. 5).
pub fn law(f: &Front, m: &mut DeviceMemory, a: &Areas, i: &Input) -> Result<f32, PcError> {
    let (_, _, ti) = gains(m, a, 5)?;
    let dv1 = a.d2.real(m, PidPast::dv1, 5)?;
    let (x, _) = shift_pv(m, a, i, 5)?;
    let bn = bn(f, m, a, i, x)?;
    let inc = f.integral(m, a.d2, i.ct, ti, i.dv, 5)?;
    a.d2.set(m, PidPast::dv1, i.dv);
    result(i.kp * (i.dv - dv1 + inc + bn), 5)
}
