//! Multi-CPU systems (004 ch. 13-19, contract §6): 2-4 MELSEC-Q CPUs, each
//! its own project, scanning in one time and exchanging data through their
//! CPU shared memories.
//!
//! Each CPU's device memory holds every installed CPU's 4096-word shared
//! memory as a `G` window (`U3E0\G…` to `U3E3\G…`): its own, which S.TO and
//! the auto refresh write, and mirrors of the others', which FROM and
//! `U3En\G` read. At each CPU's END the system ([`System::scan`]) publishes
//! that CPU's own-operation information and auto-refresh send devices into
//! its own window, copies its window (and the buffer memory of the modules
//! it controls) into the other CPUs' mirrors, and copies the other CPUs'
//! refresh areas into its devices. Another CPU therefore sees what a CPU
//! wrote as of that CPU's last END. A stop error is propagated as MULTI CPU
//! DOWN (7000) or MULTI EXE. ERROR (7010), SM244-SM247 show which CPU has
//! one, SD395 holds each CPU's number.
//!
//! Scheduling is deterministic: each CPU scans once per period (its
//! constant scan, else the driver's default), the earliest due first and
//! CPUs due at the same time in CPU-number order.

mod cpus;
mod exchange;
pub mod manifest;
pub mod names;

pub use cpus::Cpus;
pub use manifest::{is_system, SYSTEM_MANIFEST};

use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::device::{DeviceKind, MultiCpu};
use crate::engine::{Clock, Cpu};
use crate::program::{Diagnostic, Diagnostics};
use crate::project::multi_cpu::MultiCpuParams;
use crate::project::Project;
use exchange::EndPlan;
use softplc_ir::fault::Fault;

/// SD395: the own CPU number (004 L10426).
const SD_CPU_NUMBER: i64 = 395;
/// SM244-SM247: CPU 1-4 has a stop error (004 L9577-9590).
const SM_STOP_ERROR: i64 = 244;

/// One CPU of the system.
pub struct Member {
    pub cpu: Cpu,
    pub project: Project,
    /// Scan period: the project's constant scan, else the driver's default.
    period_us: u64,
    /// Time of its next scan, µs of the system's clock.
    next_due_us: u64,
    /// Its stop error was seen (and propagated).
    down: bool,
}

/// A multi-CPU system, built and powered on.
pub struct System {
    dir: PathBuf,
    members: Vec<Member>,
    plans: Vec<EndPlan>,
    params: Vec<Option<MultiCpuParams>>,
    /// Words moved through (no allocation at END).
    scratch: Box<[u16]>,
}

impl System {
    /// Loads `system.toml` and every CPU's project, compiles the programs
    /// and powers the CPUs on, each on a clock from `clock`. The parameter
    /// checks of power-on (3010, 3012) stop CPUs; they are no load error.
    pub fn load(
        path: &Path,
        clock: &mut dyn FnMut() -> Box<dyn Clock>,
    ) -> Result<System, Diagnostics> {
        let (dir, dirs) = manifest::read(path)?;
        let n = dirs.len() as u32;
        let mut projects = Vec::new();
        let mut diags = Vec::new();
        for (i, d) in dirs.iter().enumerate() {
            match crate::project::load_project(d) {
                Ok(p) if crate::profile::is_aplc(p.config.profile) => diags.push(Diagnostic {
                    file: p.manifest.display().to_string(),
                    line: 1,
                    col: 1,
                    message: format!(
                        "CPU {}: a {} cannot be part of a multi-CPU system (MELSEC-Q CPUs only)",
                        i + 1,
                        p.config.profile.model
                    ),
                }),
                Ok(p) => projects.push(p),
                Err(d) => diags.extend(d.0),
            }
        }
        if !diags.is_empty() {
            return Err(Diagnostics(diags));
        }
        let mut members = Vec::new();
        for (i, mut project) in projects.into_iter().enumerate() {
            let own = i as u32 + 1;
            let foreign = project
                .config
                .rack
                .intelligent()
                .filter(|s| s.control_cpu != own)
                .map(|s| s.unit())
                .collect();
            let refresh_words = project
                .multi_cpu
                .as_ref()
                .filter(|p| p.cpus == n)
                .map_or(0, |p| p.refresh_words(i));
            project.config.devices.set_multi_cpu(MultiCpu {
                own,
                cpus: n,
                foreign,
                refresh_words,
            });
            let cpu = project.build_cpu(clock()).map_err(|mut d| {
                for x in &mut d.0 {
                    x.message = format!("CPU {own}: {}", x.message);
                }
                d
            })?;
            members.push(Member {
                period_us: 0,
                next_due_us: 0,
                down: false,
                cpu,
                project,
            });
        }
        let params: Vec<_> = members
            .iter()
            .map(|m| m.project.multi_cpu.clone())
            .collect();
        let cpus: Vec<&Cpu> = members.iter().map(|m| &m.cpu).collect();
        let plans = exchange::plans(&cpus, &params).map_err(|e| {
            Diagnostics(vec![Diagnostic {
                file: dir.join(SYSTEM_MANIFEST).display().to_string(),
                line: 1,
                col: 1,
                message: e,
            }])
        })?;
        let mut system = System {
            dir,
            members,
            plans,
            params,
            scratch: vec![0; exchange::SCRATCH_WORDS].into_boxed_slice(),
        };
        system.power_on_checks(None);
        Ok(system)
    }

