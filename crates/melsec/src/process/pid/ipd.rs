//! 000 §9.5 S.IPD L10602-11483 (spec §4.13): I-PD control, velocity form.
//! Operands and memory as S.PID (past values +102 Bn-1, +104 PVn, +106
//! PVn-1, +108 PVn-2). Bn as in S.PID; `ΔMV = KP × {(CT/TI)·DVn ± (PVn −
//! PVn-1) + Bn}` (+ for PN = 1), so only the integral term sees SV and an SV
//! step does not kick MV.

use softplc_ir::device::DeviceMemory;

use super::basic::{bn, shift_pv};
use super::front::{Areas, Front};
use super::{gains, Input};
use crate::process::common::{result, PcError};

/// ΔMV of S.IPD (processing No. 5).
pub fn law(f: &Front, m: &mut DeviceMemory, a: &Areas, i: &Input) -> Result<f32, PcError> {
    let (_, _, ti) = gains(m, a, 5)?;
    let (x, pv1) = shift_pv(m, a, i, 5)?;
    let bn = bn(f, m, a, i, x)?;
    let inc = f.integral(m, a.d2, i.ct, ti, i.dv, 5)?;
    let p = result(i.e1 - pv1, 5)?;
    let p = if i.forward { p } else { -p };
    result(i.kp * (inc + p + bn), 5)
}
