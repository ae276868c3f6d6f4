//! `[multi_cpu]`: a CPU's multi-CPU parameters (004 §14.2, L8411-8520;
//! auto refresh L8735-8948; contract §6). The settings every CPU must share
//! are compared when the system powers on (PARAMETER ERROR 3012, in
//! `crate::system`); the limits of one CPU's refresh settings are load errors
//! here, each naming its setting.

use super::ctx::Ctx;
use super::tree::{Entry, Item, Value};
use softplc_ir::device::{parse_operand, DeviceConfig, DeviceKind, Operand, Reach, REFRESH_AREA};

/// Devices an auto-refresh setting may name (004 L8860-8868).
const REFRESH_DEVICES: &[DeviceKind] = &[
    DeviceKind::B,
    DeviceKind::M,
    DeviceKind::Y,
    DeviceKind::D,
    DeviceKind::W,
    DeviceKind::R,
    DeviceKind::ZR,
];
/// Send words of one CPU over all settings, and of the whole system
/// (004 L8780-8830).
pub const MAX_WORDS_PER_CPU: u32 = 2048;
pub const MAX_WORDS_IN_ALL: u32 = 8192;
/// Refresh settings 1-4.
pub const MAX_SETTINGS: usize = 4;

/// The multi-CPU parameters of one CPU.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MultiCpuParams {
    /// Number of CPUs, 2-4.
    pub cpus: u32,
    /// Operation mode: a stop error of CPU n (2-4, index n - 1) stops every
    /// CPU (`true`, MULTI CPU DOWN) or lets the others go on (MULTI EXE.
    /// ERROR). CPU 1's stops all, always.
    pub stop_all: [bool; 4],
    /// Load the inputs / outputs of modules other CPUs control (L9119-9215).
    pub out_of_group_input: bool,
    pub out_of_group_output: bool,
    /// Auto-refresh settings 1-4.
    pub refresh: Vec<RefreshSetting>,
}

/// One auto-refresh setting: the device this CPU refreshes and each CPU's
/// send words, consecutive from `number` in CPU order (004 L8840-8879).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RefreshSetting {
    pub device: DeviceKind,
    pub number: u32,
    /// Words each CPU sends, CPU 1 first.
    pub words: Vec<u32>,
}

impl RefreshSetting {
    /// Device points one shared word holds: 16 for a bit device.
    pub fn points_per_word(&self) -> u32 {
        if self.device.is_bit() {
            16
        } else {
            1
        }
    }

    /// The device range (first number, points) of CPU `cpu`'s (0-based) words.
    pub fn range_of(&self, cpu: usize) -> (u32, u32) {
        let before: u32 = self.words[..cpu].iter().sum();
        let k = self.points_per_word();
        (self.number + before * k, self.words[cpu] * k)
    }

    /// Every CPU's points together.
    pub fn points(&self) -> u32 {
        self.words.iter().sum::<u32>() * self.points_per_word()
    }
}

impl MultiCpuParams {
    /// What must be the same in every CPU (L8481, L8500-8512): all but the
    /// refresh devices, which may differ (L8878-8879).
    pub fn consistent_with(&self, other: &MultiCpuParams) -> bool {
        self.cpus == other.cpus
            && self.stop_all == other.stop_all
            && self.out_of_group_input == other.out_of_group_input
            && self.out_of_group_output == other.out_of_group_output
            && self.refresh.len() == other.refresh.len()
            && self
                .refresh
                .iter()
                .zip(&other.refresh)
                .all(|(a, b)| a.words == b.words)
    }

    /// Address in the shared memory of CPU `cpu` (0-based) of its send
    /// words of setting `k`: from 800H, setting after setting (L8780-8830).
    pub fn shared_address(&self, cpu: usize, k: usize) -> u32 {
        REFRESH_AREA + self.refresh[..k].iter().map(|s| s.words[cpu]).sum::<u32>()
    }

    /// Words of CPU `cpu`'s refresh area; its user area starts after them.
    pub fn refresh_words(&self, cpu: usize) -> u32 {
        self.refresh.iter().map(|s| s.words[cpu]).sum()
    }
}

/// Reads `[multi_cpu]`.
pub(super) fn multi_cpu(
    cx: &mut Ctx,
    e: &Entry,
    t: &[Entry],
    devices: &DeviceConfig,
) -> Option<MultiCpuParams> {
    cx.unknown_keys(
        t,
        Some("[multi_cpu]"),
        &[
            "cpus",
            "stop_all",
            "out_of_group_input",
            "out_of_group_output",
            "refresh",
        ],
    );
    let get = |k: &str| t.iter().find(|e| e.key == k);
    let cpus = match get("cpus") {
        Some(c) => match &c.item.value {
            Value::Int(n) if (2..=4).contains(n) => *n as u32,
            _ => {
                cx.error(&c.item.span, "cpus must be the number of CPUs, 2-4");
                return None;
            }
        },
        None => {
            cx.error(
                &e.key_span,
                "[multi_cpu] needs cpus (the number of CPUs, 2-4)",
            );
            return None;
        }
    };
    let mut params = MultiCpuParams {
        cpus,
        stop_all: [true; 4],
        out_of_group_input: false,
        out_of_group_output: false,
        refresh: Vec::new(),
    };
    if let Some(s) = get("stop_all") {
        stop_all(cx, s, cpus, &mut params.stop_all)?;
    }
    if let Some(b) = get("out_of_group_input") {
        params.out_of_group_input = cx.bool(b, "true or false")?;
    }
    if let Some(b) = get("out_of_group_output") {
        params.out_of_group_output = cx.bool(b, "true or false")?;
    }
    if let Some(r) = get("refresh") {
        let tables = cx.tables(
            r,
            "refresh is an array of tables: [[multi_cpu.refresh]] with device and words",
        )?;
        if tables.len() > MAX_SETTINGS {
            cx.error(
                &r.item.span,
                format!(
                    "{} auto-refresh settings: a multi-CPU system has settings 1-4",
                    tables.len()
                ),
            );
            return None;
        }
        for (k, (item, t)) in tables.into_iter().enumerate() {
            params
                .refresh
                .push(refresh(cx, k + 1, item, t, cpus, devices)?);
        }
        limits(cx, &r.item, &params)?;
    }
    Some(params)
}