    /// The system directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Number of CPUs.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    /// CPU `i` (0-based: CPU 1 is 0).
    pub fn cpu(&self, i: usize) -> &Cpu {
        &self.members[i].cpu
    }

    pub fn cpu_mut(&mut self, i: usize) -> &mut Cpu {
        &mut self.members[i].cpu
    }

    pub fn members(&self) -> &[Member] {
        &self.members
    }

    pub fn members_mut(&mut self) -> &mut [Member] {
        &mut self.members
    }

    /// The project of CPU `i`.
    pub fn project(&self, i: usize) -> &Project {
        &self.members[i].project
    }

    /// Sets every CPU's scan period from `now_us`: its constant scan, else
    /// `default`; each first scans one period from now.
    pub fn schedule(&mut self, default: Duration, now_us: u64) {
        for m in &mut self.members {
            let p = m.cpu.config().constant_scan.unwrap_or(default);
            m.period_us = (p.as_micros() as u64).max(1);
            m.next_due_us = now_us + m.period_us;
        }
    }

    /// The CPU that scans next and when: the earliest due, CPU-number order
    /// among equals.
    pub fn next_due(&self) -> (usize, u64) {
        self.members
            .iter()
            .enumerate()
            .map(|(i, m)| (i, m.next_due_us))
            .min_by_key(|&(i, t)| (t, i))
            .unwrap_or((0, 0))
    }

    /// When CPU `i` scans next, µs.
    pub fn next_due_of(&self, i: usize) -> u64 {
        self.members[i].next_due_us
    }

    /// CPU `i`'s period, µs.
    pub fn period_us(&self, i: usize) -> u64 {
        self.members[i].period_us
    }

    /// Runs CPU `i`'s scan now (its clock must read its due time) and its
    /// END's exchange with the others; its next scan is one period later.
    pub fn scan(&mut self, i: usize) {
        let m = &mut self.members[i];
        m.cpu.scan();
        m.next_due_us += m.period_us;
        self.after_end(i);
    }

    /// Every CPU whose END falls at or before `t_us`, in time order, on the
    /// virtual clock `clock` the CPUs read; the clock then reads `t_us`.
    pub fn run_until(&mut self, t_us: u64, clock: &softplc_ir::clock::VirtualClock) {
        while self.scan_due(t_us, clock).is_some() {}
        let now = clock.now_us();
        clock.advance_us(t_us.saturating_sub(now));
    }

    /// The next scan if it is due at or before `t_us`: the virtual clock
    /// `clock` moves to its time and the CPU scans; which CPU it was.
    pub fn scan_due(
        &mut self,
        t_us: u64,
        clock: &softplc_ir::clock::VirtualClock,
    ) -> Option<usize> {
        let (i, due) = self.next_due();
        if due > t_us {
            return None;
        }
        let now = clock.now_us();
        clock.advance_us(due.saturating_sub(now));
        self.scan(i);
        Some(i)
    }

    /// The CPU (0-based) whose input image holds input X`x` as CPU `cpu`
    /// names it: the control CPU of the slot X`x` belongs to (a write to a
    /// module's input from outside sets the module's input, whichever CPU
    /// names it), else `cpu` itself.
    pub fn input_owner(&self, cpu: usize, x: u32) -> usize {
        self.members[cpu]
            .cpu
            .config()
            .rack
            .slots
            .iter()
            .find(|s| s.kind.has_inputs() && s.io().contains(&x))
            .map_or(cpu, |s| {
                (s.control_cpu as usize - 1).min(self.members.len() - 1)
            })
    }

