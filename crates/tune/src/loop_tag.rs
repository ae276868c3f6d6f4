//! The loop tag of a process-control loop (process-control spec §3): the
//! 128 words at the head device D2 that S.IN, S.PID, S.OUT1 and S.AT1 share.
//! The tuning driver reads and writes the loop only through these words, so
//! it tunes any program that keeps this layout.

use softplc_core::access::{DeviceSpec, Value};
use softplc_core::device::{parse_operand, Operand};
use softplc_core::engine::Cpu;

/// Word offsets in the loop tag (spec §3; floats are two words, low first).
pub mod offset {
    /// MODE (BIN16, §1.5).
    pub const MODE: u32 = 1;
    /// ALM (BIN16; b14 = SPA, loop stop, §1.6).
    pub const ALM: u32 = 3;
    /// PV, engineering units.
    pub const PV: u32 = 10;
    /// MV, %.
    pub const MV: u32 = 12;
    /// SV, engineering units.
    pub const SV: u32 = 14;
    /// MH, MV high limit, %.
    pub const MH: u32 = 18;
    /// ML, MV low limit, %.
    pub const ML: u32 = 20;
    /// RH, engineering high.
    pub const RH: u32 = 22;
    /// RL, engineering low.
    pub const RL: u32 = 24;
    /// CT, control cycle, s.
    pub const CT: u32 = 46;
    /// P, gain.
    pub const P: u32 = 52;
    /// I, integral time TI, s.
    pub const I: u32 = 54;
    /// D, derivative time TD, s.
    pub const D: u32 = 56;
    /// AT1ST, the S.AT1 sampling period, s.
    pub const AT1ST: u32 = 72;
}

/// MODE value of manual (MAN, b3; spec §1.5).
pub const MODE_MAN: u16 = 0x0008;
/// MODE value of automatic (AUT, b4; spec §1.5).
pub const MODE_AUT: u16 = 0x0010;
/// ALM bit of the loop stop request SPA (b14; spec §1.6).
pub const ALM_SPA: u16 = 1 << 14;

/// The device `off` words after `head`, with the type suffix `ty`
/// (`"f32"`, `"u16"`), e.g. `R1000` + 12 → `R1012:f32`.
pub fn device_at(head: &str, off: u32, ty: &str) -> Result<DeviceSpec, String> {
    let op = parse_operand(head.trim()).map_err(|e| format!("loop tag `{head}`: {e}"))?;
    let Operand::Device {
        dev,
        digits: None,
        bit: None,
        index: None,
    } = op
    else {
        return Err(format!(
            "loop tag `{head}`: give a plain word device (e.g. R1000, D1000, ZR0)"
        ));
    };
    if dev.kind.is_bit() {
        return Err(format!("loop tag `{head}`: {} is a bit device", dev.kind));
    }
    let n = dev
        .number
        .checked_add(off)
        .ok_or_else(|| format!("loop tag `{head}`: +{off} overflows"))?;
    DeviceSpec::parse(&format!("{}:{ty}", dev.kind.format(n)))
}

/// A loop tag resolved against a CPU's memory.
#[derive(Clone, Debug)]
pub struct LoopTag {
    /// The head device as given (with its `CPUn/` prefix in a multi-CPU
    /// system).
    pub head: String,
    /// The `CPUn/` prefix given, or empty.
    prefix: String,
    mode: DeviceSpec,
    alm: DeviceSpec,
    floats: [(u32, DeviceSpec); 12],
}

impl LoopTag {
    /// Resolves the loop tag at `head`; the 128 words must exist in `cpu`.
    pub fn new(head: &str, cpu: &Cpu) -> Result<LoopTag, String> {
        LoopTag::on_cpu("", head, cpu)
    }

