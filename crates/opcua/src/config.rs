//! The OPC UA server's settings: the `[opcua]` table of plc.toml
//! (docs/plc-toml.md) with the command line's `--opcua`, `--opcua-read-only`
//! and `--opcua-pki` over it.

use std::net::SocketAddr;
use std::path::{Path, PathBuf};

/// How `serve --opcua` is set up.
#[derive(Clone, Debug, PartialEq)]
pub struct OpcuaConfig {
    /// Where the endpoint listens (`opc.tcp://ADDR/`).
    pub addr: SocketAddr,
    /// Every write is refused with BadNotWritable (`--opcua-read-only`).
    pub read_only: bool,
    /// A user name and password: when set, anonymous sessions only read and
    /// a write needs this user (BadUserAccessDenied otherwise).
    pub user: Option<(String, String)>,
    /// The certificate store: `own/cert.der`, `private/private.pem` (made
    /// self-signed on first start), `trusted/` and `rejected/` client
    /// certificates.
    pub pki: PathBuf,
    /// Accept any client certificate on the secure endpoints (otherwise a
    /// client's certificate must be moved from `rejected/` to `trusted/`).
    pub trust_client_certs: bool,
    /// Device names given typed nodes besides those the program uses
    /// (`D100:u16`, `D200:u32`).
    pub nodes: Vec<String>,
    /// The OPC UA server's sampling floor: the constant-scan period.
    pub scan: std::time::Duration,
    /// Sessions at most, in all and from one client address (`[opcua]
    /// max_sessions`, `max_sessions_per_client`); connections at most
    /// twice as many.
    pub max_sessions: usize,
    pub max_sessions_per_client: usize,
}

/// Sessions at most by default: a PLC's OPC UA clients are a few HMI,
/// SCADA and historian stations.
pub const MAX_SESSIONS: usize = 32;
/// Sessions from one client address at most by default.
pub const MAX_SESSIONS_PER_CLIENT: usize = 8;

/// The command line's part.
#[derive(Clone, Debug, Default)]
pub struct Flags {
    pub addr: Option<String>,
    pub read_only: bool,
    pub pki: Option<PathBuf>,
}

/// The certificate store when neither `--opcua-pki` nor `[opcua] pki` says
/// where: `softplc/opcua-pki` in the user's data directory
/// (`$XDG_DATA_HOME`, else `~/.local/share`), so that the server keeps one
/// certificate for its clients to trust and writes nothing into the current
/// or the project directory; in the temporary directory without a home.
pub fn default_pki() -> PathBuf {
    let env = |k: &str| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    env("XDG_DATA_HOME")
        .or_else(|| env("HOME").map(|h| h.join(".local/share")))
        .unwrap_or_else(std::env::temp_dir)
        .join("softplc")
        .join("opcua-pki")
}

impl OpcuaConfig {
    /// The settings from `[opcua]` (`table`, relative paths from `base`)
    /// and the command line; `None` when neither asks for the server.
    pub fn new(
        flags: &Flags,
        table: Option<&toml::Table>,
        base: &Path,
        scan: std::time::Duration,
    ) -> Result<Option<OpcuaConfig>, String> {
        let empty = toml::Table::new();
        let t = table.unwrap_or(&empty);
        const KEYS: &[&str] = &[
            "address",
            "read_only",
            "user",
            "password",
            "pki",
            "trust_client_certs",
            "nodes",
            "max_sessions",
            "max_sessions_per_client",
        ];
        if let Some(k) = t.keys().find(|k| !KEYS.contains(&k.as_str())) {
            return Err(format!(
                "[opcua]: unknown key `{k}` (known: {})",
                KEYS.join(", ")
            ));
        }
        let string = |k: &str| -> Result<Option<String>, String> {
            match t.get(k) {
                None => Ok(None),
                Some(toml::Value::String(s)) => Ok(Some(s.clone())),
                Some(v) => Err(format!("[opcua] {k}: expected a string, not `{v}`")),
            }
        };
        let boolean = |k: &str| -> Result<bool, String> {
            match t.get(k) {
                None => Ok(false),
                Some(toml::Value::Boolean(b)) => Ok(*b),
                Some(v) => Err(format!("[opcua] {k}: expected true or false, not `{v}`")),
            }
        };
        let count = |k: &str, default: usize| -> Result<usize, String> {
            match t.get(k) {
                None => Ok(default),
                Some(toml::Value::Integer(n)) if (1..=10_000).contains(n) => Ok(*n as usize),
                Some(v) => Err(format!(
                    "[opcua] {k}: expected a number from 1 to 10000, not `{v}`"
                )),
            }
        };
        let max_sessions = count("max_sessions", MAX_SESSIONS)?;
        let max_sessions_per_client = count(
            "max_sessions_per_client",
            MAX_SESSIONS_PER_CLIENT.min(max_sessions),
        )?;
        let addr = match flags.addr.clone().or(string("address")?) {
            Some(a) => softplc_serve::parse_addr(&a).map_err(|e| format!("--opcua {e}"))?,
            None => return Ok(None),
        };
        let user = match (string("user")?, string("password")?) {
            (Some(u), Some(p)) if !u.is_empty() && !p.is_empty() => Some((u, p)),
            (None, None) => None,
            _ => {
                return Err("[opcua]: `user` and `password` go together, neither empty".to_string())
            }
        };
        let pki = match (&flags.pki, string("pki")?) {
            (Some(p), _) => p.clone(),
            (None, Some(p)) => base.join(p),
            (None, None) => default_pki(),
        };
        let nodes = match t.get("nodes") {
            None => Vec::new(),
            Some(toml::Value::Array(a)) => a
                .iter()
                .map(|v| match v {
                    toml::Value::String(s) => Ok(s.clone()),
                    v => Err(format!("[opcua] nodes: expected device names, not `{v}`")),
                })
                .collect::<Result<_, _>>()?,
            Some(v) => return Err(format!("[opcua] nodes: expected a list, not `{v}`")),
        };
        Ok(Some(OpcuaConfig {
            addr,
            read_only: flags.read_only || boolean("read_only")?,
            user,
            pki,
            trust_client_certs: boolean("trust_client_certs")?,
            nodes,
            scan,
            max_sessions,
            max_sessions_per_client,
        }))
    }