    /// Every CPU has stopped.
    pub fn all_stopped(&self) -> bool {
        self.members
            .iter()
            .all(|m| m.cpu.state() == crate::engine::CpuState::Stop)
    }

    /// Remote RESET of CPU `i` (004 §7.6.3): accepted when CPU `i` is in
    /// STOP and its own parameter allows remote RESET; then [`Self::reset`].
    pub fn remote_reset(&mut self, i: usize) -> Result<(), crate::engine::Refusal> {
        self.members[i].cpu.remote_reset_allowed()?;
        self.reset(i).map_err(crate::engine::Refusal::StopHeld)
    }

    /// RESET of CPU `i` (accepted in STOP): CPU 1's resets the whole
    /// system; another's resets that CPU alone, and every CPU then shows
    /// MULTI CPU DOWN (004 L8521-8560).
    pub fn reset(&mut self, i: usize) -> Result<(), String> {
        if i == 0 {
            self.members[0].cpu.reset()?;
            for m in &mut self.members[1..] {
                m.cpu.set_stop();
                m.cpu.reset()?;
            }
            self.power_on_checks(None);
        } else {
            self.members[i].cpu.reset()?;
            self.power_on_checks(Some(i));
            for (j, m) in self.members.iter_mut().enumerate() {
                if j != i || !m.cpu.has_stop_error() {
                    m.cpu.raise_by_cpu(Fault::MultiCpuDown, i as u32 + 1);
                }
                m.down = true;
            }
            self.show_stop_errors();
        }
        Ok(())
    }

    /// The system's state in a state file: each CPU's (CPU 1 first, each a
    /// section `CPU1`…), then each one's scan period, next scan and whether
    /// its stop error was seen.
    pub(crate) fn snapshot(&mut self, s: &mut crate::engine::Snap) {
        const TAGS: [[u8; 4]; 4] = [*b"CPU1", *b"CPU2", *b"CPU3", *b"CPU4"];
        for (m, tag) in self.members.iter_mut().zip(TAGS) {
            s.section(tag, "CPU", |s| m.cpu.snapshot(s));
        }
        s.section(*b"SYST", "multi-CPU system", |s| {
            for m in &mut self.members {
                s.u64(&mut m.period_us);
                s.u64(&mut m.next_due_us);
                s.bool(&mut m.down);
            }
        });
    }

    /// Power-on (and RESET) of CPUs: SD395, the parameter checks against
    /// CPU 1 (3010, 3012; 004 L8481-8520), the stop-error relays. `only`:
    /// just that CPU was reset.
    fn power_on_checks(&mut self, only: Option<usize>) {
        let n = self.members.len() as u32;
        let first = self.params[0].clone();
        let first_rack = rack_key(&self.members[0].cpu);
        let count_ok = self
            .params
            .iter()
            .all(|p| p.as_ref().is_some_and(|p| p.cpus == n));
        for (i, m) in self.members.iter_mut().enumerate() {
            if only.is_some_and(|o| o != i) {
                continue;
            }
            let _ = m.cpu.set_word(DeviceKind::SD, SD_CPU_NUMBER, i as u16 + 1);
            m.down = false;
            if !count_ok {
                m.cpu.raise(Fault::CpuCount);
            } else if i > 0 {
                let same = match (&first, &self.params[i]) {
                    (Some(a), Some(b)) => a.consistent_with(b),
                    _ => false,
                };
                if !same || rack_key(&m.cpu) != first_rack {
                    m.cpu.raise(Fault::MultiCpuParameter);
                }
            }
        }
        // Parameter errors stop their CPUs: propagate as any stop error.
        for i in 0..self.members.len() {
            self.propagate(i);
        }
        self.show_stop_errors();
    }

