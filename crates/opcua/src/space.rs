//! The address space of contract §3.2 and its node manager:
//!
//! ```text
//! Objects/softplc/Devices/D100, Y0, D10:f32 …   string NodeIds = `--show` names
//!                /Diagnostics/State, Scan, ScanTimeUs, ErrorCode
//!                /Loops/<loop>/SV, PV, MV, MODE, ALARM (MVMAN)
//! ```
//!
//! A multi-CPU system (contract §6) has a folder per CPU, each with those
//! three: `Objects/softplc/CPU2/Devices/D100` (NodeId `CPU2/D100`, the name
//! with its CPU prefix), `…/CPU2/Diagnostics/State` (NodeId
//! `/softplc/CPU2/Diagnostics/State`), `…/CPU2/Loops/<loop>/SV`.
//!
//! Every node is in the namespace `urn:softplc`. Folders, diagnostics and
//! loop fields have NodeIds starting with `/` (`/softplc/Loops/…/SV`), which
//! no device name does. Values are set by [`crate::publish`] at END; a write
//! is checked here and applied at the next END through the engine queue.

use std::collections::HashMap;
use std::sync::Arc;

use async_trait::async_trait;
use opcua::nodes::{AccessLevel, ObjectBuilder, VariableBuilder};
use opcua::server::address_space::AddressSpace;
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::node_manager::memory::InMemoryNodeManagerImpl;
use opcua::server::node_manager::{RequestContext, ServerContext, WriteNode};
use opcua::sync::RwLock;
use opcua::types::{
    AttributeId, DataTypeId, NodeId, NumericRange, ObjectId, QualifiedName, StatusCode,
    VariableTypeId, Variant,
};
use softplc_core::access::Value;
use softplc_serve::EngineHandle;

use crate::points::{Kind, LoopFolder, Point};

/// The namespace of every softplc node (contract §3.2).
pub const NAMESPACE: &str = "urn:softplc";
pub const ROOT_ID: &str = "/softplc";
pub const DEVICES_ID: &str = "/softplc/Devices";
pub const DIAGNOSTICS_ID: &str = "/softplc/Diagnostics";
pub const LOOPS_ID: &str = "/softplc/Loops";

/// The diagnostics variables, in the order [`crate::publish::Diag`] holds them.
pub const DIAGNOSTICS: [(&str, DataTypeId); 4] = [
    ("State", DataTypeId::String),
    ("Scan", DataTypeId::UInt64),
    ("ScanTimeUs", DataTypeId::UInt32),
    ("ErrorCode", DataTypeId::UInt16),
];

/// The NodeId of a diagnostics variable.
pub fn diagnostic_id(name: &str) -> String {
    format!("{DIAGNOSTICS_ID}/{name}")
}

/// What the address space shows: the device variables, then the loop
/// fields, in one list that publishing indexes.
pub struct Space {
    pub points: Vec<Point>,
    /// Device variables are `points[..devices]`.
    pub devices: usize,
    /// Each loop folder's CPU, browse name and its fields' range in `points`.
    pub loops: Vec<(usize, String, std::ops::Range<usize>)>,
    /// CPUs with a folder each (a multi-CPU system's); 0: one CPU, no CPU
    /// folders.
    pub cpu_folders: usize,
}

impl Space {
    /// One CPU's space.
    pub fn new(devices: Vec<Point>, loops: Vec<LoopFolder>) -> Space {
        Space::with_cpus(devices, loops, 0)
    }

    /// A multi-CPU system's space: a folder per CPU of `cpus`.
    pub fn with_cpus(devices: Vec<Point>, loops: Vec<LoopFolder>, cpus: usize) -> Space {
        let n = devices.len();
        let mut points = devices;
        let mut folders = Vec::new();
        for l in loops {
            let start = points.len();
            points.extend(l.fields);
            folders.push((l.cpu, l.browse, start..points.len()));
        }
        Space {
            points,
            devices: n,
            loops: folders,
            cpu_folders: cpus,
        }
    }

    /// CPUs whose diagnostics the space shows.
    pub fn cpus(&self) -> usize {
        self.cpu_folders.max(1)
    }

