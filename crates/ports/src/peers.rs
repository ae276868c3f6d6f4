//! Simulated peers for a [`crate::VirtualLine`]: a Modbus RTU/ASCII slave
//! device ([`SimSlave`]) and a scripted free-port device ([`Script`]).

use std::sync::{Arc, Mutex};

use softplc_modbus::{decode, Frame, Proto, Request};

use crate::virtual_line::Peer;

/// A Modbus slave: coils, discrete inputs, holding and input registers at
/// addresses 0 to `size - 1` (others are exception 02), function codes 01-06,
/// 15 and 16 (others are exception 01). A frame for another station, a
/// broadcast read or a frame with a bad CRC/LRC gets no answer; a `silent`
/// slave never answers (an absent station).
#[derive(Clone, Debug)]
pub struct SimSlave {
    pub unit: u8,
    pub proto: Proto,
    pub size: u16,
    pub coils: Vec<bool>,
    pub inputs: Vec<bool>,
    pub holding: Vec<u16>,
    pub input_registers: Vec<u16>,
    pub silent: bool,
    /// Answer time after the request's last byte, µs (at least the line's
    /// silence in RTU).
    pub delay_us: u64,
    /// Requests it served, in order.
    pub log: Vec<Vec<u8>>,
}

impl SimSlave {
    pub fn new(unit: u8, proto: Proto, size: u16, delay_us: u64) -> SimSlave {
        let n = size as usize;
        SimSlave {
            unit,
            proto,
            size,
            coils: vec![false; n],
            inputs: vec![false; n],
            holding: vec![0; n],
            input_registers: vec![0; n],
            silent: false,
            delay_us,
            log: Vec::new(),
        }
    }

    /// The response PDU to a request PDU.
    pub fn serve(&mut self, pdu: &[u8]) -> Vec<u8> {
        let fc = pdu.first().copied().unwrap_or(0);
        let exception = |code: u8| vec![fc | 0x80, code];
        let req = match Request::parse(pdu) {
            Ok(r) => r,
            Err(e) => return exception(e.code()),
        };
        let size = self.size as usize;
        let fits = |a: u16, q: usize| q >= 1 && a as usize + q <= size;
        let bits = |v: &[bool]| {
            let mut out = vec![0u8; v.len().div_ceil(8)];
            for (k, b) in v.iter().enumerate() {
                out[k / 8] |= (*b as u8) << (k % 8);
            }
            out
        };
        match req {
            Request::ReadCoils { address, quantity }
            | Request::ReadDiscreteInputs { address, quantity } => {
                let q = quantity as usize;
                if !(1..=2000).contains(&q) {
                    return exception(3);
                }
                if !fits(address, q) {
                    return exception(2);
                }
                let a = address as usize;
                let src = if fc == 1 { &self.coils } else { &self.inputs };
                let data = bits(&src[a..a + q]);
                let mut out = vec![fc, data.len() as u8];
                out.extend(data);
                out
            }
            Request::ReadHoldingRegisters { address, quantity }
            | Request::ReadInputRegisters { address, quantity } => {
                let q = quantity as usize;
                if !(1..=125).contains(&q) {
                    return exception(3);
                }
                if !fits(address, q) {
                    return exception(2);
                }
                let a = address as usize;
                let src = if fc == 3 {
                    &self.holding
                } else {
                    &self.input_registers
                };
                let mut out = vec![fc, 2 * q as u8];
                for w in &src[a..a + q] {
                    out.extend(w.to_be_bytes());
                }
                out
            }
            Request::WriteSingleCoil { address, value } => {
                if value != 0xFF00 && value != 0 {
                    return exception(3);
                }
                if !fits(address, 1) {
                    return exception(2);
                }
                self.coils[address as usize] = value == 0xFF00;
                pdu.to_vec()
            }
            Request::WriteSingleRegister { address, value } => {
                if !fits(address, 1) {
                    return exception(2);
                }
                self.holding[address as usize] = value;
                pdu.to_vec()
            }
            Request::WriteMultipleCoils {
                address,
                quantity,
                bits,
            } => {
                let q = quantity as usize;
                if !fits(address, q) {
                    return exception(2);
                }
                for k in 0..q {
                    self.coils[address as usize + k] = bits[k / 8] >> (k % 8) & 1 != 0;
                }
                pdu[..5].to_vec()
            }
            Request::WriteMultipleRegisters { address, values } => {
                if !fits(address, values.len()) {
                    return exception(2);
                }
                let a = address as usize;
                self.holding[a..a + values.len()].copy_from_slice(&values);
                pdu[..5].to_vec()
            }
            _ => exception(1),
        }
    }
}

