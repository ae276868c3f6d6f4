//! Remote operations (004 §7.6): remote RUN/STOP/PAUSE/RESET from the
//! doors' clients and the RUN-PAUSE contacts.
//!
//! - STOP has priority (§7.6.1 (3)): the key switch ([`Cpu::set_stop`]),
//!   the RUN contact and a client's remote STOP each stop the CPU, and it
//!   runs again only when none of them says STOP.
//! - One client at a time holds a remote STOP or PAUSE (§7.6.5 (2), (3)):
//!   the same client's next operation replaces it; another client's is
//!   refused until the holder cancels it with a remote RUN (or forces it,
//!   the MC protocol's "forced execution").
//! - A PAUSE, remote or by the PAUSE contact with the family's PAUSE enable
//!   ON, shows at the END of the scan that requested it (MELSEC's PAUSE
//!   status contact) and takes hold at the next END (§7.6.2); the contact
//!   dropped, the CPU runs again from step 0.
//! - Remote RESET only in STOP and only when the parameter allows it
//!   (§7.6.3, not by default).

use std::fmt;

use super::*;
use softplc_ir::system::{Cause, Panel, Remote, Status};

/// A remote operation a client holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Hold {
    Stop,
    Pause,
}

/// Why a remote operation was refused.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Refusal {
    /// Another client holds a remote STOP or PAUSE (004 §7.6.5 (3)).
    Held { by: u32, hold: Hold },
    /// RESET outside STOP (004 §7.6.3 (3) (b)).
    NotStopped,
    /// PAUSE is possible only from RUN.
    Stopped,
    /// The parameter does not allow remote RESET (004 §7.6.3 (3) (a)).
    ResetDisabled,
    /// RUN while another source still says STOP, or a stop error holds.
    StopHeld(String),
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Refusal::Held { hold, .. } => write!(
                f,
                "another client holds a remote {}; it must cancel it with a remote RUN first",
                match hold {
                    Hold::Stop => "STOP",
                    Hold::Pause => "PAUSE",
                }
            ),
            Refusal::NotStopped => f.write_str("RESET is accepted only in STOP"),
            Refusal::Stopped => f.write_str("PAUSE is possible only from RUN"),
            Refusal::ResetDisabled => f.write_str(
                "remote RESET is not allowed by the PLC parameter ([ras] remote_reset = false)",
            ),
            Refusal::StopHeld(why) => f.write_str(why),
        }
    }
}

/// The STOP and PAUSE sources besides the CPU's own (errors, STOP
/// instruction).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct RemoteState {
    /// The key switch is at STOP ([`Cpu::set_stop`] until [`Cpu::set_run`]).
    switch_stop: bool,
    /// The RUN contact was ON at the last END.
    contact_stop: bool,
    /// The client holding a remote STOP or PAUSE.
    held: Option<(u32, Hold)>,
    /// A PAUSE was requested at an END: the CPU pauses at the next END.
    pause_status: bool,
}

impl RemoteState {
    /// The remote operations' state in a state file.
    pub(super) fn snapshot(&mut self, s: &mut softplc_ir::snapshot::Snap) {
        s.bool(&mut self.switch_stop);
        s.bool(&mut self.contact_stop);
        s.bool(&mut self.pause_status);
        let (mut client, mut hold) = self.held.unwrap_or((0, Hold::Stop));
        let mut held = self.held.is_some();
        s.bool(&mut held);
        s.u32(&mut client);
        s.one_of(&mut hold, &[Hold::Stop, Hold::Pause]);
        if s.loading() {
            self.held = held.then_some((client, hold));
        }
    }
}

impl Cpu {
    /// Remote RUN by `client`: cancels its remote STOP or PAUSE and runs the
    /// CPU when no other source says STOP. `force` overrides another
    /// client's hold.
    pub fn remote_run(&mut self, client: u32, force: bool) -> Result<(), Refusal> {
        self.check_holder(client, force)?;
        self.remote.held = None;
        self.run_unless_stopped().map_err(Refusal::StopHeld)
    }

    /// Remote STOP by `client` (004 §7.6.1): the CPU stops at once (requests
    /// are served between scans, after END) and stays stopped until this
    /// client's remote RUN.
    pub fn remote_stop(&mut self, client: u32, force: bool) -> Result<(), Refusal> {
        self.check_holder(client, force)?;
        self.remote.held = Some((client, Hold::Stop));
        self.enter_stop(Cause::Remote);
        Ok(())
    }

    /// Remote PAUSE by `client` (004 §7.6.2 (2) (b)): the PAUSE status shows
    /// at the next END and the CPU pauses at the END after it.
    pub fn remote_pause(&mut self, client: u32, force: bool) -> Result<(), Refusal> {
        self.check_holder(client, force)?;
        if self.state == CpuState::Stop {
            return Err(Refusal::Stopped);
        }
        self.remote.held = Some((client, Hold::Pause));
        Ok(())
    }

