//! `[[client]]`: an HMI or SCADA that polls one PLC of a fleet over its MC
//! protocol or Modbus TCP door in virtual time. No socket: each poll's
//! frames are encoded, handed to the same handlers `softplc serve` runs at
//! END (`softplc_mc::handle_station`, `softplc_modbus::serve`) right after
//! the polled PLC's END, and the reply decoded; the words read are written
//! into another PLC's devices through its door at once.

use softplc_core::access::{RBlock, Span};
use softplc_core::names::DevName;
use softplc_core::profile::Profile;
use softplc_mc::{
    decode_request, decode_response, encode_request, encode_response, Command, DeviceRef, Header,
    Request, Session, Unit,
};
use softplc_modbus::{Frame, Map, Preset, Proto, Slave};

use super::plcs::Plcs;
use super::spec::{BlockSpec, ClientProtocol, ClientSpec, Remote};

/// Words of a fleet device: the CPU (flat) and its span.
#[derive(Clone, Debug)]
struct Local {
    cpu: usize,
    span: Span,
}

/// What a client addresses in the polled PLC.
#[derive(Clone, Copy, Debug)]
enum Target {
    /// A device and the frame's request destination module I/O number
    /// (`03FF` the own station, `03E0`-`03E3` a system's CPU 1-4).
    Mc(DeviceRef, u16),
    Register(u16),
}

enum Door {
    Mc(Session),
    Modbus { slave: Slave, map: Map, unit: u8 },
}

/// A client ready to poll.
#[derive(Default)]
pub(super) struct Client {
    name: String,
    /// The PLC polled (0-based).
    plc: usize,
    every_us: u64,
    next_us: u64,
    door: Option<Door>,
    read: Option<(Target, u16, Local)>,
    /// The words of `Local` (its span's length) go to `Target`.
    write: Option<(Local, Target)>,
    transaction: u16,
    /// Polls done, requests that failed and the first failure.
    pub polls: u64,
    pub failed: u64,
    pub first_error: Option<String>,
}

impl Client {
    /// Resolves `spec`'s devices against the built PLCs. `modbus` is the
    /// polled PLC's `[modbus]` table of plc.toml, if any.
    pub fn new(
        spec: &ClientSpec,
        plcs: &Plcs,
        profile: &'static Profile,
        modbus: Option<&toml::Table>,
    ) -> Result<Client, String> {
        let what = format!("client `{}`", spec.name);
        // `written`: a read's destination, which the program's locals
        // (the APLC's LM/V) may not be.
        let local = |text: &str, count: u16, written: bool| -> Result<Local, String> {
            let err = |e: String| format!("{what}: {e}");
            let (cpu, rest) = plcs.layout.split(text).map_err(err)?;
            let dev = DevName::parse_for(rest.trim(), plcs.get(cpu)).map_err(err)?;
            if written && dev.is_read_only() {
                return Err(err(format!(
                    "`{text}`: a program's local device cannot be written from outside"
                )));
            }
            let (kind, number) = dev
                .spec()
                .device()
                .filter(|(k, _)| !k.is_bit())
                .ok_or_else(|| {
                    err(format!(
                        "`{text}`: a client copies words: name a word device"
                    ))
                })?;
            let span = plcs
                .get(cpu)
                .span(kind, number, u32::from(count), RBlock::First)
                .map_err(|e| err(format!("`{text}`: {e}")))?;
            Ok(Local { cpu, span })
        };
        let cpus = plcs.units[spec.plc].cpus.len();
        let target = |r: &Remote| -> Result<Target, String> {
            Ok(match r {
                Remote::Device(d) => {
                    let (io, name) = match softplc_core::system::names::prefix(d) {
                        Some((n, rest)) if (1..=cpus).contains(&n) && cpus > 1 => {
                            (softplc_mc::handler::CPU_IO.start() + n as u16 - 1, rest)
                        }
                        Some((n, _)) => {
                            return Err(format!(
                                "{what}: `{d}`: the PLC polled has no CPU {n} (it has {cpus})"
                            ))
                        }
                        None => (Header::default().io, d.as_str()),
                    };
                    let head = DeviceRef::parse(name)
                        .ok_or_else(|| format!("{what}: `{d}` is not an MC device name"))?;
                    Target::Mc(head, io)
                }
                Remote::Register(n) => Target::Register(*n),
            })
        };
        let door = match spec.protocol {
            ClientProtocol::Mc => Door::Mc(Session::new()),
            ClientProtocol::Modbus => {
                let table = modbus.cloned().unwrap_or_default();
                let preset = Preset::find(profile.doors.modbus)
                    .ok_or_else(|| format!("{what}: {} has no Modbus map", profile.model))?;
                let map = Map::from_toml_with(&table, preset)
                    .map_err(|e| format!("{what}: [modbus]: {e}"))?;
                let slave = Slave::from_toml_with(&table, profile.doors.modbus_unit)
                    .map_err(|e| format!("{what}: [modbus]: {e}"))?;
                let unit = spec.unit.unwrap_or(slave.unit_id);
                Door::Modbus { slave, map, unit }
            }
        };
        let read = match &spec.read {
            Some(BlockSpec { from, count, to }) => {
                Some((target(from)?, *count, local(to, *count, true)?))
            }
            None => None,
        };
        let write = match &spec.write {
            Some(BlockSpec { from, count, to }) => Some((local(from, *count, false)?, target(to)?)),
            None => None,
        };
        Ok(Client {
            name: spec.name.clone(),
            plc: spec.plc,
            every_us: spec.every_us,
            next_us: 0,
            door: Some(door),
            read,
            write,
            transaction: 0,
            polls: 0,
            failed: 0,
            first_error: None,
        })
    }

