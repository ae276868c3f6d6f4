//! Recording a served session: the engine clock's readings
//! ([`Recorder::clock`]), the Cpu door's journal ([`Recorder::journal`])
//! and one frame per END ([`Recorder::end`]), written by a thread of its
//! own so a slow disk never holds up the scan.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, Sender};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;

use softplc_core::engine::{Clock, Cpu, DoorEvent, Journal};

use crate::event::{Change, Event, Source};
use crate::format::{frame, write_magic, End, Header, Record};

/// The recording of one CPU's session; cheap to clone (the clock, the
/// journal and the END hook share it).
#[derive(Clone, Default)]
pub struct Recorder(Arc<Mutex<Inner>>);

#[derive(Default)]
struct Inner {
    /// Clock readings since the last frame (absolute µs).
    readings: Vec<u64>,
    /// The last reading put in a frame (deltas start from it).
    last: u64,
    events: Vec<Event>,
    /// Who is changing the CPU now.
    source: Source,
    out: Option<Output>,
    /// Recording has stopped (the size bound, a write error): readings and
    /// changes are no longer kept.
    done: bool,
    /// Recording stopped at the size bound (its `Full` record written).
    full: bool,
    /// Scan count of the last frame written.
    scans: u64,
    /// The serve engine's END number of the last frame.
    end: u64,
}

struct Output {
    path: PathBuf,
    tx: Sender<Vec<u8>>,
    writer: JoinHandle<std::io::Result<()>>,
    written: u64,
    max: u64,
}

impl Recorder {
    pub fn new() -> Recorder {
        Recorder::default()
    }

    fn lock(&self) -> MutexGuard<'_, Inner> {
        // A panic elsewhere while holding the lock leaves plain data behind.
        self.0.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// `inner` with every reading the CPU takes recorded.
    pub fn clock(&self, inner: Box<dyn Clock>) -> Box<dyn Clock> {
        Box::new(RecordingClock {
            inner,
            rec: self.clone(),
        })
    }

    /// The Cpu door's journal for [`Cpu::set_journal`].
    pub fn journal(&self) -> Box<dyn Journal> {
        Box::new(self.clone())
    }

    /// The door whose changes come next (the serve layer sets it while it
    /// serves each door's requests).
    pub fn set_source(&self, source: Source) {
        self.lock().source = source;
    }

    /// Opens `path` (replacing it), writes `header` and the changes so far
    /// (the load and the battery-backed image) as the start frame. At `max`
    /// bytes recording stops with a message on stderr.
    pub fn start(&self, path: &Path, header: &Header, max: u64) -> Result<(), String> {
        let mut file = File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let head = frame(&Record::Header(header.clone()));
        write_magic(&mut file)
            .and_then(|_| file.write_all(&head))
            .map_err(|e| format!("{}: {e}", path.display()))?;
        let (tx, rx) = channel::<Vec<u8>>();
        let writer = std::thread::Builder::new()
            .name("softplc-record".into())
            .spawn(move || {
                for f in rx {
                    file.write_all(&f)?;
                }
                file.sync_all()
            })
            .map_err(|e| format!("the recording thread: {e}"))?;
        let mut g = self.lock();
        g.out = Some(Output {
            path: path.to_path_buf(),
            tx,
            writer,
            written: (crate::format::MAGIC.len() + head.len()) as u64,
            max,
        });
        g.cut(false, 0);
        Ok(())
    }

    /// After END processing (its requests served): the frame of END
    /// number `end` (the serve engine's count of scans). Requests served
    /// again before the next scan (a paced or held END) call it with the same
    /// number: their changes stay for the next frame, before its scan.
    pub fn end(&self, cpu: &Cpu, end: u64) {
        let mut g = self.lock();
        if g.done || end == g.end {
            return;
        }
        g.end = end;
        if cpu.aborted() {
            // Stopped mid-scan (Ctrl-C/SIGTERM): that scan is not a whole
            // one; the recording ends at the END before it.
            g.done = true;
            return;
        }
        g.cut(true, cpu.scans());
    }

