//! The variables of the address space (contract §3.2): every device the
//! program uses, with its natural node (`D100` Int16, `Y0` Boolean) and, where
//! an instruction uses it as a 32-bit or real operand, its typed node
//! (`D10:i32` Int32, `D10:f32` Float), plus the names `[opcua] nodes` adds
//! (`D100:u16`, `D200:u32`); and the control loops with their named fields.
//!
//! Which devices a program uses comes from the compiler
//! (`Program::used_devices`); the loops from the loop memories the compiler
//! recorded (`Program::listing`), read by the web monitor's faceplate
//! finders (`softplc_http::loops`, `softplc_http::process_loops`), so both
//! doors show the same words.

use softplc_core::access::ValueType;
use softplc_core::engine::Cpu;
use softplc_core::names::{DevName, Names};
use softplc_ir::listing::LoopUse;
use softplc_ir::ops::{DeviceUse, Num};

/// The OPC UA built-in type of a variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Boolean,
    Int16,
    UInt16,
    Int32,
    UInt32,
    Float,
}

impl Kind {
    /// The type a device name is shown in; `None` for strings (`:str`),
    /// which contract §3.2 does not list.
    pub fn of(ty: ValueType) -> Option<Kind> {
        Some(match ty {
            ValueType::Bit => Kind::Boolean,
            ValueType::I16 => Kind::Int16,
            ValueType::U16 => Kind::UInt16,
            ValueType::I32 => Kind::Int32,
            ValueType::U32 => Kind::UInt32,
            ValueType::F32 => Kind::Float,
            ValueType::Str => return None,
        })
    }
}

/// One variable: its string NodeId, the device it shows and its type.
#[derive(Clone, Debug)]
pub struct Point {
    /// The CPU (0-based) whose device it is: 0 but in a multi-CPU system.
    pub cpu: usize,
    /// The string NodeId (`D10:f32`; a loop field `/softplc/Loops/…/SV`; a
    /// multi-CPU system's `CPU2/D10:f32`, `/softplc/CPU2/Loops/…/SV`).
    pub id: String,
    /// The browse and display name (`D10:f32`; `SV`).
    pub browse: String,
    pub name: DevName,
    pub kind: Kind,
}

impl Point {
    fn new(cpu: usize, id: String, browse: String, name: DevName) -> Option<Point> {
        let kind = Kind::of(name.ty())?;
        Some(Point {
            cpu,
            id,
            browse,
            name,
            kind,
        })
    }
}

/// A control loop's folder and its fields.
#[derive(Clone, Debug)]
pub struct LoopFolder {
    /// The CPU (0-based) of the loop.
    pub cpu: usize,
    /// The folder's browse name (`PIDCONT D600 loop 1`, `loop tag R1000`).
    pub browse: String,
    pub fields: Vec<Point>,
}

/// The device variables of `cpu`'s programs and of `extra` (`[opcua] nodes`),
/// sorted by name, each once. An `extra` name that is not a device of this
/// CPU is an error naming it.
pub fn devices(cpu: &Cpu, extra: &[String]) -> Result<Vec<Point>, String> {
    devices_at(cpu, 0, "", extra)
}

/// [`devices`] of CPU `i` (0-based) of a multi-CPU system, their NodeIds
/// after `prefix` (`CPU2/`).
pub fn devices_at(
    cpu: &Cpu,
    i: usize,
    prefix: &str,
    extra: &[String],
) -> Result<Vec<Point>, String> {
    let names = Names::of(cpu);
    let mut texts: Vec<String> = Vec::new();
    for i in 0..cpu.program_count() {
        for (text, how) in &cpu.program_at(i).used_devices {
            texts.push(text.clone());
            match how {
                DeviceUse::Word(Num::I32) => texts.push(format!("{text}:i32")),
                DeviceUse::Word(Num::F32) => texts.push(format!("{text}:f32")),
                DeviceUse::Bit | DeviceUse::Word(Num::I16) => {}
            }
        }
    }
    texts.sort();
    texts.dedup();
    let mut out = Vec::new();
    for t in &texts {
        // An operand the names layer does not take from outside (a program's
        // local label, a string) has no node.
        let Ok(n) = names.parse(t) else { continue };
        if n.raw(cpu.memory()).is_err() {
            continue;
        }
        out.extend(Point::new(i, format!("{prefix}{t}"), t.clone(), n));
    }
    for t in extra {
        // `d100:U16` is `D100:u16`, the `--show` spelling.
        let key = match t.trim().split_once(':') {
            Some((d, ty)) => format!("{}:{}", d.to_uppercase(), ty.to_lowercase()),
            None => t.trim().to_uppercase(),
        };
        let n = names
            .parse(&key)
            .map_err(|e| format!("[opcua] nodes: `{t}`: {e}"))?;
        n.raw(cpu.memory())
            .map_err(|e| format!("[opcua] nodes: `{t}`: {e}"))?;
        let p = Point::new(i, format!("{prefix}{key}"), key, n)
            .ok_or_else(|| format!("[opcua] nodes: `{t}`: strings have no OPC UA node"))?;
        if !out.iter().any(|q| q.id == p.id) {
            out.push(p);
        }
    }
    out.sort_by(|a, b| a.id.cmp(&b.id));
    Ok(out)
}