    /// Remote RESET (004 §7.6.3): in STOP only, and only when the parameter
    /// allows it.
    pub fn remote_reset(&mut self) -> Result<(), Refusal> {
        self.remote_reset_allowed()?;
        self.reset().map_err(Refusal::StopHeld)
    }

    /// Whether a remote RESET would be accepted now.
    pub fn remote_reset_allowed(&self) -> Result<(), Refusal> {
        if self.state != CpuState::Stop {
            return Err(Refusal::NotStopped);
        }
        if !self.cfg.remote_reset {
            return Err(Refusal::ResetDisabled);
        }
        Ok(())
    }

    /// The client holding a remote STOP or PAUSE, and which.
    pub fn remote_hold(&self) -> Option<(u32, Hold)> {
        self.remote.held
    }

    fn check_holder(&self, client: u32, force: bool) -> Result<(), Refusal> {
        match self.remote.held {
            Some((by, hold)) if by != client && !force => Err(Refusal::Held { by, hold }),
            _ => Ok(()),
        }
    }

    /// The key switch at STOP ([`Cpu::set_stop`]) or RUN ([`Cpu::set_run`]).
    pub(super) fn set_switch_stop(&mut self, stop: bool) {
        self.remote.switch_stop = stop;
        self.show_remote();
    }

    /// The source other than the CPU itself that keeps it in STOP, if any.
    pub(super) fn stop_source(&self) -> Option<String> {
        if self.remote.switch_stop {
            return Some("the key switch is at STOP".into());
        }
        if self.remote.contact_stop {
            let n = self.cfg.run_contact.unwrap_or(0);
            return Some(format!("the RUN contact (X{n:X}) is ON"));
        }
        if let Some((_, Hold::Stop)) = self.remote.held {
            return Some("a remote STOP holds; a remote RUN from its client releases it".into());
        }
        None
    }

    /// RUN from STOP or PAUSE unless a source still says STOP.
    pub(super) fn run_unless_stopped(&mut self) -> Result<(), String> {
        if self.state == CpuState::Stop {
            if let Some(why) = self.stop_source() {
                return Err(why);
            }
        }
        self.go_run()
    }

    /// Power-on and RESET: the remote operations are cancelled and the CPU
    /// follows the RUN contact from the start.
    pub(super) fn remote_power_on(&mut self) {
        self.remote = RemoteState::default();
        // Device memory was just cleared: the input module's signal.
        if self.cfg.run_contact.is_some_and(|n| self.input(n)) {
            self.remote.contact_stop = true;
            self.enter_stop(Cause::Contact);
        }
        self.show_remote();
    }

    /// STOP: a requested PAUSE is dropped.
    pub(super) fn remote_stopped(&mut self) {
        self.remote.pause_status = false;
        self.show_remote();
    }

    /// END (in every state): the RUN contact, then the PAUSE requests.
    pub(super) fn remote_end(&mut self) {
        let run_contact = self.contact(self.cfg.run_contact);
        if run_contact != self.remote.contact_stop {
            self.remote.contact_stop = run_contact;
            if run_contact {
                self.enter_stop(Cause::Contact);
            } else if self.state == CpuState::Stop && !self.stop_error {
                // The contact released: RUN unless another source says STOP.
                let _ = self.run_unless_stopped();
            }
        }
        let by_contact =
            self.contact(self.cfg.pause_contact) && self.rt.system.pause_enabled(&self.rt.mem);
        let remote = matches!(self.remote.held, Some((_, Hold::Pause)));
        let requested = by_contact || remote;
        match self.state {
            CpuState::Run if requested => {
                if self.remote.pause_status {
                    self.state = CpuState::Pause;
                    self.cause = if by_contact {
                        Cause::Contact
                    } else {
                        Cause::Remote
                    };
                    self.show_status();
                } else {
                    self.remote.pause_status = true;
                }
            }
            CpuState::Run => self.remote.pause_status = false,
            CpuState::Pause if !requested && self.remote.pause_status => {
                // Released: the program runs again from step 0.
                self.remote.pause_status = false;
                self.state = CpuState::Run;
                self.show_status();
            }
            _ => {}
        }
        self.show_remote();
    }

    /// Contact X`n` in device memory (the input as the program sees it).
    fn contact(&self, n: Option<u32>) -> bool {
        n.is_some_and(|n| {
            self.rt
                .mem
                .get_bit(DeviceKind::X, n as i64)
                .unwrap_or(false)
        })
    }

    fn show_remote(&mut self) {
        let r = Remote {
            stop_by_contact: self.remote.contact_stop && self.state == CpuState::Stop,
            pause: self.remote.pause_status,
        };
        self.rt.system.remote(&mut self.rt.mem, r);
        let status = match self.state {
            CpuState::Run => Status::Run,
            CpuState::Stop => Status::Stop(self.cause),
            CpuState::Pause => Status::Pause(self.cause),
        };
        let panel = Panel {
            status,
            switch_stop: self.remote.switch_stop,
            stop_error: self.stop_error,
            forced: !self.rt.forces.is_empty(),
        };
        let rt = &mut self.rt;
        rt.system.panel(&mut rt.mem, &mut rt.system_state, panel);
    }
}
