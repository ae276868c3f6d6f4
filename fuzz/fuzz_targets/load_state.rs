//! State files: no bytes make a load panic, and a refused file leaves the
//! CPU as it was. The input's length and checksum are made to fit (as a
//! deliberately edited file's would), so the checks of every section see it.
#![no_main]
use libfuzzer_sys::fuzz_target;
use softplc_core::engine::{Cpu, VirtualClock};
use softplc_core::program::compile_il;
use softplc_core::snapshot;

const SRC: &str = "LD X0\nOUT T0 K10\nLDP X1\nINC D0\nLD X0\nOUT C0 K3\nEND\n";

fuzz_target!(|data: &[u8]| {
    let cfg = softplc_core::profile::default_config();
    let prog = compile_il("fuzz.il", SRC, &cfg.devices).expect("the program loads");
    let mut cpu = Cpu::new(prog, cfg, Box::new(VirtualClock::new()));
    let before = snapshot::save(&mut cpu);
    // The CPU's own header, then the input as the body.
    let mut file = before[..snapshot::HEADER_LEN].to_vec();
    file.extend_from_slice(data);
    snapshot::reseal(&mut file);
    if snapshot::load(&mut cpu, &file).is_err() {
        assert!(snapshot::save(&mut cpu) == before, "a refused file changed the CPU");
    }
});