/// The loop memories of `cpu`'s programs as their listings record them:
/// (file, loops) per program.
pub fn program_loops(cpu: &Cpu) -> Vec<(String, Vec<LoopUse>)> {
    (0..cpu.program_count())
        .map(|i| {
            let p = cpu.program_at(i);
            (p.file.clone(), p.listing.loops.clone())
        })
        .collect()
}

/// The PID loops (PIDCONT/S.PIDCONT, 001 §5.2) and process-control loop tags
/// (000 §3.3.5) of `programs` (see [`program_loops`]), with SV, PV, MV, MODE
/// and ALARM (and MVMAN for PID). A PID set has as many loops as its
/// control data's count word says at the END the address space is built (1
/// when unreadable, at most 32).
pub fn loops(cpu: &Cpu, programs: &[(String, Vec<LoopUse>)]) -> Vec<LoopFolder> {
    loops_at(cpu, 0, crate::space::LOOPS_ID, programs)
}

/// [`loops`] of CPU `i` (0-based), their folders under `folder_id`.
pub fn loops_at(
    cpu: &Cpu,
    i: usize,
    folder_id: &str,
    programs: &[(String, Vec<LoopUse>)],
) -> Vec<LoopFolder> {
    let programs = || programs.iter().map(|(f, l)| (f.as_str(), l.as_slice()));
    let names = Names::of(cpu);
    let point = |folder: &str, field: &str, device: &str| {
        let n = names.parse(device).ok()?;
        n.raw(cpu.memory()).ok()?;
        Point::new(
            i,
            format!("{folder_id}/{folder}/{field}"),
            field.to_string(),
            n,
        )
    };
    let mut out = Vec::new();
    for set in softplc_http::loops::find_in(programs()) {
        let count = set
            .count_device()
            .and_then(|h| names.parse(&h).ok())
            .and_then(|d| d.raw(cpu.memory()).ok())
            .map_or(1, |n| (n as u16 as i16).clamp(1, 32) as u32);
        for k in 0..count {
            let Some(l) = set.loop_at(k) else { continue };
            let browse = l.title.clone();
            let fields = [
                ("SV", &l.sv),
                ("PV", &l.pv),
                ("MV", &l.mv),
                ("MVMAN", &l.mvman),
                ("MODE", &l.mode),
                ("ALARM", &l.alarm),
            ]
            .iter()
            .filter_map(|(f, d)| point(&browse, f, d))
            .collect();
            out.push(LoopFolder {
                cpu: i,
                browse,
                fields,
            });
        }
    }
    for l in softplc_http::process_loops::find_in(programs()) {
        let browse = format!("loop tag {}", l.tag);
        let fields = [
            ("SV", "sv"),
            ("PV", "pv"),
            ("MV", "mv"),
            ("MODE", "mode"),
            ("ALARM", "alm"),
        ]
        .iter()
        .filter_map(|(label, field)| point(&browse, label, &l.named(field)?))
        .collect();
        out.push(LoopFolder {
            cpu: i,
            browse,
            fields,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use softplc_core::device::DeviceConfig;
    use softplc_core::engine::VirtualClock;

    fn cpu(src: &str) -> Cpu {
        let p = softplc_core::program::compile_il("t.il", src, &DeviceConfig::default()).unwrap();
        Cpu::new(
            p,
            softplc_core::profile::default_config(),
            Box::new(VirtualClock::new()),
        )
    }

    fn ids(points: &[Point]) -> Vec<(&str, Kind)> {
        points.iter().map(|p| (p.id.as_str(), p.kind)).collect()
    }

    #[test]
    fn operands_give_natural_and_typed_nodes() {
        let c = cpu("LD X0\nOUT Y0\nDMOV D20 D22\nEMOV D30 D32\nMOV D0Z1 D5\nMOV K4M0 D6\nEND\n");
        assert_eq!(
            ids(&devices(&c, &[]).unwrap()),
            [
                ("D20", Kind::Int16),
                ("D20:i32", Kind::Int32),
                ("D22", Kind::Int16),
                ("D22:i32", Kind::Int32),
                ("D30", Kind::Int16),
                ("D30:f32", Kind::Float),
                ("D32", Kind::Int16),
                ("D32:f32", Kind::Float),
                // D0Z1 and K4M0 move or span devices: no node.
                ("D5", Kind::Int16),
                ("D6", Kind::Int16),
                ("X0", Kind::Boolean),
                ("Y0", Kind::Boolean),
            ]
        );
    }

    #[test]
    fn extra_nodes_are_checked_and_spelled_as_show() {
        let c = cpu("LD X0\nOUT Y0\nEND\n");
        let extra = ["d100:U16".to_string(), "D200:u32".into(), "Y0".into()];
        assert_eq!(
            ids(&devices(&c, &extra).unwrap()),
            [
                ("D100:u16", Kind::UInt16),
                ("D200:u32", Kind::UInt32),
                ("X0", Kind::Boolean),
                ("Y0", Kind::Boolean),
            ]
        );
        let e = devices(&c, &["QX9".to_string()]).unwrap_err();
        assert!(e.contains("[opcua] nodes: `QX9`"), "{e}");
        let e = devices(&c, &["D99999".to_string()]).unwrap_err();
        assert!(e.contains("D99999"), "{e}");
    }

    /// Buffer memory `U<n>\\G<addr>` of the rack's modules: a device like D
    /// (word, bit of a word, 32-bit operand); a unit with no module has no
    /// node (the program stops at SP.UNIT ERROR when it runs there).
    #[test]
    fn buffer_memory_words_are_devices() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("plc.toml"),
            "[[program]]\nfile = \"main.il\"\n\
             [[slot]]\ntype = \"input\"\npoints = 16\n\
             [[slot]]\ntype = \"output\"\npoints = 16\n\
             [[slot]]\ntype = \"intelligent\"\npoints = 16\nbuffer_words = 100\n",
        )
        .unwrap();
        std::fs::write(
            dir.path().join("main.il"),
            "LD SM400\nMOV U2\\G11 D0\nDMOV U2\\G20 D2\nMOV D1 U3\\G0\nLD U2\\G10.3\nOUT Y10\nEND\n",
        )
        .unwrap();
        let c = softplc_core::project::load_project(dir.path())
            .and_then(|p| p.build_cpu(Box::new(VirtualClock::new())))
            .unwrap_or_else(|d| panic!("{:?}", d.0));
        assert_eq!(
            ids(&devices(&c, &["U2\\G99:u16".to_string()]).unwrap()),
            [
                ("D0", Kind::Int16),
                ("D1", Kind::Int16),
                ("D2", Kind::Int16),
                ("D2:i32", Kind::Int32),
                ("SM400", Kind::Boolean),
                ("U2\\G10.3", Kind::Boolean),
                ("U2\\G11", Kind::Int16),
                ("U2\\G20", Kind::Int16),
                ("U2\\G20:i32", Kind::Int32),
                ("U2\\G99:u16", Kind::UInt16),
                ("Y10", Kind::Boolean),
            ]
        );
        let e = devices(&c, &["U3\\G0".to_string()]).unwrap_err();
        assert!(e.contains("U3\\G0"), "{e}");
    }

    #[test]
    fn aplc_programs_are_refused_with_the_reason() {
        let src = "LD X0\nOUT Y10\n";
        let p = softplc_core::aplc::load_bytes("t.apl", src.as_bytes()).unwrap();
        let c = softplc_core::aplc::single_cpu(
            p,
            softplc_core::aplc::cpu_config(),
            Box::new(VirtualClock::new()),
        )
        .unwrap();
        let cfg = crate::OpcuaConfig::new(
            &crate::Flags {
                addr: Some("4840".into()),
                ..Default::default()
            },
            None,
            std::path::Path::new("."),
            std::time::Duration::from_millis(10),
        )
        .unwrap()
        .unwrap();
        let e = crate::Prepared::new(cfg, &c).err().unwrap();
        assert!(e.contains("APLC-TCP programs are not served"), "{e}");
    }
}
