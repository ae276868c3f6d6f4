//! `Q62DA` and `Q64DA`: the 2- and 4-channel digital-analog converter
//! modules, in normal resolution mode — one module with two channel counts,
//! as their one manual describes them (Digital-Analog Converter Module
//! User's Manual, SH-080054: I/O signals, buffer memory assignment, analog
//! output HOLD/CLEAR function). docs/modules.md has the full map.
//!
//! Buffer memory (Un\G…): 0 D/A conversion enable/disable (bit k = CH k+1,
//! 1 = disabled; default: every channel disabled), 1-4 CH1-CH4 digital
//! values, 11-14 CH1-CH4 set value check codes, 19 error code, 20 setting
//! range (switch 1's codes). Signals: X0 module READY, X9 operating
//! condition setting completed, XF error; Y1-Y4 CH1-CH4 output enable,
//! Y9 operating condition setting request, YF error clear request.
//!
//! A channel's analog output, taken at END: 0 V/0 mA while its conversion
//! is disabled; the converted digital value while the CPU runs and its
//! output enable signal is ON; else the offset value — or, in STOP with the
//! channel set to HOLD (switch 3) and its output enabled, the last value.

use softplc_ir::rack::{Module, ModuleIo, ModuleProfile, Slot, SlotType};
use softplc_ir::snapshot::Snap;

use crate::analog::{self, get, set, Range, MA_0_20, MA_4_20, V_0_5, V_10_10, V_1_5};

pub static Q62DA: ModuleProfile = ModuleProfile {
    name: "Q62DA",
    kind: SlotType::Intelligent,
    points: 16,
    buffer_words: BUFFER_WORDS,
    pointers: None,
    causes: 0,
    manual: MANUAL,
    new: new::<2>,
    switches: Some(|r, s| switch_setting(2, r, s)),
};

pub static Q64DA: ModuleProfile = ModuleProfile {
    name: "Q64DA",
    kind: SlotType::Intelligent,
    points: 16,
    buffer_words: BUFFER_WORDS,
    pointers: None,
    causes: 0,
    manual: MANUAL,
    new: new::<4>,
    switches: Some(|r, s| switch_setting(4, r, s)),
};

const MANUAL: &str =
    "Digital-Analog Converter Module User's Manual (Q62DA, Q64DA, Q68DAV, Q68DAI), SH-080054";

/// The output ranges of switch 1 (user range setting, code F, is not
/// simulated).
pub const RANGES: &[Range] = &[MA_4_20, MA_0_20, V_1_5, V_0_5, V_10_10];

const MAX_CHANNELS: usize = 4;
/// Un\G0-217: the last assigned word is CH4's user range gain value.
const BUFFER_WORDS: u32 = 218;

const G_ENABLE: usize = 0;
/// CH1's digital value; the others follow.
const G_DIGITAL: usize = 1;
/// CH1's set value check code; the others follow.
const G_CHECK: usize = 11;
const G_ERROR: usize = 19;
const G_RANGE: usize = 20;

const X_READY: usize = 0x0;
const X_SETTING_DONE: usize = 0x9;
const X_ERROR: usize = 0xF;
/// CH1's output enable; the others follow.
const Y_OUTPUT_ENABLE: usize = 0x1;
const Y_SETTING_REQUEST: usize = 0x9;
const Y_ERROR_CLEAR: usize = 0xF;

/// Set value check codes: a digital value above or below what the range
/// converts (`Range::limits`).
const CHECK_ABOVE: u16 = 0x000F;
const CHECK_BELOW: u16 = 0x00F0;

fn new<const N: usize>(slot: &Slot) -> Box<dyn Module> {
    // The switch setting was checked at load (`switch_setting`).
    let ranges = analog::ranges_of(RANGES, N, slot.switches[0]).unwrap_or_default();
    let mut r = [MA_4_20; MAX_CHANNELS];
    for (to, from) in r.iter_mut().zip(ranges) {
        *to = from;
    }
    let hold = std::array::from_fn(|ch| analog::digit(slot.switches[2], ch) != 0);
    Box::new(Da {
        channels: N,
        ranges: r,
        hold,
        enabled: [false; MAX_CHANNELS],
        output: [0.0; MAX_CHANNELS],
        check: [0; MAX_CHANNELS],
        setting_request: false,
    })
}

/// The switch setting of a D/A slot with `channels` channels: switch 1 the
/// output ranges (from `range` names or given), switch 3 HOLD/CLEAR (a
/// channel's digit 0 = CLEAR, else HOLD), switches 2, 4 and 5 0 (switch 4 ≠
/// 0 selects the offset/gain setting mode or high resolution mode, not
/// simulated).
pub(crate) fn switch_setting(
    channels: usize,
    range: Option<&[&str]>,
    switches: Option<[u16; 5]>,
) -> Result<[u16; 5], String> {
    analog::switch_setting(RANGES, channels, "output", &[1, 3, 4], range, switches)
}