    /// [`LoopTag::new`] for the CPU of a multi-CPU system that `prefix`
    /// (`CPU2/`) names: `cpu` is that CPU, names in reports carry the prefix.
    pub fn on_cpu(prefix: &str, head: &str, cpu: &Cpu) -> Result<LoopTag, String> {
        use offset::*;
        let last = device_at(head, 127, "u16")?;
        cpu.read_device(&last)
            .map_err(|e| format!("loop tag `{head}` needs 128 words: {e}"))?;
        let f = |off| Ok::<_, String>((off, device_at(head, off, "f32")?));
        Ok(LoopTag {
            head: format!("{prefix}{}", head.trim()),
            prefix: prefix.to_string(),
            mode: device_at(head, MODE, "u16")?,
            alm: device_at(head, ALM, "u16")?,
            floats: [
                f(PV)?,
                f(MV)?,
                f(SV)?,
                f(MH)?,
                f(ML)?,
                f(RH)?,
                f(RL)?,
                f(CT)?,
                f(P)?,
                f(I)?,
                f(D)?,
                f(AT1ST)?,
            ],
        })
    }

    /// The device of the float at `off` (one of [`offset`]'s float words).
    pub fn float_device(&self, off: u32) -> Result<&DeviceSpec, String> {
        self.floats
            .iter()
            .find(|(o, _)| *o == off)
            .map(|(_, d)| d)
            .ok_or_else(|| format!("loop tag {}: +{off} is not a float word", self.head))
    }

    /// Reads the float at `off`.
    pub fn read(&self, cpu: &Cpu, off: u32) -> Result<f64, String> {
        let d = self.float_device(off)?;
        match cpu.read_device(d)? {
            Value::Float(x) => Ok(x),
            v => Err(format!("{}: read {v}", d.text)),
        }
    }

    /// Writes the float at `off`.
    pub fn write(&self, cpu: &mut Cpu, off: u32, v: f64) -> Result<(), String> {
        let d = self.float_device(off)?;
        if !v.is_finite() || v.abs() > f32::MAX as f64 {
            return Err(format!("{}: {v} is not a single-precision float", d.text));
        }
        cpu.write_value(d, &Value::Float(v))
            .map_err(|e| e.to_string())
    }

    /// MODE (+1).
    pub fn mode(&self, cpu: &Cpu) -> Result<u16, String> {
        read_u16(cpu, &self.mode)
    }

    /// Writes MODE (+1).
    pub fn set_mode(&self, cpu: &mut Cpu, mode: u16) -> Result<(), String> {
        cpu.write_value(&self.mode, &Value::Int(mode.into()))
            .map_err(|e| e.to_string())
    }

    /// ALM (+3).
    pub fn alarms(&self, cpu: &Cpu) -> Result<u16, String> {
        read_u16(cpu, &self.alm)
    }

    /// The name of the word at `off`, e.g. `R1010` (`CPU2/R1010`).
    pub fn name_at(&self, off: u32) -> String {
        device_at(&self.head[self.prefix.len()..], off, "u16")
            .map(|d| format!("{}{}", self.prefix, d.text.trim_end_matches(":u16")))
            .unwrap_or_else(|_| format!("{}+{off}", self.head))
    }
}

fn read_u16(cpu: &Cpu, d: &DeviceSpec) -> Result<u16, String> {
    match cpu.read_device(d)? {
        Value::Int(v) => Ok(v as u16),
        v => Err(format!("{}: read {v}", d.text)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_name_the_right_devices() {
        assert_eq!(device_at("R1000", 12, "f32").unwrap().text, "R1012:f32");
        assert_eq!(device_at("D1000", 1, "u16").unwrap().text, "D1001:u16");
        // W is hexadecimal.
        assert_eq!(device_at("W100", 16, "f32").unwrap().text, "W110:f32");
        assert!(device_at("M0", 1, "u16")
            .unwrap_err()
            .contains("bit device"));
        assert!(device_at("D0.1", 1, "u16")
            .unwrap_err()
            .contains("plain word"));
        assert!(device_at("K4M0", 1, "u16").is_err());
        assert!(device_at("Q", 1, "u16")
            .unwrap_err()
            .contains("loop tag `Q`"));
    }
}
