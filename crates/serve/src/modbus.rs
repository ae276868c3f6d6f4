//! The Modbus TCP server (contract §3): frames are decoded by `softplc-modbus`
//! and served at END processing against the CPU, with one slave state (unit id,
//! FC 08 diagnostic counters) shared by all connections. Listen-only mode
//! (FC 08 sub-function 04) is per connection on TCP: it silences only the
//! connection that asked for it (until its 08/01 restart), never the others.

use std::sync::Mutex;

use softplc_modbus::{decode, is_write_function, Map, Proto, Slave};

use crate::engine::ServeState;
use crate::tcp::{FrameLen, Protocol};

/// A Modbus TCP server with its address map.
pub struct ModbusTcp {
    pub map: Map,
    /// The slave state, shared by all connections (kept in the engine thread).
    pub slave: Mutex<Slave>,
}

impl ModbusTcp {
    pub fn new(map: Map, slave: Slave) -> Self {
        ModbusTcp {
            map,
            slave: Mutex::new(slave),
        }
    }
}

/// Per-connection state: this connection's listen-only mode.
#[derive(Debug, Default)]
pub struct ModbusSession {
    listen_only: bool,
}

impl Protocol for ModbusTcp {
    type Session = ModbusSession;

    fn session(&self, _peer: Option<std::net::SocketAddr>) -> ModbusSession {
        ModbusSession::default()
    }

    fn frame_len(&self, buf: &[u8]) -> FrameLen {
        match decode(Proto::Tcp, buf) {
            Ok(Some((_, used))) => FrameLen::Frame(used),
            Ok(None) => FrameLen::More,
            // An MBAP header that is not Modbus: close the connection.
            Err(_) => FrameLen::Garbage(None),
        }
    }

    fn serve(
        &self,
        frame: &[u8],
        session: &mut ModbusSession,
        s: &mut ServeState,
    ) -> Option<Vec<u8>> {
        let (frame, _) = decode(Proto::Tcp, frame).ok().flatten()?;
        if is_write_function(frame.function()) {
            s.mark_wrote(0);
        }
        // The lock is only ever taken on the engine thread: never contended.
        let mut slave = self.slave.lock().ok()?;
        // The slave's listen-only flag is this connection's for this request.
        slave.listen_only = session.listen_only;
        let reply = softplc_modbus::serve(&mut slave, &self.map, &frame, s.cpu_mut());
        session.listen_only = std::mem::take(&mut slave.listen_only);
        reply
    }

    /// Exception 06 (slave device busy) when the request queue is full.
    fn busy(&self, frame: &[u8]) -> Option<Vec<u8>> {
        let (mut f, _) = decode(Proto::Tcp, frame).ok().flatten()?;
        let fc = *f.pdu.first()?;
        f.pdu = vec![fc | 0x80, 0x06];
        Some(f.encode())
    }

    fn door(&self) -> &'static str {
        "Modbus TCP"
    }
}