    /// The NodeId of CPU `cpu`'s folder `name` (`Devices`, `Diagnostics`,
    /// `Loops`).
    pub fn folder(&self, cpu: usize, name: &str) -> String {
        if self.cpu_folders == 0 {
            format!("{ROOT_ID}/{name}")
        } else {
            format!("{}/{name}", cpu_folder(cpu))
        }
    }

    /// The NodeId of CPU `cpu`'s diagnostics variable `name`.
    pub fn diagnostic(&self, cpu: usize, name: &str) -> String {
        format!("{}/{name}", self.folder(cpu, "Diagnostics"))
    }
}

/// The NodeId of CPU `cpu`'s (0-based) folder in a multi-CPU system.
pub fn cpu_folder(cpu: usize) -> String {
    format!("{ROOT_ID}/CPU{}", cpu + 1)
}

/// The raw bits of a point (as `DevName::raw`) as a value of its node's type.
pub fn variant(kind: Kind, raw: u64) -> Variant {
    match kind {
        Kind::Boolean => Variant::Boolean(raw & 1 != 0),
        Kind::Int16 => Variant::Int16(raw as u16 as i16),
        Kind::UInt16 => Variant::UInt16(raw as u16),
        Kind::Int32 => Variant::Int32(raw as u32 as i32),
        Kind::UInt32 => Variant::UInt32(raw as u32),
        Kind::Float => Variant::Float(f32::from_bits(raw as u32)),
    }
}

fn data_type(kind: Kind) -> DataTypeId {
    match kind {
        Kind::Boolean => DataTypeId::Boolean,
        Kind::Int16 => DataTypeId::Int16,
        Kind::UInt16 => DataTypeId::UInt16,
        Kind::Int32 => DataTypeId::Int32,
        Kind::UInt32 => DataTypeId::UInt32,
        Kind::Float => DataTypeId::Float,
    }
}

/// A written value for a node of `kind`: exactly the node's type
/// (contract §3.2: BadTypeMismatch otherwise).
pub fn written(kind: Kind, v: Option<&Variant>) -> Result<Value, StatusCode> {
    Ok(match (kind, v) {
        (Kind::Boolean, Some(Variant::Boolean(b))) => Value::Bool(*b),
        (Kind::Int16, Some(Variant::Int16(n))) => Value::Int(*n as i64),
        (Kind::UInt16, Some(Variant::UInt16(n))) => Value::Int(*n as i64),
        (Kind::Int32, Some(Variant::Int32(n))) => Value::Int(*n as i64),
        (Kind::UInt32, Some(Variant::UInt32(n))) => Value::Int(*n as i64),
        (Kind::Float, Some(Variant::Float(f))) if f.is_finite() => Value::Float(*f as f64),
        (Kind::Float, Some(Variant::Float(_))) => return Err(StatusCode::BadOutOfRange),
        _ => return Err(StatusCode::BadTypeMismatch),
    })
}

/// Who may write.
#[derive(Clone, Copy, Debug)]
pub struct WriteRule {
    /// `--opcua-read-only`: nothing.
    pub read_only: bool,
    /// A user is configured: anonymous sessions only read.
    pub needs_user: bool,
}

/// The node manager of `urn:softplc`.
pub struct SoftplcNodes {
    ns: u16,
    space: Arc<Space>,
    /// Point index of each variable's NodeId.
    index: HashMap<NodeId, usize>,
    engine: EngineHandle,
    rule: WriteRule,
    feed: Arc<crate::publish::Feed>,
}

