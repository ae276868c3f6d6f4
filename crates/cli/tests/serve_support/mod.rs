//! A running `softplc serve` for the CLI tests: started from a command,
//! waited for until it says it serves, killed when dropped.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

pub struct Serve {
    pub child: Child,
    /// The web monitor's port (0 without one).
    pub port: u16,
    /// The start message.
    pub banner: String,
    /// The lines of its standard error after the start message.
    pub lines: Receiver<String>,
}

impl Serve {
    /// Waits for a standard-error line containing `what` (ample time: a
    /// watcher waits for files to settle); panics with the lines seen
    /// otherwise.
    pub fn expect(&self, what: &str) -> String {
        let deadline = Instant::now() + Duration::from_secs(30);
        let mut seen = Vec::new();
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(l) if l.contains(what) => return l,
                Ok(l) => seen.push(l),
                Err(RecvTimeoutError::Timeout | RecvTimeoutError::Disconnected) => {
                    panic!("no line with {what:?}; stderr: {seen:#?}")
                }
            }
        }
    }
}

impl Drop for Serve {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts `cmd` (a `serve`) and waits for its start message; the rest of
/// its standard error goes to `lines`.
pub fn start(mut cmd: Command) -> Serve {
    let mut child = cmd
        .stderr(Stdio::piped())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    loop {
        line.clear();
        assert!(err.read_line(&mut line).unwrap() > 0, "serve exited");
        if line.starts_with("softplc: serving") {
            break;
        }
    }
    let port = line
        .split("web monitor on 127.0.0.1:")
        .nth(1)
        .map_or(0, |rest| {
            rest.trim()
                .trim_end_matches(|c: char| !c.is_ascii_digit())
                .parse()
                .unwrap()
        });
    let (tx, lines) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for l in err.lines().map_while(Result::ok) {
            if tx.send(l).is_err() {
                break;
            }
        }
    });
    Serve {
        child,
        port,
        banner: line,
        lines,
    }
}