/// `stop_all = { 2 = true, 3 = false }`: CPU 2-4 only.
fn stop_all(cx: &mut Ctx, e: &Entry, cpus: u32, out: &mut [bool; 4]) -> Option<()> {
    let Value::Table(t) = &e.item.value else {
        cx.error(
            &e.item.span,
            "stop_all is a table of CPU numbers 2-4: { 2 = true, 3 = false }",
        );
        return None;
    };
    for c in t {
        let n =
            match c.key.parse::<u32>() {
                Ok(n) if (2..=cpus).contains(&n) => n,
                _ => {
                    cx.error(
                        &c.key_span,
                        format!(
                        "stop_all: `{}` is not CPU {} (CPU 1's stop error always stops every CPU)",
                        c.key,
                        if cpus == 2 { "2".to_string() } else { format!("2-{cpus}") }
                    ),
                    );
                    return None;
                }
            };
        out[n as usize - 1] = cx.bool(c, "true (all stop) or false (the others go on)")?;
    }
    Some(())
}

/// One `[[multi_cpu.refresh]]`: `device` and one even `words` count per CPU.
fn refresh(
    cx: &mut Ctx,
    k: usize,
    item: &Item,
    t: &[Entry],
    cpus: u32,
    devices: &DeviceConfig,
) -> Option<RefreshSetting> {
    cx.unknown_keys(t, Some("[[multi_cpu.refresh]]"), &["device", "words"]);
    let get = |key: &str| t.iter().find(|e| e.key == key);
    let (Some(d), Some(w)) = (get("device"), get("words")) else {
        cx.error(
            &item.span,
            format!("refresh setting {k}: needs device (\"B0\", \"D100\" …) and words (one count per CPU)"),
        );
        return None;
    };
    let text = cx.string(d, "a device such as \"B0\" or \"D100\"")?;
    let dev = match parse_operand(text) {
        Ok(Operand::Device {
            dev,
            digits: None,
            bit: None,
            index: None,
        }) if dev.reach == Reach::Memory && REFRESH_DEVICES.contains(&dev.kind) => dev,
        _ => {
            cx.error(
                &d.item.span,
                format!("refresh setting {k}: device \"{text}\" must be B, M, Y, D, W, R or ZR"),
            );
            return None;
        }
    };
    if dev.kind.is_bit() && dev.number % 16 != 0 {
        cx.error(
            &d.item.span,
            format!(
                "refresh setting {k}: a bit device starts at 0 or a multiple of 16, not {text}"
            ),
        );
        return None;
    }
    let counts: Option<Vec<u32>> = match &w.item.value {
        Value::Array(a) => a
            .iter()
            .map(|i| match i.value {
                Value::Int(n) if (0..=i64::from(MAX_WORDS_PER_CPU)).contains(&n) && n % 2 == 0 => {
                    Some(n as u32)
                }
                _ => None,
            })
            .collect(),
        _ => None,
    };
    let Some(words) = counts.filter(|c| c.len() == cpus as usize) else {
        cx.error(
            &w.item.span,
            format!("refresh setting {k}: words is a list of {cpus} even counts (2-word units), one per CPU"),
        );
        return None;
    };
    let setting = RefreshSetting {
        device: dev.kind,
        number: dev.number,
        words,
    };
    if setting.number as u64 + setting.points() as u64 > devices.points(dev.kind) as u64 {
        cx.error(
            &d.item.span,
            format!(
                "refresh setting {k}: {} points from {text} run past the last {} point",
                setting.points(),
                dev.kind.name()
            ),
        );
        return None;
    }
    Some(setting)
}

/// The limits over all settings: 2K words a CPU, 8K in all, no two
/// settings on the same points (L8780-8830).
fn limits(cx: &mut Ctx, at: &Item, p: &MultiCpuParams) -> Option<()> {
    for cpu in 0..p.cpus as usize {
        let n = p.refresh_words(cpu);
        if n > MAX_WORDS_PER_CPU {
            cx.error(
                &at.span,
                format!(
                    "auto refresh: CPU {} sends {n} words; at most 2048 (2K) a CPU",
                    cpu + 1
                ),
            );
            return None;
        }
    }
    let all: u32 = (0..p.cpus as usize).map(|c| p.refresh_words(c)).sum();
    if all > MAX_WORDS_IN_ALL {
        cx.error(
            &at.span,
            format!("auto refresh: {all} words in all; at most 8192 (8K)"),
        );
        return None;
    }
    for (i, a) in p.refresh.iter().enumerate() {
        for (j, b) in p.refresh.iter().enumerate().skip(i + 1) {
            let same = a.device == b.device
                || (matches!(a.device, DeviceKind::R | DeviceKind::ZR)
                    && matches!(b.device, DeviceKind::R | DeviceKind::ZR));
            let overlap = a.number < b.number + b.points() && b.number < a.number + a.points();
            if same && overlap && a.points() > 0 && b.points() > 0 {
                cx.error(
                    &at.span,
                    format!("auto refresh: settings {} and {} overlap", i + 1, j + 1),
                );
                return None;
            }
        }
    }
    Some(())
}
