//! The analog ranges of the Q series A/D and D/A converter modules in normal
//! resolution mode, their switch-setting codes and the conversion between
//! the physical value (mA or V) and the digital value (Analog-Digital
//! Converter Module User's Manual SH-080055 and Digital-Analog Converter
//! Module User's Manual SH-080054: performance specifications and I/O
//! conversion characteristics).

/// An input or output range: the physical values at digital 0 (the offset
/// value) and at 4000 (the gain value).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// As plc.toml writes it (`range = ["4-20mA"]`).
    pub name: &'static str,
    /// Its digit in switch 1 of the switch setting and in the setting range
    /// monitor (Un\G20).
    pub code: u16,
    pub unit: &'static str,
    /// Physical value at digital 0.
    pub offset: f64,
    /// Physical value at digital 4000.
    pub gain: f64,
    /// -4000..4000 instead of 0..4000 (the -10 to 10 V range).
    pub bipolar: bool,
}

/// The digital value at the gain value (normal resolution mode).
pub const FULL_SCALE: i32 = 4000;

pub const MA_4_20: Range = range("4-20mA", 0x0, "mA", 4.0, 20.0, false);
pub const MA_0_20: Range = range("0-20mA", 0x1, "mA", 0.0, 20.0, false);
pub const V_1_5: Range = range("1-5V", 0x2, "V", 1.0, 5.0, false);
pub const V_0_5: Range = range("0-5V", 0x3, "V", 0.0, 5.0, false);
pub const V_10_10: Range = range("-10-10V", 0x4, "V", 0.0, 10.0, true);
pub const V_0_10: Range = range("0-10V", 0x5, "V", 0.0, 10.0, false);

const fn range(
    name: &'static str,
    code: u16,
    unit: &'static str,
    offset: f64,
    gain: f64,
    bipolar: bool,
) -> Range {
    Range {
        name,
        code,
        unit,
        offset,
        gain,
        bipolar,
    }
}

impl Range {
    /// The digital values the module gives (A/D) or converts (D/A): the
    /// setting range widened to -96..4095, or -4096..4095 for -4000..4000.
    /// A value beyond is fixed at the nearer end.
    pub fn limits(self) -> (i32, i32) {
        if self.bipolar {
            (-4096, 4095)
        } else {
            (-96, 4095)
        }
    }

    /// The digital value of physical value `x` (A/D): the nearest digit,
    /// fixed at [`Range::limits`].
    pub fn to_digital(self, x: f64) -> i32 {
        let (lo, hi) = self.limits();
        let d = ((x - self.offset) / (self.gain - self.offset) * FULL_SCALE as f64).round();
        if d.is_nan() {
            return 0;
        }
        d.clamp(lo as f64, hi as f64) as i32
    }

    /// The physical value of digital value `d` (D/A), `d` first fixed at
    /// [`Range::limits`].
    pub fn to_analog(self, d: i32) -> f64 {
        let (lo, hi) = self.limits();
        let d = d.clamp(lo, hi);
        self.offset + (self.gain - self.offset) * f64::from(d) / FULL_SCALE as f64
    }
}

/// The range named `name` among `ranges` (case and spaces ignored).
pub fn find(ranges: &[Range], name: &str) -> Option<Range> {
    let key: String = name
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect::<String>()
        .to_ascii_lowercase();
    ranges
        .iter()
        .copied()
        .find(|r| r.name.to_ascii_lowercase() == key)
}

/// The range with switch-setting code `code`.
pub fn by_code(ranges: &[Range], code: u16) -> Option<Range> {
    ranges.iter().copied().find(|r| r.code == code)
}

/// The 4-bit digit of channel `ch` (0-based) in a switch word: CH1 in
/// b0-b3, CH2 in b4-b7 … (the switch setting's `H□□□□`, CH4 leftmost).
pub fn digit(word: u16, ch: usize) -> u16 {
    (word >> (4 * ch)) & 0xF
}

/// Switch 1 from range names, CH1 first; channels left out are 4-20mA
/// (digit 0, the default).
pub fn range_switch(ranges: &[Range], channels: usize, names: &[&str]) -> Result<u16, String> {
    if names.len() > channels {
        return Err(format!(
            "range has {} entries: the module has {channels} channels",
            names.len()
        ));
    }
    let mut word = 0u16;
    for (ch, name) in names.iter().enumerate() {
        let Some(r) = find(ranges, name) else {
            let known: Vec<&str> = ranges.iter().map(|r| r.name).collect();
            return Err(format!(
                "CH{}: no range \"{name}\" (ranges: {})",
                ch + 1,
                known.join(", ")
            ));
        };
        word |= r.code << (4 * ch);
    }
    Ok(word)
}

