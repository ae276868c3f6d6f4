//! A fleet: several PLCs in one scenario (`[[plc]]`), serial ports linked
//! between them (`[[link]]`) and clients that poll a PLC over its MC or
//! Modbus TCP door in virtual time (`[[client]]`), docs/scenarios.md
//! "Fleets". Names and references are checked here; port settings (a
//! project has them in its plc.toml) when the scenario is built.

use serde::Deserialize;
use softplc_core::profile::Profile;
use std::path::Path;

use super::values::{time_us, Layout};
use super::Source;

/// One `[[plc]]` table as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PlcDoc {
    pub name: toml::Spanned<String>,
    pub program: Option<String>,
    pub project: Option<String>,
    pub cpu: Option<String>,
    pub scan_time: Option<toml::Value>,
    pub port1: Option<toml::Table>,
    pub port2: Option<toml::Table>,
}

/// One `[[link]]` table as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LinkDoc {
    pub a: toml::Spanned<String>,
    pub b: toml::Spanned<String>,
}

/// One `[[client]]` table as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ClientDoc {
    pub name: Option<String>,
    pub plc: toml::Spanned<String>,
    pub protocol: toml::Spanned<String>,
    pub every: toml::Value,
    pub unit: Option<u8>,
    pub read: Option<BlockDoc>,
    pub write: Option<BlockDoc>,
}

/// `read = { from, count, to }` or `write = { … }` of a client.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BlockDoc {
    pub from: toml::Value,
    pub count: Option<u16>,
    pub to: toml::Value,
}

/// A PLC of a fleet.
#[derive(Clone, Debug)]
pub struct PlcSpec {
    /// Its name, the prefix of its devices (`line1/D0`).
    pub name: String,
    pub source: Source,
    /// `cpu` of a program file.
    pub cpu: Option<&'static Profile>,
    /// The CPU it runs (CPU 1's of a system).
    pub profile: &'static Profile,
    /// Its scan time, µs (default: the scenario's); a system's CPUs without
    /// a constant scan scan at it.
    pub scan_us: u64,
    /// `[port1]`/`[port2]` of a program file.
    pub ports: Vec<softplc_ports::PortConfig>,
}

/// One end of a link: the PLC (0-based) and its port (1 or 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PortRef {
    pub plc: usize,
    pub port: u8,
}

/// A `[[link]]`: two serial ports wired together.
#[derive(Clone, Debug, PartialEq)]
pub struct LinkSpec {
    pub a: PortRef,
    pub b: PortRef,
    /// How errors name it: `[[link]] #n (line l)`.
    pub what: String,
}

/// The door a client talks through.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClientProtocol {
    /// MC protocol 3E binary frames: batch read/write in word units.
    Mc,
    /// Modbus TCP: FC 03 read holding registers, FC 16 write multiple
    /// registers.
    Modbus,
}

/// An address in the polled PLC as the protocol names it.
#[derive(Clone, Debug, PartialEq)]
pub enum Remote {
    /// An MC device name (`D0`, `W1F`, `R100`; `CPU2/D0` of a system's
    /// CPU 2).
    Device(String),
    /// A Modbus holding-register address (0-based).
    Register(u16),
}

/// What a client copies each poll: `count` words from `from` to `to`.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockSpec<From, To> {
    pub from: From,
    pub count: u16,
    pub to: To,
}

/// A `[[client]]`: an HMI or SCADA polling one PLC.
#[derive(Clone, Debug, PartialEq)]
pub struct ClientSpec {
    pub name: String,
    /// The PLC polled (0-based).
    pub plc: usize,
    pub protocol: ClientProtocol,
    pub every_us: u64,
    /// Modbus unit identifier (default the PLC's; unused by MC).
    pub unit: Option<u8>,
    /// Words read from the PLC into a fleet device (`line2/D100`).
    pub read: Option<BlockSpec<Remote, String>>,
    /// Words of a fleet device written into the PLC.
    pub write: Option<BlockSpec<String, Remote>>,
}

/// `line:col` of a spanned value.
pub(super) fn at<T>(text: &str, v: &toml::Spanned<T>) -> String {
    let (line, col) = softplc_core::project::line_col(text, v.span().start);
    format!("{line}:{col}")
}

/// The line of a spanned value.
fn line_of<T>(text: &str, v: &toml::Spanned<T>) -> u32 {
    softplc_core::project::line_col(text, v.span().start).0
}

