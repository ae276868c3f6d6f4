//! PORT1/PORT2 settings: the system block's communication page (002 §10.3
//! L10381-10393, §10.4.13 L10640-10659, Appendix 7 L11296-11301; spec aplc.md
//! §6.1, §6.9), written in plc.toml `[port1]`/`[port2]` (contract §3.3) or a
//! scenario, and shown in SD120-SD124/SD135-SD137 (PORT1) and
//! SD150-SD154/SD140-SD142 (PORT2) at power-on and STOP→RUN.

/// What a port runs (the system block's protocol choice).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Protocol {
    ModbusMaster,
    ModbusSlave,
    Free,
}

/// Modbus serial framing (spec §6.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Rtu,
    Ascii,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Parity {
    None,
    Even,
    Odd,
}

/// One port's settings.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PortConfig {
    /// 1 = PORT1, 2 = PORT2.
    pub port: u8,
    pub protocol: Protocol,
    pub mode: Mode,
    pub baud: u32,
    pub parity: Parity,
    pub data_bits: u8,
    pub stop_bits: u8,
    /// Own station number (SD135/SD140), 1-31 (L10444, L11299).
    pub address: u8,
    /// Master timeout in ms (SD136/SD141; 0 means 1000, D26).
    pub timeout_ms: u16,
    /// Master retries (SD137/SD142), 0-100.
    pub retries: u16,
    /// Free port: start character (SD121, enabled when set).
    pub start_char: Option<u8>,
    /// Free port: end character (SD122).
    pub end_char: Option<u8>,
    /// Free port: inter-character timeout in ms (SD123), 1-32767.
    pub char_timeout_ms: Option<u16>,
    /// Free port: frame timeout in ms from RCV (SD124), 1-32767.
    pub frame_timeout_ms: Option<u16>,
    /// Free port: two bytes per word, low byte first (SD120 bit 12).
    pub packed: bool,
    /// The serial device or pty the port is bound to (`device`, or
    /// `--port1`/`--port2`).
    pub device: Option<String>,
}

/// A value of a settings key, whatever file it came from.
#[derive(Clone, Copy, Debug)]
pub enum Val<'a> {
    Int(i64),
    Str(&'a str),
    Bool(bool),
    /// Any other type, by name.
    Other(&'static str),
}

/// The keys of `[port1]`/`[port2]`.
pub const KEYS: &[&str] = &[
    "protocol",
    "mode",
    "baud",
    "parity",
    "data_bits",
    "stop_bits",
    "address",
    "timeout_ms",
    "retries",
    "start_char",
    "end_char",
    "char_timeout_ms",
    "frame_timeout_ms",
    "packed",
    "device",
];

/// The bauds of the SD120 encoding (bits 0-2, Appendix 2).
const BAUDS: [u32; 8] = [38400, 19200, 9600, 4800, 2400, 1200, 57600, 115200];

fn int(v: Val<'_>, lo: i64, hi: i64) -> Result<i64, String> {
    match v {
        Val::Int(n) if (lo..=hi).contains(&n) => Ok(n),
        Val::Int(n) => Err(format!("{n} is outside {lo}-{hi}")),
        _ => Err(format!("expected an integer {lo}-{hi}")),
    }
}

fn text<'a>(v: Val<'a>, choices: &str) -> Result<&'a str, String> {
    match v {
        Val::Str(s) => Ok(s),
        _ => Err(format!("expected one of {choices}")),
    }
}

fn choice<T: Copy>(v: Val<'_>, choices: &[(&str, T)]) -> Result<T, String> {
    let names: Vec<String> = choices.iter().map(|(n, _)| format!("\"{n}\"")).collect();
    let s = text(v, &names.join(", "))?;
    choices
        .iter()
        .find(|(n, _)| *n == s)
        .map(|(_, t)| *t)
        .ok_or_else(|| format!("`{s}`: expected one of {}", names.join(", ")))
}

