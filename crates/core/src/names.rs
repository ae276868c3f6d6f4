//! Device names given from outside a program — `--set`, `--show`, `--trace`,
//! scenario files, the HTTP API — in the CPU's dialect (contract §2, §3.1):
//! MELSEC's names of the shared door, or the APLC's (octal X/Y, Dn the HIGH
//! word of 32-bit values, `CN200`-`CN255` 32-bit, `LM`/`V` read only,
//! values `16#1F`, `8#17`, `2#101`).
//!
//! A [`DevName`] is parsed once and then read and written through the Cpu
//! door without parsing: [`DevName::raw`] does no string work or allocation.
//! A [`Placed`] name is also resolved once to its points in one CPU (a plain
//! name's [`Place`]): the scenario loop reads and writes its bindings,
//! expectations and traces with it every scan.

use softplc_ir::access::{AccessError, DeviceSpec, Place, Value, ValueType};
use softplc_ir::device::DeviceMemory;
use softplc_ir::profile::{NamedDevice, Naming, Profile};

use crate::engine::Cpu;

/// What names mean for a CPU: its profile's naming and its programs' global
/// variables (APLC: `启动` for `X0`, contract §2).
#[derive(Clone)]
pub struct Names {
    pub naming: &'static dyn Naming,
    /// (upper-case name, device text).
    pub globals: Vec<(String, String)>,
}

impl std::fmt::Debug for Names {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Names")
            .field("globals", &self.globals)
            .finish_non_exhaustive()
    }
}

impl Names {
    /// The names of a model without globals.
    pub fn plain(profile: &'static Profile) -> Names {
        Names {
            naming: profile.naming,
            globals: Vec::new(),
        }
    }

    /// The names of a model with the global variables its program `files`
    /// declare (the APLC's `VAR_GLOBAL`), before they are loaded.
    pub fn of_files(profile: &'static Profile, files: &[&std::path::Path]) -> Names {
        let mut names = Names::plain(profile);
        if crate::profile::source_format(profile) == crate::profile::SourceFormat::Pou {
            names.globals = crate::aplc::globals_of_files(files);
        }
        names
    }

    /// The names of a running CPU.
    pub fn of(cpu: &Cpu) -> Names {
        let mut globals: Vec<(String, String)> = (0..cpu.program_count())
            .flat_map(|i| cpu.program_at(i).globals.iter().cloned())
            .collect();
        globals.sort();
        Names {
            naming: cpu.profile().naming,
            globals,
        }
    }

    /// Parses `DEV[:TYPE]` or, where the programs name devices (APLC global
    /// variables), `GLOBAL[:TYPE]` (the name as given is the key in reports).
    pub fn parse(&self, s: &str) -> Result<DevName, String> {
        if !self.globals.is_empty() {
            let (name, ty) = match s.split_once(':') {
                Some((n, t)) => (n.trim(), Some(t)),
                None => (s.trim(), None),
            };
            let key = name.to_uppercase();
            if let Some((_, dev)) = self.globals.iter().find(|(n, _)| *n == key) {
                let text = match ty {
                    Some(t) => format!("{dev}:{t}"),
                    None => dev.clone(),
                };
                let mut n = DevName::with(&text, self.naming)?;
                n.dev.spec.text = s.trim().to_string();
                return Ok(n);
            }
        }
        DevName::with(s, self.naming)
    }
}

/// A device name of a dialect, resolved to the storage it lives in.
#[derive(Clone)]
pub struct DevName {
    dev: NamedDevice,
    naming: &'static dyn Naming,
}

impl std::fmt::Debug for DevName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.dev.fmt(f)
    }
}

impl DevName {
    /// Parses `DEV` or `DEV:TYPE` in the names of `profile`.
    pub fn parse(s: &str, profile: &'static Profile) -> Result<DevName, String> {
        DevName::with(s, profile.naming)
    }

