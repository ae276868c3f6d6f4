//! `softplc serve --record` and `softplc replay` (contract §7): a session
//! served over HTTP, Modbus TCP and the MC protocol replays to the device
//! values the live CPU had at its last END; a server killed with SIGKILL
//! leaves a recording that replays to its last complete END; a changed
//! program beside the recorded one shows the first scan where it differs;
//! a damaged recording is refused with a clear error.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use softplc_record::event::Kind;
use softplc_record::format::{Reader, Record};
use softplc_record::{Change, Event, Source};

fn softplc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
}

const PROGRAM: &str = "\
LD SM400
INC D3
MOV D0 D2
LD M0
OUT T0 K20
LD X1
OUT Y1
LD M5
MOV D10 D41
LD SM400
MOV D20 D42
MOV D21 D43
END
";

struct Served {
    child: Child,
    http: u16,
    modbus: Option<String>,
    mc: Option<String>,
    /// The server's later stderr lines.
    stderr: std::sync::mpsc::Receiver<String>,
}

impl Drop for Served {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `softplc serve PROGRAM --record REC` with the web monitor (token `t`)
/// and `extra` servers, once they are bound.
fn serve(program: &Path, rec: &Path, extra: &[&str]) -> Served {
    let mut child = softplc()
        .arg("serve")
        .arg(program)
        .arg("--record")
        .arg(rec)
        .args(["--scan-time", "5ms", "--no-realtime"])
        .args(["--http", "127.0.0.1:0", "--http-token", "t"])
        .args(extra)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    while !line.contains("web monitor on ") {
        line.clear();
        assert!(err.read_line(&mut line).unwrap() > 0, "serve exited early");
    }
    let addr = |what: &str| {
        line.split(&format!("{what} on "))
            .nth(1)
            .map(|r| r.split([',', '\n']).next().unwrap().trim().to_string())
    };
    let http = addr("web monitor").unwrap();
    let http = http.rsplit(':').next().unwrap().parse().unwrap();
    let (modbus, mc) = (addr("Modbus TCP"), addr("MC protocol"));
    let (tx, stderr) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for l in err.lines() {
            let _ = tx.send(l.unwrap_or_default());
        }
    });
    Served {
        child,
        http,
        modbus,
        mc,
        stderr,
    }
}

