//! What recording costs per END: a CPU scanned in virtual time with and
//! without a recorder (the clock recorded, the journal kept, one frame cut
//! and handed to the writer thread per END, a door write every 10th END).
//!
//! `cargo run --release -p softplc-record --example cost [ENDS]`

use std::time::Instant;

use softplc_core::access::{DeviceSpec, Value};
use softplc_core::engine::{Clock, Cpu, VirtualClock};
use softplc_core::program::compile_il;
use softplc_record::{Header, Recorder};

/// 100 rungs of contacts, a timer and word moves.
fn program() -> String {
    let mut p = String::new();
    for i in 0..100 {
        p.push_str(&format!(
            "LD M{i}\nAND X{i:X}\nOUT Y{i:X}\nLD SM400\nMOV D{i} D{}\n",
            i + 100
        ));
    }
    p.push_str("LD M0\nOUT T0 K50\nEND\n");
    p
}

fn cpu(clock: Box<dyn Clock>) -> Cpu {
    let cfg = softplc_core::profile::default_config();
    let prog = compile_il("cost.il", &program(), &cfg.devices).expect("the program loads");
    Cpu::new(prog, cfg, clock)
}

/// Mean µs per END over `ends`, with or without a recorder.
fn run(ends: u32, rec: Option<&Recorder>) -> f64 {
    let time = VirtualClock::new();
    let clock: Box<dyn Clock> = Box::new(time.clone());
    let mut c = match rec {
        Some(r) => {
            let mut c = cpu(r.clock(clock));
            c.set_journal(Some(r.journal()));
            c
        }
        None => cpu(clock),
    };
    let d0 = DeviceSpec::parse("D0").expect("D0");
    let t = Instant::now();
    for n in 0..ends {
        time.advance_us(10_000);
        c.scan();
        if n % 10 == 0 {
            let _ = c.write_value(&d0, &Value::Int(n as i64 & 0x7FFF));
        }
        if let Some(r) = rec {
            r.end(&c, u64::from(n) + 1);
        }
    }
    t.elapsed().as_secs_f64() * 1e6 / ends as f64
}

fn main() {
    let ends: u32 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100_000);
    let dir = std::env::temp_dir().join(format!("softplc-cost-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let path = dir.join("cost.rec");
    let header = Header {
        program: "cost.il".into(),
        project: false,
        model: None,
        cpu_model: "Q06HCPU".into(),
        files: Vec::new(),
        identity: String::new(),
        calendar_unix_s: 0,
        period_us: 10_000,
    };
    let plain = run(ends, None);
    let rec = Recorder::new();
    rec.start(&path, &header, u64::MAX)
        .expect("the recording opens");
    let recorded = run(ends, Some(&rec));
    let (_, bytes) = rec.finish().expect("the recording closes");
    let _ = std::fs::remove_dir_all(&dir);
    println!(
        "{ends} ENDs: {plain:.2} µs per END without recording, {recorded:.2} µs with \
         (+{:.2} µs); {:.1} bytes per END",
        recorded - plain,
        bytes as f64 / ends as f64
    );
}
