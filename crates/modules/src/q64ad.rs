//! `Q64AD`: the 4-channel analog-digital converter module, in normal
//! resolution mode (Analog-Digital Converter Module User's Manual (Q64AD,
//! Q68ADV, Q68ADI), SH-080055: I/O signals, buffer memory assignment, A/D
//! conversion methods, error codes). docs/modules.md has the full map.
//!
//! Buffer memory (Un\G…): 0 A/D conversion enable/disable (bit k = CH k+1,
//! 1 = disabled; default 0: all enabled), 1-4 CH1-CH4 averaging time (ms) or
//! count, 9 averaging processing specification (b0-b3 averaging instead of
//! sampling, b8-b11 time instead of count), 10 A/D conversion completed
//! flags, 11-14 CH1-CH4 digital output values, 19 error code, 20 setting
//! range (switch 1's codes), 30-37 CH1-CH4 maximum and minimum values.
//! Signals: X0 module READY, X9 operating condition setting completed, XD
//! maximum/minimum value reset completed, XE A/D conversion completed, XF
//! error; Y9 operating condition setting request, YD maximum/minimum value
//! reset request, YF error clear request.
//!
//! Time: the module converts its enabled channels in turn, 80 µs each, in
//! the CPU's virtual time (`now_us` at END). The physical input a plant
//! model set holds for every conversion until the next END; sampling
//! processing stores the present conversion at each END (a conversion
//! cycle is far shorter than a scan).

use std::ops::RangeInclusive;

use softplc_ir::rack::{Module, ModuleIo, ModuleProfile, Slot, SlotType};
use softplc_ir::snapshot::{Snap, StateError};

use crate::analog::{self, get, set, Range, MA_0_20, MA_4_20, V_0_10, V_0_5, V_10_10, V_1_5};

pub static Q64AD: ModuleProfile = ModuleProfile {
    name: "Q64AD",
    kind: SlotType::Intelligent,
    points: 16,
    buffer_words: BUFFER_WORDS,
    pointers: None,
    causes: 0,
    manual: "Analog-Digital Converter Module User's Manual (Q64AD, Q68ADV, Q68ADI), SH-080055",
    new,
    switches: Some(switch_setting),
};

/// The input ranges of switch 1 (user range setting, code F, is not
/// simulated).
pub const RANGES: &[Range] = &[MA_4_20, MA_0_20, V_1_5, V_0_5, V_10_10, V_0_10];

const CHANNELS: usize = 4;
/// Un\G0-217: the last assigned word is CH4's user range gain value.
const BUFFER_WORDS: u32 = 218;

const G_ENABLE: usize = 0;
/// CH1's averaging time or count; CH2-CH4 follow.
const G_AVERAGE: usize = 1;
const G_PROCESSING: usize = 9;
const G_COMPLETED: usize = 10;
/// CH1's digital output value; CH2-CH4 follow.
const G_VALUE: usize = 11;
const G_ERROR: usize = 19;
const G_RANGE: usize = 20;
/// CH1's maximum value, CH1's minimum value, CH2's maximum value …
const G_MAX_MIN: usize = 30;

const X_READY: usize = 0x0;
const X_SETTING_DONE: usize = 0x9;
const X_MAX_MIN_RESET_DONE: usize = 0xD;
const X_CONVERTED: usize = 0xE;
const X_ERROR: usize = 0xF;
const Y_SETTING_REQUEST: usize = 0x9;
const Y_MAX_MIN_RESET: usize = 0xD;
const Y_ERROR_CLEAR: usize = 0xF;

/// Conversion time per channel.
const CONVERSION_US: u64 = 80;
/// Time averaging: ms.
const AVERAGE_TIME: RangeInclusive<u16> = 2..=5000;
/// Count averaging: conversions.
const AVERAGE_COUNT: RangeInclusive<u16> = 4..=62500;
/// Error codes 20□ (averaging time out of range) and 30□ (count), □ the
/// channel.
const ERROR_TIME: u16 = 200;
const ERROR_COUNT: u16 = 300;