    /// Parses `DEV` or `DEV:TYPE` with `naming`.
    pub fn with(s: &str, naming: &'static dyn Naming) -> Result<DevName, String> {
        Ok(DevName {
            dev: naming.parse(s)?,
            naming,
        })
    }

    /// Parses `s` in the dialect of `cpu`, with its programs' global names,
    /// checking the device exists there.
    pub fn parse_for(s: &str, cpu: &Cpu) -> Result<DevName, String> {
        let n = Names::of(cpu).parse(s)?;
        if n.dev.ty != ValueType::Str {
            n.raw(cpu.memory()).map_err(|e| e.to_string())?;
        }
        Ok(n)
    }

    /// The name as given, the key in reports.
    pub fn text(&self) -> &str {
        &self.dev.spec.text
    }

    /// The type shown and written.
    pub fn ty(&self) -> ValueType {
        self.dev.ty
    }

    /// The door's spec over the storage (for tools that need a span).
    pub fn spec(&self) -> &DeviceSpec {
        &self.dev.spec
    }

    /// Reads the value.
    pub fn read(&self, cpu: &Cpu) -> Result<Value, String> {
        self.read_mem(cpu.memory())
    }

    /// Reads the value from device memory.
    pub fn read_mem(&self, mem: &DeviceMemory) -> Result<Value, String> {
        if self.dev.ty == ValueType::Str {
            return self.dev.spec.read(mem);
        }
        Ok(self.present_raw(self.raw(mem)?))
    }

    /// The raw bits in this name's type (a high-word-first pair as one `u32`);
    /// no allocation unless it fails. Not for `:str`.
    #[inline]
    pub fn raw(&self, mem: &DeviceMemory) -> Result<u64, AccessError> {
        let raw = self.dev.spec.raw(mem)?;
        Ok(if self.dev.swap {
            (raw as u32).rotate_left(16) as u64
        } else {
            raw
        })
    }

    /// Presents raw bits of [`Self::raw`] in this name's type.
    pub fn present_raw(&self, raw: u64) -> Value {
        match self.dev.ty {
            ValueType::I16 => Value::Int(raw as u16 as i16 as i64),
            ValueType::U16 => Value::Int(raw as u16 as i64),
            ValueType::I32 => Value::Int(raw as u32 as i32 as i64),
            ValueType::U32 => Value::Int(raw as u32 as i64),
            ValueType::F32 => Value::Float(f32::from_bits(raw as u32) as f64),
            ValueType::Bit => Value::Bool(raw & 1 != 0),
            ValueType::Str => Value::Int(raw as i64),
        }
    }

    /// A value the door read with [`Self::spec`] (e.g. a sampling trace's),
    /// in this name's type.
    pub fn present(&self, door: &Value) -> Value {
        match door {
            Value::Int(raw) if self.dev.swap => {
                self.present_raw((*raw as u32).rotate_left(16) as u64)
            }
            v => v.clone(),
        }
    }

    /// Writes a value given as text (`--set`) in the dialect's syntax
    /// (MELSEC `H1F`/`0x1F`; APLC `16#1F`, `8#17`, `2#101`).
    pub fn write(&self, cpu: &mut Cpu, text: &str) -> Result<(), String> {
        self.writable()?;
        // A numeric word device reports a missing device before a bad value.
        if self.dev.ty != ValueType::Str && self.dev.ty != ValueType::Bit {
            self.raw(cpu.memory()).map_err(|e| e.to_string())?;
        }
        let v = self.parse_value(text)?;
        let door = self.door_value(&v)?;
        cpu.write_value(&self.dev.spec, &door).map_err(|e| match e {
            // Named by the text as given, not the value it parsed to.
            AccessError::Value { device, ty, .. } => AccessError::Value {
                device,
                value: text.to_string(),
                ty,
            }
            .to_string(),
            e => e.to_string(),
        })
    }

    /// A value text in this name's type and dialect (for [`Self::write_value`]).
    pub fn parse_value(&self, text: &str) -> Result<Value, String> {
        self.naming.parse_value(&self.dev, text)
    }

