//! The GX Works2 CSV loader must never panic on any bytes.
#![no_main]
use libfuzzer_sys::fuzz_target;
use softplc_core::device::DeviceConfig;
use softplc_core::program::load_bytes;

fuzz_target!(|data: &[u8]| {
    let _ = load_bytes("fuzz.csv", data, &DeviceConfig::default());
});
