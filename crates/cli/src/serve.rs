//! `softplc serve` (contract §3): real-time scans at the constant-scan period with
//! protocol servers served at END processing.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

use clap::Args;
use softplc_core::engine::calendar::DateTime;
use softplc_modbus::{Map, Proto, Slave};
use softplc_serve::serial::{self, LineSettings, Parity};
use softplc_serve::{mc::Mc, modbus::ModbusTcp, EngineConfig, Listener, SerialSlave, ServeState};
use softplc_serve::{TimeScale, VirtualTime};

use softplc_record::{Recorder, Source};

use crate::run::{parse_datetime, parse_duration};
use crate::served::{load_served, Served};

#[derive(Args, Debug)]
pub struct ServeArgs {
    /// Program file (.il, .csv or .apl) or project directory (or its plc.toml).
    pub program: PathBuf,
    /// CPU model a single program file runs on (default Q06HCPU; see `run --model`).
    #[arg(long, value_name = "MODEL")]
    pub model: Option<String>,
    /// Constant scan period (default: the project's constant_scan, else 10ms).
    #[arg(long, value_name = "DUR", value_parser = parse_duration)]
    pub scan_time: Option<Duration>,
    /// MC protocol server (3E/4E, binary and ASCII), e.g. 127.0.0.1:5010 or 5010
    /// (a bare port binds loopback).
    #[arg(long, value_name = "ADDR")]
    pub mc: Option<String>,
    /// MC protocol over UDP, e.g. 127.0.0.1:5011.
    #[arg(long, value_name = "ADDR")]
    pub mc_udp: Option<String>,
    /// Modbus TCP server, e.g. 127.0.0.1:5020.
    #[arg(long, value_name = "ADDR")]
    pub modbus: Option<String>,
    /// APLC PORT1 on a serial device or pty (the project's `[port1]`
    /// settings: Modbus master or slave, or free port).
    #[arg(long, value_name = "PATH")]
    pub port1: Option<PathBuf>,
    /// APLC PORT2 on a serial device or pty (`[port2]`).
    #[arg(long, value_name = "PATH")]
    pub port2: Option<PathBuf>,
    /// Modbus RTU slave on a serial device or pty.
    #[arg(long, value_name = "PATH")]
    pub modbus_rtu: Option<PathBuf>,
    /// Modbus ASCII slave on a serial device or pty.
    #[arg(long, value_name = "PATH")]
    pub modbus_ascii: Option<PathBuf>,
    /// Serial line speed for --modbus-rtu/--modbus-ascii.
    #[arg(long, value_name = "BAUD", default_value_t = 9600)]
    pub baud: u32,
    /// Serial parity: none, even or odd.
    #[arg(long, value_name = "PARITY", default_value = "none")]
    pub parity: String,
    /// Serial stop bits: 1 or 2.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub stop_bits: u8,
    /// Refuse Modbus writes (exception 01).
    #[arg(long)]
    pub modbus_read_only: bool,
    /// Web monitor and JSON API (docs/web-monitor.md), e.g. 127.0.0.1:8080 or
    /// 8080 (a bare port binds loopback).
    #[arg(long, value_name = "ADDR")]
    pub http: Option<String>,
    /// Bearer token that allows writes, forcing and RUN/STOP over HTTP (also
    /// `[http] token` in plc.toml); without one the HTTP side is read-only.
    #[arg(long, value_name = "TOKEN")]
    pub http_token: Option<String>,
    /// Web monitor connections at once (default 64; also `[http]
    /// max_connections`). At the limit a new connection replaces one that
    /// never sent a whole request head, else one idle for 10 s; an event
    /// stream or a request being answered keeps its place.
    #[arg(long, value_name = "N")]
    pub http_max_connections: Option<usize>,
    /// Longest wait for a request head, also between requests on a kept-alive
    /// connection, before the web monitor closes it (default 10s; also `[http]
    /// header_timeout`).
    #[arg(long, value_name = "DUR", value_parser = parse_duration)]
    pub http_header_timeout: Option<Duration>,
    /// Longest wait for a whole request body; then 408 (default 10s; also
    /// `[http] body_timeout`).
    #[arg(long, value_name = "DUR", value_parser = parse_duration)]
    pub http_body_timeout: Option<Duration>,
    /// Remote password for the MC protocol: exactly 4 ASCII letters or digits,
    /// as on the QCPU. Until a connection (or UDP sender) unlocks, every MC
    /// request but unlock and loopback is refused (C201), reads included. Wrong
    /// guesses are logged and throttled per address (1 s, doubling to 60 s).
    /// It does not cover Modbus: use --modbus-read-only to refuse Modbus writes.
    #[arg(long, value_name = "PW")]
    pub password: Option<String>,
    /// State directory (default for a project: its [state] dir).
    #[arg(long, value_name = "DIR")]
    pub state: Option<PathBuf>,
    /// Calendar clock at power-on (default: the host clock, UTC, or the one kept
    /// in the state directory).
    #[arg(long, value_name = "DATETIME", value_parser = parse_datetime)]
    pub clock: Option<DateTime>,
    /// Connections per MC protocol and Modbus TCP server. At the limit a new
    /// connection replaces one that never sent a whole request, else one idle
    /// for 10 s; with only active clients it is refused.
    #[arg(long, value_name = "N", default_value_t = 16)]
    pub max_connections: usize,
    /// Do not ask for real-time priority. By default the engine thread asks for
    /// SCHED_FIFO (granted to root or with CAP_SYS_NICE / RLIMIT_RTPRIO, else
    /// it runs at normal priority); --stats-every says which it got.
    #[arg(long, conflicts_with = "realtime")]
    pub no_realtime: bool,
    /// The whole real-time path: SCHED_FIFO for the engine thread and all
    /// memory locked (mlockall; root or CAP_IPC_LOCK), so no page fault
    /// stalls a scan. What is not permitted is said once and the server runs
    /// on without it.
    #[arg(long)]
    pub realtime: bool,
    /// Busy-wait this long before each scan's deadline after the sleep, µs
    /// (default 200): the scan starts on time whenever the kernel wakes the
    /// engine within it. 0 sleeps only (no core time spent waiting).
    #[arg(long, value_name = "US", value_parser = clap::value_parser!(u32).range(0..=1_000_000))]
    pub spin_us: Option<u32>,
    /// Pin the engine thread to CPU N (e.g. a core kept free of other work).
    #[arg(long, value_name = "N")]
    pub cpu: Option<usize>,
    /// Write the scan timing (start lateness, period jitter and execution
    /// time percentiles, as GET /api/v1/timing) to FILE as JSON at exit.
    #[arg(long, value_name = "FILE")]
    pub timing_report: Option<PathBuf>,
    /// OPC UA server (docs/opcua.md), e.g. 127.0.0.1:4840 or 4840 (a bare port
    /// binds loopback; also `[opcua] address`). Security None only on loopback.
    #[arg(long, value_name = "ADDR")]
    pub opcua: Option<String>,
    /// Refuse OPC UA writes (BadNotWritable; also `[opcua] read_only`).
    #[arg(long)]
    pub opcua_read_only: bool,
    /// OPC UA certificate store (default: softplc/opcua-pki in the user's data
    /// directory, ~/.local/share; also `[opcua] pki`).
    #[arg(long, value_name = "DIR")]
    pub opcua_pki: Option<PathBuf>,
    /// Print scan statistics (scan time, overruns, jitter, real-time) this often.
    #[arg(long, value_name = "DUR", value_parser = parse_duration)]
    pub stats_every: Option<Duration>,
    /// Execution tier: auto, jit or interp (as `run --exec`).
    #[arg(long, value_name = "TIER", value_parser = softplc_core::tier::Exec::parse)]
    pub exec: Option<softplc_core::tier::Exec>,
    /// Print the tier and its compile time at load (on stderr).
    #[arg(long)]
    pub stats: bool,
    /// Publish devices to an MQTT broker (docs/mqtt.md):
    /// mqtt://[USER[:PASSWORD]@]HOST[:PORT] or mqtts://… (TLS).
    #[arg(long, value_name = "URL")]
    pub mqtt: Option<String>,
    /// Topic prefix: devices go to PREFIX/DEV, the connection state to
    /// PREFIX/$state, writes come from PREFIX/set/DEV.
    #[arg(
        long,
        value_name = "PREFIX",
        default_value = "softplc",
        requires = "mqtt"
    )]
    pub mqtt_topic: String,
    /// Devices published at the END where their value changes, retained
    /// (names as --show, comma-separated: D0,Y0,D10:f32).
    #[arg(long, value_name = "DEV,...", value_delimiter = ',', requires = "mqtt")]
    pub mqtt_publish: Vec<String>,
    /// Accept writes: {"value": 7} published to PREFIX/set/DEV is written at
    /// the next END. Anyone who may publish there writes the PLC: restrict
    /// it with the broker's ACLs (docs/mqtt.md).
    #[arg(long, requires = "mqtt")]
    pub mqtt_write: bool,
    /// MQTT client id (default softplc-HOSTNAME-PID).
    #[arg(long, value_name = "ID", requires = "mqtt")]
    pub mqtt_client_id: Option<String>,
    /// CA certificate (PEM) that signed an mqtts:// broker's certificate
    /// (default: the system's root certificates).
    #[arg(long, value_name = "FILE", requires = "mqtt")]
    pub mqtt_ca: Option<PathBuf>,
    /// Run in virtual time at F times real time (0.01 to 1000), or `max`: as
    /// fast as the scans go. Timers, the calendar and the scan time follow
    /// virtual time, and the scan period is virtual (a 10ms scan at 2 starts
    /// every 5 ms of real time). See docs/cosimulation.md.
    #[arg(long, value_name = "F", value_parser = TimeScale::parse)]
    pub time_scale: Option<TimeScale>,
    /// Hold the CPU before scan 1 and after each END until a client advances
    /// it (POST /api/v1/sim/advance; needs --http and a token). Requests of
    /// every door are served at the held END. An advance's scans run at
    /// --time-scale, else as fast as possible.
    #[arg(long)]
    pub lockstep: bool,
    /// Write each program file during RUN when it is rewritten or replaced
    /// on disk, as PUT /api/v1/program does (docs/online-change.md);
    /// plc.toml changes need a restart.
    #[arg(long)]
    pub watch: bool,
    /// Record the session for `softplc replay` (docs/recording.md): every
    /// change from outside (writes by MC, Modbus, HTTP, OPC UA, MQTT and the
    /// serial ports, forcing, RUN/STOP/PAUSE/RESET) with the END it took effect at,
    /// every clock reading the CPU takes and the program's files. A single CPU
    /// only.
    #[arg(long, value_name = "FILE")]
    pub record: Option<PathBuf>,
    /// Largest recording, e.g. 200MiB (default 1GiB). Recording stops there
    /// with a message and the server runs on; the recording replays up to
    /// that END.
    #[arg(long, value_name = "SIZE", value_parser = crate::record::parse_size, requires = "record")]
    pub record_max_size: Option<u64>,
}