/// How a channel's digital output value is made.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Processing {
    Sampling,
    /// Averaging over this many ms.
    Time(u16),
    /// Averaging over this many conversions.
    Count(u16),
}

/// The conversions of an averaging period so far. The average leaves out
/// one maximum and one minimum value (SH-080055, A/D conversion methods).
#[derive(Clone, Copy, Debug, Default)]
struct Average {
    n: u64,
    sum: i64,
    max: i32,
    min: i32,
}

impl Average {
    /// Adds `k` conversions of value `d` to periods of `period` conversions
    /// (at least 3); the last period completed, if any.
    fn add(&mut self, mut k: u64, d: i32, period: u64) -> Option<i32> {
        let mut done = None;
        while k > 0 {
            if self.n == 0 && k >= period {
                // Whole periods of one value average to it.
                k %= period;
                done = Some(d);
                continue;
            }
            let take = k.min(period - self.n);
            if self.n == 0 {
                (self.max, self.min) = (d, d);
            }
            self.n += take;
            self.sum += take as i64 * i64::from(d);
            self.max = self.max.max(d);
            self.min = self.min.min(d);
            k -= take;
            if self.n == period {
                let kept = self.sum - i64::from(self.max) - i64::from(self.min);
                done = Some((kept / (period as i64 - 2)) as i32);
                *self = Average::default();
            }
        }
        done
    }
}

fn new(slot: &Slot) -> Box<dyn Module> {
    // The switch setting was checked at load (`switch_setting`).
    let ranges = analog::ranges_of(RANGES, CHANNELS, slot.switches[0]).unwrap_or_default();
    let mut r = [MA_4_20; CHANNELS];
    for (to, from) in r.iter_mut().zip(ranges) {
        *to = from;
    }
    Box::new(Q64ad {
        ranges: r,
        input: [0.0; CHANNELS],
        state: State::default(),
    })
}

/// The switch setting of a Q64AD slot: switch 1 the input ranges (from
/// `range` names or given), switches 2-5 0 (switch 4 ≠ 0 selects the
/// offset/gain setting mode or high resolution mode, not simulated).
pub(crate) fn switch_setting(
    range: Option<&[&str]>,
    switches: Option<[u16; 5]>,
) -> Result<[u16; 5], String> {
    analog::switch_setting(RANGES, CHANNELS, "input", &[1, 2, 3, 4], range, switches)
}

#[derive(Debug)]
struct Q64ad {
    ranges: [Range; CHANNELS],
    /// The physical value at each input (mA or V), kept over a CPU reset:
    /// it is the plant's.
    input: [f64; CHANNELS],
    state: State,
}

/// What power-on resets.
#[derive(Debug)]
struct State {
    enabled: [bool; CHANNELS],
    processing: [Processing; CHANNELS],
    average: [Average; CHANNELS],
    /// When the conversion cycles under the present settings began, and
    /// how many have run.
    start_us: Option<u64>,
    cycles: u64,
    /// Digital output values and their completed flags (bit k = CH k+1).
    value: [i32; CHANNELS],
    completed: u16,
    /// Maximum and minimum values since power-on or the last reset.
    max_min: [Option<(i32, i32)>; CHANNELS],
    error: u16,
    /// Y9 at the previous END.
    setting_request: bool,
}

impl Default for State {
    fn default() -> State {
        State {
            enabled: [true; CHANNELS],
            processing: [Processing::Sampling; CHANNELS],
            average: [Average::default(); CHANNELS],
            start_us: None,
            cycles: 0,
            value: [0; CHANNELS],
            completed: 0,
            max_min: [None; CHANNELS],
            error: 0,
            setting_request: false,
        }
    }
}

