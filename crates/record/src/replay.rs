//! Replaying a recording in virtual time: each CPU gets a [`ReplayClock`]
//! that gives back the recorded readings in order, and [`Player::step`]
//! runs one recorded END — the scan, then the changes from outside made at
//! that END — on every CPU it is given (the recorded program's, and a
//! changed program's beside it).

use std::collections::VecDeque;
use std::io::Read;
use std::path::Path;
use std::sync::{Arc, Mutex, MutexGuard};

use softplc_core::engine::{Clock, Cpu};

use crate::event::apply;
use crate::format::{End, FormatError, Header, Reader, Record};

/// The recorded clock readings, given back in the order they were taken.
#[derive(Clone, Default)]
pub struct ReplayClock(Arc<Mutex<Readings>>);

#[derive(Default)]
struct Readings {
    queue: VecDeque<u64>,
    /// The last reading given (and the first, for the elapsed time).
    last: u64,
    first: Option<u64>,
    /// Readings asked for beyond those recorded (the replay diverged).
    short: u64,
}

impl ReplayClock {
    fn lock(&self) -> MutexGuard<'_, Readings> {
        self.0.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn push(&self, t: u64) {
        self.lock().queue.push_back(t);
    }

    /// Time from the first reading (power-on) to the last one given, µs.
    pub fn elapsed_us(&self) -> u64 {
        let g = self.lock();
        g.last - g.first.unwrap_or(g.last)
    }

    /// Readings left over and readings asked for beyond the recording.
    fn balance(&self) -> (usize, u64) {
        let g = self.lock();
        (g.queue.len(), g.short)
    }
}

impl Clock for ReplayClock {
    fn now_us(&self) -> u64 {
        let mut g = self.lock();
        match g.queue.pop_front() {
            Some(t) => {
                g.last = t;
                g.first.get_or_insert(t);
                t
            }
            None => {
                g.short += 1;
                g.last
            }
        }
    }

    fn peek_us(&self) -> u64 {
        self.lock().last
    }

    /// A replay never loads a state file (a recording stops before one).
    fn restore_us(&mut self, now_us: u64) {
        let mut g = self.lock();
        g.last = now_us;
    }
}

/// How a recording ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Ending {
    /// The server stopped after the END with this scan count.
    Shutdown { scans: u64 },
    /// `--record-max-size` was reached after this scan count.
    Full { scans: u64 },
    /// Recording stopped after this scan count before a change it cannot
    /// follow.
    Stopped { scans: u64, why: String },
    /// A torn last frame at this byte offset (the server was killed while
    /// writing it).
    Torn { at: u64 },
    /// The file ends after a whole frame without a shutdown record (the
    /// server was killed between two ENDs).
    Cut,
}

impl Ending {
    pub fn describe(&self) -> String {
        match self {
            Ending::Shutdown { scans } => format!("the server stopped after scan {scans}"),
            Ending::Full { scans } => {
                format!("the recording reached its size bound after scan {scans}")
            }
            Ending::Stopped { scans, why } => {
                format!("recording stopped after scan {scans}: {why}")
            }
            Ending::Torn { at } => format!(
                "the server was killed while writing an END (a torn frame at byte {at} was left out)"
            ),
            Ending::Cut => "the server was killed (no shutdown record)".to_string(),
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            Ending::Shutdown { .. } => "shutdown",
            Ending::Full { .. } => "full",
            Ending::Stopped { .. } => "stopped",
            Ending::Torn { .. } => "torn",
            Ending::Cut => "killed",
        }
    }
}

/// Plays a recording back, END by END.
pub struct Player<R> {
    reader: Reader<R>,
    header: Header,
    start: End,
    clocks: Vec<ReplayClock>,
    ending: Option<Ending>,
    /// ENDs played.
    ends: u64,
    /// The last reading recorded so far (readings are deltas from it).
    t: u64,
    /// The recording's name in messages.
    name: String,
}

impl Player<std::io::BufReader<std::fs::File>> {
    /// Opens a recording file.
    pub fn open(path: &Path) -> Result<Self, FormatError> {
        Player::new(Reader::open(path)?, &path.display().to_string())
    }
}

impl<R: Read> Player<R> {
    /// Reads the header and the start frame.
    pub fn new(mut reader: Reader<R>, name: &str) -> Result<Self, FormatError> {
        let short = || {
            FormatError(format!(
                "{name}: the recording ends before its first frames"
            ))
        };
        let header = match reader.read_record()? {
            Some(Record::Header(h)) => h,
            Some(_) => {
                return Err(FormatError(format!(
                    "{name}: the first frame is not the header"
                )))
            }
            None => return Err(short()),
        };
        let start = match reader.read_record()? {
            Some(Record::End(e)) if !e.scanned => e,
            Some(_) => {
                return Err(FormatError(format!(
                    "{name}: the second frame is not the start of the session"
                )))
            }
            None => return Err(short()),
        };
        let t = start.clock.iter().fold(0u64, |t, d| t.wrapping_add(*d));
        Ok(Player {
            name: name.to_string(),
            t,
            reader,
            header,
            start,
            clocks: Vec::new(),
            ending: None,
            ends: 0,
        })
    }

