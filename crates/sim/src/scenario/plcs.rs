//! The PLCs a scenario runs, in one virtual time: one PLC (a CPU or a
//! multi-CPU system) or a fleet's (`[[plc]]`). CPUs are numbered flat,
//! the first PLC's first ([`Layout`]); each PLC scans at its own period,
//! earliest due first and PLCs due at the same time in `[[plc]]` order,
//! each scan followed by its APLC ports' communication phase and the
//! clients that poll it.

use softplc_core::access::DeviceSpec;
use softplc_core::engine::{Clock, Cpu, CpuState, VirtualClock};
use softplc_core::system::Cpus;

use super::client::Client;
use super::spec::Layout;

/// One PLC: its CPUs, its APLC ports and its schedule.
pub(super) struct Plc {
    pub cpus: Cpus,
    pub ports: softplc_ports::Ports,
    /// A single CPU's period and next END, µs (a system keeps its own).
    pub period_us: u64,
    pub next_due_us: u64,
}

impl Plc {
    /// When its next scan ends.
    fn next_due(&self) -> u64 {
        match &self.cpus {
            Cpus::One(_) => self.next_due_us,
            Cpus::System(sys) => sys.next_due().1,
        }
    }

    /// Its next scan (a system's earliest CPU), at the time the clock reads.
    fn scan(&mut self) {
        match &mut self.cpus {
            Cpus::One(cpu) => {
                cpu.scan();
                // The communication phase after END (L914-941).
                if !self.ports.is_empty() {
                    self.ports.after_end(cpu);
                }
                self.next_due_us += self.period_us;
            }
            Cpus::System(sys) => {
                let (i, _) = sys.next_due();
                sys.scan(i);
            }
        }
    }
}

/// Every PLC of a run.
pub struct Plcs {
    pub(super) units: Vec<Plc>,
    pub(super) layout: Layout,
    pub(super) clients: Vec<Client>,
    /// The PLC and its own CPU of each flat CPU ([`Layout::locate`], looked
    /// up once: every binding reads through it every scan).
    located: Vec<(usize, usize)>,
}

impl Plcs {
    /// The PLCs `units` as `layout` numbers their CPUs, no clients yet.
    pub(super) fn new(units: Vec<Plc>, layout: Layout) -> Plcs {
        let located = (0..layout.cpus()).map(|i| layout.locate(i)).collect();
        Plcs {
            units,
            layout,
            clients: Vec::new(),
            located,
        }
    }

    /// CPUs of every PLC.
    pub fn len(&self) -> usize {
        self.located.len()
    }

    /// CPU `i` (flat, `i < len()`).
    #[inline]
    pub fn get(&self, i: usize) -> &Cpu {
        let (u, c) = self.located[i];
        self.units[u].cpus.get(c)
    }

    #[inline]
    pub fn get_mut(&mut self, i: usize) -> &mut Cpu {
        let (u, c) = self.located[i];
        self.units[u].cpus.get_mut(c)
    }

    /// Every CPU, in flat order.
    pub fn iter(&self) -> impl Iterator<Item = &Cpu> {
        (0..self.len()).map(|i| self.get(i))
    }

    /// CPU `i` belongs to a multi-CPU system.
    pub fn in_system(&self, i: usize) -> bool {
        let (u, _) = self.located[i];
        self.units[u].cpus.system().is_some()
    }

    /// The CPU of its own PLC (0-based) that flat CPU `i` is.
    pub fn own_index(&self, i: usize) -> usize {
        self.located[i].1
    }

    /// The CPU a write from outside to `spec`, named in CPU `i`, goes to
    /// ([`Cpus::write_owner`] inside its PLC).
    pub fn write_owner(&self, i: usize, spec: &DeviceSpec) -> usize {
        let (u, c) = self.located[i];
        i - c + self.units[u].cpus.write_owner(c, spec)
    }

    /// The first CPU in STOP, if any.
    pub fn first_stopped(&self) -> Option<usize> {
        self.iter().position(|c| c.state() == CpuState::Stop)
    }

    /// Every scan that ends at or before `t_us`, earliest first (PLCs due
    /// at the same time in their order), each followed by its clients
    /// that are due; the clock then reads `t_us`.
    pub(super) fn run_until(&mut self, t_us: u64, clock: &VirtualClock) {
        // One PLC polled by no client (most scenarios): its scans in turn.
        if let ([unit], true) = (&mut self.units[..], self.clients.is_empty()) {
            loop {
                let due = unit.next_due();
                if due > t_us {
                    break;
                }
                advance_to(clock, due);
                unit.scan();
            }
            advance_to(clock, t_us);
            return;
        }
        loop {
            let mut next: Option<(u64, usize)> = None;
            for (u, p) in self.units.iter().enumerate() {
                let due = p.next_due();
                if due <= t_us && next.is_none_or(|(d, _)| due < d) {
                    next = Some((due, u));
                }
            }
            let Some((due, u)) = next else { break };
            advance_to(clock, due);
            self.units[u].scan();
            for k in 0..self.clients.len() {
                if self.clients[k].plc() == u {
                    let mut c = std::mem::take(&mut self.clients[k]);
                    c.poll(due, self);
                    self.clients[k] = c;
                }
            }
        }
        advance_to(clock, t_us);
    }
}

/// Advances `clock` to `t_us` (nothing when it reads that already: no
/// atomic write).
#[inline]
fn advance_to(clock: &VirtualClock, t_us: u64) {
    let now = clock.now_us();
    if t_us > now {
        clock.advance_us(t_us - now);
    }
}