    /// CPU `i`'s END: the exchange with the other CPUs, then what its stop
    /// error (if new) does to them.
    fn after_end(&mut self, i: usize) {
        let stopped = self.members[i].cpu.has_stop_error();
        let plan = &self.plans[i];
        let scratch = &mut self.scratch;
        let cpu = &mut self.members[i].cpu;
        // The own-operation information, a stopped CPU's error included.
        for c in &plan.own_info {
            copy(scratch, cpu, None, c);
        }
        let _ = cpu.write_span_words(&plan.valid, &[1]);
        // No auto refresh after a stop error: the others keep the last data
        // (L8759-8766).
        if !stopped {
            for c in &plan.publish {
                copy(scratch, cpu, None, c);
            }
        }
        for (j, c) in &plan.mirror {
            let (from, to) = pair(&mut self.members, i, *j);
            copy(scratch, from, Some(to), c);
        }
        for &(j, first, points, input) in &plan.io {
            let (from, to) = pair(&mut self.members, i, j);
            for x in first..first + points {
                if input {
                    to.set_input(x, from.input(x));
                } else {
                    let on = from.output(x);
                    let _ = to.set_bit(DeviceKind::Y, x as i64, on);
                }
            }
        }
        if !stopped {
            let cpu = &mut self.members[i].cpu;
            for c in &plan.import {
                copy(scratch, cpu, None, c);
            }
        }
        if stopped && !self.members[i].down {
            self.propagate(i);
            self.show_stop_errors();
        }
    }

    /// A new stop error of CPU `i`: CPU 1's stops every CPU with MULTI CPU
    /// DOWN; CPU 2-4's too when its operation mode says all stop, else the
    /// others go on with MULTI EXE. ERROR (004 L8521-8598). The CPU where
    /// the error began keeps its code; a CPU already stopped keeps its own.
    fn propagate(&mut self, i: usize) {
        if !self.members[i].cpu.has_stop_error() || self.members[i].down {
            return;
        }
        self.members[i].down = true;
        let all_stop = i == 0
            || self.params[0]
                .as_ref()
                .is_none_or(|p| p.stop_all.get(i).copied().unwrap_or(true));
        let fault = if all_stop {
            Fault::MultiCpuDown
        } else {
            Fault::MultiCpuError
        };
        for (j, m) in self.members.iter_mut().enumerate() {
            if j == i || m.cpu.has_stop_error() {
                continue;
            }
            m.cpu.raise_by_cpu(fault, i as u32 + 1);
            if all_stop {
                // Stopped by the system: not a cause to propagate again.
                m.down = true;
            }
        }
    }

    /// SM244-SM247 in every CPU: which CPUs have a stop error.
    fn show_stop_errors(&mut self) {
        let down: Vec<bool> = self
            .members
            .iter()
            .map(|m| m.cpu.has_stop_error())
            .collect();
        for m in &mut self.members {
            for (k, &d) in down.iter().enumerate() {
                let _ = m.cpu.set_bit(DeviceKind::SM, SM_STOP_ERROR + k as i64, d);
            }
        }
    }
}

/// A slot as the consistency check compares it: index, type, points,
/// start, module and control CPU.
type SlotKey = (u32, &'static str, u32, u32, Option<&'static str>, u32);

/// What of the I/O assignment must be the same in every CPU: each slot's
/// place, type, points, module and control CPU (004 L8500-8512).
fn rack_key(cpu: &Cpu) -> Vec<SlotKey> {
    cpu.config()
        .rack
        .slots
        .iter()
        .map(|s| {
            (
                s.index,
                s.kind.name(),
                s.points,
                s.start,
                s.module.map(|m| m.name),
                s.control_cpu,
            )
        })
        .collect()
}

/// CPUs `i` and `j` (different) at once.
fn pair(members: &mut [Member], i: usize, j: usize) -> (&mut Cpu, &mut Cpu) {
    if i < j {
        let (a, b) = members.split_at_mut(j);
        (&mut a[i].cpu, &mut b[0].cpu)
    } else {
        let (a, b) = members.split_at_mut(i);
        (&mut b[0].cpu, &mut a[j].cpu)
    }
}

/// One planned copy through the CPUs' doors: from `from` to `to` (or
/// within `from`).
fn copy(scratch: &mut [u16], from: &mut Cpu, to: Option<&mut Cpu>, c: &exchange::Copy) {
    let buf = &mut scratch[..c.words];
    if from.memory().read_span_into(&c.from, buf).is_err() {
        return;
    }
    let target = match to {
        Some(t) => t,
        None => from,
    };
    // Spans were resolved against these CPUs' memories: the write holds.
    let _ = target.write_span_words(&c.to, buf);
}
