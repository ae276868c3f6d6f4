//! The rack at run time (004 ch. 5, ch. 8, App. 3): the input refresh of the
//! slots that have inputs, the simulated intelligent function modules run at
//! END, and the interrupt requests of modules (an interrupt module's rising
//! inputs, an intelligent module's interrupt causes).

use super::*;
use softplc_ir::rack::{Module, ModuleIo, Rack, SlotType};
use std::ops::Range;

/// A module in its slot, with where its signals and buffer memory are.
#[derive(Debug)]
pub(crate) struct RackModule {
    /// Its slot in [`CpuConfig::rack`].
    pub slot: usize,
    pub module: Box<dyn Module>,
    /// Its X and Y numbers (clipped to the CPU's X/Y points).
    pub io: Range<usize>,
    /// Its buffer memory: flat word indices.
    pub buffer: Range<usize>,
    /// Its interrupt causes → pointers (I50-I255).
    pub pointers: Box<[(u32, u32)]>,
    /// Its auto refresh at END.
    pub refresh: Box<[Refresh]>,
}

/// One auto refresh ([`softplc_ir::rack::AutoRefresh`]) in flat word
/// indices.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Refresh {
    pub buffer: usize,
    pub device: usize,
    pub words: usize,
    /// Module → CPU.
    pub to_cpu: bool,
}

impl Refresh {
    /// Copies it in its direction when that is `to_cpu`.
    fn run(&self, words: &mut [u16], to_cpu: bool) {
        if self.to_cpu != to_cpu {
            return;
        }
        let n = self.words;
        if to_cpu {
            words.copy_within(self.buffer..self.buffer + n, self.device);
        } else {
            words.copy_within(self.device..self.device + n, self.buffer);
        }
    }
}

/// The interrupt module's inputs: X numbers and the pointer of the first.
#[derive(Clone, Debug)]
pub(crate) struct InterruptInputs {
    pub io: Range<usize>,
    pub first_pointer: u32,
}

/// What the engine keeps of the rack.
#[derive(Debug, Default)]
pub(crate) struct RackState {
    pub modules: Vec<RackModule>,
    pub interrupt_inputs: Option<InterruptInputs>,
    /// The interrupt module's inputs at the previous input refresh.
    pub previous: u64,
}

impl RackState {
    /// Each module's own state and the interrupt module's inputs, in a
    /// state file.
    pub fn snapshot(&mut self, s: &mut softplc_ir::snapshot::Snap) {
        s.u64(&mut self.previous);
        if !s.same_len(self.modules.len()) {
            return;
        }
        for m in &mut self.modules {
            // Each module's state after its slot number, which must match.
            if s.same_len(m.slot) {
                m.module.snapshot(s);
            }
        }
    }

    /// The modules of `rack` in a memory of `map` with `x` input points.
    pub fn new(rack: &Rack, mem: &DeviceMemory) -> RackState {
        let x = mem.map.points(DeviceKind::X) as usize;
        let io = |s: &softplc_ir::rack::Slot| {
            let r = s.io();
            (r.start as usize).min(x)..(r.end as usize).min(x)
        };
        let g = mem.map.base(DeviceKind::G) as usize;
        let mut state = RackState::default();
        for (i, s) in rack.slots.iter().enumerate() {
            let Some(profile) = s.module else { continue };
            // In a multi-CPU system only the control CPU runs a module.
            if !s.controlled_by(mem.map.own_cpu()) {
                continue;
            }
            if s.kind == SlotType::Interrupt {
                if let Some(p) = &profile.pointers {
                    state.interrupt_inputs = Some(InterruptInputs {
                        io: io(s),
                        first_pointer: p.start,
                    });
                }
                continue;
            }
            let buffer = match mem.map.unit(s.unit()) {
                Some(w) => g + w.first as usize..g + (w.first + w.words) as usize,
                None => 0..0,
            };
            // Checked at load: inside the buffer memory and the device.
            let refresh = s
                .refresh
                .iter()
                .filter_map(|r| {
                    let dev = mem.map.index(r.device, r.number)? as usize;
                    let at = buffer.start + r.buffer as usize;
                    (at + r.words as usize <= buffer.end).then_some(Refresh {
                        buffer: at,
                        device: dev,
                        words: r.words as usize,
                        to_cpu: r.to_cpu,
                    })
                })
                .collect();
            state.modules.push(RackModule {
                slot: i,
                module: (profile.new)(s),
                io: io(s),
                buffer,
                pointers: s.interrupts.clone().into_boxed_slice(),
                refresh,
            });
        }
        state
    }
}