#[derive(Debug)]
struct Da {
    channels: usize,
    ranges: [Range; MAX_CHANNELS],
    /// Switch 3: HOLD (true) or CLEAR in STOP.
    hold: [bool; MAX_CHANNELS],
    enabled: [bool; MAX_CHANNELS],
    /// The analog output, mA or V.
    output: [f64; MAX_CHANNELS],
    check: [u16; MAX_CHANNELS],
    /// Y9 at the previous END.
    setting_request: bool,
}

impl Da {
    /// Un\G0 with every channel disabled: the default.
    fn all_disabled(&self) -> u16 {
        (1 << self.channels) - 1
    }

    fn publish(&self, io: &mut ModuleIo<'_>) {
        let mut put = |g: usize, v: u16| {
            if let Some(w) = io.buffer.get_mut(g) {
                *w = v;
            }
        };
        for ch in 0..self.channels {
            put(G_CHECK + ch, self.check[ch]);
        }
        put(G_ERROR, 0);
        put(G_RANGE, analog::range_codes(&self.ranges[..self.channels]));
        set(io.x, X_READY, true);
        set(io.x, X_ERROR, false);
    }
}

impl Module for Da {
    /// What the program set and the outputs.
    fn snapshot(&mut self, s: &mut Snap) {
        s.bools(&mut self.enabled);
        for v in &mut self.output {
            s.f64(v);
        }
        s.words(&mut self.check);
        s.bool(&mut self.setting_request);
    }

    /// Power-on and RESET: every channel disabled, outputs 0 V/0 mA.
    fn power_on(&mut self, io: &mut ModuleIo<'_>) {
        self.enabled = [false; MAX_CHANNELS];
        self.output = [0.0; MAX_CHANNELS];
        self.check = [0; MAX_CHANNELS];
        self.setting_request = false;
        io.buffer.fill(0);
        if let Some(w) = io.buffer.get_mut(G_ENABLE) {
            *w = self.all_disabled();
        }
        io.x.fill(false);
        set(io.x, X_SETTING_DONE, true);
        self.publish(io);
    }

    fn end(&mut self, io: &mut ModuleIo<'_>, _now_us: u64) {
        if get(io.y, Y_ERROR_CLEAR) {
            self.check = [0; MAX_CHANNELS];
        }
        // Operating condition setting: X9 turns OFF while Y9 is ON.
        let request = get(io.y, Y_SETTING_REQUEST);
        if request && !self.setting_request {
            let word = io.buffer.get(G_ENABLE).copied().unwrap_or(0);
            for ch in 0..self.channels {
                self.enabled[ch] = word >> ch & 1 == 0;
            }
        }
        self.setting_request = request;
        set(io.x, X_SETTING_DONE, !request);
        for ch in 0..self.channels {
            let range = self.ranges[ch];
            let d = i32::from(io.buffer.get(G_DIGITAL + ch).copied().unwrap_or(0) as i16);
            let (lo, hi) = range.limits();
            // A check code stays until the error clear request.
            if d > hi {
                self.check[ch] = CHECK_ABOVE;
            } else if d < lo {
                self.check[ch] = CHECK_BELOW;
            }
            let output_enabled = get(io.y, Y_OUTPUT_ENABLE + ch);
            self.output[ch] = if !self.enabled[ch] {
                0.0
            } else if io.running && output_enabled {
                range.to_analog(d)
            } else if !io.running && output_enabled && self.hold[ch] {
                self.output[ch]
            } else {
                range.offset
            };
        }
        self.publish(io);
    }

