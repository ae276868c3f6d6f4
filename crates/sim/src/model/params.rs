//! Reading model parameters from a TOML table.

/// Parses a duration in seconds: a plain number (`"2.5"` = 2.5 s) or one or
/// more `<number><unit>` parts, summed (`"1h30min"`, `"1.5s"`, `"500 ms"`).
/// Units: `ns`, `us`/`µs`, `ms`, `s`/`sec`, `min`/`m`, `h`. Negative, NaN and
/// infinite values are rejected.
pub fn parse_duration(text: &str) -> Result<f64, String> {
    let err = || format!("invalid duration `{text}` (e.g. \"30s\", \"500ms\", \"2min\", 1.5)");
    let s = text.trim();
    if s.is_empty() {
        return Err(err());
    }
    if let Ok(v) = s.parse::<f64>() {
        return if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(err())
        };
    }
    let mut total = 0.0;
    let mut rest = s;
    while !rest.is_empty() {
        let num_len = rest
            .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '_'))
            .ok_or_else(err)?;
        if num_len == 0 {
            return Err(err());
        }
        let num: f64 = rest[..num_len]
            .replace('_', "")
            .parse()
            .map_err(|_| err())?;
        rest = rest[num_len..].trim_start();
        let unit_len = rest
            .find(|c: char| !c.is_alphabetic())
            .unwrap_or(rest.len());
        let scale = match &rest[..unit_len] {
            "ns" => 1e-9,
            "us" | "µs" => 1e-6,
            "ms" => 1e-3,
            "s" | "sec" => 1.0,
            "m" | "min" => 60.0,
            "h" => 3600.0,
            _ => return Err(err()),
        };
        total += num * scale;
        rest = rest[unit_len..].trim_start();
    }
    if total.is_finite() {
        Ok(total)
    } else {
        Err(err())
    }
}

/// A model's parameter table with its type name for error messages.
pub(crate) struct Params<'a> {
    kind: &'static str,
    table: &'a toml::Table,
}

impl<'a> Params<'a> {
    /// Wraps `table`, rejecting keys not in `allowed`.
    pub(crate) fn new(
        kind: &'static str,
        table: &'a toml::Table,
        allowed: &[&str],
    ) -> Result<Self, String> {
        for key in table.keys() {
            if !allowed.contains(&key.as_str()) {
                return Err(format!(
                    "{kind}: unknown parameter `{key}` (parameters: {})",
                    allowed.join(", ")
                ));
            }
        }
        Ok(Params { kind, table })
    }

    fn bad(&self, key: &str, what: &str) -> String {
        format!("{}: parameter `{key}`: {what}", self.kind)
    }

    /// Whether `key` is present.
    pub(crate) fn has(&self, key: &str) -> bool {
        self.table.contains_key(key)
    }

    /// A number (integer or float).
    pub(crate) fn num(&self, key: &str) -> Result<Option<f64>, String> {
        match self.table.get(key) {
            None => Ok(None),
            Some(toml::Value::Integer(i)) => Ok(Some(*i as f64)),
            Some(toml::Value::Float(f)) if !f.is_nan() => Ok(Some(*f)),
            Some(_) => Err(self.bad(key, "expected a number")),
        }
    }

    /// A number, or `default` when absent.
    pub(crate) fn num_or(&self, key: &str, default: f64) -> Result<f64, String> {
        Ok(self.num(key)?.unwrap_or(default))
    }

    /// A required number.
    pub(crate) fn num_req(&self, key: &str) -> Result<f64, String> {
        self.num(key)?
            .ok_or_else(|| self.bad(key, "required (a number)"))
    }

    /// A duration in seconds: number or string with units.
    pub(crate) fn dur(&self, key: &str) -> Result<Option<f64>, String> {
        match self.table.get(key) {
            None => Ok(None),
            Some(toml::Value::Integer(i)) if *i >= 0 => Ok(Some(*i as f64)),
            Some(toml::Value::Float(f)) if *f >= 0.0 => Ok(Some(*f)),
            Some(toml::Value::String(s)) => {
                parse_duration(s).map(Some).map_err(|e| self.bad(key, &e))
            }
            Some(_) => Err(self.bad(
                key,
                "expected a duration ≥ 0 (seconds, or a string like \"30s\", \"500ms\")",
            )),
        }
    }

    /// A duration, or `default` when absent.
    pub(crate) fn dur_or(&self, key: &str, default: f64) -> Result<f64, String> {
        Ok(self.dur(key)?.unwrap_or(default))
    }

    /// A boolean, or `default` when absent.
    pub(crate) fn bool_or(&self, key: &str, default: bool) -> Result<bool, String> {
        match self.table.get(key) {
            None => Ok(default),
            Some(toml::Value::Boolean(b)) => Ok(*b),
            Some(_) => Err(self.bad(key, "expected true or false")),
        }
    }

    /// A string.
    pub(crate) fn str(&self, key: &str) -> Result<Option<&'a str>, String> {
        match self.table.get(key) {
            None => Ok(None),
            Some(toml::Value::String(s)) => Ok(Some(s.as_str())),
            Some(_) => Err(self.bad(key, "expected a string")),
        }
    }

    /// An integer taken as 64 raw bits (negative values wrap), or `default`.
    pub(crate) fn u64_or(&self, key: &str, default: u64) -> Result<u64, String> {
        match self.table.get(key) {
            None => Ok(default),
            Some(toml::Value::Integer(i)) => Ok(*i as u64),
            Some(_) => Err(self.bad(key, "expected an integer")),
        }
    }
}

/// Prefixes a constructor's validation error with the model type.
pub(crate) fn ctx<T>(kind: &str, r: Result<T, String>) -> Result<T, String> {
    r.map_err(|e| format!("{kind}: {e}"))
}

#[cfg(test)]
mod tests {
    use super::parse_duration;

    #[test]
    fn durations() {
        assert_eq!(parse_duration("30s"), Ok(30.0));
        assert_eq!(parse_duration("500ms"), Ok(0.5));
        assert_eq!(parse_duration("2min"), Ok(120.0));
        assert_eq!(parse_duration("1h30min"), Ok(5400.0));
        assert_eq!(parse_duration("1m30s"), Ok(90.0));
        assert_eq!(parse_duration(" 250 us "), Ok(250e-6));
        assert_eq!(parse_duration("1.5"), Ok(1.5));
        assert_eq!(parse_duration("0"), Ok(0.0));
        for bad in ["", "s", "-1s", "1x", "inf", "NaN", "1.2.3s", "-3"] {
            assert!(parse_duration(bad).is_err(), "{bad}");
        }
    }
}
