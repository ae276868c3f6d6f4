//! The APLC-TCP as a [`Profile`]: its names outside programs ([`names`]),
//! value syntax (`16#1F`, `8#17`, `2#101`), program memory and doors (no MC
//! protocol; Modbus with seed 002's map, decision D2, at unit 8).

use softplc_ir::access::{Value, ValueType};
use softplc_ir::device::DeviceKind;
use softplc_ir::profile::{Capacity, Doors, NamedDevice, Naming, Profile};

use crate::names::Name;

/// The family name (`--dialect aplc` selects it by its lower case).
pub const FAMILY: &str = "APLC";

/// APLC device names and constants outside programs.
pub struct AplcNames;

impl Naming for AplcNames {
    fn parse(&self, text: &str) -> Result<NamedDevice, String> {
        let n = Name::parse(text)?;
        Ok(NamedDevice {
            ty: n.ty,
            swap: n.swaps(),
            read_only: n.is_local(),
            spec: n.spec,
        })
    }

    /// `16#1F`, `8#17`, `2#101` (a bit pattern, also for `f32`), decimal, a
    /// float for `f32`, `true`/`false`/`on`/`off`/`1`/`0` for bits.
    fn parse_value(&self, dev: &NamedDevice, text: &str) -> Result<Value, String> {
        let bad = || format!("`{}`: bad value `{text}`", dev.spec.text);
        let t = text.trim();
        if dev.ty == ValueType::Bit {
            return match t.to_ascii_lowercase().as_str() {
                "1" | "true" | "on" => Ok(Value::Bool(true)),
                "0" | "false" | "off" => Ok(Value::Bool(false)),
                _ => Err(bad()),
            };
        }
        if dev.ty == ValueType::F32 {
            if let Some(bits) = int(t).filter(|_| t.contains('#')) {
                let bits = u32::try_from(bits).map_err(|_| bad())?;
                return Ok(Value::Float(f32::from_bits(bits) as f64));
            }
            return t
                .parse::<f64>()
                .ok()
                .filter(|f| (*f as f32).is_finite())
                .map(Value::Float)
                .ok_or_else(bad);
        }
        int(t).map(Value::Int).ok_or_else(bad)
    }

    fn current_value(&self, dev: &str) -> Option<String> {
        let u = dev.to_ascii_uppercase();
        [("T", "TN"), ("C", "CN")].iter().find_map(|(p, n)| {
            let rest = u.strip_prefix(p)?;
            (!rest.is_empty() && rest.bytes().all(|b| b.is_ascii_digit()))
                .then(|| format!("{n}{rest}"))
        })
    }

    fn io_name(&self, kind: DeviceKind, n: u32) -> String {
        format!("{kind:?}{n:o}")
    }

    /// LM and V: a POU's locals.
    fn is_local(&self, dev: &str) -> bool {
        let u = dev.to_ascii_uppercase();
        u.starts_with('V') || u.contains("LM")
    }
}

/// `16#1F`, `8#17`, `2#101`, `+5`, `-5`.
fn int(t: &str) -> Option<i64> {
    for (p, r) in [("16#", 16), ("8#", 8), ("2#", 2)] {
        if let Some(d) = t.strip_prefix(p) {
            return i64::from_str_radix(d, r).ok();
        }
    }
    t.strip_prefix('+').unwrap_or(t).parse().ok()
}

/// The APLC-TCP (002 ch. 1-3).
pub static PROFILE: Profile = Profile {
    model: "APLC-TCP",
    family: FAMILY,
    naming: &AplcNames,
    // The manual sets no limit on program files; softplc keeps those of the
    // largest QnHCPU for a project's files.
    capacity: Capacity {
        program_steps: 252 * 1024,
        programs: 124,
    },
    default_devices: crate::devices::device_config,
    step_numbers: false,
    doors: Doors {
        mc: None,
        modbus: "aplc",
        modbus_unit: 8,
        serial_ports: 2,
        opcua: false,
    },
    // At most 128 bit devices (and 16 words) forced at once (002 ch. 1, performance specifications note 5).
    max_forces: 128,
    default_system: crate::system,
};