impl SoftplcNodes {
    /// Adds the folders and variables of `feed`'s points, with their latest
    /// values, and the diagnostics to `address_space`.
    pub fn build(
        context: &ServerContext,
        address_space: &mut AddressSpace,
        engine: EngineHandle,
        rule: WriteRule,
        feed: Arc<crate::publish::Feed>,
    ) -> SoftplcNodes {
        let space = feed.space().clone();
        let (raw, diags) = feed.latest();
        let ns =
            opcua::server::address_space::add_namespaces(context, address_space, &[NAMESPACE])[0];
        let id = |s: &str| NodeId::new(ns, s.to_string());
        let folder = |a: &mut AddressSpace, node: &str, name: &str, parent: &NodeId| {
            ObjectBuilder::new(&id(node), QualifiedName::new(ns, name), name)
                .is_folder()
                .organized_by(parent.clone())
                .insert(a);
        };
        folder(
            address_space,
            ROOT_ID,
            "softplc",
            &ObjectId::ObjectsFolder.into(),
        );
        for cpu in 0..space.cpus() {
            let parent = if space.cpu_folders == 0 {
                id(ROOT_ID)
            } else {
                let c = cpu_folder(cpu);
                folder(address_space, &c, &format!("CPU{}", cpu + 1), &id(ROOT_ID));
                id(&c)
            };
            for name in ["Devices", "Diagnostics", "Loops"] {
                folder(address_space, &space.folder(cpu, name), name, &parent);
            }
        }
        let writable = |p: &Point| !rule.read_only && !p.name.is_read_only();
        let mut index = HashMap::new();
        let mut variable = |a: &mut AddressSpace, k: usize, parent: &NodeId| {
            let p = &space.points[k];
            let access = if writable(p) {
                AccessLevel::CURRENT_READ | AccessLevel::CURRENT_WRITE
            } else {
                AccessLevel::CURRENT_READ
            };
            let node = id(&p.id);
            VariableBuilder::new(
                &node,
                QualifiedName::new(ns, p.browse.as_str()),
                p.browse.as_str(),
            )
            .data_type(data_type(p.kind))
            .value(variant(p.kind, raw[k]))
            .access_level(access)
            .user_access_level(access)
            .has_type_definition(VariableTypeId::BaseDataVariableType)
            .organized_by(parent.clone())
            .insert(a);
            index.insert(node, k);
        };
        for k in 0..space.devices {
            let devices = id(&space.folder(space.points[k].cpu, "Devices"));
            variable(address_space, k, &devices);
        }
        for (cpu, name, range) in &space.loops {
            let loops = space.folder(*cpu, "Loops");
            let fid = format!("{loops}/{name}");
            folder(address_space, &fid, name, &id(&loops));
            for k in range.clone() {
                variable(address_space, k, &id(&fid));
            }
        }
        for (cpu, diag) in diags.iter().enumerate() {
            let diag_folder = id(&space.folder(cpu, "Diagnostics"));
            for ((name, ty), initial) in DIAGNOSTICS.into_iter().zip(diag.variants()) {
                VariableBuilder::new(
                    &id(&space.diagnostic(cpu, name)),
                    QualifiedName::new(ns, name),
                    name,
                )
                .data_type(ty)
                .value(initial)
                .access_level(AccessLevel::CURRENT_READ)
                .user_access_level(AccessLevel::CURRENT_READ)
                .has_type_definition(VariableTypeId::BaseDataVariableType)
                .organized_by(diag_folder.clone())
                .insert(address_space);
            }
        }
        SoftplcNodes {
            ns,
            space,
            index,
            engine,
            rule,
            feed,
        }
    }

    /// The namespace index of `urn:softplc`.
    pub fn namespace(&self) -> u16 {
        self.ns
    }

    /// Checks one write; the point and value to write, or the status.
    fn check(
        &self,
        context: &RequestContext,
        address_space: &RwLock<AddressSpace>,
        w: &WriteNode,
    ) -> Result<(usize, Value), StatusCode> {
        let v = w.value();
        let Some(&k) = self.index.get(&v.node_id) else {
            return Err(if address_space.read().find(&v.node_id).is_some() {
                StatusCode::BadNotWritable
            } else {
                StatusCode::BadNodeIdUnknown
            });
        };
        let p = &self.space.points[k];
        if v.attribute_id != AttributeId::Value || self.rule.read_only || p.name.is_read_only() {
            return Err(StatusCode::BadNotWritable);
        }
        if !matches!(v.index_range, NumericRange::None) {
            return Err(StatusCode::BadWriteNotSupported);
        }
        if self.rule.needs_user && context.user_token().is_anonymous() {
            return Err(StatusCode::BadUserAccessDenied);
        }
        Ok((k, written(p.kind, v.value.value.as_ref())?))
    }
}

#[async_trait]
impl InMemoryNodeManagerImpl for SoftplcNodes {
    async fn init(&self, _address_space: &mut AddressSpace, _context: ServerContext) {}

