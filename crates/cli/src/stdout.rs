//! Report output on stdout. `println!` panics when the reader has gone away
//! (`softplc run … --trace D0 | head`); a CLI should stop quietly instead, as
//! `cat` does. State and files are written before the report, so nothing is
//! lost by stopping here.

use std::io::{ErrorKind, Write};

/// Exit status of a process ended by a broken pipe, as a shell reports a
/// SIGPIPE death (128 + 13).
const BROKEN_PIPE_EXIT: i32 = 141;

/// Writes `args` to stdout and flushes; a closed stdout ends the process with
/// status 141, any other write error is reported on stderr and ends it with 1.
pub fn write(args: std::fmt::Arguments) {
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.flush()) {
        if e.kind() == ErrorKind::BrokenPipe {
            std::process::exit(BROKEN_PIPE_EXIT);
        }
        eprintln!("softplc: cannot write to stdout: {e}");
        std::process::exit(1);
    }
}

/// `print!` that does not panic on a closed stdout ([`write`]).
macro_rules! out {
    ($($t:tt)*) => { $crate::stdout::write(format_args!($($t)*)) };
}

/// `println!` that does not panic on a closed stdout ([`write`]).
macro_rules! outln {
    ($($t:tt)*) => { $crate::stdout::write(format_args!("{}\n", format_args!($($t)*))) };
}

pub(crate) use {out, outln};
