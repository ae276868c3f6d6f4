//! A change from outside as recorded ([`Event`], from the Cpu door's
//! [`DoorEvent`]) and as replayed ([`apply`]: the same door call again).

use serde::{Deserialize, Serialize};
use softplc_core::access::{DeviceSpec, RBlock, Value};
use softplc_core::device::DeviceKind;
use softplc_core::engine::{Cpu, DoorEvent, RunClear};

/// Who made a change: the door whose request was being served.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Source {
    /// The host itself: the load and the battery-backed image before the
    /// servers start, END hooks of no door.
    #[default]
    Host,
    Mc,
    Modbus,
    Http,
    OpcUa,
    /// Writes published to the MQTT broker's set topics.
    Mqtt,
    /// A Modbus RTU/ASCII slave line.
    Serial,
    /// The APLC serial ports PORT1/PORT2 (Modbus master, free port).
    Ports,
}

impl Source {
    pub fn name(self) -> &'static str {
        match self {
            Source::Host => "host",
            Source::Mc => "MC",
            Source::Modbus => "Modbus",
            Source::Http => "HTTP",
            Source::OpcUa => "OPC UA",
            Source::Mqtt => "MQTT",
            Source::Serial => "serial",
            Source::Ports => "ports",
        }
    }

    /// The source of a door named by the serve layer (`softplc_serve::Listener::door`).
    pub fn of_door(door: &str) -> Source {
        match door {
            "MC protocol" => Source::Mc,
            "Modbus TCP" => Source::Modbus,
            "HTTP" => Source::Http,
            "OPC UA" => Source::OpcUa,
            "MQTT" => Source::Mqtt,
            "serial" => Source::Serial,
            _ => Source::Host,
        }
    }
}

/// A device kind by its name (`D`, `TN`), stable across versions.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Kind(pub String);

impl Kind {
    fn of(k: DeviceKind) -> Kind {
        Kind(k.name().to_string())
    }

    fn kind(&self) -> Result<DeviceKind, String> {
        DeviceKind::ALL
            .iter()
            .copied()
            .find(|k| k.name() == self.0)
            .ok_or_else(|| format!("unknown device kind `{}`", self.0))
    }
}

/// A written value ([`Value`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Val {
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
}

/// One change from outside, with the door that made it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Event {
    pub source: Source,
    pub change: Change,
}

/// What changed (one [`DoorEvent`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Change {
    /// By name: the door's text of the device (MELSEC syntax).
    Value {
        name: String,
        value: Val,
    },
    Text {
        name: String,
        value: String,
    },
    Words {
        kind: Kind,
        number: u32,
        selected_block: bool,
        values: Vec<u16>,
    },
    Bits {
        kind: Kind,
        number: u32,
        selected_block: bool,
        values: Vec<bool>,
    },
    Word {
        kind: Kind,
        n: i64,
        value: u16,
    },
    Bit {
        kind: Kind,
        n: i64,
        value: bool,
    },
    Input {
        n: u32,
        on: bool,
    },
    Force {
        kind: Kind,
        n: u32,
        on: bool,
    },
    Release {
        kind: Kind,
        n: u32,
    },
    ReleaseAll,
    Run,
    Stop,
    Pause,
    Reset,
    LatchClear {
        remote: bool,
    },
    RunClear {
        latch_too: bool,
    },
    RemoteRun {
        client: u32,
        force: bool,
    },
    RemoteStop {
        client: u32,
        force: bool,
    },
    RemotePause {
        client: u32,
        force: bool,
    },
    RemoteReset,
    Calendar {
        unix_us: i64,
    },
    Retained {
        data: Vec<Option<Vec<u8>>>,
    },
    BatteryError {
        stop: bool,
    },
    LocalsOf {
        slot: u32,
    },
    LocalsEnd,
}

