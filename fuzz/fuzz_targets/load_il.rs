//! The `.il` loader must never panic: any bytes give a program or diagnostics.
#![no_main]
use libfuzzer_sys::fuzz_target;
use softplc_core::device::DeviceConfig;
use softplc_core::program::load_bytes;

fuzz_target!(|data: &[u8]| {
    let _ = load_bytes("fuzz.il", data, &DeviceConfig::default());
});
