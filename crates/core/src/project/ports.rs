//! `[port1]`/`[port2]` of an APLC-TCP project (contract §3.3): the keys of
//! the system block's communication page, read by
//! [`softplc_aplc::comm::PortConfig::build`]; each error at its key. A
//! `device` path is relative to the project directory.

use std::path::Path;

use softplc_aplc::comm::{PortConfig, Val};

use super::ctx::Ctx;
use super::tree::{Entry, Value};

/// Reads the port tables of `top`; reports them as errors on another model.
pub(crate) fn ports(cx: &mut Ctx, top: &[Entry], aplc: bool, dir: &Path) -> Vec<PortConfig> {
    let mut out = Vec::new();
    for (port, name) in [(1u8, "port1"), (2, "port2")] {
        let Some(e) = top.iter().find(|e| e.key == name) else {
            continue;
        };
        if !aplc {
            cx.error(
                &e.key_span,
                format!("[{name}] is an APLC-TCP setting (set [cpu] model = \"APLC-TCP\")"),
            );
            continue;
        }
        let Some(t) = cx.table(e, &format!("[{name}]")) else {
            continue;
        };
        let items: Vec<(&str, Val<'_>)> = t
            .iter()
            .map(|e| {
                let v = match &e.item.value {
                    Value::Int(n) => Val::Int(*n),
                    Value::Str(s) => Val::Str(s),
                    Value::Bool(b) => Val::Bool(*b),
                    v => Val::Other(v.type_name()),
                };
                (e.key.as_str(), v)
            })
            .collect();
        match PortConfig::build(port, &items) {
            Ok(mut c) => {
                if let Some(d) = &c.device {
                    c.device = Some(dir.join(d).display().to_string());
                }
                out.push(c);
            }
            Err(errors) => {
                for (i, msg) in errors {
                    let span = t.get(i).map_or(e.key_span.clone(), |e| e.item.span.clone());
                    cx.error(&span, format!("[{name}] {msg}"));
                }
            }
        }
    }
    out
}
