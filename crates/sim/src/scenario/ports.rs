//! The APLC ports of a scenario run: each configured port on a virtual line
//! to its `[[peer]]` devices (several on one port share the RS-485 line;
//! none: nothing answers), and the slave registers that follow a plant
//! model's output. The run loop calls the communication phase after every
//! scan (`Ports::after_end`), so a scenario is deterministic byte for byte.

use std::sync::{Arc, Mutex};

use softplc_modbus::Proto;
use softplc_ports::peers::{self, Bus, Script, SimSlave, Step};
use softplc_ports::{LinkEnd, Mode, Peer, PortConfig, Ports, Timing};

use super::spec::{LinkSpec, ModelSpec, PeerKind, PeerSpec, PlcSpec, PortRef, ScriptStep};
use crate::model::Model;

/// A slave register written from a model output before every scan.
pub(super) struct Follow {
    slave: Arc<Mutex<SimSlave>>,
    register: u16,
    model: usize,
    output: usize,
    gain: f64,
}

impl Follow {
    pub(super) fn apply(&self, outputs: &[f64]) {
        let v = (outputs[self.output] * self.gain)
            .round()
            .clamp(-32768.0, 65535.0) as i64;
        if let Ok(mut s) = self.slave.lock() {
            s.holding[self.register as usize] = v as u16;
            s.input_registers[self.register as usize] = v as u16;
        }
    }

    pub(super) fn model(&self) -> usize {
        self.model
    }
}

fn slave(cfg: &PortConfig, peer: &PeerSpec) -> Option<SimSlave> {
    let PeerKind::Slave {
        station,
        ascii,
        size,
        silent,
        holding,
        input_registers,
        coils,
        inputs,
        ..
    } = &peer.kind
    else {
        return None;
    };
    let ascii = ascii.unwrap_or(cfg.mode == Mode::Ascii);
    let proto = if ascii { Proto::Ascii } else { Proto::Rtu };
    let t = Timing::of(cfg);
    let delay = peer
        .delay_us
        .unwrap_or(if ascii { 1000 } else { t.silence_us + 1000 });
    let mut s = SimSlave::new(*station, proto, *size, delay);
    s.silent = *silent;
    for (a, v) in holding {
        s.holding[*a as usize] = *v as u16;
    }
    for (a, v) in input_registers {
        s.input_registers[*a as usize] = *v as u16;
    }
    for (a, v) in coils {
        s.coils[*a as usize] = *v != 0;
    }
    for (a, v) in inputs {
        s.inputs[*a as usize] = *v != 0;
    }
    Some(s)
}