/// The X numbers the input refresh copies from the input image: every X
/// without a rack, else the slots that have inputs.
pub(crate) fn input_spans(rack: &Rack, x_points: u32) -> Box<[(u32, u32)]> {
    if rack.is_empty() {
        return Box::new([(0, x_points)]);
    }
    rack.slots
        .iter()
        .filter(|s| s.kind.has_inputs() && s.points > 0)
        .filter_map(|s| {
            let r = s.io();
            (r.start < x_points).then(|| (r.start, r.end.min(x_points) - r.start))
        })
        .collect()
}

impl Cpu {
    /// Power-on and RESET of the modules: their initial buffer memory and
    /// signals.
    pub(super) fn modules_power_on(&mut self) {
        let rt = &mut self.rt;
        let y = rt.mem.map.base(DeviceKind::Y) as usize;
        for m in &mut self.rack.modules {
            let mut io = ModuleIo {
                buffer: &mut rt.mem.words[m.buffer.clone()],
                x: &mut rt.inputs[m.io.clone()],
                y: &rt.mem.bits[y + m.io.start..y + m.io.end],
                raised: 0,
                running: false,
            };
            m.module.power_on(&mut io);
            if !m.io.is_empty() {
                rt.x_holds_image = false;
            }
        }
        self.rack.previous = 0;
    }

    /// The modules' END: the auto refresh CPU → module, each module sees its
    /// Y outputs and buffer memory and updates them, the auto refresh module
    /// → CPU; the causes they raise request their interrupt pointers.
    pub(super) fn modules_end(&mut self, now: u64) {
        // In STOP the outputs are OFF outside (`Cpu::output`); Y device memory
        // keeps its values, so the modules are told.
        let running = self.state != CpuState::Stop;
        let rt = &mut self.rt;
        let y = rt.mem.map.base(DeviceKind::Y) as usize;
        for m in &mut self.rack.modules {
            for r in m.refresh.iter() {
                r.run(&mut rt.mem.words, false);
            }
            let mut io = ModuleIo {
                buffer: &mut rt.mem.words[m.buffer.clone()],
                x: &mut rt.inputs[m.io.clone()],
                y: &rt.mem.bits[y + m.io.start..y + m.io.end],
                raised: 0,
                running,
            };
            m.module.end(&mut io, now);
            let raised = io.raised;
            if !m.io.is_empty() {
                // The module may have changed its inputs in the image.
                rt.x_holds_image = false;
            }
            for r in m.refresh.iter() {
                r.run(&mut rt.mem.words, true);
            }
            if raised != 0 {
                for &(cause, pointer) in m.pointers.iter() {
                    if cause < 64 && raised >> cause & 1 != 0 {
                        rt.requests.set(pointer);
                    }
                }
            }
        }
    }

    /// After the input refresh: a rising input of the interrupt module
    /// requests its pointer (I0-I15, App. 3).
    pub(super) fn interrupt_module_edges(&mut self) {
        let Some(ii) = &self.rack.interrupt_inputs else {
            return;
        };
        let xb = self.rt.mem.map.base(DeviceKind::X) as usize;
        let mut now = 0u64;
        for (k, b) in self.rt.mem.bits[xb + ii.io.start..xb + ii.io.end]
            .iter()
            .enumerate()
        {
            now |= (*b as u64) << k;
        }
        let rising = now & !self.rack.previous;
        self.rack.previous = now;
        let first = ii.first_pointer;
        for k in 0..64 {
            if rising >> k & 1 != 0 {
                self.rt.requests.set(first + k);
            }
        }
    }

    /// The simulated module in slot `slot` (a plant model's channels).
    pub fn module_mut(&mut self, slot: usize) -> Option<&mut dyn Module> {
        self.rack
            .modules
            .iter_mut()
            .find(|m| m.slot == slot)
            .map(|m| &mut *m.module as &mut dyn Module)
    }

    /// The module in slot `slot`.
    pub fn module(&self, slot: usize) -> Option<&dyn Module> {
        self.rack
            .modules
            .iter()
            .find(|m| m.slot == slot)
            .map(|m| &*m.module as &dyn Module)
    }

    /// The rack the CPU was configured with.
    pub fn rack(&self) -> &Rack {
        &self.cfg.rack
    }
}