impl Q64ad {
    /// Y9 turned ON: the settings in buffer memory take effect (the
    /// completed flags restart), or the error code of the first bad one.
    fn apply_settings(&mut self, buffer: &[u16]) {
        let word = |g: usize| buffer.get(g).copied().unwrap_or(0);
        let mut enabled = [false; CHANNELS];
        let mut processing = [Processing::Sampling; CHANNELS];
        for ch in 0..CHANNELS {
            enabled[ch] = word(G_ENABLE) >> ch & 1 == 0;
            let mode = word(G_PROCESSING);
            if mode >> ch & 1 == 0 {
                continue;
            }
            let v = word(G_AVERAGE + ch);
            let number = ch as u16 + 1;
            processing[ch] = if mode >> (8 + ch) & 1 != 0 {
                if enabled[ch] && !AVERAGE_TIME.contains(&v) {
                    self.state.error = ERROR_TIME + number;
                    return;
                }
                Processing::Time(v)
            } else {
                if enabled[ch] && !AVERAGE_COUNT.contains(&v) {
                    self.state.error = ERROR_COUNT + number;
                    return;
                }
                Processing::Count(v)
            };
        }
        let s = &mut self.state;
        s.enabled = enabled;
        s.processing = processing;
        s.average = [Average::default(); CHANNELS];
        s.start_us = None;
        s.cycles = 0;
        s.completed = 0;
    }

    /// Stores a digital output value of channel `ch`.
    fn store(&mut self, ch: usize, d: i32) {
        let s = &mut self.state;
        s.value[ch] = d;
        s.completed |= 1 << ch;
        s.max_min[ch] = Some(match s.max_min[ch] {
            Some((max, min)) => (max.max(d), min.min(d)),
            None => (d, d),
        });
    }

    /// The conversions since the last END.
    fn convert(&mut self, now_us: u64) {
        let channels = self.state.enabled.iter().filter(|e| **e).count() as u64;
        if channels == 0 {
            return;
        }
        let cycle_us = CONVERSION_US * channels;
        let start = *self.state.start_us.get_or_insert(now_us);
        let total = now_us.saturating_sub(start) / cycle_us;
        let new = total.saturating_sub(self.state.cycles);
        self.state.cycles = total;
        for ch in 0..CHANNELS {
            if !self.state.enabled[ch] {
                continue;
            }
            let d = self.ranges[ch].to_digital(self.input[ch]);
            let period = match self.state.processing[ch] {
                Processing::Sampling => {
                    self.store(ch, d);
                    continue;
                }
                Processing::Time(ms) => (u64::from(ms) * 1000 / cycle_us).max(3),
                Processing::Count(n) => u64::from(n),
            };
            if let Some(avg) = self.state.average[ch].add(new, d, period) {
                self.store(ch, avg);
            }
        }
    }

    /// Buffer memory and X signals from the state.
    fn publish(&self, io: &mut ModuleIo<'_>) {
        let s = &self.state;
        let mut put = |g: usize, v: u16| {
            if let Some(w) = io.buffer.get_mut(g) {
                *w = v;
            }
        };
        put(G_COMPLETED, s.completed);
        put(G_ERROR, s.error);
        put(G_RANGE, analog::range_codes(&self.ranges));
        for ch in 0..CHANNELS {
            put(G_VALUE + ch, s.value[ch] as u16);
            let (max, min) = s.max_min[ch].unwrap_or((0, 0));
            put(G_MAX_MIN + 2 * ch, max as u16);
            put(G_MAX_MIN + 2 * ch + 1, min as u16);
        }
        let enabled = s
            .enabled
            .iter()
            .enumerate()
            .fold(0u16, |m, (ch, e)| m | (u16::from(*e) << ch));
        set(io.x, X_READY, true);
        set(
            io.x,
            X_CONVERTED,
            enabled != 0 && s.completed & enabled == enabled,
        );
        set(io.x, X_ERROR, s.error != 0);
    }
}

