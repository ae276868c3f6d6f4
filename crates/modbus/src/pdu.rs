//! Request PDUs (function code + data) and exception codes.

use std::fmt;

/// Modbus exception codes a slave sends (spec/aplc.md §6.5; Modbus application
/// protocol V1.1b3 §7).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum Exception {
    /// 01: function code not supported, or not allowed now (read-only slave).
    IllegalFunction = 1,
    /// 02: address outside the map, or a range that runs past a mapped area.
    IllegalDataAddress = 2,
    /// 03: bad quantity, byte count, coil value or PDU length.
    IllegalDataValue = 3,
    /// 04: the map is valid but the CPU lacks the devices (device setting smaller
    /// than the map).
    ServerDeviceFailure = 4,
}

impl Exception {
    pub fn code(self) -> u8 {
        self as u8
    }

    /// Exception response PDU for function `fc`.
    pub fn pdu(self, fc: u8) -> Vec<u8> {
        vec![fc | 0x80, self.code()]
    }
}

impl fmt::Display for Exception {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = match self {
            Exception::IllegalFunction => "illegal function",
            Exception::IllegalDataAddress => "illegal data address",
            Exception::IllegalDataValue => "illegal data value",
            Exception::ServerDeviceFailure => "server device failure",
        };
        write!(f, "{:02X} {name}", self.code())
    }
}

/// A parsed request PDU. Quantities are as sent; their limits depend on the map
/// ([`crate::Limits`]) and are checked when the request is served.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Request {
    /// FC 01.
    ReadCoils { address: u16, quantity: u16 },
    /// FC 02.
    ReadDiscreteInputs { address: u16, quantity: u16 },
    /// FC 03.
    ReadHoldingRegisters { address: u16, quantity: u16 },
    /// FC 04.
    ReadInputRegisters { address: u16, quantity: u16 },
    /// FC 05; `value` is FF00 (ON) or 0000 (OFF) in a valid request.
    WriteSingleCoil { address: u16, value: u16 },
    /// FC 06.
    WriteSingleRegister { address: u16, value: u16 },
    /// FC 08; `data` is everything after the sub-function.
    Diagnostics { sub: u16, data: Vec<u8> },
    /// FC 15; `bits` holds ⌈quantity/8⌉ bytes, LSB first.
    WriteMultipleCoils {
        address: u16,
        quantity: u16,
        bits: Vec<u8>,
    },
    /// FC 16; one value per register.
    WriteMultipleRegisters { address: u16, values: Vec<u16> },
    /// FC 22: register = (register AND and_mask) OR (or_mask AND NOT and_mask).
    MaskWriteRegister {
        address: u16,
        and_mask: u16,
        or_mask: u16,
    },
    /// FC 23: the write is done before the read.
    ReadWriteMultipleRegisters {
        read_address: u16,
        read_quantity: u16,
        write_address: u16,
        values: Vec<u16>,
    },
}

fn be(p: &[u8], at: usize) -> u16 {
    u16::from_be_bytes([p[at], p[at + 1]])
}

fn words(data: &[u8]) -> Vec<u16> {
    data.chunks_exact(2)
        .map(|c| u16::from_be_bytes([c[0], c[1]]))
        .collect()
}