    pub fn header(&self) -> &Header {
        &self.header
    }

    /// A clock for one more CPU, holding the readings of the start (its
    /// power-on): create it before the CPU.
    pub fn clock(&mut self) -> ReplayClock {
        let c = ReplayClock::default();
        let mut t = 0u64;
        for d in &self.start.clock {
            t = t.wrapping_add(*d);
            c.push(t);
        }
        self.clocks.push(c.clone());
        c
    }

    /// The changes of the start (the battery-backed image, the calendar)
    /// on every CPU, in the order of [`Self::clock`]'s calls.
    pub fn start(&mut self, cpus: &mut [&mut Cpu]) -> Result<(), String> {
        for (i, cpu) in cpus.iter_mut().enumerate() {
            apply(cpu, &self.start.events)
                .map_err(|e| format!("{}: the start, CPU {}: {e}", self.name, i + 1))?;
        }
        self.check(cpus, &self.start.clone())
            .map_err(|e| format!("{}: {e}", self.name))
    }

    /// Plays the next END on every CPU; the recorded END, or `None` when
    /// the recording is over ([`Self::ending`]).
    pub fn step(&mut self, cpus: &mut [&mut Cpu]) -> Result<Option<End>, String> {
        let end = loop {
            match self.reader.read_record().map_err(|e| e.to_string())? {
                Some(Record::End(e)) => break e,
                Some(Record::Shutdown { scans }) => self.ending = Some(Ending::Shutdown { scans }),
                Some(Record::Full { scans }) => self.ending = Some(Ending::Full { scans }),
                Some(Record::Stopped { scans, why }) => {
                    self.ending = Some(Ending::Stopped { scans, why })
                }
                Some(Record::Header(_)) => {
                    return Err(format!("{}: a second header in the recording", self.name))
                }
                None => {
                    if self.ending.is_none() {
                        self.ending = Some(match self.reader.torn() {
                            Some(at) => Ending::Torn { at },
                            None => Ending::Cut,
                        });
                    }
                    return Ok(None);
                }
            }
        };
        let mut t = self.t;
        let mut times = Vec::with_capacity(end.clock.len());
        for d in &end.clock {
            t = t.wrapping_add(*d);
            times.push(t);
        }
        self.t = t;
        for c in &self.clocks {
            for &t in &times {
                c.push(t);
            }
        }
        for (i, cpu) in cpus.iter_mut().enumerate() {
            if end.scanned {
                cpu.scan();
            }
            apply(cpu, &end.events)
                .map_err(|e| format!("{}: END {}, CPU {}: {e}", self.name, self.ends + 1, i + 1))?;
        }
        self.ends += 1;
        self.check(cpus, &end)
            .map_err(|e| format!("{}: {e}", self.name))?;
        Ok(Some(end))
    }

    /// The recorded program's CPU (the first) took every reading and ran
    /// the scans it did live; otherwise the replay is not that session.
    fn check(&self, cpus: &[&mut Cpu], end: &End) -> Result<(), String> {
        let (Some(cpu), Some(clock)) = (cpus.first(), self.clocks.first()) else {
            return Ok(());
        };
        let (left, short) = clock.balance();
        if end.scanned && cpu.scans() != end.scans {
            return Err(format!(
                "the replay went apart from the recording at END {}: the CPU had executed {} scans, the replay {} \
                 (see docs/recording.md, what a replay cannot reproduce)",
                self.ends,
                end.scans,
                cpu.scans()
            ));
        }
        if left > 0 || short > 0 {
            return Err(format!(
                "the replay went apart from the recording at END {}: the CPU read the clock {} times, the replay {} \
                 (see docs/recording.md, what a replay cannot reproduce)",
                self.ends,
                end.clock.len() as u64,
                end.clock.len() as u64 + short - left as u64
            ));
        }
        Ok(())
    }

    /// The changes before scan 1 (the battery-backed image, the calendar).
    pub fn start_events(&self) -> Vec<crate::event::Event> {
        self.start.events.clone()
    }

    /// How the recording ended (after [`Self::step`] returned `None`).
    pub fn ending(&self) -> Option<Ending> {
        self.ending.clone()
    }

    /// Virtual time of the recorded program's CPU from power-on to the last
    /// END played, µs.
    pub fn clock_elapsed_us(&self) -> u64 {
        self.clocks.first().map_or(0, ReplayClock::elapsed_us)
    }

    /// ENDs played so far.
    pub fn ends(&self) -> u64 {
        self.ends
    }
}
