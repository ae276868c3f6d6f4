//! `softplc`: run and check MELSEC-Q programs (contract §2).

// `unsafe` only in the modules marked `#[allow(unsafe_code)]`, each block with its SAFETY reason.
#![deny(unsafe_code)]

mod fmu_cmd;
mod http;
mod names;
mod online;
mod opcua;
mod record;
mod replay;
mod run;
mod run_system;
mod serve;
mod served;
// The SIGINT/SIGTERM handler (libc::signal).
#[allow(unsafe_code)]
mod signal;
mod state_file;
mod stdout;
mod test_cmd;
mod tune_cmd;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// softplc — a MELSEC-Q compatible soft PLC.
///
/// Loads a sequence program (text mnemonic list `.il`, a GX Works2
/// instruction-list CSV export `.csv`, or an APLC-TCP instruction list `.apl`)
/// or a project directory with its plc.toml, and executes it scan by scan as
/// the CPU does: input refresh, program from step 0 to END, END processing.
#[derive(Parser, Debug)]
#[command(name = "softplc", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Execute a program for a number of scans in virtual time and report devices.
    ///
    /// Time is virtual: each scan takes exactly --scan-time, so timers, the
    /// SM409-SM415 clocks and SD520 scan-time registers are reproducible.
    /// Devices use MELSEC names: X1F, Y10, B, W, SB, SW in hex; M100, D0, SM400,
    /// SD520, R0, ZR100000, Z0; K4M0 (digit specification), D0.F (bit of a word),
    /// D200Z0 (index modification); T0/C0/ST0 the contact, TN0/CN0/STN0 the
    /// current value. An APLC program (.apl, --dialect aplc, an APLC-TCP
    /// project) takes APLC names: X10/Y10 octal, Dn the high word of
    /// :i32/:u32/:f32, CN200-CN255 32-bit, values 16#1F.
    ///
    /// Example: softplc run examples/blink.il --scans 100 --set X0=1 --show Y0 --show TN0
    Run(Box<run::RunArgs>),
    /// Load a program and report every diagnostic as file:line:column: message.
    ///
    /// Exit status is non-zero when the program has errors.
    Check {
        /// Program file (.il, .csv or .apl), or a project directory.
        program: PathBuf,
        /// CPU model a single program file is checked for (default Q06HCPU).
        #[arg(long, value_name = "MODEL")]
        model: Option<String>,
        /// How a single program file is read: melsec or aplc, or a family
        /// (MELSEC-Q, MELSEC-QnPH, APLC) (default by name: `.apl` is aplc).
        #[arg(long, value_name = "D", value_parser = names::parse_family)]
        dialect: Option<&'static softplc_core::profile::Profile>,
        /// Also compile for this tier (auto, jit, interp; as `run --exec`).
        #[arg(long, value_name = "TIER", value_parser = softplc_core::tier::Exec::parse)]
        exec: Option<softplc_core::tier::Exec>,
        /// Compile on the tier and print its compile time (on stderr).
        #[arg(long)]
        stats: bool,
    },
    /// Run scenario tests: a program against plant models in virtual time,
    /// with a timeline of inputs and assertions (docs/scenarios.md).
    ///
    /// Prints a PASS/FAIL line per assertion (a failure shows its first failing
    /// scan and the device history around it) and ends with `N passed, M
    /// failed`; the exit status is non-zero when any assertion fails.
    ///
    /// Example: softplc test examples/sim/*.toml --plot tank.svg
    Test(Box<test_cmd::TestArgs>),
    /// Tune a process-control loop offline, in virtual time, on a scenario's
    /// program and plant model.
    ///
    /// Puts the loop tag (--loop, the D2 of S.IN/S.PID/S.OUT1) in MAN, waits
    /// for a steady PV, steps MV by --step %, fits a first-order-plus-dead-time
    /// model to the response (K in % of range per %MV, τ, θ, RMS error, R²),
    /// prints the tuning rules (ZN, CHR, SIMC, IMC) in S.PID's units (P, TI,
    /// TD, η = 1/MTD) beside what S.AT1 would identify, then writes the
    /// --rule's P/I/D, switches to AUT, steps SV and reports overshoot, rise
    /// and settling time and IAE. Exit status 1 when the verification does
    /// not settle, 2 on errors.
    ///
    /// Example: softplc tune examples/process/fopdt_loop.toml --loop R1000 --svg loop.svg
    Tune(Box<tune_cmd::TuneArgs>),
    /// Run a program in real time at its constant scan period and serve it over
    /// the MC protocol (TCP, UDP) and Modbus (TCP, RTU, ASCII) until Ctrl-C or SIGTERM.
    /// An APLC-TCP program answers Modbus with the map of the APLC programming
    /// manual (§10.4.6, Appendix 7) at unit 8 and has no MC protocol.
    ///
    /// Requests are served at END processing, so a client never sees a
    /// half-written scan. Servers bind loopback unless an address says otherwise.
    ///
    /// Example: softplc serve examples/blink.il --mc 127.0.0.1:5010
    Serve(Box<serve::ServeArgs>),
    /// Replay a recording of `serve --record` in virtual time and report
    /// devices as `run` does (docs/recording.md).
    ///
    /// The recording embeds the program's files, its model, the calendar at
    /// power-on, every clock reading the CPU took and every change from
    /// outside with the END it took effect at, so the replay ends with the
    /// device values the live CPU had at its last recorded END. With
    /// --program, a changed program runs beside the recorded one on the same
    /// changes and clock, and the first scan where each --diverge device
    /// differs is reported: what a fix would have done in that session.
    ///
    /// Example: softplc replay incident.rec --show D0 --program fixed.il --diverge Y0
    Replay(Box<replay::ReplayArgs>),
    /// Write the program as an FMI 3.0 co-simulation FMU whose variables
    /// are the given devices (docs/fmu-export.md).
    ///
    /// A doStep from t to t+h runs the scans that end at or before t+h,
    /// counted from the start time, each --scan-time long, in virtual time:
    /// the master gets what `softplc run` gives. Inputs set before a doStep
    /// are written before its first scan. The FMU's binary is
    /// libsoftplc_fmu.so, built by cargo next to softplc.
    ///
    /// Example: softplc fmu examples/blink.il -o blink.fmu --input X0 --input X1 --output Y0 --output CN0
    Fmu(Box<fmu_cmd::FmuArgs>),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Run(args) => run::run(*args),
        Command::Check {
            program,
            model,
            dialect,
            exec,
            stats,
        } => run::check(&program, model.as_deref(), dialect, exec, stats),
        Command::Test(args) => test_cmd::run(*args),
        Command::Tune(args) => tune_cmd::run(*args),
        Command::Serve(args) => serve::serve(*args),
        Command::Replay(args) => replay::replay(*args),
        Command::Fmu(args) => fmu_cmd::run(*args),
    }
}