impl Request {
    /// Parses a PDU. An unknown function code is exception 01; a PDU whose length
    /// or byte count does not fit its function is exception 03.
    pub fn parse(pdu: &[u8]) -> Result<Request, Exception> {
        use Exception::{IllegalDataValue as Bad, IllegalFunction};
        let Some(&fc) = pdu.first() else {
            return Err(IllegalFunction);
        };
        let exact = |n: usize| if pdu.len() == n { Ok(()) } else { Err(Bad) };
        Ok(match fc {
            1..=6 => {
                exact(5)?;
                let (address, q) = (be(pdu, 1), be(pdu, 3));
                match fc {
                    1 => Request::ReadCoils {
                        address,
                        quantity: q,
                    },
                    2 => Request::ReadDiscreteInputs {
                        address,
                        quantity: q,
                    },
                    3 => Request::ReadHoldingRegisters {
                        address,
                        quantity: q,
                    },
                    4 => Request::ReadInputRegisters {
                        address,
                        quantity: q,
                    },
                    5 => Request::WriteSingleCoil { address, value: q },
                    _ => Request::WriteSingleRegister { address, value: q },
                }
            }
            8 => {
                if pdu.len() < 3 {
                    return Err(Bad);
                }
                Request::Diagnostics {
                    sub: be(pdu, 1),
                    data: pdu[3..].to_vec(),
                }
            }
            15 | 16 => {
                if pdu.len() < 6 {
                    return Err(Bad);
                }
                let (address, quantity, count) = (be(pdu, 1), be(pdu, 3), pdu[5] as usize);
                exact(6 + count)?;
                let data = &pdu[6..];
                if fc == 15 {
                    if count != (quantity as usize).div_ceil(8) {
                        return Err(Bad);
                    }
                    Request::WriteMultipleCoils {
                        address,
                        quantity,
                        bits: data.to_vec(),
                    }
                } else {
                    if count != 2 * quantity as usize {
                        return Err(Bad);
                    }
                    Request::WriteMultipleRegisters {
                        address,
                        values: words(data),
                    }
                }
            }
            22 => {
                exact(7)?;
                Request::MaskWriteRegister {
                    address: be(pdu, 1),
                    and_mask: be(pdu, 3),
                    or_mask: be(pdu, 5),
                }
            }
            23 => {
                if pdu.len() < 10 {
                    return Err(Bad);
                }
                let count = pdu[9] as usize;
                exact(10 + count)?;
                if count != 2 * be(pdu, 7) as usize {
                    return Err(Bad);
                }
                Request::ReadWriteMultipleRegisters {
                    read_address: be(pdu, 1),
                    read_quantity: be(pdu, 3),
                    write_address: be(pdu, 5),
                    values: words(&pdu[10..]),
                }
            }
            _ => return Err(IllegalFunction),
        })
    }

    pub fn function(&self) -> u8 {
        match self {
            Request::ReadCoils { .. } => 1,
            Request::ReadDiscreteInputs { .. } => 2,
            Request::ReadHoldingRegisters { .. } => 3,
            Request::ReadInputRegisters { .. } => 4,
            Request::WriteSingleCoil { .. } => 5,
            Request::WriteSingleRegister { .. } => 6,
            Request::Diagnostics { .. } => 8,
            Request::WriteMultipleCoils { .. } => 15,
            Request::WriteMultipleRegisters { .. } => 16,
            Request::MaskWriteRegister { .. } => 22,
            Request::ReadWriteMultipleRegisters { .. } => 23,
        }
    }

    /// Whether the request changes devices (refused by a read-only slave; executed
    /// when broadcast).
    pub fn writes(&self) -> bool {
        is_write_function(self.function())
    }

    /// The PDU bytes (what a master sends).
    pub fn to_pdu(&self) -> Vec<u8> {
        let mut p = vec![self.function()];
        fn put(v: u16, p: &mut Vec<u8>) {
            p.extend_from_slice(&v.to_be_bytes());
        }
        match self {
            Request::ReadCoils { address, quantity }
            | Request::ReadDiscreteInputs { address, quantity }
            | Request::ReadHoldingRegisters { address, quantity }
            | Request::ReadInputRegisters { address, quantity } => {
                put(*address, &mut p);
                put(*quantity, &mut p);
            }
            Request::WriteSingleCoil { address, value }
            | Request::WriteSingleRegister { address, value } => {
                put(*address, &mut p);
                put(*value, &mut p);
            }
            Request::Diagnostics { sub, data } => {
                put(*sub, &mut p);
                p.extend_from_slice(data);
            }
            Request::WriteMultipleCoils {
                address,
                quantity,
                bits,
            } => {
                put(*address, &mut p);
                put(*quantity, &mut p);
                p.push(bits.len() as u8);
                p.extend_from_slice(bits);
            }
            Request::WriteMultipleRegisters { address, values } => {
                put(*address, &mut p);
                put(values.len() as u16, &mut p);
                p.push((values.len() * 2) as u8);
                for v in values {
                    put(*v, &mut p);
                }
            }
            Request::MaskWriteRegister {
                address,
                and_mask,
                or_mask,
            } => {
                put(*address, &mut p);
                put(*and_mask, &mut p);
                put(*or_mask, &mut p);
            }
            Request::ReadWriteMultipleRegisters {
                read_address,
                read_quantity,
                write_address,
                values,
            } => {
                put(*read_address, &mut p);
                put(*read_quantity, &mut p);
                put(*write_address, &mut p);
                put(values.len() as u16, &mut p);
                p.push((values.len() * 2) as u8);
                for v in values {
                    put(*v, &mut p);
                }
            }
        }
        p
    }
}

/// Function codes that write devices: 05, 06, 15, 16, 22, 23.
pub fn is_write_function(fc: u8) -> bool {
    matches!(fc, 5 | 6 | 15 | 16 | 22 | 23)
}
