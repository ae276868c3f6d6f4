//! The MELSEC CPU models softplc runs, as [`Profile`]s: names, program
//! memory, the family (its instruction set) and the MELSEC device names from
//! outside programs.

use softplc_ir::access::{DeviceSpec, Value};
use softplc_ir::device::{DeviceConfig, DeviceKind};
use softplc_ir::profile::{Capacity, Doors, NamedDevice, Naming, Profile};

/// The family of the MELSEC-Q High Performance models (QnHCPU).
pub const FAMILY_Q: &str = "MELSEC-Q";
/// The process CPUs (QnPHCPU) and the redundant CPUs (QnPRHCPU): the
/// QnHCPU's memory plus the process-control instructions (000 §1). The
/// QnPHCPU lacks the PID control instructions, the QnPRHCPU has both (001
/// §1 point): [`crate::is_redundant_model`].
pub const FAMILY_QNPH: &str = "MELSEC-QnPH";
/// The Universal models (QnUCPU): the QnHCPU's instructions plus those the
/// Universal models add ([`crate::qnu`]).
pub const FAMILY_QNU: &str = "MELSEC-QnU";

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

/// Forced X/Y registrations a QCPU takes; the 33rd is refused (004 §7.9.3).
const MAX_FORCES: usize = 32;

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
        default_devices: DeviceConfig::q06h,
        step_numbers: true,
        doors: Doors {
            mc: Some(mc_code),
            modbus: "q",
            modbus_unit: 1,
            serial_ports: 0,
            opcua: true,
        },
        max_forces: MAX_FORCES,
        default_system: crate::system::system,
    }
}

/// A Universal model: program files, program memory, the default devices
/// with its file registers and the MC model code.
/// `ZR` is the points of its standard RAM's file registers.
const fn qnu<const ZR: u32>(model: &'static str, k_steps: u32, mc: u16) -> Profile {
    Profile {
        default_devices: qnu_devices::<ZR>,
        default_system: crate::system::qnu_system::<ZR>,
        ..self::model(model, FAMILY_QNU, QNU_PROGRAMS, k_steps, mc)
    }
}

/// File-register points `profile`'s standard RAM holds (SD640 reports a
/// file this size or smaller there): a Universal model's default file
/// registers, a QnHCPU's or QnPHCPU's 32K (004 §10.7.1 (1)).
pub fn standard_ram(profile: &Profile) -> u32 {
    if profile.family == FAMILY_QNU {
        (profile.default_devices)().points(DeviceKind::ZR)
    } else {
        crate::system::file_register::QNH_STANDARD_RAM
    }
}

/// Program files of every Universal model (QnUCPU User's Manual, Function
/// Explanation, Program Fundamentals, SH-080807ENG, performance
/// specifications: 124; recalled, not read from the manual: see
/// COMPATIBILITY.md).
const QNU_PROGRAMS: usize = 124;

/// The device defaults of a Universal model: the QnHCPU's points (the
/// parameter defaults are the same, SH-080807ENG "device setting"), with as
/// file registers the points of the model's standard RAM, `ZR` (R is the
/// first 32K of them). A model without standard RAM has none.
///
/// Decision: the CPU's own parameter default is "file register not used";
/// softplc gives the standard RAM's, as it gives a QnHCPU a 1 MB card.
fn qnu_devices<const ZR: u32>() -> DeviceConfig {
    let mut c = DeviceConfig::q06h();
    c.set_points(DeviceKind::ZR, ZR);
    c
}

/// File registers in standard RAM (SH-080807ENG performance specifications,
/// recalled: see COMPATIBILITY.md): none on the Q00UJCPU; 128 KB = 64K
/// points (Q00U, Q01U, Q02U); 192 KB (Q03UD…); 256 KB (Q04UD…); 768 KB
/// (Q06UD…); 1 MB (Q10UD…, Q13UD…); 1.25 MB (Q20UD…, Q26UD…).
const ZR_NONE: u32 = 0;
const ZR_128K: u32 = 65_536;
const ZR_192K: u32 = 98_304;
const ZR_256K: u32 = 131_072;
const ZR_768K: u32 = 393_216;
const ZR_1M: u32 = 524_288;
const ZR_1M25: u32 = 655_360;

/// The models, program files and program memory of 004 Table 3.1 (and the
/// process and redundant CPUs of 000 §1, with the QnHCPU's memory), with the
/// model codes the MC protocol's "read CPU model" answers (SLMP reference;
/// none is published for the QnPHCPUs: 0). The redundant CPUs run as one
/// CPU: redundancy (tracking, system switching) is not modelled. Then the Universal models: program
/// memory in steps from the performance specifications of SH-080807ENG
/// (10K … 260K steps, 1k = 1024), program files and file registers as above.
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
    model("Q12PRHCPU", FAMILY_QNPH, 124, 124, 0x004B),
    model("Q25PRHCPU", FAMILY_QNPH, 124, 252, 0x004C),
    qnu::<ZR_NONE>("Q00UJCPU", 10, 0x0260),
    qnu::<ZR_128K>("Q00UCPU", 10, 0x0261),
    qnu::<ZR_128K>("Q01UCPU", 15, 0x0262),
    qnu::<ZR_128K>("Q02UCPU", 20, 0x0263),
    qnu::<ZR_192K>("Q03UDCPU", 30, 0x0268),
    qnu::<ZR_192K>("Q03UDECPU", 30, 0x0268),
    qnu::<ZR_192K>("Q03UDVCPU", 30, 0x0366),
    qnu::<ZR_256K>("Q04UDHCPU", 40, 0x0269),
    qnu::<ZR_256K>("Q04UDEHCPU", 40, 0x0269),
    qnu::<ZR_256K>("Q04UDVCPU", 40, 0x0367),
    qnu::<ZR_768K>("Q06UDHCPU", 60, 0x026A),
    qnu::<ZR_768K>("Q06UDEHCPU", 60, 0x026A),
    qnu::<ZR_768K>("Q06UDVCPU", 60, 0x0368),
    qnu::<ZR_1M>("Q10UDHCPU", 100, 0x0266),
    qnu::<ZR_1M>("Q10UDEHCPU", 100, 0x0266),
    qnu::<ZR_1M>("Q13UDHCPU", 130, 0x026B),
    qnu::<ZR_1M>("Q13UDEHCPU", 130, 0x026B),
    qnu::<ZR_1M>("Q13UDVCPU", 130, 0x036A),
    qnu::<ZR_1M25>("Q20UDHCPU", 200, 0x0267),
    qnu::<ZR_1M25>("Q20UDEHCPU", 200, 0x0267),
    qnu::<ZR_1M25>("Q26UDHCPU", 260, 0x026C),
    qnu::<ZR_1M25>("Q26UDEHCPU", 260, 0x026C),
    qnu::<ZR_1M25>("Q26UDVCPU", 260, 0x036C),
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