/// A PLC name is a plain identifier: a letter or `_`, then letters,
/// digits and `_`.
pub(super) fn check_name(name: &str) -> Result<(), String> {
    let mut chars = name.chars();
    let ok = chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !ok {
        return Err(format!(
            "`{name}` is not a plain name (a letter or _, then letters, digits or _)"
        ));
    }
    if softplc_core::system::names::prefix(&format!("{name}/D0")).is_some() {
        return Err(format!(
            "`{name}` is how a CPU of a system is named: choose another"
        ));
    }
    Ok(())
}

/// The PLC called `name` among `plcs`.
pub(super) fn find_plc(plcs: &[PlcSpec], name: &str) -> Result<usize, String> {
    plcs.iter()
        .position(|p| p.name == name.trim())
        .ok_or_else(|| {
            format!(
                "no PLC is named `{}` (PLCs: {})",
                name.trim(),
                plcs.iter()
                    .map(|p| p.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })
}

/// `"line1:port1"`: a PLC and its PORT1 or PORT2.
fn port_ref(text: &str, plcs: &[PlcSpec]) -> Result<PortRef, String> {
    let (plc, port) = text
        .split_once(':')
        .ok_or_else(|| format!("`{text}`: expected PLC:PORT, e.g. \"line1:port1\""))?;
    let i = find_plc(plcs, plc)?;
    let port = match port.trim().to_ascii_lowercase().as_str() {
        "port1" => 1,
        "port2" => 2,
        p => return Err(format!("`{text}`: unknown port `{p}` (port1 or port2)")),
    };
    let p = &plcs[i];
    if p.profile.doors.serial_ports < port {
        return Err(format!(
            "`{text}`: {} ({}) has no serial port PORT{port}: links join the APLC-TCP's PORT1/PORT2",
            p.name, p.profile.model
        ));
    }
    if matches!(p.source, Source::System(_)) {
        return Err(format!(
            "`{text}`: {} is a multi-CPU system, which has no APLC serial ports",
            p.name
        ));
    }
    Ok(PortRef { plc: i, port })
}

/// The `[[link]]` tables: each end an APLC port, no port linked twice.
pub(super) fn links(
    docs: &[LinkDoc],
    plcs: &[PlcSpec],
    text: &str,
) -> Result<Vec<LinkSpec>, String> {
    let mut out: Vec<LinkSpec> = Vec::new();
    for (i, d) in docs.iter().enumerate() {
        let mut ends = [PortRef { plc: 0, port: 0 }; 2];
        for (k, (key, v)) in [("a", &d.a), ("b", &d.b)].into_iter().enumerate() {
            let e = port_ref(v.get_ref(), plcs)
                .map_err(|e| format!("{}: [[link]] #{} {key}: {e}", at(text, v), i + 1))?;
            let twice = out
                .iter()
                .flat_map(|l| [(l.a, &l.what), (l.b, &l.what)])
                .find(|(p, _)| *p == e)
                .map(|(_, w)| w.clone())
                .or_else(|| (k == 1 && ends[0] == e).then(|| "its own `a`".to_string()));
            if let Some(w) = twice {
                return Err(format!(
                    "{}: [[link]] #{} {key}: `{}` is linked twice (also in {w})",
                    at(text, v),
                    i + 1,
                    v.get_ref()
                ));
            }
            ends[k] = e;
        }
        out.push(LinkSpec {
            a: ends[0],
            b: ends[1],
            what: format!("[[link]] #{} (line {})", i + 1, line_of(text, &d.a)),
        });
    }
    Ok(out)
}

/// The `[[client]]` tables; their fleet devices (`to` of a read, `from` of
/// a write) are checked with `device`.
pub(super) fn clients(
    docs: Vec<ClientDoc>,
    plcs: &[PlcSpec],
    layout: &Layout,
    text: &str,
    device: &dyn Fn(&str, &str) -> Result<(), String>,
) -> Result<Vec<ClientSpec>, String> {
    let mut out = Vec::new();
    for (i, d) in docs.into_iter().enumerate() {
        let name = d
            .name
            .clone()
            .unwrap_or_else(|| format!("client #{}", i + 1));
        let what = format!("[[client]] #{} `{name}`", i + 1);
        let plc = find_plc(plcs, d.plc.get_ref())
            .map_err(|e| format!("{}: {what} plc: {e}", at(text, &d.plc)))?;
        let p = &plcs[plc];
        let protocol = match d.protocol.get_ref().as_str() {
            "mc" => {
                if p.profile.doors.mc.is_none() {
                    return Err(format!(
                        "{}: {what} protocol: {} ({}) has no MC protocol door",
                        at(text, &d.protocol),
                        p.name,
                        p.profile.model
                    ));
                }
                ClientProtocol::Mc
            }
            "modbus" => ClientProtocol::Modbus,
            other => {
                return Err(format!(
                    "{}: {what} protocol: `{other}` (expected \"mc\" or \"modbus\")",
                    at(text, &d.protocol)
                ))
            }
        };
        let every_us = time_us(&d.every, &format!("{what} every"))?;
        if every_us == 0 {
            return Err(format!("{what} every: must be more than 0"));
        }
        if d.unit.is_some() && protocol == ClientProtocol::Mc {
            return Err(format!(
                "{what} unit: a Modbus unit id; MC frames have none"
            ));
        }
        if d.read.is_none() && d.write.is_none() {
            return Err(format!("{what}: give `read`, `write` or both"));
        }
        let remote = |v: &toml::Value, key: &str| -> Result<Remote, String> {
            match (protocol, v) {
                (ClientProtocol::Mc, toml::Value::String(s)) => {
                    // A system's CPU n: `CPUn/D0` (the frame's destination).
                    let name =
                        softplc_core::system::names::prefix(s).map_or(s.as_str(), |(_, r)| r);
                    if softplc_mc::DeviceRef::parse(name).is_some() {
                        Ok(Remote::Device(s.trim().to_string()))
                    } else {
                        Err(format!(
                            "{what} {key}: `{s}` is not an MC device name (D0, W1F, R10 …)"
                        ))
                    }
                }
                (ClientProtocol::Modbus, toml::Value::Integer(n)) if (0..=65535).contains(n) => {
                    Ok(Remote::Register(*n as u16))
                }
                (ClientProtocol::Mc, _) => Err(format!(
                    "{what} {key}: a device name of {} as the MC protocol names it (\"D0\")",
                    p.name
                )),
                (ClientProtocol::Modbus, _) => Err(format!(
                    "{what} {key}: a holding-register address 0-65535 of {}",
                    p.name
                )),
            }
        };
        let local = |v: &toml::Value, key: &str| -> Result<String, String> {
            let s = v.as_str().ok_or_else(|| {
                format!("{what} {key}: a device of the fleet, such as \"line2/D100\"")
            })?;
            layout.split(s).map_err(|e| format!("{what} {key}: {e}"))?;
            device(s, &format!("{what} {key}"))?;
            Ok(s.trim().to_string())
        };
        let count = |c: Option<u16>, key: &str| -> Result<u16, String> {
            match c.unwrap_or(1) {
                n @ 1..=123 => Ok(n),
                n => Err(format!("{what} {key}.count: {n} words (1-123 a request)")),
            }
        };
        let read = match &d.read {
            Some(b) => Some(BlockSpec {
                from: remote(&b.from, "read.from")?,
                count: count(b.count, "read")?,
                to: local(&b.to, "read.to")?,
            }),
            None => None,
        };
        let write = match &d.write {
            Some(b) => Some(BlockSpec {
                from: local(&b.from, "write.from")?,
                count: count(b.count, "write")?,
                to: remote(&b.to, "write.to")?,
            }),
            None => None,
        };
        out.push(ClientSpec {
            name,
            plc,
            protocol,
            every_us,
            unit: d.unit,
            read,
            write,
        });
    }
    Ok(out)
}

/// The source of a PLC's `program` or `project` relative to `base`.
pub(super) fn source_of(
    program: &Option<String>,
    project: &Option<String>,
    base: &Path,
) -> Result<Source, String> {
    use softplc_core::system;
    Ok(match (program, project) {
        (Some(p), None) | (None, Some(p)) if system::is_system(&base.join(p)) => {
            Source::System(base.join(p))
        }
        (Some(p), None) => Source::Program(base.join(p)),
        (None, Some(p)) => Source::Project(base.join(p)),
        _ => {
            return Err("give exactly one of `program` (a file) or `project` (a directory)".into())
        }
    })
}