    fn channel(&self, channel: u32) -> Option<f64> {
        let ch = (channel as usize).checked_sub(1)?;
        (ch < self.channels).then(|| self.output[ch])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Bench {
        module: Box<dyn Module>,
        buffer: Vec<u16>,
        x: [bool; 16],
        y: [bool; 16],
        running: bool,
    }

    impl Bench {
        fn new(profile: &'static ModuleProfile, switches: [u16; 5]) -> Bench {
            let slot = Slot {
                switches,
                ..Slot::with_module(0, 0, profile)
            };
            let mut b = Bench {
                module: (profile.new)(&slot),
                buffer: vec![0; BUFFER_WORDS as usize],
                x: [false; 16],
                y: [false; 16],
                running: true,
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
                running: self.running,
            };
            f(self.module.as_mut(), &mut io);
        }

        fn end(&mut self) -> &mut Self {
            self.run(|m, io| m.end(io, 0));
            self
        }

        fn out(&self, ch: u32) -> f64 {
            self.module.channel(ch).unwrap()
        }

        /// Un\G0 = `enable`, then Y9 ON and OFF.
        fn enable(&mut self, enable: u16) {
            self.buffer[0] = enable;
            self.y[9] = true;
            self.end();
            assert!(!self.x[9]);
            self.y[9] = false;
            self.end();
            assert!(self.x[9]);
        }
    }

    /// Power-on: every channel disabled (Un\G0 = 000FH), 0 V/0 mA out,
    /// READY.
    #[test]
    fn power_on() {
        let mut b = Bench::new(&Q64DA, [0x4320, 0, 0, 0, 0]);
        assert_eq!(b.buffer[0], 0x000F);
        assert_eq!(b.buffer[20], 0x4320);
        assert!(b.x[0] && b.x[9]);
        b.buffer[1] = 2000;
        b.y[1] = true;
        b.end();
        assert_eq!(b.out(1), 0.0, "disabled: 0 V/0 mA");
        let b2 = Bench::new(&Q62DA, [0; 5]);
        assert_eq!(b2.buffer[0], 0x0003);
        assert_eq!(b2.module.channel(3), None);
    }

    /// Enabled, output enable ON: the digital value converted at END (CH1
    /// 4-20 mA: 2000 is 12 mA; CH2 1-5 V: 1000 is 2 V; CH3 -10-10 V: -2000
    /// is -5 V). Output enable OFF gives the offset value: 4 mA, 1 V, 0 V.
    #[test]
    fn conversion_and_output_enable() {
        let mut b = Bench::new(&Q64DA, [0x0420, 0, 0, 0, 0]);
        b.enable(0x0000);
        b.buffer[1] = 2000;
        b.buffer[2] = 1000;
        b.buffer[3] = (-2000i16) as u16;
        b.end();
        assert_eq!((b.out(1), b.out(2), b.out(3)), (4.0, 1.0, 0.0));
        b.y[1] = true;
        b.y[2] = true;
        b.y[3] = true;
        b.end();
        assert_eq!((b.out(1), b.out(2), b.out(3)), (12.0, 2.0, -5.0));
        b.y[2] = false;
        b.end();
        assert_eq!(b.out(2), 1.0);
    }

    /// A digital value beyond -96..4095 is converted at the nearer end and
    /// leaves a check code (000FH above, 00F0H below) until YF.
    #[test]
    fn out_of_range_and_check_code() {
        let mut b = Bench::new(&Q62DA, [0x0003, 0, 0, 0, 0]);
        b.enable(0x0000);
        b.y[1] = true;
        b.y[2] = true;
        b.buffer[1] = 5000;
        b.buffer[2] = (-200i16) as u16;
        b.end();
        assert_eq!(b.out(1), 0.0 + 5.0 * 4095.0 / 4000.0);
        assert_eq!(b.out(2), 4.0 - 16.0 * 96.0 / 4000.0);
        assert_eq!((b.buffer[11], b.buffer[12]), (0x000F, 0x00F0));
        b.buffer[1] = 4000;
        b.end();
        assert_eq!(b.out(1), 5.0);
        assert_eq!(b.buffer[11], 0x000F, "the code stays");
        b.y[0xF] = true;
        b.end();
        assert_eq!(b.buffer[11], 0);
    }

    /// STOP: CLEAR gives the offset value, HOLD (switch 3, CH2) keeps the
    /// last value.
    #[test]
    fn stop_clear_and_hold() {
        let mut b = Bench::new(&Q62DA, [0x0000, 0, 0x0010, 0, 0]);
        b.enable(0x0000);
        b.y[1] = true;
        b.y[2] = true;
        b.buffer[1] = 3000;
        b.buffer[2] = 3000;
        b.end();
        assert_eq!((b.out(1), b.out(2)), (16.0, 16.0));
        b.running = false;
        b.buffer[2] = 0;
        b.end();
        assert_eq!((b.out(1), b.out(2)), (4.0, 16.0));
        b.running = true;
        b.end();
        assert_eq!(b.out(2), 4.0);
    }

    /// Disabling a channel with Y9: 0 mA.
    #[test]
    fn disable() {
        let mut b = Bench::new(&Q64DA, [0; 5]);
        b.enable(0x000E);
        b.y[1] = true;
        b.y[2] = true;
        b.buffer[1] = 4000;
        b.buffer[2] = 4000;
        b.end();
        assert_eq!((b.out(1), b.out(2)), (20.0, 0.0));
        assert!(b.module.set_channel(1, 1.0).is_err());
    }

    #[test]
    fn switches() {
        assert_eq!(
            switch_setting(2, Some(&["0-5V", "-10-10V"]), Some([0, 0, 0x11, 0, 0])),
            Ok([0x0043, 0, 0x11, 0, 0])
        );
        assert!(switch_setting(2, Some(&["0-10V"]), None).is_err());
        assert!(switch_setting(4, None, Some([0, 0, 0, 1, 0])).is_err());
        assert!(switch_setting(2, Some(&["0-5V", "0-5V", "0-5V"]), None).is_err());
    }
}
