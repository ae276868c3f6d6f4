//! A recorded session replays to the same CPU (in-process, without a
//! server: the door calls the servers make, between scans), and recordings
//! that are torn or damaged are read as far as they are whole or refused
//! with the byte offset — never a panic.

use softplc_core::access::{DeviceSpec, RBlock, Value};
use softplc_core::device::DeviceKind;
use softplc_core::engine::{Cpu, CpuState, VirtualClock};
use softplc_core::program::compile_il;
use softplc_record::format::Reader;
use softplc_record::{Ending, Header, Player, Recorder, SourceFile};

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
END
";

fn cpu(clock: Box<dyn softplc_core::engine::Clock>) -> Cpu {
    let cfg = softplc_core::profile::default_config();
    let prog = compile_il("p.il", PROGRAM, &cfg.devices).unwrap();
    Cpu::new(prog, cfg, clock)
}

fn header() -> Header {
    let files = vec![SourceFile {
        path: "p.il".into(),
        bytes: PROGRAM.as_bytes().to_vec(),
    }];
    Header {
        identity: Header::identity_of(&files, None),
        program: "p.il".into(),
        project: false,
        model: None,
        cpu_model: "Q06HCPU".into(),
        files,
        calendar_unix_s: 0,
        period_us: 10_000,
    }
}

/// Records 60 ENDs with writes of every kind between scans, at uneven
/// scan times; the CPU at the end and the recording.
fn record(path: &std::path::Path) -> Cpu {
    let rec = Recorder::new();
    let time = VirtualClock::new();
    let mut live = cpu(rec.clock(Box::new(time.clone())));
    live.set_journal(Some(rec.journal()));
    rec.start(path, &header(), 1 << 20).unwrap();
    let d = |s: &str| DeviceSpec::parse(s).unwrap();
    for n in 1..=60u64 {
        // Uneven periods, as a real clock gives.
        time.advance_us(9_000 + (n * 7919) % 3_000);
        live.scan();
        match n {
            5 => live.write_value(&d("D0"), &Value::Int(1234)).unwrap(),
            8 => {
                let s = live.span(DeviceKind::D, 10, 3, RBlock::First).unwrap();
                live.write_span_words(&s, &[7, 8, 9]).unwrap();
                let m = live.span(DeviceKind::M, 0, 1, RBlock::First).unwrap();
                live.write_span_bits(&m, &[true]).unwrap();
            }
            12 => live.set_bit(DeviceKind::M, 5, true).unwrap(),
            15 => live.force(DeviceKind::X, 1, true).unwrap(),
            20 => live.write_device(&d("D20"), "H7F").unwrap(),
            30 => live.set_stop(),
            33 => live.set_run().unwrap(),
            38 => live.force(DeviceKind::Y, 3, true).unwrap(),
            40 => {
                live.release(DeviceKind::X, 1);
            }
            42 => live.release_all(),
            45 => live.set_pause().unwrap(),
            50 => live.set_run().unwrap(),
            _ => {}
        }
        rec.end(&live, n);
    }
    rec.finish().unwrap();
    live
}

#[test]
fn a_recorded_session_replays_to_the_same_device_memory() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.rec");
    let live = record(&path);
    let mut player = Player::open(&path).unwrap();
    let mut again = cpu(Box::new(player.clock()));
    player.start(&mut [&mut again]).unwrap();
    while player.step(&mut [&mut again]).unwrap().is_some() {}
    assert_eq!(player.ending(), Some(Ending::Shutdown { scans: 52 }));
    assert_eq!(player.ends(), 60);
    // 60 ENDs, 3 in STOP (31-33) and 5 in PAUSE (46-50) execute nothing.
    assert_eq!(live.scans(), 52);
    assert_eq!(again.scans(), 52);
    assert_eq!(again.state(), CpuState::Run);
    assert_eq!(again.memory().words, live.memory().words);
    assert_eq!(again.memory().bits, live.memory().bits);
    let word = |c: &Cpu, s: &str| c.read_device(&DeviceSpec::parse(s).unwrap()).unwrap();
    assert_eq!(word(&again, "D2"), Value::Int(1234));
    assert_eq!(word(&again, "D41"), Value::Int(7));
    assert_eq!(word(&again, "D42"), Value::Int(0x7F));
    assert_eq!(word(&again, "D3"), Value::Int(52));
    // M0 set after END 8 (its period summed), T0 counting 100 ms steps since.
    assert_eq!(word(&again, "TN0"), word(&live, "TN0"));
    assert!(matches!(word(&again, "TN0"), Value::Int(t) if t > 0));
}

#[test]
fn a_changed_program_beside_the_recorded_one_sees_the_same_changes() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.rec");
    record(&path);
    let mut player = Player::open(&path).unwrap();
    let mut old = cpu(Box::new(player.clock()));
    let cfg = softplc_core::profile::default_config();
    // D41 gets twice D10 instead.
    let fixed = PROGRAM.replace("MOV D10 D41", "MOV D10 D41\n+ D10 D41");
    let prog = compile_il("p.il", &fixed, &cfg.devices).unwrap();
    let mut new = Cpu::new(prog, cfg, Box::new(player.clock()));
    player.start(&mut [&mut old, &mut new]).unwrap();
    let d41 = DeviceSpec::parse("D41").unwrap();
    let mut first = None;
    while let Some(end) = player.step(&mut [&mut old, &mut new]).unwrap() {
        if first.is_none() && old.read_device(&d41) != new.read_device(&d41) {
            first = Some((end.scans, old.read_device(&d41), new.read_device(&d41)));
        }
    }
    // M5 set after END 12 (scan 12): scan 13 moves D10 = 7 into D41.
    assert_eq!(first, Some((13, Ok(Value::Int(7)), Ok(Value::Int(14)))));
}

