//! The MELSEC CPU models softplc runs, as [`Profile`]s: names, program
//! memory, the family (its instruction set) and the MELSEC device names from
//! outside programs.

use softplc_ir::access::{DeviceSpec, Value};
use softplc_ir::device::DeviceKind;
use softplc_ir::profile::{Capacity, Doors, NamedDevice, Naming, Profile};

/// The family of the MELSEC-Q High Performance models (QnHCPU).
pub const FAMILY_Q: &str = "MELSEC-Q";
/// The process CPUs (QnPHCPU): the QnHCPU's memory plus the
/// process-control instructions (000 §1).
pub const FAMILY_QNPH: &str = "MELSEC-QnPH";

/// MELSEC device names outside programs: the shared door's own syntax
/// (`X1F` hex, `D10:f32`, `K4M0`, `D0.F`, `TN0`; values `H1F`, `0x1F`).
pub struct MelsecNames;

impl Naming for MelsecNames {
    fn parse(&self, text: &str) -> Result<NamedDevice, String> {
        let spec = DeviceSpec::parse(text)?;
        Ok(NamedDevice {
            ty: spec.ty,
            spec,
            swap: false,
            read_only: false,
        })
    }

    fn parse_value(&self, dev: &NamedDevice, text: &str) -> Result<Value, String> {
        dev.spec.parse_value(text).map_err(|e| e.to_string())
    }

    fn current_value(&self, dev: &str) -> Option<String> {
        current_value(dev, &[("ST", "STN"), ("T", "TN"), ("C", "CN")])
    }

    fn io_name(&self, kind: DeviceKind, n: u32) -> String {
        kind.format(n)
    }
}

/// `T0` → `TN0` for the given (contact prefix, value prefix) pairs, first
/// match wins.
pub fn current_value(dev: &str, kinds: &[(&str, &str)]) -> Option<String> {
    let u = dev.to_ascii_uppercase();
    kinds.iter().find_map(|(p, n)| {
        let rest = u.strip_prefix(p)?;
        (!rest.is_empty() && rest.bytes().all(|b| b.is_ascii_digit())).then(|| format!("{n}{rest}"))
    })
}

const fn model(
    model: &'static str,
    family: &'static str,
    programs: usize,
    k_steps: u32,
    mc_code: u16,
) -> Profile {
    Profile {
        model,
        family,
        naming: &MelsecNames,
        capacity: Capacity {
            // 1k = 1024 steps (decision, COMPATIBILITY.md).
            program_steps: k_steps * 1024,
            programs,
        },
        step_numbers: true,
        doors: Doors {
            mc: Some(mc_code),
            modbus: "q",
            modbus_unit: 1,
            serial_ports: 0,
        },
        default_system: crate::system::system,
    }
}

/// The models, program files and program memory of 004 Table 3.1 (and the
/// process CPUs of 000 §1, with the QnHCPU's memory), with the model codes
/// the MC protocol's "read CPU model" answers (SLMP reference; none is
/// published for the process CPUs: 0).
pub static PROFILES: &[Profile] = &[
    model("Q02CPU", FAMILY_Q, 28, 28, 0x0041),
    model("Q02HCPU", FAMILY_Q, 28, 28, 0x0041),
    model("Q06HCPU", FAMILY_Q, 60, 60, 0x0042),
    model("Q12HCPU", FAMILY_Q, 124, 124, 0x0043),
    model("Q25HCPU", FAMILY_Q, 124, 252, 0x0044),
    model("Q02PHCPU", FAMILY_QNPH, 28, 28, 0),
    model("Q06PHCPU", FAMILY_QNPH, 60, 60, 0),
    model("Q12PHCPU", FAMILY_QNPH, 124, 124, 0),
    model("Q25PHCPU", FAMILY_QNPH, 124, 252, 0),
];

/// The profile a project gets without `[cpu] model` (and `run` without
/// `--model`): the Q06HCPU.
pub fn default_profile() -> &'static Profile {
    &PROFILES[2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_is_the_q06hcpu_and_names_are_unique() {
        assert_eq!(default_profile().model, "Q06HCPU");
        for (i, p) in PROFILES.iter().enumerate() {
            assert!(PROFILES[i + 1..].iter().all(|q| q.model != p.model));
        }
        assert_eq!(MelsecNames.current_value("st1").as_deref(), Some("STN1"));
        assert_eq!(MelsecNames.current_value("T0").as_deref(), Some("TN0"));
        assert_eq!(MelsecNames.current_value("D0"), None);
        assert_eq!(MelsecNames.current_value("TN"), None);
    }
}