impl Change {
    /// The recorded form of a door event; `None` for one a recording
    /// cannot hold ([`DoorEvent::Unrecordable`]: the recorder stops there).
    pub fn of(e: &DoorEvent<'_>) -> Option<Change> {
        let selected = |b: &RBlock| *b == RBlock::Selected;
        Some(match *e {
            DoorEvent::Value { spec, value } => Change::Value {
                name: spec.door_text().to_string(),
                value: match value {
                    Value::Bool(b) => Val::Bool(*b),
                    Value::Int(i) => Val::Int(*i),
                    Value::Float(x) => Val::Float(*x),
                    Value::Str(s) => Val::Str(s.clone()),
                },
            },
            DoorEvent::Text { spec, value } => Change::Text {
                name: spec.door_text().to_string(),
                value: value.to_string(),
            },
            DoorEvent::Words {
                kind,
                number,
                block,
                values,
                ..
            } => Change::Words {
                kind: Kind::of(kind),
                number,
                selected_block: selected(&block),
                values: values.to_vec(),
            },
            DoorEvent::Bits {
                kind,
                number,
                block,
                values,
            } => Change::Bits {
                kind: Kind::of(kind),
                number,
                selected_block: selected(&block),
                values: values.to_vec(),
            },
            DoorEvent::Word { kind, n, value } => Change::Word {
                kind: Kind::of(kind),
                n,
                value,
            },
            DoorEvent::Bit { kind, n, value } => Change::Bit {
                kind: Kind::of(kind),
                n,
                value,
            },
            DoorEvent::Input { n, on } => Change::Input { n, on },
            DoorEvent::Force { kind, n, on } => Change::Force {
                kind: Kind::of(kind),
                n,
                on,
            },
            DoorEvent::Release { kind, n } => Change::Release {
                kind: Kind::of(kind),
                n,
            },
            DoorEvent::ReleaseAll => Change::ReleaseAll,
            DoorEvent::Run => Change::Run,
            DoorEvent::Stop => Change::Stop,
            DoorEvent::Pause => Change::Pause,
            DoorEvent::Reset => Change::Reset,
            DoorEvent::LatchClear { remote } => Change::LatchClear { remote },
            DoorEvent::RunClear(mode) => Change::RunClear {
                latch_too: mode == RunClear::All,
            },
            DoorEvent::RemoteRun { client, force } => Change::RemoteRun { client, force },
            DoorEvent::RemoteStop { client, force } => Change::RemoteStop { client, force },
            DoorEvent::RemotePause { client, force } => Change::RemotePause { client, force },
            DoorEvent::RemoteReset => Change::RemoteReset,
            DoorEvent::Calendar { unix_us } => Change::Calendar { unix_us },
            DoorEvent::Retained { data } => Change::Retained {
                data: data.to_vec(),
            },
            DoorEvent::BatteryError { stop } => Change::BatteryError { stop },
            DoorEvent::LocalsOf { slot } => Change::LocalsOf { slot: slot as u32 },
            DoorEvent::LocalsEnd => Change::LocalsEnd,
            DoorEvent::Unrecordable { .. } => return None,
        })
    }
}

/// Makes the recorded changes again, through the same door calls. A
/// change the CPU refuses now (a write out of its range) is an error: the
/// recording does not fit this CPU. Writes between `LocalsOf` and
/// `LocalsEnd` go to that program's local devices.
pub fn apply(cpu: &mut Cpu, changes: &[Event]) -> Result<(), String> {
    let mut i = 0;
    while i < changes.len() {
        match &changes[i].change {
            Change::LocalsOf { slot } => {
                let end = changes[i + 1..]
                    .iter()
                    .position(|e| e.change == Change::LocalsEnd)
                    .map_or(changes.len(), |p| i + 1 + p);
                let inner = &changes[i + 1..end];
                let slot = *slot as usize;
                if slot >= cpu.program_count() {
                    return Err(format!(
                        "the recording names program file {slot} of {}",
                        cpu.program_count()
                    ));
                }
                cpu.with_local_devices_of(slot, |c| apply(c, inner))?;
                i = end + 1;
            }
            Change::LocalsEnd => i += 1,
            c => {
                apply_one(cpu, c)?;
                i += 1;
            }
        }
    }
    Ok(())
}

fn apply_one(cpu: &mut Cpu, c: &Change) -> Result<(), String> {
    let block = |selected: bool| match selected {
        true => RBlock::Selected,
        false => RBlock::First,
    };
    match c {
        Change::Value { name, value } => {
            let spec = DeviceSpec::parse(name)?;
            let v = match value {
                Val::Bool(b) => Value::Bool(*b),
                Val::Int(i) => Value::Int(*i),
                Val::Float(x) => Value::Float(*x),
                Val::Str(s) => Value::Str(s.clone()),
            };
            cpu.write_value(&spec, &v).map_err(|e| e.to_string())?;
        }
        Change::Text { name, value } => {
            let spec = DeviceSpec::parse(name)?;
            cpu.write_device(&spec, value)?;
        }
        Change::Words {
            kind,
            number,
            selected_block,
            values,
        } => {
            let s = cpu
                .span(
                    kind.kind()?,
                    *number,
                    values.len() as u32,
                    block(*selected_block),
                )
                .map_err(|e| e.to_string())?;
            cpu.write_span_words(&s, values)
                .map_err(|e| e.to_string())?;
        }
        Change::Bits {
            kind,
            number,
            selected_block,
            values,
        } => {
            let s = cpu
                .span(
                    kind.kind()?,
                    *number,
                    values.len() as u32,
                    block(*selected_block),
                )
                .map_err(|e| e.to_string())?;
            cpu.write_span_bits(&s, values).map_err(|e| e.to_string())?;
        }
        Change::Word { kind, n, value } => {
            cpu.set_word(kind.kind()?, *n, *value)
                .map_err(|e| e.to_string())?;
        }
        Change::Bit { kind, n, value } => {
            cpu.set_bit(kind.kind()?, *n, *value)
                .map_err(|e| e.to_string())?;
        }
        Change::Input { n, on } => cpu.set_input(*n, *on),
        Change::Force { kind, n, on } => cpu.force(kind.kind()?, *n, *on)?,
        Change::Release { kind, n } => {
            cpu.release(kind.kind()?, *n);
        }
        Change::ReleaseAll => cpu.release_all(),
        // The operations answer now as they did then; a refusal was recorded too.
        Change::Run => {
            let _ = cpu.set_run();
        }
        Change::Stop => cpu.set_stop(),
        Change::Pause => {
            let _ = cpu.set_pause();
        }
        Change::Reset => {
            let _ = cpu.reset();
        }
        Change::LatchClear { remote } => {
            let _ = cpu.latch_clear(*remote);
        }
        Change::RunClear { latch_too } => cpu.remote_run_clear(match latch_too {
            true => RunClear::All,
            false => RunClear::OutsideLatch,
        }),
        Change::RemoteRun { client, force } => {
            let _ = cpu.remote_run(*client, *force);
        }
        Change::RemoteStop { client, force } => {
            let _ = cpu.remote_stop(*client, *force);
        }
        Change::RemotePause { client, force } => {
            let _ = cpu.remote_pause(*client, *force);
        }
        Change::RemoteReset => {
            let _ = cpu.remote_reset();
        }
        Change::Calendar { unix_us } => cpu.set_calendar_unix_us(*unix_us),
        Change::Retained { data } => {
            // Regions as this CPU lays them out (a changed program may not).
            let layout = cpu.retained_layout();
            let fits = data.len() <= layout.len()
                && data
                    .iter()
                    .zip(&layout)
                    .all(|(d, (_, n))| d.as_ref().is_none_or(|d| d.len() == *n));
            if !fits {
                return Err("the recorded battery-backed image does not fit this CPU's \
                            latch ranges and file registers"
                    .into());
            }
            cpu.restore_retained(data)
        }
        Change::BatteryError { stop } => cpu.report_battery_error(*stop),
        Change::LocalsOf { .. } | Change::LocalsEnd => {}
    }
    Ok(())
}