#[test]
fn a_torn_or_damaged_recording_is_read_as_far_as_it_is_whole() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.rec");
    record(&path);
    let bytes = std::fs::read(&path).unwrap();
    // Where each frame ends.
    let ends: Vec<usize> = {
        let mut r = Reader::new(&bytes[..], "s.rec").unwrap();
        let mut pos = 14;
        let mut ends = vec![];
        while let Some(rec) = r.read_record().unwrap() {
            pos += postcard::to_stdvec(&rec).unwrap().len() + 8;
            ends.push(pos);
        }
        ends
    };
    assert_eq!(*ends.last().unwrap(), bytes.len());
    // Every cut: the whole frames before it are read, a torn tail is named,
    // nothing panics.
    for cut in 14..bytes.len() {
        let mut r = Reader::new(&bytes[..cut], "cut").unwrap();
        let mut whole = 0;
        while r.read_record().unwrap().is_some() {
            whole += 1;
        }
        assert_eq!(
            whole,
            ends.iter().filter(|&&e| e <= cut).count(),
            "cut at {cut}"
        );
        assert_eq!(
            r.torn().is_some(),
            cut != 14 && !ends.contains(&cut),
            "cut at {cut}"
        );
    }
    assert!(Reader::new(&bytes[..13], "short").is_err());
    // A byte changed inside a frame with frames after it: refused, with where.
    let mut damaged = bytes.clone();
    damaged[bytes.len() / 2] ^= 0x55;
    let mut r = Reader::new(&damaged[..], "damaged.rec").unwrap();
    let err = loop {
        match r.read_record() {
            Ok(Some(_)) => continue,
            Ok(None) => panic!("the damage went unnoticed"),
            Err(e) => break e.to_string(),
        }
    };
    assert!(
        err.starts_with("damaged.rec: damaged frame at byte "),
        "{err}"
    );
    // Not a recording at all.
    let err = Reader::new(&b"LD X0\nOUT Y0\n"[..], "p.il").err().unwrap();
    assert!(err.to_string().contains("not a softplc recording"), "{err}");
    // Cut in its last END frame (the one before the shutdown record): the
    // replay stops at the END before it.
    let last_end = ends[ends.len() - 3];
    let torn = &bytes[..last_end as usize + 5];
    let mut player = Player::new(Reader::new(torn, "torn.rec").unwrap(), "torn.rec").unwrap();
    let mut again = cpu(Box::new(player.clock()));
    player.start(&mut [&mut again]).unwrap();
    while player.step(&mut [&mut again]).unwrap().is_some() {}
    assert_eq!(
        player.ending(),
        Some(Ending::Torn {
            at: last_end as u64
        })
    );
    assert_eq!(player.ends(), 59);
    assert_eq!(again.scans(), 51);
}

/// A program written during RUN, or a state file loaded, is not a door
/// write a replay could make: the recording stops at the END before it
/// (a `Stopped` record with the reason) and replays to that END exactly.
#[test]
fn a_program_written_or_a_state_loaded_during_recording_ends_it_there() {
    for case in ["program", "state"] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.rec");
        let rec = Recorder::new();
        let time = VirtualClock::new();
        let mut live = cpu(rec.clock(Box::new(time.clone())));
        live.set_journal(Some(rec.journal()));
        rec.start(&path, &header(), 1 << 20).unwrap();
        let saved = softplc_core::snapshot::save(&mut live);
        for n in 1..=20u64 {
            time.advance_us(10_000);
            live.scan();
            if n == 10 {
                match case {
                    "program" => {
                        let cfg = softplc_core::profile::default_config();
                        let p = compile_il(
                            "p.il",
                            &PROGRAM.replace("INC D3", "INC D3\nINC D3"),
                            &cfg.devices,
                        )
                        .unwrap();
                        live.replace_program(0, p).unwrap();
                    }
                    _ => softplc_core::snapshot::load(&mut live, &saved).unwrap(),
                }
            }
            rec.end(&live, n);
        }
        let _ = rec.finish();
        let mut player = Player::open(&path).unwrap();
        let mut again = cpu(Box::new(player.clock()));
        player.start(&mut [&mut again]).unwrap();
        while player.step(&mut [&mut again]).unwrap().is_some() {}
        let why = match case {
            "program" => "a program file was written during RUN",
            _ => "a state file was loaded",
        };
        assert_eq!(
            player.ending(),
            Some(Ending::Stopped {
                scans: 9,
                why: why.into()
            }),
            "{case}"
        );
        // The replay ends at END 9: D3 counts its scans.
        assert_eq!(again.scans(), 9, "{case}");
        assert_eq!(
            again.read_device(&DeviceSpec::parse("D3").unwrap()),
            Ok(Value::Int(9)),
            "{case}"
        );
    }
}