    /// The server stopped: the shutdown record, then waits for the writer.
    /// The path and bytes written, or why recording failed.
    pub fn finish(&self) -> Result<(PathBuf, u64), String> {
        let mut g = self.lock();
        let scans = g.scans;
        let full = g.full;
        let Some(out) = g.out.take() else {
            return Err("the recording was not started".into());
        };
        g.done = true;
        drop(g);
        let mut written = out.written;
        if !full {
            let f = frame(&Record::Shutdown { scans });
            written += f.len() as u64;
            let _ = out.tx.send(f);
        }
        drop(out.tx);
        match out.writer.join() {
            Ok(Ok(())) => Ok((out.path, written)),
            Ok(Err(e)) => Err(format!("{}: {e}", out.path.display())),
            Err(_) => Err(format!(
                "{}: the recording thread failed",
                out.path.display()
            )),
        }
    }
}

impl Inner {
    /// Ends the recording before a change it cannot follow (the server runs
    /// on): the `Stopped` record after the last whole END.
    fn stop(&mut self, why: &str) {
        self.done = true;
        self.full = true;
        let Some(out) = &mut self.out else { return };
        let f = frame(&Record::Stopped {
            scans: self.scans,
            why: why.to_string(),
        });
        out.written += f.len() as u64;
        let _ = out.tx.send(f);
        eprintln!(
            "softplc: --record {}: {why} after scan {}; a recording cannot follow that, so it \
             stopped there (the server runs on; the replay ends there)",
            out.path.display(),
            self.scans
        );
    }

    /// Sends the readings and changes since the last frame as one frame.
    fn cut(&mut self, scanned: bool, scans: u64) {
        let mut clock = Vec::with_capacity(self.readings.len());
        for &r in &self.readings {
            clock.push(r.wrapping_sub(self.last));
            self.last = r;
        }
        self.readings.clear();
        let end = End {
            scanned,
            scans,
            clock,
            events: std::mem::take(&mut self.events),
        };
        let bytes = frame(&Record::End(end));
        let Some(out) = &mut self.out else { return };
        // Room is kept for the last record (Full or Shutdown).
        let tail = frame(&Record::Full { scans: u64::MAX }).len() as u64;
        if out.written + bytes.len() as u64 + tail > out.max {
            let full = frame(&Record::Full { scans: self.scans });
            out.written += full.len() as u64;
            let _ = out.tx.send(full);
            eprintln!(
                "softplc: --record {}: the recording reached --record-max-size ({} bytes) after scan {}; \
                 recording stopped, the server runs on (replay ends there)",
                out.path.display(),
                out.max,
                self.scans
            );
            self.done = true;
            self.full = true;
            return;
        }
        out.written += bytes.len() as u64;
        if out.tx.send(bytes).is_err() {
            eprintln!(
                "softplc: --record {}: cannot write the recording; recording stopped",
                out.path.display()
            );
            self.done = true;
            return;
        }
        self.scans = scans;
    }
}

impl Journal for Recorder {
    fn record(&mut self, event: DoorEvent<'_>) {
        let mut g = self.lock();
        if g.done {
            return;
        }
        let Some(change) = Change::of(&event) else {
            if let DoorEvent::Unrecordable { why } = event {
                g.stop(why);
            }
            return;
        };
        // A look at a program's local devices that wrote nothing.
        if change == Change::LocalsEnd
            && g.events
                .last()
                .is_some_and(|e| matches!(e.change, Change::LocalsOf { .. }))
        {
            g.events.pop();
            return;
        }
        let source = g.source;
        g.events.push(Event { source, change });
    }
}

/// The engine clock with every reading recorded.
struct RecordingClock {
    inner: Box<dyn Clock>,
    rec: Recorder,
}

impl Clock for RecordingClock {
    fn now_us(&self) -> u64 {
        let t = self.inner.now_us();
        let mut g = self.rec.lock();
        if !g.done {
            g.readings.push(t);
        }
        t
    }

    fn peek_us(&self) -> u64 {
        self.inner.now_us()
    }

    /// A state file loaded: the recording has already stopped
    /// ([`DoorEvent::Unrecordable`]); the clock itself goes on from there.
    fn restore_us(&mut self, now_us: u64) {
        self.inner.restore_us(now_us);
    }

    fn is_virtual(&self) -> bool {
        self.inner.is_virtual()
    }
}
