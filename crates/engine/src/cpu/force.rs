//! Forced ON/OFF of X and Y (the web monitor's forcing, contract §3.1; 004
//! §7.9.3 forced ON/OFF of external I/O).
//!
//! A forced input is written over X after the input refresh, before the
//! programs; a forced output is written over Y after the programs (before the
//! output refresh), the programs themselves computing from Y's value under the
//! force; both are written again after every write through the
//! [`door`](super::door), so a forced value wins over the program and over
//! external writes. The value the device would have without the force (the
//! input image for X, the program's or an external write's last value for Y) is
//! kept and takes effect at release. Forces live only in the CPU: power-off and
//! RESET release them all (docs/forcing.md).
//!
//! With nothing forced the scan pays one `is_empty` test.

use super::*;

/// One forced device.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Force {
    pub kind: DeviceKind,
    pub n: u32,
    /// Index in the flat bit memory.
    pub bit: usize,
    pub on: bool,
    /// The value the device would have without the force.
    pub under: bool,
}

impl Cpu {
    /// Devices that can be forced at once: the model's registrations
    /// (32 on MELSEC-Q, the 33rd refused, 004 §7.9.3).
    pub fn max_forces(&self) -> usize {
        self.profile().max_forces
    }

    /// Forces X`n` or Y`n` ON or OFF until [`Self::release`] (or power-off,
    /// RESET). Errors for another device kind, a point beyond the CPU's X/Y
    /// points or more devices than the model registers
    /// ([`Self::max_forces`]).
    pub fn force(&mut self, kind: DeviceKind, n: u32, on: bool) -> Result<(), String> {
        self.rt.x_touched();
        if !matches!(kind, DeviceKind::X | DeviceKind::Y) {
            return Err(format!("only X and Y can be forced, not {kind:?}"));
        }
        if n >= self.rt.mem.map.points(kind) {
            return Err(format!(
                "{kind:?}{n:X} is beyond the CPU's {} points",
                self.rt.mem.map.points(kind)
            ));
        }
        let bit = self.rt.mem.map.base(kind) as usize + n as usize;
        match self.rt.forces.iter_mut().find(|f| f.bit == bit) {
            Some(f) => f.on = on,
            None => {
                let max = self.max_forces();
                if self.rt.forces.len() >= max {
                    return Err(format!(
                        "at most {max} devices can be forced on a {} (release one first)",
                        self.profile().model
                    ));
                }
                let under = self.rt.mem.bits[bit];
                self.rt.forces.push(Force {
                    kind,
                    n,
                    bit,
                    on,
                    under,
                });
            }
        }
        self.rt.mem.bits[bit] = on;
        self.note(DoorEvent::Force { kind, n, on });
        Ok(())
    }

    /// Releases the force of X`n`/Y`n` (nothing if it is not forced): the
    /// device takes the value it would have had without it. True when it was forced.
    pub fn release(&mut self, kind: DeviceKind, n: u32) -> bool {
        self.rt.x_touched();
        let Some(i) = self
            .rt
            .forces
            .iter()
            .position(|f| f.kind == kind && f.n == n)
        else {
            return false;
        };
        let f = self.rt.forces.swap_remove(i);
        self.rt.mem.bits[f.bit] = match kind {
            DeviceKind::X => self.rt.inputs.get(n as usize).copied().unwrap_or(f.under),
            _ => f.under,
        };
        self.note(DoorEvent::Release { kind, n });
        true
    }

    /// Releases every force.
    pub fn release_all(&mut self) {
        self.rt.x_touched();
        self.untold(|cpu| {
            while let Some(f) = cpu.rt.forces.last().copied() {
                cpu.release(f.kind, f.n);
            }
        });
        self.note(DoorEvent::ReleaseAll);
    }

    /// The forced devices: (kind, number, value), in the order they were forced.
    pub fn forced(&self) -> impl Iterator<Item = (DeviceKind, u32, bool)> + '_ {
        self.rt.forces.iter().map(|f| (f.kind, f.n, f.on))
    }

    /// Writes the forced values of `kind` over device memory. What was there is
    /// the value under the force (the input image after the input refresh, the
    /// program's result after the programs).
    pub(super) fn apply_forces(&mut self, kind: DeviceKind) {
        self.rt.apply_forces(kind);
    }

    /// Before the programs: forced outputs go back to their values under the
    /// force, so the program computes from its own results (a self-holding
    /// circuit keeps working) and a write made while forced is seen; the
    /// forced value is written again after the programs.
    pub(super) fn unforce_outputs(&mut self) {
        for f in &self.rt.forces {
            if f.kind == DeviceKind::Y {
                self.rt.mem.bits[f.bit] = f.under;
            }
        }
    }

    /// After a write from outside: forced points in `kind` `first..first+count`
    /// keep the written value as the one under the force; a write whose span is
    /// unknown (`None`, e.g. an indexed name) counts where it changed a point.
    pub(super) fn force_written(&mut self, span: Option<(DeviceKind, u32, u32)>) {
        for f in &mut self.rt.forces {
            let cur = self.rt.mem.bits[f.bit];
            let hit = match span {
                Some((k, first, count)) => k == f.kind && f.n >= first && f.n - first < count,
                None => cur != f.on,
            };
            if hit {
                f.under = cur;
            }
            self.rt.mem.bits[f.bit] = f.on;
        }
    }
}
