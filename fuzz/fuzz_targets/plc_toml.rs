//! The plc.toml loader must never panic: any text gives a project or
//! diagnostics. Program files it names are looked up in an empty directory.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let dir = std::env::temp_dir().join("softplc-fuzz-empty");
        let _ = softplc_core::project::load_str("plc.toml", text, &dir);
    }
});
