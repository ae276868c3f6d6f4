//! The rack over HTTP: `GET /api/v1/rack` lists the slots of the base units
//! as plc.toml configured them (004 ch. 5 I/O numbering, ch. 8 intelligent
//! function modules, App. 3 interrupt pointers), and `status` carries a short
//! summary ([`summary`]). The buffer memory itself is read and written as
//! the devices `U<n>\G<addr>` through `/api/v1/devices`.

use std::collections::HashMap;
use std::sync::Arc;

use axum::extract::{Query, State};
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde_json::{json, Value as Json_};
use softplc_ir::rack::{Rack, Slot, SlotType};

use crate::App;

/// `GET /api/v1/rack[?cpu=N]`: `{"slots": [...]}`, one object a slot in
/// slot order (see [`slot`]); an empty list without `[[slot]]` tables. A
/// multi-CPU system's CPUs share the I/O assignment; each shows its own
/// view (`?cpu=N`, default CPU 1).
pub async fn rack(
    State(app): State<Arc<App>>,
    Query(q): Query<HashMap<String, String>>,
) -> Response {
    let cpu = match crate::api::cpu_param(&app, &q) {
        Ok(c) => c,
        Err(r) => return r,
    };
    match crate::api::at_end(&app, move |s| slots(s.cpu_at(cpu).rack())).await {
        Ok(j) => Json(j).into_response(),
        Err(e) => e,
    }
}

/// The rack as JSON: `{"slots": [...]}`.
pub fn slots(rack: &Rack) -> Json_ {
    json!({ "slots": rack.slots.iter().map(slot).collect::<Vec<_>>() })
}

/// One slot: `index`, `type` (plc.toml's), `points`, `start` and `end` I/O
/// numbers (4 hex digits; `end` null for a slot of 0 points), `module` (the
/// simulated profile, null for none), `unit` (`U2` for buffer memory
/// `U2\G…`, null without buffer memory), `buffer_words`, and `interrupts`:
/// the interrupt pointers the slot raises, each with its cause (an interrupt
/// module's input number, an intelligent module's interrupt cause).
pub fn slot(s: &Slot) -> Json_ {
    let io = s.io();
    let buffer = s.kind == SlotType::Intelligent && s.buffer_words > 0;
    json!({
        "index": s.index,
        "type": s.kind.name(),
        "points": s.points,
        "start": format!("{:04X}", io.start),
        "end": (s.points > 0).then(|| format!("{:04X}", io.end - 1)),
        "module": s.module.map(|m| m.name),
        "unit": buffer.then(|| format!("U{:X}", s.unit())),
        "buffer_words": s.buffer_words,
        "interrupts": interrupts(s),
    })
}

/// The slot's interrupt causes and pointers: an interrupt module's inputs
/// (I0-I15, App. 3) or an intelligent module's interrupt pointer setting
/// (I50-I255).
fn interrupts(s: &Slot) -> Vec<Json_> {
    let own = s.module.and_then(|m| m.pointers.clone());
    match own {
        Some(pointers) if s.kind == SlotType::Interrupt => pointers
            .enumerate()
            .map(|(cause, p)| json!({ "cause": cause, "pointer": format!("I{p}") }))
            .collect(),
        _ => s
            .interrupts
            .iter()
            .map(|&(cause, p)| json!({ "cause": cause, "pointer": format!("I{p}") }))
            .collect(),
    }
}

/// The short rack summary of `GET /api/v1/status`: null without a rack,
/// else the number of slots and the modules by slot (`{"slots": 5,
/// "modules": {"2": "generic"}}`).
pub fn summary(rack: &Rack) -> Json_ {
    if rack.is_empty() {
        return Json_::Null;
    }
    let modules: serde_json::Map<String, Json_> = rack
        .slots
        .iter()
        .filter_map(|s| Some((s.index.to_string(), json!(s.module?.name))))
        .collect();
    json!({ "slots": rack.slots.len(), "modules": modules })
}