impl Module for Q64ad {
    /// The physical inputs and everything power-on resets.
    fn snapshot(&mut self, s: &mut Snap) {
        for v in &mut self.input {
            s.f64(v);
        }
        let st = &mut self.state;
        for ch in 0..CHANNELS {
            s.bool(&mut st.enabled[ch]);
            let (mut kind, mut n) = match st.processing[ch] {
                Processing::Sampling => (0u8, 0u16),
                Processing::Time(t) => (1, t),
                Processing::Count(c) => (2, c),
            };
            s.u8(&mut kind);
            s.u16(&mut n);
            match kind {
                0..=2 if s.loading() => {
                    st.processing[ch] = match kind {
                        0 => Processing::Sampling,
                        1 => Processing::Time(n),
                        _ => Processing::Count(n),
                    }
                }
                0..=2 => {}
                _ => s.fail(StateError::Invalid {
                    what: "Q64AD averaging",
                    value: u64::from(kind),
                }),
            }
            let a = &mut st.average[ch];
            s.u64(&mut a.n);
            s.i64(&mut a.sum);
            s.i32(&mut a.max);
            s.i32(&mut a.min);
            s.i32(&mut st.value[ch]);
            let (mut max, mut min) = st.max_min[ch].unwrap_or((0, 0));
            let mut some = st.max_min[ch].is_some();
            s.bool(&mut some);
            s.i32(&mut max);
            s.i32(&mut min);
            if s.loading() {
                st.max_min[ch] = some.then_some((max, min));
            }
        }
        s.option(&mut st.start_us, Snap::u64);
        s.u64(&mut st.cycles);
        s.u16(&mut st.completed);
        s.u16(&mut st.error);
        s.bool(&mut st.setting_request);
    }

    fn power_on(&mut self, io: &mut ModuleIo<'_>) {
        self.state = State::default();
        io.buffer.fill(0);
        io.x.fill(false);
        set(io.x, X_SETTING_DONE, true);
        self.publish(io);
    }

    fn end(&mut self, io: &mut ModuleIo<'_>, now_us: u64) {
        if get(io.y, Y_ERROR_CLEAR) {
            self.state.error = 0;
        }
        // Operating condition setting: X9 turns OFF while Y9 is ON.
        let request = get(io.y, Y_SETTING_REQUEST);
        if request && !self.state.setting_request {
            self.apply_settings(io.buffer);
        }
        self.state.setting_request = request;
        set(io.x, X_SETTING_DONE, !request);
        let reset = get(io.y, Y_MAX_MIN_RESET);
        self.convert(now_us);
        if reset {
            // The stored values restart from the present ones.
            for ch in 0..CHANNELS {
                let v = self.state.value[ch];
                if self.state.max_min[ch].is_some() {
                    self.state.max_min[ch] = Some((v, v));
                }
            }
        }
        set(io.x, X_MAX_MIN_RESET_DONE, reset);
        self.publish(io);
    }

    fn set_channel(&mut self, channel: u32, value: f64) -> Result<(), String> {
        if value.is_nan() {
            return Err(format!("CH{channel}: not a number"));
        }
        match (channel as usize).checked_sub(1).filter(|&c| c < CHANNELS) {
            Some(ch) => {
                self.input[ch] = value;
                Ok(())
            }
            None => Err(format!(
                "the Q64AD has channels CH1-CH{CHANNELS}, not CH{channel}"
            )),
        }
    }

