//! `serve --opcua`: the OPC UA server of softplc-opcua, built in with the
//! cargo feature `opcua` (on by default); a build without it refuses the
//! options with the way to build it.

use std::path::Path;
use std::time::Duration;

use softplc_serve::{Listener, ServeState};

/// The command line's OPC UA options.
pub struct OpcuaArgs<'a> {
    pub addr: Option<&'a str>,
    pub read_only: bool,
    pub pki: Option<&'a Path>,
}

/// The OPC UA listener when `--opcua` or `[opcua] address` asks for one.
/// `base` is where a relative `[opcua] pki` lives.
#[cfg(feature = "opcua")]
pub fn listener(
    args: &OpcuaArgs,
    table: Option<&toml::Table>,
    base: &Path,
    scan: Duration,
    state: &ServeState,
) -> Result<Option<Listener>, String> {
    let flags = softplc_opcua::Flags {
        addr: args.addr.map(str::to_string),
        read_only: args.read_only,
        pki: args.pki.map(Path::to_path_buf),
    };
    let Some(cfg) = softplc_opcua::OpcuaConfig::new(&flags, table, base, scan)? else {
        if args.read_only || args.pki.is_some() {
            eprintln!("softplc: --opcua-read-only/--opcua-pki have no effect without --opcua");
        }
        return Ok(None);
    };
    let prepared = match state.cpu_count() {
        1 => softplc_opcua::Prepared::new(cfg, state.cpu())?,
        n => {
            let cpus: Vec<_> = (0..n).map(|i| state.cpu_at(i)).collect();
            softplc_opcua::Prepared::system(cfg, &cpus)?
        }
    };
    Ok(Some(prepared.listener()))
}

#[cfg(not(feature = "opcua"))]
pub fn listener(
    args: &OpcuaArgs,
    table: Option<&toml::Table>,
    _base: &Path,
    _scan: Duration,
    _state: &ServeState,
) -> Result<Option<Listener>, String> {
    let asked = args.addr.is_some()
        || args.read_only
        || args.pki.is_some()
        || table.is_some_and(|t| t.contains_key("address"));
    if asked {
        return Err(
            "--opcua: this softplc is built without the OPC UA server (--no-default-features); \
             build it with the default features or `cargo build --release -p softplc \
             --features opcua`"
                .to_string(),
        );
    }
    Ok(None)
}