/// The ranges switch 1 selects for `channels` channels, or which digit is
/// not one of `ranges`.
pub fn ranges_of(ranges: &[Range], channels: usize, switch1: u16) -> Result<Vec<Range>, String> {
    (0..channels)
        .map(|ch| {
            let code = digit(switch1, ch);
            by_code(ranges, code).ok_or_else(|| {
                format!(
                    "switch 1 gives CH{} the range code {code:X}H, which is not simulated (codes: {})",
                    ch + 1,
                    ranges
                        .iter()
                        .map(|r| format!("{:X}H {}", r.code, r.name))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            })
        })
        .collect()
}

/// Sets signal `k` of a module's X (nothing past its points).
pub(crate) fn set(x: &mut [bool], k: usize, on: bool) {
    if let Some(b) = x.get_mut(k) {
        *b = on;
    }
}

/// Signal `k` of a module's Y (OFF past its points).
pub(crate) fn get(y: &[bool], k: usize) -> bool {
    y.get(k).copied().unwrap_or(false)
}

/// The setting-range word (Un\\G20): each channel's range code, CH1 in
/// bits 0-3.
pub(crate) fn range_codes(ranges: &[Range]) -> u16 {
    ranges
        .iter()
        .enumerate()
        .fold(0, |w, (ch, r)| w | r.code << (4 * ch))
}

/// A slot's switch setting for an analog module with `channels` channels of
/// `ranges`: switch 1 the `what` ranges (from `range` names or given), the
/// switches `zero` (0-based) 0 — they select modes the simulation does not
/// have (switch 4: the offset/gain setting mode, high resolution mode).
pub(crate) fn switch_setting(
    ranges: &[Range],
    channels: usize,
    what: &str,
    zero: &[usize],
    range: Option<&[&str]>,
    switches: Option<[u16; 5]>,
) -> Result<[u16; 5], String> {
    let mut sw = switches.unwrap_or_default();
    if let Some(names) = range {
        if sw[0] != 0 {
            return Err(format!(
                "give the {what} ranges either as range or as switch 1, not both"
            ));
        }
        sw[0] = range_switch(ranges, channels, names)?;
    }
    ranges_of(ranges, channels, sw[0])?;
    if let Some(&k) = zero.iter().find(|&&k| sw[k] != 0) {
        return Err(format!(
            "switch {} must be 0 (normal mode, normal resolution: the offset/gain setting mode and high resolution mode are not simulated)",
            k + 1
        ));
    }
    Ok(sw)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SH-080055 I/O conversion characteristic: 4-20 mA is 0-4000, so
    /// 4 µA a digit; 12 mA is the middle.
    #[test]
    fn current_input() {
        assert_eq!(MA_4_20.to_digital(4.0), 0);
        assert_eq!(MA_4_20.to_digital(12.0), 2000);
        assert_eq!(MA_4_20.to_digital(20.0), 4000);
        assert_eq!(MA_4_20.to_digital(12.001), 2000); // 2000.25: the nearest digit
        assert_eq!(MA_0_20.to_digital(5.0), 1000);
    }

    /// Beyond the range the value is fixed at -96..4095 (-4096..4095 for
    /// -10 to 10 V).
    #[test]
    fn out_of_range_is_fixed() {
        assert_eq!(MA_4_20.to_digital(25.0), 4095);
        assert_eq!(MA_4_20.to_digital(0.0), -96);
        assert_eq!(MA_4_20.to_digital(3.7), -75);
        assert_eq!(V_10_10.to_digital(-15.0), -4096);
        assert_eq!(V_10_10.to_digital(15.0), 4095);
        assert_eq!(V_10_10.to_digital(-5.0), -2000);
        assert_eq!(V_1_5.to_digital(f64::NAN), 0);
    }

    /// SH-080054 I/O conversion characteristic: 0-4000 onto the range.
    #[test]
    fn output() {
        assert_eq!(V_0_5.to_analog(2000), 2.5);
        assert_eq!(MA_4_20.to_analog(0), 4.0);
        assert_eq!(MA_4_20.to_analog(4000), 20.0);
        assert_eq!(V_10_10.to_analog(-4000), -10.0);
        // Fixed at 4095: 4 + 16·4095/4000.
        assert_eq!(MA_4_20.to_analog(30000), 4.0 + 16.0 * 4095.0 / 4000.0);
        assert_eq!(V_1_5.to_analog(-1000), 1.0 - 4.0 * 96.0 / 4000.0);
    }

    #[test]
    fn switch_1() {
        let all = [MA_4_20, MA_0_20, V_1_5, V_0_5, V_10_10, V_0_10];
        assert_eq!(
            range_switch(&all, 4, &["0-10V", "4-20 mA", "-10-10v"]),
            Ok(0x0405)
        );
        assert!(range_switch(&all, 2, &["0-5V", "0-5V", "0-5V"]).is_err());
        assert!(range_switch(&all, 4, &["2-10V"])
            .unwrap_err()
            .contains("no range"));
        let r = ranges_of(&all, 4, 0x0405).unwrap();
        assert_eq!(
            (r[0], r[1], r[2], r[3]),
            (V_0_10, MA_4_20, V_10_10, MA_4_20)
        );
        assert!(ranges_of(&all, 4, 0x00F0).unwrap_err().contains("CH2"));
    }
}
