//! The `[[expect]]` tables of a scenario file: keys, checks and their labels.

use super::values::Space;
use softplc_core::access::ValueType;

use super::values::{device, number, scan_at, scan_before, time_us};
use super::{Band, Cond, ExpectKind, ExpectSpec, Setpoint};
use crate::scenario::fmt::{fmt_num, fmt_time};

pub(super) fn expect_label(t: &toml::Table) -> String {
    match (t.get("name"), t.get("device")) {
        (Some(toml::Value::String(n)), _) => n.clone(),
        (_, Some(toml::Value::String(d))) => d.clone(),
        _ => "?".into(),
    }
}

const EXPECT_KEYS: &[&str] = &[
    "name",
    "device",
    "show",
    "at",
    "within",
    "after",
    "always",
    "never",
    "from",
    "to",
    "equals",
    "tolerance",
    "above",
    "below",
    "at_least",
    "at_most",
    "never_exceeds",
    "never_below",
    "setpoint",
    "band",
    "band_abs",
    "settle_within",
    "max_overshoot",
];

pub(super) fn expect_spec(
    t: &toml::Table,
    scan_us: u64,
    scans: u64,
    names: &Space,
) -> Result<ExpectSpec, String> {
    for k in t.keys() {
        if !EXPECT_KEYS.contains(&k.as_str()) {
            return Err(format!(
                "unknown key `{k}` (keys: {})",
                EXPECT_KEYS.join(", ")
            ));
        }
    }
    let dev = t
        .get("device")
        .and_then(|v| v.as_str())
        .ok_or("`device` (a string) is required")?
        .to_string();
    let spec = device(&dev, "device", names)?;
    let is_bit = spec.ty() == ValueType::Bit;
    let show = match t.get("show") {
        None => Vec::new(),
        Some(toml::Value::Array(a)) => a
            .iter()
            .map(|v| {
                let s = v.as_str().ok_or("show: expected device names")?;
                device(s, "show", names)?;
                Ok(s.to_string())
            })
            .collect::<Result<Vec<_>, String>>()?,
        Some(_) => return Err("show: expected a list of device names".into()),
    };
    let end_us = scans * scan_us;
    let get_time = |k: &str| t.get(k).map(|v| time_us(v, k)).transpose();
    let check_end = |us: u64, what: &str| {
        if us > end_us {
            Err(format!(
                "{what} {} is after the end of the run ({})",
                fmt_time(us),
                fmt_time(end_us)
            ))
        } else {
            Ok(())
        }
    };
    // The window of always/never/settle.
    let window = || -> Result<(u64, u64, u64, u64), String> {
        let from = get_time("from")?.unwrap_or(0);
        let to = get_time("to")?.unwrap_or(end_us);
        check_end(to, "to")?;
        // `to` itself is excluded (a timeline change at `to` starts a new
        // phase); without `to` the window runs to the last scan.
        let last = if t.contains_key("to") {
            scan_before(to.saturating_sub(1), scan_us)
        } else {
            scans
        };
        let first = scan_at(from, scan_us);
        if first > last {
            return Err(format!(
                "the window {}–{} holds no scan",
                fmt_time(from),
                fmt_time(to)
            ));
        }
        Ok((first, last, from, to))
    };
    let fmt_v = |v: f64| {
        if is_bit {
            (if v > 0.5 { "true" } else { "false" }).to_string()
        } else {
            fmt_num(v)
        }
    };
    let name_prefix = match t.get("name") {
        Some(toml::Value::String(n)) => format!("{n}: "),
        Some(_) => return Err("name: expected a string".into()),
        None => String::new(),
    };
    let finish = |text: String, kind: ExpectKind| {
        Ok(ExpectSpec {
            text: format!("{name_prefix}{text}"),
            device: dev.clone(),
            show: show.clone(),
            kind,
        })
    };

    // Loop performance.
    if let Some(sp) = t.get("setpoint") {
        if is_bit {
            return Err("a settle check needs a word device".into());
        }
        for k in [
            "at",
            "within",
            "after",
            "always",
            "never",
            "equals",
            "tolerance",
            "above",
            "below",
            "at_least",
            "at_most",
            "never_exceeds",
            "never_below",
        ] {
            if t.contains_key(k) {
                return Err(format!("`{k}` does not go with `setpoint`"));
            }
        }
        let setpoint = match sp {
            toml::Value::String(s) => {
                device(s, "setpoint", names)?;
                Setpoint::Device(s.clone())
            }
            v => Setpoint::Value(number(v, "setpoint")?),
        };
        let band = match (t.get("band"), t.get("band_abs")) {
            (Some(b), None) => Band::Percent(number(b, "band")?),
            (None, Some(b)) => Band::Abs(number(b, "band_abs")?),
            _ => return Err("give one of `band` (% of the step) or `band_abs`".into()),
        };
        if matches!(band, Band::Percent(b) | Band::Abs(b) if !(b >= 0.0 && b.is_finite())) {
            return Err("the band must be ≥ 0".into());
        }
        let settle = get_time("settle_within")?;
        let max_overshoot = t
            .get("max_overshoot")
            .map(|v| number(v, "max_overshoot"))
            .transpose()?;
        if settle.is_none() && max_overshoot.is_none() {
            return Err("give `settle_within` and/or `max_overshoot`".into());
        }
        let (first, last, from, to) = window()?;
        let deadline = match settle {
            Some(s) => {
                check_end(from + s, "from + settle_within =")?;
                Some(scan_at(from + s, scan_us))
            }
            None => None,
        };
        let sp_text = match &setpoint {
            Setpoint::Value(v) => fmt_num(*v),
            Setpoint::Device(d) => d.clone(),
        };
        let band_text = match band {
            Band::Percent(b) => format!("±{} %", fmt_num(b)),
            Band::Abs(b) => format!("±{}", fmt_num(b)),
        };
        let mut text = format!("{dev} settles to {sp_text} {band_text}");
        if let Some(s) = settle {
            text += &format!(" within {}", fmt_time(s));
        }
        if from > 0 {
            text += &format!(" after {}", fmt_time(from));
        }
        if let Some(o) = max_overshoot {
            text += &format!(", overshoot ≤ {} %", fmt_num(o));
        }
        if to != end_us {
            text += &format!(" (until {})", fmt_time(to));
        }
        return finish(
            text,
            ExpectKind::Settle {
                first,
                last,
                setpoint,
                band,
                deadline,
                max_overshoot,
            },
        );
    }

    // Sugar: never_exceeds / never_below.
    for (k, gt) in [("never_exceeds", true), ("never_below", false)] {
        if let Some(v) = t.get(k) {
            for other in [
                "at",
                "within",
                "after",
                "always",
                "never",
                "equals",
                "above",
                "below",
                "at_least",
                "at_most",
                "tolerance",
            ] {
                if t.contains_key(other) {
                    return Err(format!("`{other}` does not go with `{k}`"));
                }
            }
            if t.contains_key(if gt { "never_below" } else { "never_exceeds" }) {
                return Err("give one of `never_exceeds` or `never_below`".into());
            }
            let v = number(v, k)?;
            let (first, last, from, to) = window()?;
            let cond = if gt { Cond::Gt(v) } else { Cond::Lt(v) };
            let text = format!(
                "{dev} never {} {}{}",
                if gt { "exceeds" } else { "falls below" },
                fmt_num(v),
                window_text(from, to, end_us)
            );
            return finish(text, ExpectKind::Never { first, last, cond });
        }
    }

    // The condition.
    let mut conds = Vec::new();
    if let Some(v) = t.get("equals") {
        let value = number(v, "equals")?;
        let tol = t
            .get("tolerance")
            .map(|v| number(v, "tolerance"))
            .transpose()?
            .unwrap_or(0.0);
        if tol.is_nan() || tol < 0.0 {
            return Err("tolerance must be ≥ 0".into());
        }
        let value = if spec.ty() == ValueType::F32 && tol == 0.0 {
            value as f32 as f64
        } else {
            value
        };
        conds.push(Cond::Eq { value, tol });
    } else if t.contains_key("tolerance") {
        return Err("`tolerance` goes with `equals`".into());
    }
    for (k, mk) in [
        ("above", Cond::Gt as fn(f64) -> Cond),
        ("below", Cond::Lt),
        ("at_least", Cond::Ge),
        ("at_most", Cond::Le),
    ] {
        if let Some(v) = t.get(k) {
            if is_bit {
                return Err(format!("`{k}`: a bit device takes `equals = true/false`"));
            }
            conds.push(mk(number(v, k)?));
        }
    }
    let cond = match conds.as_slice() {
        [c] => *c,
        [] => {
            return Err(
                "give a condition: equals (with tolerance), above, below, at_least or at_most"
                    .into(),
            )
        }
        _ => return Err("give only one of equals, above, below, at_least, at_most".into()),
    };
    let cond_text = match cond {
        Cond::Eq { value, tol } if tol > 0.0 => format!("= {} ±{}", fmt_v(value), fmt_num(tol)),
        Cond::Eq { value, .. } => format!("= {}", fmt_v(value)),
        Cond::Gt(v) => format!("> {}", fmt_num(v)),
        Cond::Lt(v) => format!("< {}", fmt_num(v)),
        Cond::Ge(v) => format!("≥ {}", fmt_num(v)),
        Cond::Le(v) => format!("≤ {}", fmt_num(v)),
    };

    // When.
    let always = match t.get("always") {
        None => false,
        Some(toml::Value::Boolean(true)) => true,
        Some(_) => return Err("always: write `always = true`".into()),
    };
    let never = match t.get("never") {
        None => false,
        Some(toml::Value::Boolean(true)) => true,
        Some(_) => return Err("never: write `never = true`".into()),
    };
    let whens = [
        t.contains_key("at"),
        t.contains_key("within"),
        always,
        never,
    ];
    if whens.iter().filter(|w| **w).count() != 1 {
        return Err("give exactly one of `at`, `within`, `always = true`, `never = true`".into());
    }
    if (t.contains_key("from") || t.contains_key("to")) && !(always || never) {
        return Err("`from`/`to` go with `always`, `never` and `setpoint`".into());
    }
    if t.contains_key("after") && !t.contains_key("within") {
        return Err("`after` goes with `within`".into());
    }
    if let Some(at) = get_time("at")? {
        check_end(at, "at")?;
        return finish(
            format!("{dev} {cond_text} at {}", fmt_time(at)),
            ExpectKind::At {
                scan: scan_at(at, scan_us),
                cond,
            },
        );
    }
    if let Some(w) = get_time("within")? {
        let after = get_time("after")?.unwrap_or(0);
        check_end(after + w, "after + within =")?;
        let (first, last) = (scan_at(after, scan_us), scan_before(after + w, scan_us));
        if first > last {
            return Err(format!(
                "the window {}–{} holds no scan",
                fmt_time(after),
                fmt_time(after + w)
            ));
        }
        let verb = if matches!(cond, Cond::Eq { .. }) {
            format!("becomes {}", cond_text.trim_start_matches("= "))
        } else {
            format!("becomes {cond_text}")
        };
        let mut text = format!("{dev} {verb} within {}", fmt_time(w));
        if after > 0 {
            text += &format!(" after {}", fmt_time(after));
        }
        return finish(text, ExpectKind::Within { first, last, cond });
    }
    let (first, last, from, to) = window()?;
    let wt = window_text(from, to, end_us);
    // "Y1 never true" rather than "Y1 never = true".
    let cond_text = match cond {
        Cond::Eq { .. } if is_bit => cond_text.trim_start_matches("= ").to_string(),
        _ => cond_text,
    };
    if always {
        finish(
            format!("{dev} always {cond_text}{wt}"),
            ExpectKind::Always { first, last, cond },
        )
    } else {
        finish(
            format!("{dev} never {cond_text}{wt}"),
            ExpectKind::Never { first, last, cond },
        )
    }
}

fn window_text(from: u64, to: u64, end: u64) -> String {
    match (from, to == end) {
        (0, true) => String::new(),
        (f, true) => format!(" from {}", fmt_time(f)),
        (f, false) => format!(" from {} to {}", fmt_time(f), fmt_time(to)),
    }
}
