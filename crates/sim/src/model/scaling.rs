//! A/D and D/A scaling between engineering units and the raw digital values of
//! MELSEC-Q analog modules.
//!
//! An A/D module converts a sensor signal to a digital value: [`to_raw`]
//! (linear, rounded half away from zero, clamped to the raw range). A D/A module
//! converts the digital value written by the program to an actuator signal:
//! [`from_raw`] (linear, not clamped; clamp the raw value first if the module
//! would). Ranges are `(value at the low end, value at the high end)`; either may
//! be decreasing (e.g. a reverse-acting signal `(100.0, 0.0)`).
//!
//! The usual raw ranges are the constants below, e.g. a 4–20 mA level
//! transmitter for 0–5 m on a Q64AD in normal resolution:
//! `to_raw(level, (0.0, 5.0), RAW_0_4000)`.

/// 0–2000 (A-series and some FX modules).
pub const RAW_0_2000: (i32, i32) = (0, 2000);
/// −2000…2000.
pub const RAW_PM_2000: (i32, i32) = (-2000, 2000);
/// 0–4000: Q64AD/Q64DA normal resolution, unipolar ranges (0–10 V, 0–5 V,
/// 1–5 V, 0–20 mA, 4–20 mA).
pub const RAW_0_4000: (i32, i32) = (0, 4000);
/// −4000…4000: normal resolution, −10…10 V.
pub const RAW_PM_4000: (i32, i32) = (-4000, 4000);
/// 0–12000: high resolution, 0–5 V, 1–5 V, 0–20 mA, 4–20 mA.
pub const RAW_0_12000: (i32, i32) = (0, 12000);
/// −12000…12000: high resolution, −5…5 V (D/A).
pub const RAW_PM_12000: (i32, i32) = (-12000, 12000);
/// 0–16000: high resolution, 0–10 V.
pub const RAW_0_16000: (i32, i32) = (0, 16000);
/// −16000…16000: high resolution, −10…10 V.
pub const RAW_PM_16000: (i32, i32) = (-16000, 16000);
/// 0–32000: Q64AD-GH / Q62DA-FG class modules.
pub const RAW_0_32000: (i32, i32) = (0, 32000);
/// −32000…32000.
pub const RAW_PM_32000: (i32, i32) = (-32000, 32000);

/// 0–10 V.
pub const V_0_10: (f64, f64) = (0.0, 10.0);
/// 0–5 V.
pub const V_0_5: (f64, f64) = (0.0, 5.0);
/// 1–5 V.
pub const V_1_5: (f64, f64) = (1.0, 5.0);
/// −10…10 V.
pub const V_PM_10: (f64, f64) = (-10.0, 10.0);
/// 4–20 mA.
pub const MA_4_20: (f64, f64) = (4.0, 20.0);
/// 0–20 mA.
pub const MA_0_20: (f64, f64) = (0.0, 20.0);

/// Engineering value → raw digital value, as an A/D module: linear map of
/// `eng_range` onto `raw_range`, rounded half away from zero, clamped to the
/// raw range. NaN, and any value when `eng_range` is empty (both ends equal),
/// give the raw range's first value.
pub fn to_raw(eng: f64, eng_range: (f64, f64), raw_range: (i32, i32)) -> i32 {
    let (e0, e1) = eng_range;
    let (r0, r1) = (f64::from(raw_range.0), f64::from(raw_range.1));
    let span = e1 - e0;
    if eng.is_nan() || span == 0.0 || !span.is_finite() {
        return raw_range.0;
    }
    let raw = (r0 + (eng - e0) / span * (r1 - r0)).round();
    // Both ends fit an i32, so the clamped value converts exactly.
    raw.clamp(r0.min(r1), r0.max(r1)) as i32
}

/// Raw digital value → engineering value, as a D/A module (or reading back an
/// A/D value): linear map of `raw_range` onto `eng_range`, not clamped. An
/// empty raw range (both ends equal) gives the engineering range's first value.
pub fn from_raw(raw: i32, raw_range: (i32, i32), eng_range: (f64, f64)) -> f64 {
    let (r0, r1) = raw_range;
    let (e0, e1) = eng_range;
    if r0 == r1 {
        return e0;
    }
    let frac = (f64::from(raw) - f64::from(r0)) / (f64::from(r1) - f64::from(r0));
    e0 + frac * (e1 - e0)
}

/// [`from_raw`] with the raw value first clamped to the raw range, as a D/A
/// module does with an out-of-range digital value.
pub fn from_raw_clamped(raw: i32, raw_range: (i32, i32), eng_range: (f64, f64)) -> f64 {
    let (lo, hi) = (raw_range.0.min(raw_range.1), raw_range.0.max(raw_range.1));
    from_raw(raw.clamp(lo, hi), raw_range, eng_range)
}
