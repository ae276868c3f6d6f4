//! The web monitor's settings: `[http]` in plc.toml (docs/plc-toml.md) with
//! the command line's `--http-*` options over it.

use std::time::Duration;

use softplc_http::door::Limits;

use crate::run::parse_duration;

/// The command line's part.
#[derive(Debug, Default)]
pub struct Flags<'a> {
    pub token: Option<&'a str>,
    pub max_connections: Option<usize>,
    pub header_timeout: Option<Duration>,
    pub body_timeout: Option<Duration>,
}

const KEYS: &[&str] = &["token", "max_connections", "header_timeout", "body_timeout"];

/// The bearer token (`None`: read-only) and the door's limits.
pub fn settings(
    flags: &Flags,
    table: Option<&toml::Table>,
) -> Result<(Option<String>, Limits), String> {
    let empty = toml::Table::new();
    let t = table.unwrap_or(&empty);
    if let Some(k) = t.keys().find(|k| !KEYS.contains(&k.as_str())) {
        return Err(format!(
            "[http]: unknown key `{k}` (known: {})",
            KEYS.join(", ")
        ));
    }
    let from_toml = match t.get("token") {
        None => None,
        Some(toml::Value::String(s)) => Some(s.clone()),
        Some(v) => return Err(format!("[http] token: expected a string, not `{v}`")),
    };
    let token = match flags.token.map(str::to_string).or(from_toml) {
        Some(t) if t.is_empty() || !t.bytes().all(|b| b.is_ascii_graphic()) => {
            return Err("--http-token: the token must be printable ASCII without spaces".into())
        }
        t => t,
    };
    let d = Limits::default();
    let max_connections = match (flags.max_connections, t.get("max_connections")) {
        (Some(n), _) => n,
        (None, None) => d.max_connections,
        (None, Some(toml::Value::Integer(n))) => usize::try_from(*n).unwrap_or(0),
        (None, Some(v)) => {
            return Err(format!(
                "[http] max_connections: expected a number, not `{v}`"
            ))
        }
    };
    if max_connections == 0 {
        return Err("[http] max_connections / --http-max-connections: at least 1".into());
    }
    let duration = |flag: Option<Duration>, key: &str, default: Duration| match (flag, t.get(key)) {
        (Some(d), _) => Ok(d),
        (None, None) => Ok(default),
        (None, Some(toml::Value::String(s))) => {
            parse_duration(s).map_err(|e| format!("[http] {key}: {e}"))
        }
        (None, Some(v)) => Err(format!(
            "[http] {key}: expected a duration such as \"10s\", not `{v}`"
        )),
    };
    let limits = Limits {
        max_connections,
        header_timeout: duration(flags.header_timeout, "header_timeout", d.header_timeout)?,
        body_timeout: duration(flags.body_timeout, "body_timeout", d.body_timeout)?,
    };
    Ok((token, limits))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> toml::Table {
        let t: toml::Table = toml::from_str(text).unwrap();
        t.get("http").and_then(|v| v.as_table()).cloned().unwrap()
    }

    #[test]
    fn defaults_table_and_flags() {
        assert_eq!(
            settings(&Flags::default(), None).unwrap(),
            (None, Limits::default())
        );
        let t = table(
            "[http]\ntoken = \"tk\"\nmax_connections = 8\nheader_timeout = \"2s\"\nbody_timeout = \"500ms\"\n",
        );
        let (token, l) = settings(&Flags::default(), Some(&t)).unwrap();
        assert_eq!(token.as_deref(), Some("tk"));
        assert_eq!(
            l,
            Limits {
                max_connections: 8,
                header_timeout: Duration::from_secs(2),
                body_timeout: Duration::from_millis(500),
            }
        );
        // The command line wins.
        let flags = Flags {
            token: Some("cli"),
            max_connections: Some(3),
            header_timeout: Some(Duration::from_secs(1)),
            body_timeout: None,
        };
        let (token, l) = settings(&flags, Some(&t)).unwrap();
        assert_eq!(token.as_deref(), Some("cli"));
        assert_eq!(l.max_connections, 3);
        assert_eq!(l.header_timeout, Duration::from_secs(1));
        assert_eq!(l.body_timeout, Duration::from_millis(500));
    }

    #[test]
    fn bad_settings_name_the_key() {
        for (text, want) in [
            ("[http]\ntokn = \"x\"\n", "unknown key `tokn`"),
            ("[http]\nmax_connections = 0\n", "at least 1"),
            ("[http]\nmax_connections = \"8\"\n", "max_connections"),
            ("[http]\nheader_timeout = 10\n", "header_timeout"),
            ("[http]\nbody_timeout = \"10\"\n", "body_timeout"),
            ("[http]\ntoken = \"a b\"\n", "printable"),
        ] {
            let e = settings(&Flags::default(), Some(&table(text))).unwrap_err();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