impl std::fmt::Display for Val {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Val::Bool(b) => write!(f, "{b}"),
            Val::Int(i) => write!(f, "{i}"),
            Val::Float(x) => write!(f, "{x:?}"),
            Val::Str(s) => write!(f, "{s:?}"),
        }
    }
}

/// A change as a line of `softplc replay --log`, device names in the
/// door's own (MELSEC) syntax.
impl std::fmt::Display for Change {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let list = |v: &[String]| v.join(" ");
        match self {
            Change::Value { name, value } => write!(f, "{name} = {value}"),
            Change::Text { name, value } => write!(f, "{name} = {value}"),
            Change::Words {
                kind,
                number,
                values,
                ..
            } => write!(
                f,
                "{}{number}.. = {}",
                kind.0,
                list(&values.iter().map(|v| v.to_string()).collect::<Vec<_>>())
            ),
            Change::Bits {
                kind,
                number,
                values,
                ..
            } => write!(
                f,
                "{}{number}.. = {}",
                kind.0,
                list(
                    &values
                        .iter()
                        .map(|&b| (b as u8).to_string())
                        .collect::<Vec<_>>()
                )
            ),
            Change::Word { kind, n, value } => write!(f, "{}{n} = {value}", kind.0),
            Change::Bit { kind, n, value } => write!(f, "{}{n} = {value}", kind.0),
            Change::Input { n, on } => write!(f, "input X{n} = {on}"),
            Change::Force { kind, n, on } => {
                write!(f, "force {}{n} {}", kind.0, if *on { "ON" } else { "OFF" })
            }
            Change::Release { kind, n } => write!(f, "release {}{n}", kind.0),
            Change::ReleaseAll => f.write_str("release all"),
            Change::Run => f.write_str("RUN"),
            Change::Stop => f.write_str("STOP"),
            Change::Pause => f.write_str("PAUSE"),
            Change::Reset => f.write_str("RESET"),
            Change::LatchClear { remote } => {
                write!(f, "latch clear{}", if *remote { " (remote)" } else { "" })
            }
            Change::RunClear { latch_too } => write!(
                f,
                "device clear of remote RUN{}",
                if *latch_too { ", latch ranges too" } else { "" }
            ),
            Change::RemoteRun { client, .. } => write!(f, "remote RUN by client {client}"),
            Change::RemoteStop { client, .. } => write!(f, "remote STOP by client {client}"),
            Change::RemotePause { client, .. } => write!(f, "remote PAUSE by client {client}"),
            Change::RemoteReset => f.write_str("remote RESET"),
            Change::Calendar { unix_us } => {
                write!(f, "calendar set ({} s since 1970)", unix_us / 1_000_000)
            }
            Change::Retained { data } => write!(
                f,
                "battery-backed image restored ({} bytes)",
                data.iter().flatten().map(Vec::len).sum::<usize>()
            ),
            Change::BatteryError { stop } => {
                write!(
                    f,
                    "battery error{}",
                    if *stop { " (stops the CPU)" } else { "" }
                )
            }
            Change::LocalsOf { slot } => write!(f, "local devices of program {slot}:"),
            Change::LocalsEnd => f.write_str("end of local devices"),
        }
    }
}