    /// Writes a typed value in this name's type (the HTTP API, plant models):
    /// `Int` that fits the type as signed or unsigned, `Float` for `f32`,
    /// `Bool` for bits. Nothing is written when it does not fit.
    pub fn write_value(&self, cpu: &mut Cpu, v: &Value) -> Result<(), String> {
        let door = self.door_value(v)?;
        cpu.write_value(&self.dev.spec, &door)
            .map_err(|e| e.to_string())
    }

    /// The value the door writes (through [`Self::spec`]) for `v` given in
    /// this name's type; an error for a read-only name.
    pub fn door_value(&self, v: &Value) -> Result<Value, String> {
        self.writable()?;
        if !self.dev.swap {
            return Ok(v.clone());
        }
        let bad = || format!("`{}`: bad value `{v}` for {:?}", self.text(), self.dev.ty);
        let bits: u32 = match (self.dev.ty, v) {
            (ValueType::F32, Value::Float(f)) => {
                let x = *f as f32;
                if !x.is_finite() {
                    return Err(bad());
                }
                x.to_bits()
            }
            (ValueType::F32, Value::Int(i)) => (*i as f32).to_bits(),
            (ValueType::I32 | ValueType::U32, Value::Int(i)) => u32::try_from(*i)
                .or_else(|_| i32::try_from(*i).map(|x| x as u32))
                .map_err(|_| bad())?,
            _ => return Err(bad()),
        };
        Ok(Value::Int(bits.rotate_left(16) as i64))
    }

    /// The raw bits the door writes (through [`Self::spec`]) for `raw` given
    /// in this name's type: [`Self::door_value`] on raw bits (a swapped pair
    /// turned; a non-finite `f32` refused there, as a value is).
    #[inline]
    pub fn door_raw(&self, raw: u64) -> Result<u64, String> {
        if self.dev.read_only {
            return Err(self.read_only());
        }
        if !self.dev.swap {
            return Ok(raw);
        }
        let bits = raw as u32;
        let finite = self.dev.ty != ValueType::F32 || f32::from_bits(bits).is_finite();
        match self.dev.ty {
            ValueType::F32 | ValueType::I32 | ValueType::U32 if finite => {
                Ok(bits.rotate_left(16) as u64)
            }
            _ => Err(self.bad_raw(raw)),
        }
    }

    #[cold]
    fn bad_raw(&self, raw: u64) -> String {
        format!(
            "`{}`: bad value `{}` for {:?}",
            self.text(),
            self.present_raw(raw),
            self.dev.ty
        )
    }

    /// Not writable from outside (APLC LM and V).
    pub fn is_read_only(&self) -> bool {
        self.dev.read_only
    }

    fn writable(&self) -> Result<(), String> {
        if self.dev.read_only {
            return Err(self.read_only());
        }
        Ok(())
    }

    #[cold]
    fn read_only(&self) -> String {
        format!(
            "`{}`: LM and V are POU locals and cannot be set",
            self.text()
        )
    }
}

/// A [`DevName`] resolved against one CPU: a plain name (a bit, a bit of a
/// word, a numeric word device, a digit-specified bit device, without index
/// modification) at its [`Place`], read and written through the Cpu door
/// without resolving the name again; an index-modified name through the
/// name at each access, and a digit-specified one written through the name
/// (its value must fit the digits). Raw bits are in the name's type, as
/// [`DevName::raw`] reads them.
#[derive(Clone, Debug)]
pub struct Placed {
    name: DevName,
    place: Option<Place>,
}

impl Placed {
    /// Resolves `name` in `cpu`: an error names a plain device outside its
    /// points.
    pub fn new(name: DevName, cpu: &Cpu) -> Result<Placed, String> {
        let place = match name.dev.spec.place(cpu.memory()) {
            Some(p) => Some(p.map_err(|e| e.to_string())?),
            None => None,
        };
        Ok(Placed { name, place })
    }

