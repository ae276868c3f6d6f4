//! The MC protocol (SLMP) server over TCP: 3E/4E frames, binary or ASCII,
//! detected per frame (contract §3). Decoding and the commands are in
//! `softplc-mc`; this adapter cuts frames from the stream and serves them at END.

use softplc_mc::{decode_request, FrameError, Served, Session};

use crate::engine::ServeState;
use crate::tcp::{FrameLen, Protocol};

/// MC protocol server settings.
pub struct Mc {
    /// Remote password (plc.toml); `None`: no password.
    pub password: Option<String>,
}

impl Protocol for Mc {
    type Session = Session;

    fn session(&self) -> Session {
        Session::new()
    }

    fn frame_len(&self, buf: &[u8]) -> FrameLen {
        match decode_request(buf) {
            Ok((_, used)) => FrameLen::Frame(used),
            Err(FrameError::Incomplete) => FrameLen::More,
            // A delimited but wrong request is answered with its end code at END.
            Err(FrameError::Rejected(r)) => FrameLen::Frame(r.used),
            Err(FrameError::Malformed { .. }) => FrameLen::Garbage(None),
        }
    }

    fn serve(&self, frame: &[u8], session: &mut Session, s: &mut ServeState) -> Option<Vec<u8>> {
        match softplc_mc::serve(frame, &mut s.cpu, session, self.password.as_deref()) {
            Served::Reply { response, .. } => Some(response),
            Served::Incomplete | Served::Close { .. } => None,
        }
    }

    fn busy(&self, _frame: &[u8]) -> Option<Vec<u8>> {
        None
    }
}