/// The MQTT publisher when `--mqtt` asks for one.
fn mqtt_listener(
    args: &ServeArgs,
    state: &ServeState,
) -> Result<Option<softplc_serve::Listener>, String> {
    let Some(url) = &args.mqtt else {
        return Ok(None);
    };
    let cfg = softplc_mqtt::MqttConfig {
        broker: softplc_mqtt::Broker::parse(url)?,
        prefix: softplc_mqtt::check_prefix(&args.mqtt_topic)?,
        publish: args
            .mqtt_publish
            .iter()
            .map(|d| d.trim().to_string())
            .filter(|d| !d.is_empty())
            .collect(),
        write: args.mqtt_write,
        client_id: args
            .mqtt_client_id
            .clone()
            .unwrap_or_else(softplc_mqtt::broker::default_client_id),
        ca: args.mqtt_ca.clone(),
    };
    Ok(Some(softplc_mqtt::Prepared::new(cfg, state)?.listener()))
}

/// "a" or "an" before a model name read letter by letter ("an APLC-TCP",
/// "a Q06HCPU", "an L02CPU").
fn article(model: &str) -> &'static str {
    match model.chars().next().map(|c| c.to_ascii_uppercase()) {
        Some('A' | 'E' | 'F' | 'H' | 'I' | 'L' | 'M' | 'N' | 'O' | 'R' | 'S' | 'X') => "an",
        _ => "a",
    }
}

