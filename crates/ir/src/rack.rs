//! The rack: the slots of the base units, the I/O numbers each takes and the
//! module in it (004 ch. 5 I/O numbering, ch. 8 intelligent function modules,
//! App. 3 interrupt pointers). Data and the module seam only: the project file
//! builds a [`Rack`] (softplc-core), the simulated modules implement [`Module`]
//! (softplc-modules), the engine refreshes and runs them.

use std::fmt;
use std::ops::Range;

/// What a slot holds, as the I/O assignment parameter types it (004 §5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SlotType {
    Empty,
    Input,
    Output,
    /// Mixed input/output: X and Y of the same numbers.
    Io,
    Intelligent,
    /// An interrupt module (QI60): inputs that raise I0-I15.
    Interrupt,
}

impl SlotType {
    /// The name in `plc.toml` and reports.
    pub fn name(self) -> &'static str {
        match self {
            SlotType::Empty => "empty",
            SlotType::Input => "input",
            SlotType::Output => "output",
            SlotType::Io => "io",
            SlotType::Intelligent => "intelligent",
            SlotType::Interrupt => "interrupt",
        }
    }

    /// Its X points are refreshed from the module at the input refresh.
    pub fn has_inputs(self) -> bool {
        !matches!(self, SlotType::Empty | SlotType::Output)
    }

    /// Its Y points go to the module at the output refresh.
    pub fn has_outputs(self) -> bool {
        matches!(
            self,
            SlotType::Output | SlotType::Io | SlotType::Intelligent
        )
    }
}

/// One slot of the rack, numbered from 0 (main base left to right, then the
/// extension bases).
#[derive(Clone, Debug)]
pub struct Slot {
    pub index: u32,
    pub kind: SlotType,
    /// I/O points it takes (X and Y from `start`).
    pub points: u32,
    /// Its first I/O number (a multiple of 16).
    pub start: u32,
    /// The simulated module in an intelligent or interrupt slot.
    pub module: Option<&'static ModuleProfile>,
    /// Words of its buffer memory (intelligent slots; 0 otherwise).
    pub buffer_words: u32,
    /// The interrupt pointer each of its interrupt causes raises (the
    /// intelligent function module's interrupt pointer setting, I50-I255):
    /// `(cause, pointer)`.
    pub interrupts: Vec<(u32, u32)>,
    /// Auto refresh between its buffer memory and CPU devices at END (the
    /// intelligent function module's auto refresh setting, 004 ch. 8).
    pub refresh: Vec<AutoRefresh>,
    /// The intelligent function module switch setting (switches 1-5 of the
    /// I/O assignment parameter): input/output ranges, HOLD/CLEAR, modes, as
    /// the module's manual assigns them. All 0 when the project sets none.
    pub switches: [u16; 5],
    /// The CPU of a multi-CPU system that controls the module (1-4; 1 in a
    /// single-CPU system): only it runs the module, writes its outputs and
    /// buffer memory (004 L8493-8503, L9119-9215).
    pub control_cpu: u32,
}

/// One auto-refresh setting: `words` words between buffer-memory address
/// `buffer` and the CPU's word device `device` number `number`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AutoRefresh {
    pub buffer: u32,
    pub device: crate::device::DeviceKind,
    pub number: u32,
    pub words: u32,
    /// Module → CPU (`to = "D100"`); else CPU → module (`from = "D200"`).
    pub to_cpu: bool,
}

impl Slot {
    /// Slot `index` at I/O number `start` holding `module`, with the
    /// module's points, slot type and buffer memory and nothing else set
    /// (a rack built without plc.toml: tests, tools).
    pub fn with_module(index: u32, start: u32, module: &'static ModuleProfile) -> Slot {
        Slot {
            index,
            kind: module.kind,
            points: module.points,
            start,
            module: Some(module),
            buffer_words: module.buffer_words,
            interrupts: Vec::new(),
            refresh: Vec::new(),
            switches: [0; 5],
            control_cpu: 1,
        }
    }

    /// Whether CPU `cpu` (1-4; `None` for a single CPU) controls it.
    pub fn controlled_by(&self, cpu: Option<u32>) -> bool {
        cpu.is_none_or(|c| c == self.control_cpu)
    }

    /// Its I/O numbers.
    pub fn io(&self) -> Range<u32> {
        self.start..self.start + self.points
    }

    /// Its unit number: the start I/O number without its last hex digit
    /// (`U2\G11` for a module at X/Y20).
    pub fn unit(&self) -> u32 {
        self.start >> 4
    }

    /// The name of its module, or its type.
    pub fn describe(&self) -> String {
        match self.module {
            Some(m) => format!("slot {} ({} {})", self.index, self.kind.name(), m.name),
            None => format!("slot {} ({})", self.index, self.kind.name()),
        }
    }
}

