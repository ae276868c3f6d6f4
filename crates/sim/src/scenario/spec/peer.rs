//! `[port1]`/`[port2]` and `[[peer]]` of a scenario: the APLC ports of a
//! program file and the simulated devices on the lines (docs/scenarios.md
//! "Serial peers"), in virtual time.

use softplc_ports::{PortConfig, Val};

use super::values::time_us;
use super::{PeerKind, PeerSpec, ScriptStep};

/// Converts a TOML table to the port settings' items.
pub(super) fn port_config(port: u8, t: &toml::Table) -> Result<PortConfig, String> {
    let items: Vec<(&str, Val<'_>)> = t
        .iter()
        .map(|(k, v)| {
            let v = match v {
                toml::Value::Integer(n) => Val::Int(*n),
                toml::Value::String(s) => Val::Str(s),
                toml::Value::Boolean(b) => Val::Bool(*b),
                v => Val::Other(v.type_str()),
            };
            (k.as_str(), v)
        })
        .collect();
    PortConfig::build(port, &items).map_err(|errors| {
        errors
            .into_iter()
            .map(|(_, e)| format!("[port{port}] {e}"))
            .collect::<Vec<_>>()
            .join("; ")
    })
}

/// Bytes: an array of 0-255 or a string (its UTF-8 bytes).
fn bytes(v: &toml::Value, what: &str) -> Result<Vec<u8>, String> {
    match v {
        toml::Value::String(s) => Ok(s.as_bytes().to_vec()),
        toml::Value::Array(a) => a
            .iter()
            .map(|b| match b.as_integer() {
                Some(n @ 0..=255) => Ok(n as u8),
                _ => Err(format!("{what}: bytes are integers 0-255")),
            })
            .collect(),
        _ => Err(format!("{what}: expected an array of bytes or a string")),
    }
}

fn table_values(
    t: &toml::Table,
    key: &str,
    what: &str,
    size: u16,
) -> Result<Vec<(u16, i64)>, String> {
    let Some(v) = t.get(key) else {
        return Ok(Vec::new());
    };
    let tab = v
        .as_table()
        .ok_or_else(|| format!("{what}.{key}: expected a table of address = value"))?;
    let mut out = Vec::new();
    for (a, v) in tab {
        let addr: u16 = a
            .parse()
            .ok()
            .filter(|n| *n < size)
            .ok_or_else(|| format!("{what}.{key}: `{a}` is not an address 0-{}", size - 1))?;
        let n = match v {
            toml::Value::Integer(n) if (-32768..=65535).contains(n) => *n,
            toml::Value::Boolean(b) => *b as i64,
            _ => {
                return Err(format!(
                    "{what}.{key}.{a}: expected a 16-bit value or true/false"
                ))
            }
        };
        out.push((addr, n));
    }
    Ok(out)
}

const PEER_KEYS: &[&str] = &[
    "port",
    "type",
    "station",
    "mode",
    "delay",
    "size",
    "silent",
    "holding",
    "input_registers",
    "coils",
    "inputs",
    "follow",
    "step",
];

/// One `[[peer]]`.
pub(super) fn peer(t: &toml::Table, i: usize) -> Result<PeerSpec, String> {
    let what = format!("peer #{}", i + 1);
    if let Some(k) = t.keys().find(|k| !PEER_KEYS.contains(&k.as_str())) {
        return Err(format!(
            "{what}: unknown key `{k}`; expected one of {}",
            PEER_KEYS.join(", ")
        ));
    }
    let port = match t.get("port").and_then(|v| v.as_integer()) {
        Some(n @ 1..=2) => n as u8,
        _ => return Err(format!("{what}: `port` is 1 (PORT1) or 2 (PORT2)")),
    };
    let delay_us = t
        .get("delay")
        .map(|v| time_us(v, &format!("{what}: delay")))
        .transpose()?;
    let kind = match t.get("type").and_then(|v| v.as_str()) {
        Some("modbus-slave") => {
            let station = match t.get("station").and_then(|v| v.as_integer()) {
                Some(n @ 1..=247) => n as u8,
                _ => return Err(format!("{what}: `station` is 1-247")),
            };
            let ascii = match t.get("mode").map(|v| v.as_str()) {
                None => None,
                Some(Some("rtu")) => Some(false),
                Some(Some("ascii")) => Some(true),
                _ => return Err(format!("{what}: `mode` is \"rtu\" or \"ascii\"")),
            };
            let size = match t.get("size").map(|v| v.as_integer()) {
                None => 1000,
                Some(Some(n @ 1..=65535)) => n as u16,
                _ => return Err(format!("{what}: `size` is 1-65535 addresses")),
            };
            let silent = match t.get("silent") {
                None => false,
                Some(toml::Value::Boolean(b)) => *b,
                _ => return Err(format!("{what}: `silent` is true or false")),
            };
            let mut follow = Vec::new();
            if let Some(v) = t.get("follow") {
                let arr = v
                    .as_array()
                    .ok_or_else(|| format!("{what}: `follow` is an array of tables"))?;
                for f in arr {
                    let get = |k: &str| f.get(k).and_then(|v| v.as_str()).map(str::to_string);
                    let register = f
                        .get("register")
                        .and_then(|v| v.as_integer())
                        .filter(|n| (0..size as i64).contains(n))
                        .ok_or_else(|| {
                            format!("{what}: follow: `register` is an address 0-{}", size - 1)
                        })?;
                    let (Some(model), Some(output)) = (get("model"), get("output")) else {
                        return Err(format!("{what}: follow: give `model` and `output`"));
                    };
                    let gain = match f.get("gain") {
                        None => 1.0,
                        Some(v) => super::values::number(v, "follow: gain")?,
                    };
                    follow.push((register as u16, model, output, gain));
                }
            }
            PeerKind::Slave {
                station,
                ascii,
                size,
                silent,
                holding: table_values(t, "holding", &what, size)?,
                input_registers: table_values(t, "input_registers", &what, size)?,
                coils: table_values(t, "coils", &what, size)?,
                inputs: table_values(t, "inputs", &what, size)?,
                follow,
            }
        }
        Some("script") => {
            let steps = t
                .get("step")
                .and_then(|v| v.as_array())
                .ok_or_else(|| format!("{what}: a script has [[peer.step]] tables"))?;
            let mut out = Vec::new();
            for (k, s) in steps.iter().enumerate() {
                let sw = format!("{what} step #{}", k + 1);
                let s = s
                    .as_table()
                    .ok_or_else(|| format!("{sw}: expected a table"))?;
                if let Some(bad) = s
                    .keys()
                    .find(|k| !["expect", "answer", "delay", "at", "send"].contains(&k.as_str()))
                {
                    return Err(format!(
                        "{sw}: unknown key `{bad}`; expected expect, answer, delay, at, send"
                    ));
                }
                out.push(match (s.get("expect"), s.get("at")) {
                    (Some(e), None) => ScriptStep::Expect {
                        expect: bytes(e, &format!("{sw}: expect"))?,
                        answer: match s.get("answer") {
                            Some(a) => bytes(a, &format!("{sw}: answer"))?,
                            None => Vec::new(),
                        },
                        delay_us: match s.get("delay") {
                            Some(d) => time_us(d, &format!("{sw}: delay"))?,
                            None => 0,
                        },
                    },
                    (None, Some(at)) => ScriptStep::Send {
                        at_us: time_us(at, &format!("{sw}: at"))?,
                        bytes: bytes(
                            s.get("send")
                                .ok_or_else(|| format!("{sw}: `at` needs `send`"))?,
                            &format!("{sw}: send"),
                        )?,
                    },
                    _ => {
                        return Err(format!(
                            "{sw}: give `expect` (and `answer`) or `at` and `send`"
                        ))
                    }
                });
            }
            PeerKind::Script(out)
        }
        _ => return Err(format!("{what}: `type` is \"modbus-slave\" or \"script\"")),
    };
    Ok(PeerSpec {
        plc: 0,
        port,
        delay_us,
        kind,
    })
}