impl Peer for SimSlave {
    fn receive(&mut self, _at_us: u64, bytes: &[u8]) -> Option<(u64, Vec<u8>)> {
        let Ok(Some((frame, _))) = decode(self.proto, bytes) else {
            return None;
        };
        self.log.push(bytes.to_vec());
        if self.silent || frame.unit != self.unit {
            return None; // another station, or absent
        }
        let reply = self.serve(&frame.pdu);
        Some((
            self.delay_us,
            Frame::new(self.proto, 0, self.unit, reply).encode(),
        ))
    }
}

/// One step of a [`Script`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Step {
    /// When the bytes received since the previous step end with `expect`,
    /// answer `answer` after `delay_us`.
    Expect {
        expect: Vec<u8>,
        answer: Vec<u8>,
        delay_us: u64,
    },
    /// Send `bytes` at `at_us` (virtual time).
    Send { at_us: u64, bytes: Vec<u8> },
}

/// A free-port device driven by a script of steps, taken in order.
#[derive(Clone, Debug, Default)]
pub struct Script {
    pub steps: Vec<Step>,
    next: usize,
    heard: Vec<u8>,
    /// Everything the PLC sent, in order.
    pub received: Vec<u8>,
    /// When each of the PLC's frames ended (its last byte arrived), µs.
    pub frames_at: Vec<u64>,
}

impl Script {
    pub fn new(steps: Vec<Step>) -> Script {
        Script {
            steps,
            ..Script::default()
        }
    }
}

impl Peer for Script {
    fn receive(&mut self, at_us: u64, bytes: &[u8]) -> Option<(u64, Vec<u8>)> {
        self.received.extend_from_slice(bytes);
        self.frames_at.push(at_us);
        self.heard.extend_from_slice(bytes);
        if let Some(Step::Expect {
            expect,
            answer,
            delay_us,
        }) = self.steps.get(self.next)
        {
            if self.heard.ends_with(expect) {
                let out = (*delay_us, answer.clone());
                self.heard.clear();
                self.next += 1;
                return Some(out);
            }
        }
        None
    }

    fn poll(&mut self, now_us: u64) -> Option<(u64, Vec<u8>)> {
        match self.steps.get(self.next) {
            Some(Step::Send { at_us, bytes }) if *at_us <= now_us => {
                let out = (*at_us, bytes.clone());
                self.next += 1;
                Some(out)
            }
            _ => None,
        }
    }
}

/// Several devices on one RS-485 line: every frame reaches each of them;
/// the first that answers is heard (a slave ignores other stations).
#[derive(Default)]
pub struct Bus(pub Vec<Box<dyn Peer>>);

impl Peer for Bus {
    fn receive(&mut self, at_us: u64, bytes: &[u8]) -> Option<(u64, Vec<u8>)> {
        let mut answer = None;
        for p in &mut self.0 {
            let a = p.receive(at_us, bytes);
            answer = answer.or(a);
        }
        answer
    }

    fn poll(&mut self, now_us: u64) -> Option<(u64, Vec<u8>)> {
        self.0.iter_mut().find_map(|p| p.poll(now_us))
    }
}

/// Nothing connected: a port bound to no device hears nothing (the master
/// times out with 0x10).
pub struct Silent;

impl Peer for Silent {
    fn receive(&mut self, _at_us: u64, _bytes: &[u8]) -> Option<(u64, Vec<u8>)> {
        None
    }
}

/// A peer also held by its owner (a scenario's plant model writes a
/// simulated slave's registers; a test looks at what a script heard).
pub struct Shared<P>(pub Arc<Mutex<P>>);

impl<P: Peer> Peer for Shared<P> {
    fn receive(&mut self, at_us: u64, bytes: &[u8]) -> Option<(u64, Vec<u8>)> {
        self.0.lock().ok()?.receive(at_us, bytes)
    }
    fn poll(&mut self, now_us: u64) -> Option<(u64, Vec<u8>)> {
        self.0.lock().ok()?.poll(now_us)
    }
}

/// `p` as a peer, and the handle to it.
pub fn shared<P: Peer + 'static>(p: P) -> (Arc<Mutex<P>>, Box<dyn Peer>) {
    let a = Arc::new(Mutex::new(p));
    (a.clone(), Box::new(Shared(a)))
}