    fn name(&self) -> &str {
        "softplc"
    }

    fn namespaces(&self) -> Vec<NamespaceMetadata> {
        vec![NamespaceMetadata {
            is_namespace_subset: Some(false),
            namespace_uri: NAMESPACE.to_string(),
            namespace_index: self.ns,
            ..Default::default()
        }]
    }

    /// Writes are checked now and applied together at the next END (like MC
    /// and Modbus writes); the reply waits for that END, its commit and the
    /// publishing of its values, so a read after the reply shows them.
    async fn write(
        &self,
        context: &RequestContext,
        address_space: &RwLock<AddressSpace>,
        nodes_to_write: &mut [&mut WriteNode],
    ) -> Result<(), StatusCode> {
        let mut todo = Vec::new();
        for (slot, w) in nodes_to_write.iter_mut().enumerate() {
            match self.check(context, address_space, w) {
                Ok((k, v)) => todo.push((slot, k, v)),
                Err(e) => w.set_status(e),
            }
        }
        if todo.is_empty() {
            return Ok(());
        }
        let space = self.space.clone();
        let feed = self.feed.clone();
        let jobs: Vec<(usize, Value)> = todo.iter().map(|(_, k, v)| (*k, v.clone())).collect();
        let done = self
            .engine
            .at_end(move |s| {
                let statuses: Vec<StatusCode> = jobs
                    .iter()
                    .map(|(k, v)| {
                        let p = &space.points[*k];
                        match p.name.write_value(s.cpu_mut_at(p.cpu), v) {
                            Ok(()) => {
                                s.mark_wrote(p.cpu);
                                StatusCode::Good
                            }
                            Err(_) => StatusCode::BadOutOfRange,
                        }
                    })
                    .collect();
                (statuses, feed.sample(s))
            })
            .await;
        match done {
            Ok((statuses, seq)) => {
                self.feed.published(seq).await;
                for ((slot, _, _), st) in todo.iter().zip(statuses) {
                    nodes_to_write[*slot].set_status(st);
                }
            }
            Err(softplc_serve::Busy) => {
                for (slot, _, _) in &todo {
                    nodes_to_write[*slot].set_status(StatusCode::BadResourceUnavailable);
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raw_bits_become_the_node_type() {
        assert_eq!(variant(Kind::Boolean, 1), Variant::Boolean(true));
        assert_eq!(variant(Kind::Int16, 0xFFFF), Variant::Int16(-1));
        assert_eq!(variant(Kind::UInt16, 0xFFFF), Variant::UInt16(65535));
        assert_eq!(variant(Kind::Int32, 0xFFFF_FFFE), Variant::Int32(-2));
        assert_eq!(
            variant(Kind::UInt32, 0xFFFF_FFFE),
            Variant::UInt32(4294967294)
        );
        // 1.5f32 = 0x3FC00000.
        assert_eq!(variant(Kind::Float, 0x3FC0_0000), Variant::Float(1.5));
    }

    #[test]
    fn writes_must_be_of_the_node_type() {
        assert_eq!(
            written(Kind::Int16, Some(&Variant::Int16(-5))),
            Ok(Value::Int(-5))
        );
        assert_eq!(
            written(Kind::UInt32, Some(&Variant::UInt32(70000))),
            Ok(Value::Int(70000))
        );
        assert_eq!(
            written(Kind::Float, Some(&Variant::Float(2.5))),
            Ok(Value::Float(2.5))
        );
        for (k, v) in [
            (Kind::Int16, Variant::Int32(5)),
            (Kind::Int32, Variant::Int16(5)),
            (Kind::Boolean, Variant::Int16(1)),
            (Kind::Float, Variant::Double(1.0)),
            (Kind::UInt16, Variant::from("5")),
        ] {
            assert_eq!(
                written(k, Some(&v)),
                Err(StatusCode::BadTypeMismatch),
                "{v:?}"
            );
        }
        assert_eq!(written(Kind::Int16, None), Err(StatusCode::BadTypeMismatch));
        assert_eq!(
            written(Kind::Float, Some(&Variant::Float(f32::NAN))),
            Err(StatusCode::BadOutOfRange)
        );
    }
}
