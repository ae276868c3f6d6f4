//! A running `softplc serve` for the CLI tests: started from a command,
//! waited for until it says it serves, killed when dropped.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

pub struct Serve {
    pub child: Child,
    /// The web monitor's port (0 without one).
    pub port: u16,
    /// The start message.
    pub banner: String,
}

impl Drop for Serve {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts `cmd` (a `serve`) and waits for its start message; the rest of
/// its standard error is read and dropped.
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
    std::thread::spawn(move || std::io::copy(&mut err, &mut std::io::sink()));
    Serve {
        child,
        port,
        banner: line,
    }
}