/// `--record-max-size` by default.
const DEFAULT_RECORD_MAX: u64 = 1 << 30;

fn host_clock() -> DateTime {
    let s = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() as i64);
    DateTime::from_unix(s)
}

/// Only the web monitor's advance moves a held CPU.
const LOCKSTEP_NEEDS: &str = "--lockstep: the CPU runs only when a client advances it \
     (POST /api/v1/sim/advance): give --http and a token (--http-token or [http] token)";

pub fn serve(args: ServeArgs) -> ExitCode {
    let fail = |msg: String| {
        eprintln!("softplc: {msg}");
        ExitCode::from(2)
    };
    if let Some(n) = args.cpu {
        if let Err(e) = softplc_serve::realtime::check_cpu(n) {
            return fail(format!("--cpu {n}: {e}"));
        }
    }
    if let Some(p) = &args.password {
        if let Err(e) = softplc_serve::mc::check_password(p) {
            return fail(format!("--password: {e}"));
        }
    }
    let restore_clock = args.clock.is_none();
    let start = args.clock.unwrap_or_else(host_clock);
    let recorder = args.record.as_ref().map(|_| Recorder::new());
    let Served {
        mut state,
        battery,
        period,
        modbus,
        http,
        opcua,
        ports,
        cpus,
        state_dir,
        virtual_clock,
    } = match load_served(&args, start, restore_clock, recorder.as_ref()) {
        Ok(s) => s,
        Err(code) => return code,
    };
    if let (Some(rec), Some(path)) = (&recorder, &args.record) {
        let skip: Vec<PathBuf> = [Some(path.clone()), state_dir]
            .into_iter()
            .flatten()
            .collect();
        let header = crate::record::header(
            &args.program,
            args.model.as_deref(),
            state.cpu().profile().model,
            start,
            period.as_micros() as u64,
            &skip,
        );
        let max = args.record_max_size.unwrap_or(DEFAULT_RECORD_MAX);
        if let Err(e) = header.and_then(|h| crate::record::start(rec, &mut state, path, &h, max)) {
            return fail(format!("--record: {e}"));
        }
    }
    if let Some(clock) = virtual_clock {
        state.set_virtual_time(VirtualTime {
            clock,
            scale: args.time_scale.unwrap_or(TimeScale::Max),
            lockstep: args.lockstep,
        });
    }
    let (online, _watching) = match crate::online::setup(&args.program, args.watch, &mut state) {
        Ok(o) => o,
        Err(e) => return fail(e),
    };
    // The doors ask CPU 1 (a system's CPUs are all MELSEC-Q CPUs).
    let cpu = state.cpu();
    let doors = cpu.profile().doors;
    if doors.mc.is_none() {
        // A model without the MC protocol (the APLC-TCP speaks Modbus and free
        // port only); see COMPATIBILITY.md.
        for (flag, given) in [
            ("--mc", args.mc.is_some()),
            ("--mc-udp", args.mc_udp.is_some()),
        ] {
            if given {
                let model = cpu.profile().model;
                return fail(format!(
                    "{flag}: {} {model} has no MC protocol; use --modbus",
                    article(model)
                ));
            }
        }
    }
    let mut listeners = Vec::new();
    let mut names = Vec::new();
    if let Some(a) = &args.mc {
        match softplc_serve::parse_addr(a) {
            Ok(addr) => {
                let mc = Mc::new(args.password.clone());
                listeners.push(Listener::tcp(addr, mc, args.max_connections));
                names.push("MC protocol".to_string());
            }
            Err(e) => return fail(format!("--mc {e}")),
        }
    }
    if let Some(a) = &args.mc_udp {
        match softplc_serve::parse_addr(a) {
            Ok(addr) => {
                let mc = Mc::new(args.password.clone());
                listeners.push(Listener::mc_udp(addr, mc));
                names.push("MC protocol (UDP)".to_string());
            }
            Err(e) => return fail(format!("--mc-udp {e}")),
        }
    }
    if let Some(a) = &args.http {
        let addr = match softplc_serve::parse_addr(a) {
            Ok(a) => a,
            Err(e) => return fail(format!("--http {e}")),
        };
        let flags = crate::http::Flags {
            token: args.http_token.as_deref(),
            max_connections: args.http_max_connections,
            header_timeout: args.http_header_timeout,
            body_timeout: args.http_body_timeout,
        };
        let (token, limits) = match crate::http::settings(&flags, http.as_ref()) {
            Ok(t) => t,
            Err(e) => return fail(e),
        };
        if args.lockstep && token.is_none() {
            return fail(LOCKSTEP_NEEDS.to_string());
        }
        let cfg = softplc_http::HttpConfig {
            token,
            model: cpu.profile().model.to_string(),
            ladder: softplc_http::ladder::load_programs(cpu),
            limits,
            online,
        };
        listeners.push(softplc_http::listener(addr, cfg).door("HTTP"));
        names.push("web monitor".to_string());
    } else {
        if args.lockstep {
            return fail(LOCKSTEP_NEEDS.to_string());
        }
        for (flag, given) in [
            ("--http-token", args.http_token.is_some()),
            (
                "--http-max-connections",
                args.http_max_connections.is_some(),
            ),
            ("--http-header-timeout", args.http_header_timeout.is_some()),
            ("--http-body-timeout", args.http_body_timeout.is_some()),
        ] {
            if given {
                eprintln!("softplc: {flag} has no effect without --http");
            }
        }
    }
    let base = if softplc_core::project::is_project(&args.program) {
        if args.program.is_dir() {
            args.program.clone()
        } else {
            args.program.parent().map(PathBuf::from).unwrap_or_default()
        }
    } else {
        PathBuf::from(".")
    };
    let opcua_args = crate::opcua::OpcuaArgs {
        addr: args.opcua.as_deref(),
        read_only: args.opcua_read_only,
        pki: args.opcua_pki.as_deref(),
    };
    match crate::opcua::listener(&opcua_args, opcua.as_ref(), &base, period, &state) {
        Ok(Some(l)) => {
            listeners.push(l.door("OPC UA"));
            names.push("OPC UA".to_string());
        }
        Ok(None) => {}
        Err(e) => return fail(e),
    }
    let table = modbus.unwrap_or_default();
    // The model's Modbus map and unit address (the APLC-TCP's: seed 002's map
    // at unit 8, L10686, contract §3).
    let Some(preset) = softplc_modbus::Preset::find(doors.modbus) else {
        return fail(format!(
            "{}: no Modbus map named \"{}\"",
            cpu.profile().model,
            doors.modbus
        ));
    };
    let unit = doors.modbus_unit;
    let modbus_setup = || -> Result<(Map, Slave), String> {
        let map = Map::from_toml_with(&table, preset).map_err(|e| format!("[modbus]: {e}"))?;
        let mut slave =
            Slave::from_toml_with(&table, unit).map_err(|e| format!("[modbus]: {e}"))?;
        slave.read_only |= args.modbus_read_only;
        Ok((map, slave))
    };
    if let Some(a) = &args.modbus {
        let addr = match softplc_serve::parse_addr(a) {
            Ok(a) => a,
            Err(e) => return fail(format!("--modbus {e}")),
        };
        let (map, slave) = match modbus_setup() {
            Ok(x) => x,
            Err(e) => return fail(e),
        };
        for w in map.check_devices(&cpu.config().devices) {
            eprintln!("softplc: [modbus]: {w}");
        }
        listeners.push(Listener::tcp(
            addr,
            ModbusTcp::new(map, slave),
            args.max_connections,
        ));
        names.push("Modbus TCP".to_string());
    }
    let parity = match args.parity.to_ascii_lowercase().as_str() {
        "none" | "n" => Parity::None,
        "even" | "e" => Parity::Even,
        "odd" | "o" => Parity::Odd,
        p => return fail(format!("--parity {p}: expected none, even or odd")),
    };
    let line = LineSettings {
        baud: args.baud,
        parity,
        stop_bits: args.stop_bits,
    };
    let mut serial_slaves = Vec::new();
    for (path, proto, name) in [
        (&args.modbus_rtu, Proto::Rtu, "Modbus RTU"),
        (&args.modbus_ascii, Proto::Ascii, "Modbus ASCII"),
    ] {
        let Some(path) = path else { continue };
        let (map, slave) = match modbus_setup() {
            Ok(x) => x,
            Err(e) => return fail(e),
        };
        let file = match serial::open(path, line) {
            Ok(f) => f,
            Err(e) => {
                return fail(format!(
                    "--{}: {e}",
                    name.to_ascii_lowercase().replace(' ', "-")
                ))
            }
        };
        serial_slaves.push(SerialSlave {
            line: file,
            proto,
            map,
            slave,
        });
        names.push(format!("{name} on {}", path.display()));
    }
    let realtime = softplc_serve::RealTime {
        fifo: !args.no_realtime,
        lock_memory: args.realtime,
        spin: args
            .spin_us
            .map_or(softplc_serve::RealTime::DEFAULT_SPIN, |us| {
                Duration::from_micros(us.into())
            }),
        cpu: args.cpu,
    };
    // Requests are served at every CPU's END: a quarter of the shortest period.
    let shortest = state.cpus.periods(period).into_iter().min();
    let shortest = shortest.unwrap_or(period);
    let cfg = EngineConfig {
        period,
        end_budget: (shortest / 4).max(Duration::from_micros(200)),
        queue: 1024,
        battery,
        log_every: args.stats_every,
        realtime,
        ack_after_commit: true,
    };
    let program = args.program.display().to_string();
    let time = match (args.lockstep, args.time_scale) {
        (true, Some(f)) => format!(", lockstep (advances at {f})"),
        (true, None) => ", lockstep".to_string(),
        (false, Some(f)) => format!(", virtual time at {f}"),
        (false, None) => String::new(),
    };
    let stop = Arc::new(AtomicBool::new(false));
    // APLC PORT1/PORT2: the communication phase after every END.
    let mut ports =
        match crate::run::open_ports(&ports, args.port1.as_deref(), args.port2.as_deref()) {
            Ok(p) => p,
            Err(e) => return fail(e),
        };
    for (path, n) in [(&args.port1, 1), (&args.port2, 2)] {
        if let Some(p) = path {
            names.push(format!("PORT{n} on {}", p.display()));
        }
    }
    if !ports.is_empty() {
        let rec = recorder.clone();
        state.add_hook(Box::new(move |st: &mut ServeState| {
            if let Some(r) = &rec {
                r.set_source(Source::Ports);
            }
            ports.after_end(st.cpu_mut());
            for e in ports.take_errors() {
                eprintln!("softplc: {e}");
            }
        }));
    }
    // Last: a client binds nothing, so the bound addresses stay in the
    // order of the servers' names.
    match mqtt_listener(&args, &state) {
        Ok(Some(l)) => {
            listeners.push(l.door("MQTT"));
            if let Some(url) = &args.mqtt {
                let broker = softplc_mqtt::Broker::parse(url).map(|b| b.display());
                names.push(format!("MQTT to {}", broker.unwrap_or_default()));
            }
        }
        Ok(None) => {}
        Err(e) => return fail(e),
    }
    let result = softplc_serve::run(state, cfg, listeners, serial_slaves, stop, |bound| {
        let mut servers: Vec<String> = names
            .iter()
            .zip(bound)
            .map(|(n, a)| format!("{n} on {a}"))
            .collect();
        servers.extend(names.iter().skip(bound.len()).cloned());
        if cpus.is_empty() {
            eprintln!(
                "softplc: serving {program}, constant scan {period:?}{time}{}{}",
                if servers.is_empty() { "" } else { "; " },
                servers.join(", ")
            );
        } else {
            eprintln!(
                "softplc: serving the multi-CPU system {program} ({} CPUs){time}{}{}",
                cpus.len(),
                if servers.is_empty() { "" } else { "; " },
                servers.join(", ")
            );
            for c in &cpus {
                eprintln!("softplc:   {c}");
            }
        }
    });
    let recorded = recorder.map(|r| r.finish());
    match result {
        Ok(s) => {
            let st = &s.stats;
            eprintln!(
                "softplc: stopped after {} scans; max scan {} us, {} overruns, {} requests",
                st.scans, st.max_us, st.overruns, st.requests
            );
            if let Some(path) = &args.timing_report {
                if let Err(e) = write_timing(path, &s) {
                    return fail(format!("--timing-report {}: {e}", path.display()));
                }
            }
            match recorded {
                Some(Ok((path, bytes))) => {
                    eprintln!("softplc: recorded to {} ({bytes} bytes)", path.display());
                    ExitCode::SUCCESS
                }
                Some(Err(e)) => fail(format!("--record: {e}")),
                None => ExitCode::SUCCESS,
            }
        }
        Err(e) => fail(format!("cannot serve: {e}")),
    }
}

/// `--timing-report FILE`: the figures of `GET /api/v1/timing` at exit.
fn write_timing(path: &std::path::Path, s: &ServeState) -> Result<(), String> {
    let json = softplc_http::timing::to_json(s);
    let text = serde_json::to_string_pretty(&json).map_err(|e| e.to_string())?;
    softplc_core::online::write_file(path, format!("{text}\n").as_bytes())
}