    /// Security None is offered only on a loopback address (contract §3.2).
    pub fn allows_none(&self) -> bool {
        self.addr.ip().is_loopback()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn cfg(flags: Flags, toml_text: &str) -> Result<Option<OpcuaConfig>, String> {
        let t: toml::Table = toml::from_str(toml_text).unwrap();
        let table = t.get("opcua").and_then(|v| v.as_table());
        OpcuaConfig::new(&flags, table, Path::new("/p"), Duration::from_millis(10))
    }

    #[test]
    fn table_and_flags() {
        assert_eq!(cfg(Flags::default(), ""), Ok(None));
        let c = cfg(
            Flags::default(),
            "[opcua]\naddress = \"4840\"\nuser = \"op\"\npassword = \"pw\"\nnodes = [\"D100:u16\"]\n",
        )
        .unwrap()
        .unwrap();
        assert_eq!(c.addr, "127.0.0.1:4840".parse().unwrap());
        assert_eq!(c.user, Some(("op".into(), "pw".into())));
        assert_eq!(c.pki, default_pki());
        assert!(c.pki.ends_with("softplc/opcua-pki") && c.pki.is_absolute());
        assert_eq!(c.nodes, vec!["D100:u16".to_string()]);
        assert_eq!((c.max_sessions, c.max_sessions_per_client), (32, 8));
        assert!(!c.read_only && c.allows_none());
        // The command line wins; a non-loopback address has no security None.
        let flags = Flags {
            addr: Some("0.0.0.0:4841".into()),
            read_only: true,
            pki: Some("/k".into()),
        };
        let c = cfg(flags, "[opcua]\naddress = \"4840\"\npki = \"x\"\n")
            .unwrap()
            .unwrap();
        assert_eq!(c.addr.port(), 4841);
        assert!(c.read_only && !c.allows_none());
        assert_eq!(c.pki, PathBuf::from("/k"));
        // A relative `[opcua] pki` is in the project directory.
        let c = cfg(
            Flags::default(),
            "[opcua]\naddress = \"4840\"\npki = \"x\"\n",
        )
        .unwrap()
        .unwrap();
        assert_eq!(c.pki, PathBuf::from("/p/x"));
    }

    #[test]
    fn bad_tables_name_the_key() {
        let e = cfg(Flags::default(), "[opcua]\naddres = \"4840\"\n").unwrap_err();
        assert!(e.contains("unknown key `addres`"), "{e}");
        let e = cfg(
            Flags::default(),
            "[opcua]\naddress = \"4840\"\nuser = \"op\"\n",
        )
        .unwrap_err();
        assert!(e.contains("go together"), "{e}");
        let e = cfg(Flags::default(), "[opcua]\naddress = 4840\n").unwrap_err();
        assert!(e.contains("address: expected a string"), "{e}");
        let e = cfg(
            Flags::default(),
            "[opcua]\naddress = \"4840\"\nmax_sessions = 0\n",
        )
        .unwrap_err();
        assert!(e.contains("max_sessions: expected a number from 1"), "{e}");
        let c = cfg(
            Flags::default(),
            "[opcua]\naddress = \"4840\"\nmax_sessions = 4\n",
        )
        .unwrap()
        .unwrap();
        assert_eq!((c.max_sessions, c.max_sessions_per_client), (4, 4));
        let e = cfg(Flags::default(), "[opcua]\naddress = \"x\"\n").unwrap_err();
        assert!(e.contains("--opcua `x`"), "{e}");
    }
}