/// Builds the ports of `configs` with `peers` (numbered as in the file) and
/// the ends of `linked` ports; `models` (spec and built) resolve the
/// registers that follow a model.
pub(super) fn build(
    configs: &[PortConfig],
    peers_spec: &[(usize, &PeerSpec)],
    mut linked: Vec<(u8, LinkEnd)>,
    models: &[(&ModelSpec, &dyn Model)],
) -> Result<(Ports, Vec<Follow>), String> {
    for &(i, p) in peers_spec {
        if !configs.iter().any(|c| c.port == p.port) {
            return Err(format!(
                "peer #{}: PORT{} has no settings ([port{}] in the scenario or plc.toml)",
                i + 1,
                p.port,
                p.port
            ));
        }
    }
    let mut ports = Ports::new();
    let mut follows = Vec::new();
    for cfg in configs {
        if let Some(k) = linked.iter().position(|(port, _)| *port == cfg.port) {
            if let Some((i, _)) = peers_spec.iter().find(|(_, p)| p.port == cfg.port) {
                return Err(format!(
                    "peer #{}: PORT{} is linked to another PLC ([[link]]): a linked port takes no [[peer]]",
                    i + 1,
                    cfg.port
                ));
            }
            let (_, end) = linked.swap_remove(k);
            ports.add(cfg.clone(), Box::new(end));
            continue;
        }
        let mut on_line: Vec<Box<dyn Peer>> = Vec::new();
        for &(i, p) in peers_spec.iter().filter(|(_, p)| p.port == cfg.port) {
            match &p.kind {
                PeerKind::Slave { follow, .. } => {
                    let s = slave(cfg, p).expect("a slave peer");
                    let (handle, peer) = peers::shared(s);
                    for (register, model, output, gain) in follow {
                        let what = format!("peer #{} follow", i + 1);
                        let m = models
                            .iter()
                            .position(|(spec, _)| spec.name == *model)
                            .ok_or_else(|| format!("{what}: no model named `{model}`"))?;
                        let outs = models[m].1.outputs();
                        let o = outs.iter().position(|n| n == output).ok_or_else(|| {
                            format!(
                                "{what}: model `{model}` has no output `{output}` (it has {})",
                                outs.join(", ")
                            )
                        })?;
                        follows.push(Follow {
                            slave: handle.clone(),
                            register: *register,
                            model: m,
                            output: o,
                            gain: *gain,
                        });
                    }
                    on_line.push(peer);
                }
                PeerKind::Script(steps) => {
                    let steps = steps
                        .iter()
                        .map(|s| match s {
                            ScriptStep::Expect {
                                expect,
                                answer,
                                delay_us,
                            } => Step::Expect {
                                expect: expect.clone(),
                                answer: answer.clone(),
                                delay_us: *delay_us,
                            },
                            ScriptStep::Send { at_us, bytes } => Step::Send {
                                at_us: *at_us,
                                bytes: bytes.clone(),
                            },
                        })
                        .collect();
                    on_line.push(Box::new(Script::new(steps)));
                }
            }
        }
        let peer: Box<dyn Peer> = match on_line.len() {
            0 => Box::new(peers::Silent),
            1 => on_line.pop().expect("one peer"),
            _ => Box::new(Bus(on_line)),
        };
        ports.add_virtual(cfg.clone(), peer);
    }
    Ok((ports, follows))
}

/// The ends of every `[[link]]`, per PLC: (port, end). Both ports must have
/// settings (`configs`, per PLC) that agree on the character format.
pub(super) fn links(
    links: &[LinkSpec],
    configs: &[Vec<PortConfig>],
    plcs: &[PlcSpec],
) -> Result<Vec<Vec<(u8, LinkEnd)>>, String> {
    let mut out: Vec<Vec<(u8, LinkEnd)>> = configs.iter().map(|_| Vec::new()).collect();
    for l in links {
        let name = |e: PortRef| format!("{}:port{}", plcs[e.plc].name, e.port);
        let config = |e: PortRef| {
            configs[e.plc]
                .iter()
                .find(|c| c.port == e.port)
                .ok_or_else(|| {
                    format!(
                        "{}: `{}` has no settings ([port{}] in its [[plc]] table, or in its plc.toml)",
                        l.what,
                        name(e),
                        e.port
                    )
                })
        };
        let (a, b) = (config(l.a)?, config(l.b)?);
        let format = |c: &PortConfig| {
            format!(
                "{} baud, parity {:?}, {} data bits, {} stop bits",
                c.baud, c.parity, c.data_bits, c.stop_bits
            )
            .to_lowercase()
        };
        if (a.baud, a.parity, a.data_bits, a.stop_bits)
            != (b.baud, b.parity, b.data_bits, b.stop_bits)
        {
            return Err(format!(
                "{}: the two ends do not agree: `{}` has {}, `{}` has {}",
                l.what,
                name(l.a),
                format(a),
                name(l.b),
                format(b)
            ));
        }
        let (end_a, end_b) = softplc_ports::link(Timing::of(a));
        out[l.a.plc].push((l.a.port, end_a));
        out[l.b.plc].push((l.b.port, end_b));
    }
    Ok(out)
}
