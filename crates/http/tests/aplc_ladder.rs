//! The web monitor on an APLC-TCP program: the ladder page draws the `.apl`
//! source with APLC device names, and RESET restarts the `scan` count.

mod common;

use std::time::Duration;

use common::{get, send, start_cpu, Server, TOKEN};
use softplc_core::engine::{Cpu, MonotonicClock};
use softplc_http::HttpConfig;

/// A global on octal X10 (input 8), a MAIN TEMP, a timer and a CALL.
const APL: &str = "VAR_GLOBAL\n  急停 X10 // emergency stop\nEND_VAR\n\
POU SBR_1\nVAR\n  A IN INT\n  B OUT INT\nEND_VAR\nLD SM0\nMOV #A #B\n\
POU MAIN\nVAR\n  OK TEMP BOOL\nEND_VAR\n// run while not stopped\nLDI 急停\nOUT #OK\nLD #OK\nOUT Y0\n\
LD X0\nTON T1 30\nLD SM0\nCALL SBR_1 7 D0\n";

fn start() -> Server {
    let program = softplc_core::aplc::load_bytes("main.apl", APL.as_bytes()).unwrap();
    let cfg = softplc_core::aplc::cpu_config();
    let cpu = Cpu::new(program, cfg, Box::new(MonotonicClock::default()));
    let http = HttpConfig {
        token: Some(TOKEN.into()),
        model: softplc_core::profile::aplc().model.into(),
        ladder: vec![softplc_http::ladder::aplc::from_bytes("main.apl", APL.as_bytes()).unwrap()],
        limits: Default::default(),
        online: None,
    };
    start_cpu(cpu, http)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_ladder_of_an_apl_program_has_aplc_names() {
    let s = start();
    let r = get(s.addr, "/").await;
    assert_eq!(r.status, 200);
    let b = &r.body;
    // POU sections in file order, the MAIN's TEMP and the rung comment.
    let sbr = b
        .find(r#"<h3 class="pou">SBR_1</h3>"#)
        .expect("SBR_1's heading");
    let main = b
        .find(r#"<h3 class="pou">MAIN</h3>"#)
        .expect("MAIN's heading");
    assert!(sbr < main);
    assert!(b.contains("VAR OK TEMP BOOL = LM0"), "{b}");
    assert!(
        b.contains(r#"<p class="note">run while not stopped</p>"#),
        "{b}"
    );
    // The global drawn with its octal device, which is what is read and clicked.
    assert!(
        b.contains(r#"class="el k-nc" id="e0-2" data-dev="X10""#),
        "{b}"
    );
    assert!(b.contains(">急停=X10</text>"), "{b}");
    assert!(
        b.contains(r#"data-dev="LM0""#) && b.contains("#OK=LM0"),
        "{b}"
    );
    assert!(b.contains("CALL SBR_1 A:=7 B:=D0"), "{b}");
    // Subscribed names: APLC names; the subroutine's V locals are not.
    assert!(
        b.contains(r#"data-names="SM0,X10,LM0,Y0,X0,T1,TN1,D0""#),
        "{b}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_ladder_text_of_an_apl_program() {
    let s = start();
    let r = get(s.addr, "/ladder.txt").await;
    assert_eq!(r.status, 200);
    assert!(r.headers.contains("text/plain"), "{}", r.headers);
    assert_eq!(
        r.body,
        "== SBR_1 A IN INT = V0, B OUT INT = V1\n\
         |--| SM0 |----[MOV #A=V0 #B=V1]\n\
         == MAIN OK TEMP BOOL = LM0\n\
         // run while not stopped\n\
         |--|/X10 |----( LM0 )\n\
         |--| LM0 |----( Y0 )\n\
         |---| X0 |----[TON T1 30]\n\
         |--| SM0 |----[CALL SBR_1 A:=7 B:=D0]\n"
    );
    assert_eq!(get(s.addr, "/ladder.txt?prog=1").await.status, 404);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn reset_restarts_the_scan_count() {
    let s = start();
    // Let the CPU count a few hundred scans, then STOP and RESET.
    let mut before = 0;
    while before < 300 {
        tokio::time::sleep(Duration::from_millis(50)).await;
        before = get(s.addr, "/api/v1/status").await.json()["scan"]
            .as_u64()
            .unwrap();
    }
    assert_eq!(
        send(s.addr, "POST", "/api/v1/cpu/stop", None).await.status,
        200
    );
    let stopped = get(s.addr, "/api/v1/status").await.json()["scan"]
        .as_u64()
        .unwrap();
    assert!(stopped >= before);
    let r = send(s.addr, "POST", "/api/v1/cpu/reset", None).await;
    assert_eq!(r.status, 200, "{}", r.body);
    let r = send(s.addr, "POST", "/api/v1/cpu/pause", None).await;
    assert_eq!(r.status, 200, "{}", r.body);
    let after = get(s.addr, "/api/v1/status").await.json()["scan"]
        .as_u64()
        .unwrap();
    // Power-on processing counts from 0 again: far below the count at STOP.
    assert!(after < stopped, "{after} after RESET, {stopped} before");
    // A step of 3 scans adds exactly 3 from there.
    let r = send(s.addr, "POST", "/api/v1/cpu/step?scans=3", None).await;
    assert_eq!(r.json()["scan"].as_u64(), Some(after + 3));
}