/// The base units' slots in slot order. An empty rack (no `[[slot]]` in the
/// project) leaves X and Y plain device memory, every X an input.
#[derive(Clone, Debug, Default)]
pub struct Rack {
    pub slots: Vec<Slot>,
}

impl Rack {
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }

    /// The slot whose unit number is `unit`.
    pub fn unit(&self, unit: u32) -> Option<&Slot> {
        self.slots
            .iter()
            .find(|s| s.kind != SlotType::Empty && s.points > 0 && s.unit() == unit)
    }

    /// The slots holding intelligent function modules with buffer memory.
    pub fn intelligent(&self) -> impl Iterator<Item = &Slot> {
        self.slots
            .iter()
            .filter(|s| s.kind == SlotType::Intelligent && s.buffer_words > 0)
    }

    /// Whether a configured slot can raise interrupt pointer `I<n>`
    /// (I0-I15 from an interrupt module, I50-I255 by a slot's interrupt
    /// pointer setting; App. 3).
    pub fn raises(&self, n: u32) -> bool {
        self.slots.iter().any(|s| {
            s.interrupts.iter().any(|&(_, p)| p == n)
                || s.module
                    .and_then(|m| m.pointers.clone())
                    .is_some_and(|r| r.contains(&n))
        })
    }
}

/// A profile's check of a slot's `range` names and `switches`.
pub type SwitchSetting = fn(Option<&[&str]>, Option<[u16; 5]>) -> Result<[u16; 5], String>;

/// A simulated module's profile: what `module = "…"` in a slot names.
#[derive(Debug)]
pub struct ModuleProfile {
    /// The model name (`Q64AD`), as `plc.toml` writes it.
    pub name: &'static str,
    /// The slot type it needs (intelligent or interrupt).
    pub kind: SlotType,
    /// I/O points it occupies.
    pub points: u32,
    /// Words of its buffer memory; 0 for the `generic` module, whose size
    /// the slot gives.
    pub buffer_words: u32,
    /// The interrupt pointers it raises itself (a QI60: I0-I15).
    pub pointers: Option<Range<u32>>,
    /// How many interrupt causes it has for the interrupt pointer setting
    /// (I50-I255); 0 for none.
    pub causes: u32,
    /// The manual it follows, by title and number.
    pub manual: &'static str,
    /// A new module of this profile in `slot`.
    pub new: fn(&Slot) -> Box<dyn Module>,
    /// Checks a slot's analog `range` names and `switches` (the switch
    /// setting 1-5) and gives the switch setting; `None`: a module without
    /// analog ranges, which takes any switches.
    pub switches: Option<SwitchSetting>,
}

/// What a module sees and changes at END: its buffer memory, its input
/// signals (X) as the next input refresh reads them, its output signals (Y)
/// as the output refresh gave them.
pub struct ModuleIo<'a> {
    pub buffer: &'a mut [u16],
    pub x: &'a mut [bool],
    pub y: &'a [bool],
    /// Interrupt causes it raised: bit k is cause k.
    pub raised: u64,
    /// The CPU is in RUN or PAUSE. False in STOP (a stop error included),
    /// when the outputs are OFF: an analog output module then clears or
    /// holds its outputs as its HOLD/CLEAR setting says.
    pub running: bool,
}

/// A simulated intelligent function module. It runs between scans, at END
/// after the output refresh, in the CPU's time: no threads, no wall clock.
pub trait Module: Send + fmt::Debug {
    /// Power-on and RESET: the module's initial buffer memory and signals.
    fn power_on(&mut self, io: &mut ModuleIo<'_>);
    /// Once a scan, at END: the module takes its Y outputs and the buffer
    /// memory the program wrote, and updates its buffer memory and X
    /// signals; `now_us` is the CPU's clock.
    fn end(&mut self, io: &mut ModuleIo<'_>, now_us: u64);
    /// The module's own state in a state file, besides its buffer memory
    /// and signals (which are device memory): walked to save, check and
    /// load it ([`crate::snapshot::Snap`]). A module that keeps none (plain
    /// buffer memory) walks nothing.
    fn snapshot(&mut self, s: &mut crate::snapshot::Snap) {
        let _ = s;
    }
    /// A channel's physical value from outside (a plant model or a
    /// scenario): mA or V at an analog input. Channels count from 1, as
    /// the manuals' CH1.
    fn set_channel(&mut self, channel: u32, value: f64) -> Result<(), String> {
        let _ = value;
        Err(format!("this module has no input channel {channel}"))
    }
    /// A channel's physical value as the module outputs it (an analog
    /// output's V or mA), `None` for no such channel.
    fn channel(&self, channel: u32) -> Option<f64> {
        let _ = channel;
        None
    }
}