impl PortConfig {
    /// Reads a port's keys (`items` as written, in order). Errors name the
    /// item (its index in `items`) and the problem. Defaults: Modbus 19200
    /// baud, 8 data bits (7 in ASCII), even parity, 1 stop bit (Appendix 7
    /// L11301); free port 9600 8N1 (L10382-10385); station 1; timeout 0
    /// (1000 ms); retries 0.
    pub fn build(port: u8, items: &[(&str, Val<'_>)]) -> Result<PortConfig, Vec<(usize, String)>> {
        let mut errors = Vec::new();
        let find = |k: &str| items.iter().position(|(key, _)| *key == k);
        let protocol = match find("protocol") {
            None => {
                errors.push((
                    usize::MAX,
                    "`protocol` is required: \"modbus-master\", \"modbus-slave\" or \"free\""
                        .into(),
                ));
                Protocol::Free
            }
            Some(i) => match text(items[i].1, "\"modbus-master\", \"modbus-slave\", \"free\"") {
                Ok("modbus-master") => Protocol::ModbusMaster,
                Ok("modbus-slave") => Protocol::ModbusSlave,
                Ok("free") => Protocol::Free,
                Ok(s) => {
                    errors.push((i, format!("protocol `{s}`: expected \"modbus-master\", \"modbus-slave\" or \"free\" (APLC programming manual §10.1; PORT0's programming protocol is not public)")));
                    Protocol::Free
                }
                Err(e) => {
                    errors.push((i, e));
                    Protocol::Free
                }
            },
        };
        let free = protocol == Protocol::Free;
        let mut c = PortConfig {
            port,
            protocol,
            mode: Mode::Rtu,
            baud: if free { 9600 } else { 19200 },
            parity: if free { Parity::None } else { Parity::Even },
            data_bits: 8,
            stop_bits: 1,
            address: 1,
            timeout_ms: 0,
            retries: 0,
            start_char: None,
            end_char: None,
            char_timeout_ms: None,
            frame_timeout_ms: None,
            packed: false,
            device: None,
        };
        let mut data_bits_set = false;
        for (i, (key, v)) in items.iter().enumerate() {
            let v = *v;
            let r: Result<(), String> = match *key {
                "protocol" => Ok(()),
                "mode" => choice(v, &[("rtu", Mode::Rtu), ("ascii", Mode::Ascii)])
                    .map(|m| c.mode = m),
                "baud" => int(v, 0, i64::MAX).and_then(|n| {
                    if BAUDS.contains(&(n as u32)) {
                        c.baud = n as u32;
                        Ok(())
                    } else {
                        Err(format!("baud {n}: expected 1200, 2400, 4800, 9600, 19200, 38400, 57600 or 115200 (APLC programming manual §10.3.2, SD120)"))
                    }
                }),
                "parity" => choice(
                    v,
                    &[("none", Parity::None), ("even", Parity::Even), ("odd", Parity::Odd)],
                )
                .map(|p| c.parity = p),
                "data_bits" => int(v, 7, 8).map(|n| {
                    c.data_bits = n as u8;
                    data_bits_set = true;
                }),
                "stop_bits" => int(v, 1, 2).map(|n| c.stop_bits = n as u8),
                "address" => int(v, 1, 31).map(|n| c.address = n as u8),
                "timeout_ms" => int(v, 0, 32767).map(|n| c.timeout_ms = n as u16),
                "retries" => int(v, 0, 100).map(|n| c.retries = n as u16),
                "start_char" => int(v, 0, 255).map(|n| c.start_char = Some(n as u8)),
                "end_char" => int(v, 0, 255).map(|n| c.end_char = Some(n as u8)),
                "char_timeout_ms" => int(v, 1, 32767).map(|n| c.char_timeout_ms = Some(n as u16)),
                "frame_timeout_ms" => {
                    int(v, 1, 32767).map(|n| c.frame_timeout_ms = Some(n as u16))
                }
                "packed" => match v {
                    Val::Bool(b) => {
                        c.packed = b;
                        Ok(())
                    }
                    _ => Err("expected true or false".into()),
                },
                "device" => match v {
                    Val::Str(s) if !s.is_empty() => {
                        c.device = Some(s.to_string());
                        Ok(())
                    }
                    _ => Err("expected the path of a serial device or pty".into()),
                },
                k => Err(format!("unknown key `{k}`; expected one of {}", KEYS.join(", "))),
            };
            if let Err(e) = r {
                errors.push((i, format!("{key}: {e}")));
            }
        }
        if c.mode == Mode::Ascii && !data_bits_set {
            c.data_bits = 7; // ASCII frames have 7 data bits (L10466).
        }
        let free_keys = [
            "start_char",
            "end_char",
            "char_timeout_ms",
            "frame_timeout_ms",
            "packed",
        ];
        for (i, (key, _)) in items.iter().enumerate() {
            if !free && free_keys.contains(key) {
                errors.push((
                    i,
                    format!("{key}: a free-port setting, but the protocol is Modbus"),
                ));
            }
            if free && matches!(*key, "mode" | "timeout_ms" | "retries") {
                errors.push((
                    i,
                    format!("{key}: a Modbus setting, but the protocol is free"),
                ));
            }
        }
        if errors.is_empty() {
            Ok(c)
        } else {
            Err(errors)
        }
    }

    /// Bits per character on the line: start, data, parity, stop.
    pub fn char_bits(&self) -> u32 {
        1 + self.data_bits as u32 + (self.parity != Parity::None) as u32 + self.stop_bits as u32
    }

    /// The SD120/SD150 mode word (Appendix 2 bit layout).
    pub fn mode_word(&self) -> u16 {
        let code = BAUDS.iter().position(|b| *b == self.baud).unwrap_or(2) as u16;
        let mut w = code;
        w |= ((self.stop_bits == 2) as u16) << 3;
        w |= ((self.parity == Parity::Odd) as u16) << 4;
        w |= ((self.parity != Parity::None) as u16) << 5;
        w |= ((self.data_bits == 7) as u16) << 6;
        w |= (self.start_char.is_some() as u16) << 7;
        w |= (self.end_char.is_some() as u16) << 8;
        w |= (self.char_timeout_ms.is_some() as u16) << 9;
        w |= (self.frame_timeout_ms.is_some() as u16) << 10;
        w |= (self.packed as u16) << 12;
        w
    }

    /// The SD words this port shows: (SD number, value).
    pub fn registers(&self) -> [(u32, u16); 8] {
        let r = super::Regs::of(self.port);
        [
            (r.sd_free, self.mode_word()),
            (r.sd_free + 1, self.start_char.unwrap_or(0) as u16),
            (r.sd_free + 2, self.end_char.unwrap_or(0) as u16),
            (r.sd_free + 3, self.char_timeout_ms.unwrap_or(0)),
            (r.sd_free + 4, self.frame_timeout_ms.unwrap_or(0)),
            (r.sd_station, self.address as u16),
            (r.sd_timeout, self.timeout_ms),
            (r.sd_retries, self.retries),
        ]
    }

    /// The mailbox's protocol word (see [`super::mailbox`]).
    pub fn protocol_code(&self) -> u16 {
        match self.protocol {
            Protocol::ModbusMaster => super::mailbox::MASTER,
            Protocol::ModbusSlave => super::mailbox::SLAVE,
            Protocol::Free => super::mailbox::FREE,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_and_mode_word() {
        let c = PortConfig::build(1, &[("protocol", Val::Str("modbus-master"))]).unwrap();
        // 19200 8E1 (L11301): baud code 001, parity enable (bit 5), even.
        assert_eq!((c.baud, c.parity, c.data_bits), (19200, Parity::Even, 8));
        assert_eq!(c.mode_word(), 0b10_0001);
        assert_eq!(c.char_bits(), 11);
        let f = PortConfig::build(
            2,
            &[
                ("protocol", Val::Str("free")),
                ("end_char", Val::Int(13)),
                ("packed", Val::Bool(true)),
            ],
        )
        .unwrap();
        // 9600 8N1: code 010, end-character mode bit 8, packing bit 12.
        assert_eq!(f.mode_word(), 0b1_0001_0000_0010);
        assert_eq!(f.registers()[0], (150, f.mode_word()));
        assert_eq!(f.registers()[2], (152, 13));
    }

    #[test]
    fn errors_name_the_item() {
        let e = PortConfig::build(
            1,
            &[
                ("protocol", Val::Str("modbus-slave")),
                ("baud", Val::Int(300)),
                ("end_char", Val::Int(10)),
            ],
        )
        .unwrap_err();
        assert_eq!(e.len(), 2);
        assert_eq!(e[0].0, 1);
        assert!(e[0].1.contains("baud 300"), "{}", e[0].1);
        assert_eq!(e[1].0, 2);
        assert!(PortConfig::build(1, &[]).is_err());
    }
}