    /// An input channel reads back the value at its terminals (a second
    /// plant model may watch the same loop).
    fn channel(&self, channel: u32) -> Option<f64> {
        let ch = (channel as usize).checked_sub(1)?;
        self.input.get(ch).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Q64AD with switch 1 `switch1`, its buffer memory and X/Y.
    struct Bench {
        module: Box<dyn Module>,
        buffer: Vec<u16>,
        x: [bool; 16],
        y: [bool; 16],
    }

    impl Bench {
        fn new(switch1: u16) -> Bench {
            let slot = Slot {
                switches: [switch1, 0, 0, 0, 0],
                ..Slot::with_module(0, 0, &Q64AD)
            };
            let mut b = Bench {
                module: new(&slot),
                buffer: vec![0; BUFFER_WORDS as usize],
                x: [false; 16],
                y: [false; 16],
            };
            b.run(|m, io| m.power_on(io));
            b
        }

        fn run(&mut self, f: impl FnOnce(&mut dyn Module, &mut ModuleIo<'_>)) {
            let mut io = ModuleIo {
                buffer: &mut self.buffer,
                x: &mut self.x,
                y: &self.y,
                raised: 0,
                running: true,
            };
            f(self.module.as_mut(), &mut io);
        }

        fn end(&mut self, now_us: u64) -> &mut Self {
            self.run(|m, io| m.end(io, now_us));
            self
        }

        fn input(&mut self, ch: u32, v: f64) -> &mut Self {
            self.module.set_channel(ch, v).unwrap();
            self
        }

        fn g(&self, a: usize) -> i16 {
            self.buffer[a] as i16
        }

        /// Y9 ON then OFF over two ENDs.
        fn request_settings(&mut self, now_us: u64) {
            self.y[9] = true;
            self.end(now_us);
            assert!(!self.x[9], "X9 turns OFF while Y9 is ON");
            self.y[9] = false;
            self.end(now_us);
            assert!(self.x[9]);
        }
    }

    /// Power-on: READY, settings completed, ranges in Un\G20, all enabled.
    #[test]
    fn power_on() {
        let b = Bench::new(0x5421);
        assert!(b.x[0] && b.x[9] && !b.x[0xE] && !b.x[0xF]);
        assert_eq!(b.buffer[20], 0x5421);
        assert_eq!(b.buffer[0], 0);
    }

    /// Sampling, 4-20 mA on CH1: 12 mA is 2000, 20 mA 4000; 25 mA is
    /// fixed at 4095 and 0 mA at -96. The completed flags and XE come with
    /// the first conversion of every enabled channel.
    #[test]
    fn sampling_4_20_ma() {
        let mut b = Bench::new(0);
        b.input(1, 12.0).end(10_000);
        assert_eq!(b.g(11), 2000);
        assert_eq!(b.buffer[10], 0xF);
        assert!(b.x[0xE]);
        b.input(1, 20.0).end(20_000);
        assert_eq!(b.g(11), 4000);
        b.input(1, 25.0).end(30_000);
        assert_eq!(b.g(11), 4095);
        b.input(1, 0.0).end(40_000);
        assert_eq!(b.g(11), -96);
        // CH2-CH4 at 0 mA.
        assert_eq!((b.g(12), b.g(13), b.g(14)), (-96, -96, -96));
        // Maximum and minimum of CH1: 4095 and -96.
        assert_eq!((b.g(30), b.g(31)), (4095, -96));
    }

    /// Ranges per channel from switch 1: CH1 0-10V, CH2 -10-10V, CH3 1-5V,
    /// CH4 0-20mA.
    #[test]
    fn ranges() {
        let mut b = Bench::new(0x1245);
        b.input(1, 2.5).input(2, -2.5).input(3, 2.0).input(4, 10.0);
        b.end(10_000);
        assert_eq!(
            (b.g(11), b.g(12), b.g(13), b.g(14)),
            (1000, -1000, 1000, 2000)
        );
        b.input(2, -12.0).end(20_000);
        assert_eq!(b.g(12), -4096);
    }

    /// Disabling CH2-CH4 (Un\G0 = 000EH) takes effect with Y9: their
    /// values stop, XE needs only CH1.
    #[test]
    fn enable_disable_with_y9() {
        let mut b = Bench::new(0);
        b.input(2, 8.0).end(10_000);
        assert_eq!(b.g(12), 1000);
        b.buffer[0] = 0x000E;
        b.input(2, 12.0).end(20_000);
        assert_eq!(b.g(12), 2000, "not applied before Y9");
        b.request_settings(30_000);
        b.input(2, 16.0).end(40_000);
        assert_eq!(b.g(12), 2000, "CH2 disabled: its value stays");
        assert_eq!(b.buffer[10], 0x1);
        assert!(b.x[0xE]);
    }

    /// Count averaging of 10 conversions on CH1, the only enabled channel
    /// (80 µs a cycle): a period takes 800 µs. 4 mA (0) for the first 400 µs
    /// and 12 mA (2000) after: the average leaves out one maximum and one
    /// minimum, (5·0 + 5·2000 − 2000 − 0) / 8 = 1000.
    #[test]
    fn count_averaging() {
        let mut b = Bench::new(0);
        b.buffer[0] = 0x000E;
        b.buffer[9] = 0x0001;
        b.buffer[1] = 10;
        b.request_settings(0);
        assert_eq!(b.buffer[10], 0, "Y9 restarts the completed flags");
        b.input(1, 4.0).end(400);
        assert_eq!(b.buffer[10], 0);
        b.input(1, 12.0).end(800);
        assert_eq!(b.g(11), 1000);
        assert_eq!(b.buffer[10], 1);
        assert!(b.x[0xE]);
        // Many whole periods of 12 mA: 2000.
        b.end(100_000);
        assert_eq!(b.g(11), 2000);
    }

    /// Time averaging of 2 ms with all four channels enabled: a cycle is
    /// 320 µs, so a period is 6 conversions (1920 µs): 5 at 8 mA (1000) and
    /// 1 at 16 mA (3000): (5·1000 + 3000 − 3000 − 1000) / 4 = 1000.
    #[test]
    fn time_averaging() {
        let mut b = Bench::new(0);
        b.buffer[9] = 0x0101;
        b.buffer[1] = 2;
        b.request_settings(0);
        b.input(1, 8.0).end(1600);
        assert_eq!(b.buffer[10] & 1, 0);
        b.input(1, 16.0).end(1920);
        assert_eq!(b.g(11), 1000);
        assert_eq!(b.buffer[10], 0xF);
    }

    /// An averaging value out of range is error 20□/30□, XF ON; the
    /// settings stay; YF clears it.
    #[test]
    fn averaging_errors() {
        let mut b = Bench::new(0);
        b.buffer[9] = 0x0404;
        b.buffer[3] = 1;
        b.request_settings(0);
        assert_eq!(b.buffer[19], 203);
        assert!(b.x[0xF]);
        b.buffer[9] = 0x0002;
        b.buffer[2] = 3;
        b.request_settings(10);
        assert_eq!(b.buffer[19], 302);
        b.y[0xF] = true;
        b.end(20);
        assert_eq!(b.buffer[19], 0);
        assert!(!b.x[0xF]);
        // Still sampling.
        b.input(2, 12.0).end(30);
        assert_eq!(b.g(12), 2000);
    }

    /// YD resets the maximum and minimum values to the present value; XD
    /// follows YD.
    #[test]
    fn max_min_reset() {
        let mut b = Bench::new(0);
        b.input(1, 20.0).end(10);
        b.input(1, 12.0).end(20);
        assert_eq!((b.g(30), b.g(31)), (4000, 2000));
        b.y[0xD] = true;
        b.end(30);
        assert!(b.x[0xD]);
        assert_eq!((b.g(30), b.g(31)), (2000, 2000));
        b.y[0xD] = false;
        b.end(40);
        assert!(!b.x[0xD]);
    }

    #[test]
    fn channels() {
        let mut b = Bench::new(0);
        assert!(b.module.set_channel(5, 1.0).is_err());
        assert!(b.module.set_channel(0, 1.0).is_err());
        assert!(b.module.set_channel(1, f64::NAN).is_err());
        b.input(4, 7.5);
        assert_eq!(b.module.channel(4), Some(7.5));
    }

    #[test]
    fn switches() {
        assert_eq!(
            switch_setting(Some(&["0-10V", "1-5V"]), None),
            Ok([0x0025, 0, 0, 0, 0])
        );
        assert!(switch_setting(Some(&["0-10V"]), Some([1, 0, 0, 0, 0])).is_err());
        assert!(switch_setting(None, Some([0x000F, 0, 0, 0, 0])).is_err());
        assert!(switch_setting(None, Some([0, 0, 0, 0x0010, 0])).is_err());
        assert_eq!(switch_setting(None, None), Ok([0; 5]));
    }
}
