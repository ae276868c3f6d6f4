//! The scenario parser must never panic: any text gives a scenario or an error.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = softplc_sim::scenario::Scenario::parse(text, std::path::Path::new("fuzz.toml"));
    }
});