    pub fn name(&self) -> &DevName {
        &self.name
    }

    /// Whether the name was resolved to a place (the fast path).
    pub fn is_placed(&self) -> bool {
        self.place.is_some()
    }

    /// The raw bits now in `cpu` (the CPU it was resolved in).
    #[inline]
    pub fn raw(&self, cpu: &Cpu) -> Result<u64, AccessError> {
        let raw = match &self.place {
            Some(p) => cpu.read_place(p)?,
            None => self.name.dev.spec.raw(cpu.memory())?,
        };
        Ok(if self.name.dev.swap {
            (raw as u32).rotate_left(16) as u64
        } else {
            raw
        })
    }

    /// Writes raw bits in the name's type through the door, as
    /// [`DevName::write_value`] writes the value they present: X reaches the
    /// input image, a forced point stays forced. Nothing is written when the
    /// value does not fit (a digit-specified name narrower than its type) or
    /// the name is read only.
    #[inline]
    pub fn write_raw(&self, cpu: &mut Cpu, raw: u64) -> Result<(), String> {
        let door = self.name.door_raw(raw)?;
        match &self.place {
            Some(p) if !p.is_digits() => cpu.write_place(p, door).map_err(|e| e.to_string()),
            _ => {
                let spec = &self.name.dev.spec;
                cpu.write_value(spec, &spec.present_raw(door))
                    .map_err(|e| e.to_string())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::{Cpu, VirtualClock};

    fn aplc_cpu() -> Cpu {
        let p = crate::aplc::load_bytes("t.apl", b"LD SM0\nOUT Y0\n").unwrap();
        Cpu::new(p, crate::aplc::cpu_config(), Box::new(VirtualClock::new()))
    }

    #[test]
    fn aplc_names_reach_their_storage_high_word_first() {
        let mut cpu = aplc_cpu();
        assert_eq!(cpu.profile().family, "APLC");
        // D10:i32 = 16#00020001: D10 (high) = 2, D11 (low) = 1.
        let n = DevName::parse("D10:i32", crate::profile::aplc()).unwrap();
        n.write(&mut cpu, "16#00020001").unwrap();
        let d = |cpu: &Cpu, s| {
            DevName::parse(s, crate::profile::aplc())
                .unwrap()
                .read(cpu)
                .unwrap()
        };
        assert_eq!(d(&cpu, "D10"), Value::Int(2));
        assert_eq!(d(&cpu, "D11"), Value::Int(1));
        assert_eq!(n.read(&cpu).unwrap(), Value::Int(0x0002_0001));
        assert_eq!(n.raw(cpu.memory()).unwrap(), 0x0002_0001);
        // 1.5f32 = 16#3FC00000: D20 = 16#3FC0, D21 = 0.
        let f = DevName::parse("D20:f32", crate::profile::aplc()).unwrap();
        f.write_value(&mut cpu, &Value::Float(1.5)).unwrap();
        assert_eq!(d(&cpu, "D20:u16"), Value::Int(0x3FC0));
        assert_eq!(d(&cpu, "D21"), Value::Int(0));
        // CN201 is 32-bit: -2 is FFFF FFFE in the CN pair of C201.
        let c = DevName::parse("CN201", crate::profile::aplc()).unwrap();
        assert_eq!(c.ty(), ValueType::I32);
        c.write(&mut cpu, "-2").unwrap();
        assert_eq!(c.read(&cpu).unwrap(), Value::Int(-2));
        // X10 is input 8; V0 cannot be set.
        DevName::parse("X10", crate::profile::aplc())
            .unwrap()
            .write(&mut cpu, "1")
            .unwrap();
        assert_eq!(
            cpu.memory().get_bit(crate::device::DeviceKind::X, 8),
            Ok(true)
        );
        assert!(DevName::parse("V0", crate::profile::aplc())
            .unwrap()
            .write(&mut cpu, "1")
            .is_err());
        assert!(DevName::parse("X8", crate::profile::aplc()).is_err());
        // A global name stands for its device, shown as given.
        let names = Names {
            naming: crate::profile::aplc().naming,
            globals: vec![("流量".into(), "D20".into())],
        };
        let g = names.parse("流量:f32").unwrap();
        assert_eq!(g.text(), "流量:f32");
        assert_eq!(g.read(&cpu).unwrap(), Value::Float(1.5));
        assert!(Names::plain(crate::profile::aplc()).parse("流量").is_err());
        // 16# is only APLC's; H is only MELSEC's.
        assert!(DevName::parse("D0", crate::profile::aplc())
            .unwrap()
            .write(&mut cpu, "H10")
            .is_err());
    }

    fn melsec_cpu(program: &str) -> Cpu {
        let p =
            crate::program::compile_il("t.il", program, &crate::device::DeviceConfig::default())
                .unwrap();
        Cpu::new(
            p,
            crate::profile::default_config(),
            Box::new(VirtualClock::new()),
        )
    }

    /// Every write the journal is told, as text.
    #[derive(Clone, Default)]
    struct Told(std::sync::Arc<std::sync::Mutex<Vec<String>>>);

    impl crate::engine::Journal for Told {
        fn record(&mut self, event: crate::engine::DoorEvent<'_>) {
            self.0.lock().unwrap().push(format!("{event:?}"));
        }
    }

    fn placed(s: &str, cpu: &Cpu) -> Placed {
        Placed::new(DevName::parse_for(s, cpu).unwrap(), cpu).unwrap()
    }

    #[test]
    fn placed_names_read_and_write_what_names_do() {
        use crate::device::DeviceKind::{D, M, X};
        let mut cpu = melsec_cpu("LD X5\nOUT Y0\nEND\n");
        cpu.set_word(D, 0, 5).unwrap();
        let told = Told::default();
        cpu.set_journal(Some(Box::new(told.clone())));
        // D10:f32 = 1.5 is 3FC0 0000, low word first: D10 = 0, D11 = 3FC0.
        let f = placed("D10:f32", &cpu);
        assert!(f.is_placed());
        f.write_raw(&mut cpu, 1.5f32.to_bits() as u64).unwrap();
        assert_eq!(cpu.memory().get_word(D, 10), Ok(0));
        assert_eq!(cpu.memory().get_word(D, 11), Ok(0x3FC0));
        assert_eq!(f.raw(&cpu).unwrap(), 0x3FC0_0000);
        // D0.3 sets bit 3 only: 5 becomes 13.
        let b = placed("D0.3", &cpu);
        b.write_raw(&mut cpu, 1).unwrap();
        assert_eq!(cpu.memory().get_word(D, 0), Ok(13));
        assert_eq!(b.raw(&cpu).unwrap(), 1);
        assert_eq!(placed("D0.2", &cpu).raw(&cpu).unwrap(), 1);
        assert_eq!(placed("D0.1", &cpu).raw(&cpu).unwrap(), 0);
        // K4M0 is read at its place and written through its name: 0x1234
        // on M2, M4, M5, M9 and M12; K2M0 refuses 300, which does not fit
        // 8 bits.
        let k = placed("K4M0", &cpu);
        assert!(k.is_placed());
        k.write_raw(&mut cpu, 0x1234).unwrap();
        assert_eq!(k.raw(&cpu).unwrap(), 0x1234);
        assert_eq!(cpu.memory().get_bit(M, 2), Ok(true));
        assert_eq!(cpu.memory().get_bit(M, 3), Ok(false));
        assert_eq!(cpu.memory().get_bit(M, 12), Ok(true));
        assert!(placed("K2M0", &cpu).write_raw(&mut cpu, 300).is_err());
        assert_eq!(k.raw(&cpu).unwrap(), 0x1234);
        // D0Z0 is no place: read through its name, Z0 = 1 making it D1.
        cpu.set_word(D, 1, 77).unwrap();
        cpu.set_word(crate::device::DeviceKind::Z, 0, 1).unwrap();
        let z = placed("D0Z0", &cpu);
        assert!(!z.is_placed());
        assert_eq!(z.raw(&cpu).unwrap(), 77);
        // K4X10 through the door at its place: X10-X1F reach the input
        // image, and the journal hears the 16 bits.
        let kx = DeviceSpec::parse("K4X10").unwrap();
        let at = kx.place(cpu.memory()).unwrap().unwrap();
        cpu.write_place(&at, 0x8001).unwrap();
        assert!(cpu.input(0x10) && !cpu.input(0x11) && cpu.input(0x1F));
        // X5 reaches the input image: the next scan's input refresh keeps it.
        let x = placed("X5", &cpu);
        x.write_raw(&mut cpu, 1).unwrap();
        assert!(cpu.input(5));
        cpu.scan();
        assert_eq!(cpu.memory().get_bit(X, 5), Ok(true));
        assert_eq!(placed("Y0", &cpu).raw(&cpu).unwrap(), 1);
        // The journal heard each write as the point write that replays it.
        let told = told.0.lock().unwrap().clone();
        assert_eq!(told.len(), 7, "{told:?}");
        assert!(
            told[0].contains(
                "Words { kind: D, number: 10, len: 2, block: First, values: [0, 16320] }"
            ),
            "{told:?}"
        );
        assert!(
            told[1].contains("Words { kind: D, number: 0, len: 1, block: First, values: [13] }"),
            "{told:?}"
        );
        assert!(
            told[2].starts_with("Value { spec: DeviceSpec { text: \"K4M0\""),
            "{told:?}"
        );
        let mut bits = vec!["false"; 16];
        (bits[0], bits[15]) = ("true", "true");
        let k4x10 = format!(
            "Bits {{ kind: X, number: 16, block: First, values: [{}] }}",
            bits.join(", ")
        );
        assert!(told[5].contains(&k4x10), "{told:?}");
        assert!(
            told[6].contains("Bit { kind: X, n: 5, value: true }"),
            "{told:?}"
        );
    }

    #[test]
    fn placed_writes_keep_a_forced_point_forced() {
        use crate::device::DeviceKind::X;
        let mut cpu = melsec_cpu("LD X5\nOUT Y0\nEND\n");
        cpu.force(X, 5, true).unwrap();
        let x = placed("X5", &cpu);
        x.write_raw(&mut cpu, 0).unwrap();
        // Forced ON wins; the write is the value under the force.
        assert_eq!(x.raw(&cpu).unwrap(), 1);
        assert!(!cpu.input(5));
        cpu.scan();
        assert_eq!(placed("Y0", &cpu).raw(&cpu).unwrap(), 1);
        assert!(cpu.release(X, 5));
        assert_eq!(x.raw(&cpu).unwrap(), 0);
    }

    #[test]
    fn melsec_names_are_the_doors() {
        let p = crate::program::compile_il(
            "t.il",
            "LD SM400\nOUT Y0\nEND\n",
            &crate::device::DeviceConfig::default(),
        )
        .unwrap();
        let mut cpu = Cpu::new(
            p,
            crate::profile::default_config(),
            Box::new(VirtualClock::new()),
        );
        assert_eq!(cpu.profile().family, "MELSEC-Q");
        let n = DevName::parse_for("D0:i32", &cpu).unwrap();
        n.write(&mut cpu, "H20001").unwrap();
        // Low word first on MELSEC: D0 = 1, D1 = 2.
        assert_eq!(
            cpu.memory().get_word(crate::device::DeviceKind::D, 0),
            Ok(1)
        );
        assert_eq!(n.read(&cpu).unwrap(), Value::Int(0x0002_0001));
        assert!(DevName::parse_for("X1F", &cpu).is_ok());
    }
}