fn request(port: u16, method: &str, path: &str, body: &str) -> serde_json::Value {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    write!(
        s,
        "{method} {path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\nAuthorization: Bearer t\r\n\
         Content-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    let mut out = String::new();
    s.read_to_string(&mut out).unwrap();
    assert!(out.starts_with("HTTP/1.1 200"), "{method} {path}: {out}");
    let body = out.split("\r\n\r\n").nth(1).unwrap();
    serde_json::from_str(body).unwrap()
}

/// A Modbus TCP request; the response.
fn modbus(addr: &str, pdu: &[u8]) -> Vec<u8> {
    let mut c = TcpStream::connect(addr).unwrap();
    c.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let mut req = vec![0, 1, 0, 0];
    req.extend_from_slice(&(pdu.len() as u16 + 1).to_be_bytes());
    req.push(1);
    req.extend_from_slice(pdu);
    c.write_all(&req).unwrap();
    let mut head = [0u8; 6];
    c.read_exact(&mut head).unwrap();
    let mut rest = vec![0u8; u16::from_be_bytes([head[4], head[5]]) as usize];
    c.read_exact(&mut rest).unwrap();
    rest
}

/// MC protocol 3E binary batch write of words from D`first` (1401).
fn mc_write_d(addr: &str, first: u32, words: &[u16]) {
    let mut c = TcpStream::connect(addr).unwrap();
    c.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let mut body = vec![0x10, 0x00, 0x01, 0x14, 0x00, 0x00];
    body.extend_from_slice(&first.to_le_bytes()[..3]);
    body.push(0xA8);
    body.extend_from_slice(&(words.len() as u16).to_le_bytes());
    for w in words {
        body.extend_from_slice(&w.to_le_bytes());
    }
    let mut req = vec![0x50, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00];
    req.extend_from_slice(&(body.len() as u16).to_le_bytes());
    req.extend_from_slice(&body);
    c.write_all(&req).unwrap();
    let mut resp = [0u8; 11];
    c.read_exact(&mut resp).unwrap();
    assert_eq!(&resp[9..11], &[0, 0], "MC end code");
}

fn sigterm(child: &mut Child) {
    let ok = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(ok.success());
    let st = child.wait().unwrap();
    assert!(st.success(), "serve: {st}");
}

/// `softplc replay` with `args`; its JSON.
fn replay(rec: &Path, args: &[String]) -> serde_json::Value {
    let out = softplc()
        .arg("replay")
        .arg(rec)
        .arg("--json")
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

fn program(dir: &Path, text: &str) -> PathBuf {
    let p = dir.join("p.il");
    std::fs::write(&p, text).unwrap();
    p
}

/// The devices compared: D0-D99, M0-M99, X0-X1F, Y0-Y1F, T0-T9 and their
/// current values.
fn wide() -> Vec<String> {
    let mut v = Vec::new();
    for n in 0..100 {
        v.push(format!("D{n}"));
        v.push(format!("M{n}"));
    }
    for n in 0..32 {
        v.push(format!("X{n:X}"));
        v.push(format!("Y{n:X}"));
    }
    for n in 0..10 {
        v.push(format!("T{n}"));
        v.push(format!("TN{n}"));
    }
    v
}

#[test]
fn a_served_session_replays_to_the_devices_of_its_last_end() {
    let dir = tempfile::tempdir().unwrap();
    let p = program(dir.path(), PROGRAM);
    let rec = dir.path().join("session.rec");
    let mut s = serve(
        &p,
        &rec,
        &["--modbus", "127.0.0.1:0", "--mc", "127.0.0.1:0"],
    );
    // HTTP: D0, M0 (starts T0) and X1 forced ON.
    request(
        s.http,
        "POST",
        "/api/v1/devices",
        r#"{"D0": 1234, "M0": true}"#,
    );
    request(s.http, "POST", "/api/v1/force", r#"{"X1": true}"#);
    // Modbus: FC16 D10-D12 = 7, 8, 9; FC05 coil 8197 = M5 ON.
    let mb = s.modbus.clone().unwrap();
    let r = modbus(&mb, &[16, 0, 10, 0, 3, 6, 0, 7, 0, 8, 0, 9]);
    assert_eq!(r[1], 16);
    let r = modbus(&mb, &[5, 0x20, 0x05, 0xFF, 0x00]);
    assert_eq!(r[1], 5);
    // MC: D20-D21 = 0x1111, 0x2222.
    mc_write_d(&s.mc.clone().unwrap(), 20, &[0x1111, 0x2222]);
    // Let T0 count, then STOP: the devices hold still to be read.
    std::thread::sleep(Duration::from_millis(300));
    request(s.http, "POST", "/api/v1/cpu/stop", "");
    let names = wide();
    let live = request(
        s.http,
        "GET",
        &format!("/api/v1/devices?names={}", names.join(",")),
        "",
    );
    sigterm(&mut s.child);
    let args: Vec<String> = names
        .iter()
        .flat_map(|n| ["--show".into(), n.clone()])
        .collect();
    let again = replay(&rec, &args);
    assert_eq!(again["devices"], live["devices"]);
    assert_eq!(again["scans"], live["scan"]);
    assert_eq!(again["state"], "STOP");
    assert_eq!(again["recording"]["ending"], "shutdown");
    let d = &again["devices"];
    assert_eq!(d["D2"], 1234);
    assert_eq!(d["D41"], 7);
    assert_eq!(d["D42"], 0x1111);
    assert_eq!(d["D43"], 0x2222);
    assert_eq!(d["Y1"], true);
    // D3 counts the scans since power-on.
    assert_eq!(d["D3"], again["scans"]);
    // Each change is named by the door it came through.
    let changes = changes(&rec);
    let by = |source: Source| -> Vec<&Change> {
        changes
            .iter()
            .filter(|e| e.source == source)
            .map(|e| &e.change)
            .collect()
    };
    // Modbus writes register by register.
    for (n, v) in [(10, 7), (11, 8), (12, 9)] {
        assert!(by(Source::Modbus).contains(&&Change::Words {
            kind: Kind("D".into()),
            number: n,
            selected_block: false,
            values: vec![v],
        }));
    }
    assert!(by(Source::Modbus).contains(&&Change::Bits {
        kind: Kind("M".into()),
        number: 5,
        selected_block: false,
        values: vec![true],
    }));
    assert!(by(Source::Mc).contains(&&Change::Words {
        kind: Kind("D".into()),
        number: 20,
        selected_block: false,
        values: vec![0x1111, 0x2222],
    }));
    assert!(by(Source::Http).contains(&&Change::Force {
        kind: Kind("X".into()),
        n: 1,
        on: true,
    }));
    assert!(by(Source::Http).contains(&&Change::Stop));
    // --log tells them as they are replayed, with the scan of their END.
    let out = softplc()
        .arg("replay")
        .arg(&rec)
        .arg("--log")
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&out.stderr);
    for line in [
        " HTTP: D0 = 1234",
        " HTTP: force X1 ON",
        " Modbus: D10.. = 7",
        " MC: D20.. = 4369 8738",
        " HTTP: STOP",
    ] {
        assert!(
            log.lines()
                .any(|l| l.starts_with("scan ") && l.ends_with(line)),
            "{line} in {log}"
        );
    }
}

/// Every change from outside a recording holds, in order.
fn changes(rec: &Path) -> Vec<Event> {
    let mut r = Reader::open(rec).unwrap();
    let mut out = Vec::new();
    while let Some(x) = r.read_record().unwrap() {
        if let Record::End(e) = x {
            out.extend(e.events);
        }
    }
    out
}

#[test]
fn a_killed_server_replays_to_its_last_complete_end() {
    let dir = tempfile::tempdir().unwrap();
    let p = program(dir.path(), PROGRAM);
    let rec = dir.path().join("killed.rec");
    let mut s = serve(&p, &rec, &[]);
    let at = request(s.http, "POST", "/api/v1/devices", r#"{"D0": 4321}"#)["scan"]
        .as_u64()
        .unwrap();
    // The END's frame is written by the recording thread right after it.
    std::thread::sleep(Duration::from_millis(300));
    s.child.kill().unwrap();
    s.child.wait().unwrap();
    let again = replay(
        &rec,
        &["--show".into(), "D2".into(), "--show".into(), "D3".into()],
    );
    let scans = again["scans"].as_u64().unwrap();
    assert!(
        scans > at,
        "replayed to scan {scans}, the write was at {at}"
    );
    assert_eq!(again["devices"]["D2"], 4321);
    assert_eq!(again["devices"]["D3"], scans);
    let ending = again["recording"]["ending"].as_str().unwrap();
    assert!(ending == "killed" || ending == "torn", "{ending}");
    // The incident's last state goes on with `run --load-state`.
    let state = dir.path().join("incident.state");
    replay(
        &rec,
        &["--save-state".into(), state.to_str().unwrap().into()],
    );
    let out = softplc()
        .arg("run")
        .arg(&p)
        .args(["--load-state", state.to_str().unwrap()])
        .args(["--scans", "5", "--show", "D2", "--show", "D3", "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let went_on: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(went_on["devices"]["D2"], 4321);
    assert_eq!(went_on["devices"]["D3"], scans + 5);
}

#[test]
fn a_changed_program_reports_where_it_first_differs() {
    let dir = tempfile::tempdir().unwrap();
    let p = program(dir.path(), PROGRAM);
    let rec = dir.path().join("incident.rec");
    let mut s = serve(&p, &rec, &[]);
    let at = request(
        s.http,
        "POST",
        "/api/v1/devices",
        r#"{"M5": true, "D10": 21}"#,
    )["scan"]
        .as_u64()
        .unwrap();
    std::thread::sleep(Duration::from_millis(100));
    request(s.http, "POST", "/api/v1/cpu/stop", "");
    sigterm(&mut s.child);
    // The fix adds D10 once more into D41.
    let fixed = dir.path().join("fixed.il");
    std::fs::write(
        &fixed,
        PROGRAM.replace("MOV D10 D41", "MOV D10 D41\n+ D10 D41"),
    )
    .unwrap();
    let args: Vec<String> = ["--program", fixed.to_str().unwrap()]
        .iter()
        .chain(&["--diverge", "D41", "--diverge", "D3", "--show", "D41"])
        .map(|s| s.to_string())
        .collect();
    let r = replay(&rec, &args);
    // Written at END `at`: scan at + 1 is the first with M5 ON.
    assert_eq!(r["diverge"]["D41"]["scan"], at + 1);
    assert_eq!(r["diverge"]["D41"]["recorded"], 21);
    assert_eq!(r["diverge"]["D41"]["new"], 42);
    assert_eq!(r["diverge"]["D3"], serde_json::Value::Null);
    // The report is the recorded program's.
    assert_eq!(r["devices"]["D41"], 21);
}

#[test]
fn damaged_recordings_are_refused_with_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let p = program(dir.path(), PROGRAM);
    let rec = dir.path().join("short.rec");
    let mut s = serve(&p, &rec, &[]);
    request(s.http, "POST", "/api/v1/devices", r#"{"D0": 5}"#);
    sigterm(&mut s.child);
    let bytes = std::fs::read(&rec).unwrap();
    let run = |data: &[u8]| {
        let f = dir.path().join("bad.rec");
        std::fs::write(&f, data).unwrap();
        let out = softplc().arg("replay").arg(&f).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(!err.contains("panicked"), "{err}");
        (out.status.code(), err)
    };
    // Not a recording.
    let (code, err) = run(b"LD X0\nOUT Y0\nEND\n");
    assert_eq!(code, Some(2));
    assert!(err.contains("not a softplc recording"), "{err}");
    // Cut inside the header: nothing to replay.
    let (code, err) = run(&bytes[..40]);
    assert_eq!(code, Some(2));
    assert!(err.contains("ends before its first frames"), "{err}");
    // A byte of the program text in the header changed: the frame and its
    // offset (after the 14-byte magic line) are named.
    let mut damaged = bytes.clone();
    damaged[14 + 8 + 10] ^= 0xA5;
    let (code, err) = run(&damaged);
    assert_eq!(code, Some(2));
    assert!(
        err.contains("damaged frame at byte 14: its checksum does not match"),
        "{err}"
    );
    // Cut anywhere after the start: replays what is whole.
    for cut in [bytes.len() - 1, bytes.len() - 7, bytes.len() * 9 / 10] {
        let (code, err) = run(&bytes[..cut]);
        assert_eq!(code, Some(0), "cut at {cut}: {err}");
    }
}

#[test]
fn an_aplc_program_replays_with_its_names() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("t.apl");
    std::fs::write(&p, "LD X10\nOUT Y10\nLD M1\nDIV 1 D0 D2\n").unwrap();
    let rec = dir.path().join("aplc.rec");
    let mut s = serve(&p, &rec, &[]);
    let body = r#"{"D10:i32": 100000, "X10": true, "D20": "16#1F", "D0": 9, "M1": true}"#;
    request(s.http, "POST", "/api/v1/devices", body);
    std::thread::sleep(Duration::from_millis(50));
    request(s.http, "POST", "/api/v1/cpu/stop", "");
    let names = [
        "D0", "D2", "D10", "D11:u16", "D10:i32", "Y10", "X10", "D20", "M1",
    ];
    let live = request(
        s.http,
        "GET",
        &format!("/api/v1/devices?names={}", names.join(",")),
        "",
    );
    sigterm(&mut s.child);
    let args: Vec<String> = names
        .iter()
        .flat_map(|n| ["--show".into(), n.to_string()])
        .collect();
    let again = replay(&rec, &args);
    assert_eq!(again["devices"], live["devices"]);
    let d = &again["devices"];
    // 100000 = 16#0001_86A0, the high word first in D10.
    assert_eq!(d["D10"], 1);
    assert_eq!(d["D11:u16"], 34464);
    assert_eq!(d["Y10"], true);
    assert_eq!(d["D20"], 31);
    assert_eq!(again["recording"]["model"], "APLC-TCP");
}

#[test]
fn a_project_replays_with_the_battery_backed_image_it_started_from() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("plc.toml"),
        "[[program]]\nfile = \"p.il\"\n[devices]\nfile_register = 1024\n\
         [latch]\nlatch1 = [\"D0-D99\"]\n",
    )
    .unwrap();
    program(dir.path(), PROGRAM);
    // A first session leaves D0 and D50 in the state directory.
    let first = dir.path().join("first.rec");
    let mut s = serve(dir.path(), &first, &[]);
    request(
        s.http,
        "POST",
        "/api/v1/devices",
        r#"{"D0": 777, "D50": 5}"#,
    );
    sigterm(&mut s.child);
    // The recorded one starts from them.
    let rec = dir.path().join("second.rec");
    let mut s = serve(dir.path(), &rec, &[]);
    request(s.http, "POST", "/api/v1/devices", r#"{"D60": 6}"#);
    std::thread::sleep(Duration::from_millis(50));
    request(s.http, "POST", "/api/v1/cpu/stop", "");
    let names = ["D0", "D2", "D3", "D50", "D60"];
    let live = request(
        s.http,
        "GET",
        &format!("/api/v1/devices?names={}", names.join(",")),
        "",
    );
    sigterm(&mut s.child);
    let args: Vec<String> = names
        .iter()
        .flat_map(|n| ["--show".into(), n.to_string()])
        .collect();
    let again = replay(&rec, &args);
    assert_eq!(again["devices"], live["devices"]);
    let d = &again["devices"];
    assert_eq!(d["D0"], 777);
    assert_eq!(d["D2"], 777);
    assert_eq!(d["D50"], 5);
    assert_eq!(d["D60"], 6);
    // D3 is latched too: both sessions' scans.
    assert!(d["D3"].as_u64().unwrap() > again["scans"].as_u64().unwrap());
    // The project's files are embedded, not its state directory or recordings.
    let mut r = Reader::open(&rec).unwrap();
    let Some(Record::Header(h)) = r.read_record().unwrap() else {
        panic!("no header");
    };
    let files: Vec<&str> = h.files.iter().map(|f| f.path.as_str()).collect();
    assert_eq!(files, ["p.il", "plc.toml"]);
    assert!(h.project);
    assert!(changes(&rec)
        .iter()
        .any(|e| e.source == Source::Host && matches!(e.change, Change::Retained { .. })));
}

#[test]
fn a_multi_cpu_system_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let system = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/multi_cpu");
    let out = softplc()
        .arg("serve")
        .arg(&system)
        .arg("--record")
        .arg(dir.path().join("x.rec"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--record: a multi-CPU system cannot be recorded yet"),
        "{err}"
    );
    assert!(!dir.path().join("x.rec").exists());
}

#[test]
fn recording_stops_at_its_size_bound_and_replays_to_there() {
    let dir = tempfile::tempdir().unwrap();
    let p = program(dir.path(), PROGRAM);
    let rec = dir.path().join("bounded.rec");
    let mut s = serve(&p, &rec, &["--record-max-size", "4KiB"]);
    request(s.http, "POST", "/api/v1/devices", r#"{"D0": 99}"#);
    // About 16 bytes per END: the bound comes after some 200 ENDs.
    let line = loop {
        let l = s.stderr.recv_timeout(Duration::from_secs(60)).unwrap();
        if l.contains("--record-max-size") {
            break l;
        }
    };
    assert!(
        line.contains("recording stopped, the server runs on"),
        "{line}"
    );
    sigterm(&mut s.child);
    assert!(std::fs::metadata(&rec).unwrap().len() <= 4096);
    let again = replay(
        &rec,
        &["--show".into(), "D2".into(), "--show".into(), "D3".into()],
    );
    assert_eq!(again["recording"]["ending"], "full");
    assert_eq!(again["devices"]["D2"], 99);
    assert_eq!(again["devices"]["D3"], again["scans"]);
}