    /// The PLC it polls.
    pub fn plc(&self) -> usize {
        self.plc
    }

    /// Polls when due: at the first END at or after 0, `every`, 2·`every`
    /// …; the write first (an HMI's setpoint), then the read.
    pub fn poll(&mut self, now_us: u64, plcs: &mut Plcs) {
        if now_us < self.next_us {
            return;
        }
        self.next_us = (now_us / self.every_us + 1) * self.every_us;
        self.polls += 1;
        if let Some((from, to)) = self.write.clone() {
            // The span was resolved in this memory at build.
            let sent = match plcs.get(from.cpu).memory().read_span_words(&from.span) {
                Ok(values) => self.request(plcs, Op::Write(to, &values)),
                Err(e) => Err(e.to_string()),
            };
            if let Err(e) = sent {
                self.fail(now_us, e);
            }
        }
        if let Some((from, count, to)) = self.read.clone() {
            match self.request(plcs, Op::Read(from, count)) {
                Ok(words) => {
                    let _ = plcs.get_mut(to.cpu).write_span_words(&to.span, &words);
                }
                Err(e) => self.fail(now_us, e),
            }
        }
    }

    fn fail(&mut self, now_us: u64, e: String) {
        self.failed += 1;
        if self.first_error.is_none() {
            self.first_error = Some(format!("at {}: {e}", super::fmt::fmt_time(now_us)));
        }
    }

    /// One request through the door's handler; the words read.
    fn request(&mut self, plcs: &mut Plcs, op: Op<'_>) -> Result<Vec<u16>, String> {
        let unit = &mut plcs.units[self.plc];
        match self.door.as_mut() {
            Some(Door::Mc(session)) => {
                let (command, io) = match op {
                    Op::Read(Target::Mc(head, io), n) => (
                        Command::BatchRead {
                            unit: Unit::Word,
                            head,
                            points: n,
                        },
                        io,
                    ),
                    Op::Write(Target::Mc(head, io), values) => (
                        Command::BatchWriteWords {
                            head,
                            values: values.to_vec(),
                        },
                        io,
                    ),
                    _ => return Err("not an MC device".into()),
                };
                let frame = encode_request(&Request {
                    header: Header {
                        io,
                        ..Header::default()
                    },
                    command,
                });
                let (req, _) = decode_request(&frame).map_err(|e| e.to_string())?;
                let resp = softplc_mc::handle_station(&req, &mut unit.cpus, session, None);
                let bytes = encode_response(&req.header, &resp);
                let (reply, _) = decode_response(&bytes).map_err(|e| e.to_string())?;
                if reply.end_code != softplc_mc::EndCode::OK {
                    return Err(format!("MC end code {:04X}H", reply.end_code.0));
                }
                Ok(reply.words().unwrap_or_default())
            }
            Some(Door::Modbus {
                slave,
                map,
                unit: id,
            }) => {
                self.transaction = self.transaction.wrapping_add(1);
                let pdu = match op {
                    Op::Read(Target::Register(a), n) => {
                        let [ah, al] = a.to_be_bytes();
                        let [nh, nl] = n.to_be_bytes();
                        vec![3, ah, al, nh, nl]
                    }
                    Op::Write(Target::Register(a), values) => {
                        let [ah, al] = a.to_be_bytes();
                        let [nh, nl] = (values.len() as u16).to_be_bytes();
                        let mut p = vec![16, ah, al, nh, nl, (values.len() * 2) as u8];
                        for v in values {
                            p.extend_from_slice(&v.to_be_bytes());
                        }
                        p
                    }
                    _ => return Err("not a Modbus register".into()),
                };
                let wire = Frame::new(Proto::Tcp, self.transaction, *id, pdu).encode();
                let frame = match softplc_modbus::decode(Proto::Tcp, &wire) {
                    Ok(Some((f, _))) => f,
                    _ => return Err("request frame not decoded".into()),
                };
                let cpu = unit.cpus.get_mut(0);
                let reply = softplc_modbus::serve(slave, map, &frame, cpu)
                    .ok_or("no reply (another unit id?)")?;
                let reply = match softplc_modbus::decode(Proto::Tcp, &reply) {
                    Ok(Some((f, _))) => f,
                    _ => return Err("reply frame not decoded".into()),
                };
                match reply.pdu.as_slice() {
                    [f, code] if f & 0x80 != 0 => Err(format!("Modbus exception {code:02X}")),
                    [3, _, data @ ..] => Ok(data
                        .chunks_exact(2)
                        .map(|c| u16::from_be_bytes([c[0], c[1]]))
                        .collect()),
                    [16, ..] => Ok(Vec::new()),
                    _ => Err("unexpected reply".into()),
                }
            }
            None => Ok(Vec::new()),
        }
    }
}

/// A client's request.
enum Op<'a> {
    Read(Target, u16),
    Write(Target, &'a [u16]),
}

/// The failed line of a client whose polls failed.
pub(super) fn result(c: &Client) -> Option<(String, String)> {
    (c.failed > 0).then(|| {
        (
            format!("client `{}` polls without error", c.name),
            format!(
                "{} of {} polls failed, the first {}",
                c.failed,
                c.polls,
                c.first_error.as_deref().unwrap_or("")
            ),
        )
    })
}
