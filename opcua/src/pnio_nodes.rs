// SPDX-License-Identifier: MIT OR Apache-2.0
//! The PNIO item names as string NodeIds of namespace [`PNIO_NAMESPACE`], beside the
//! browsable tree: any item [`Item::parse`] reads is a variable, resolved when it is read or
//! monitored, from the newest snapshot (so an image of any size costs no nodes). A Read takes
//! one snapshot for all its items: they are of one cycle.

use crate::items::{Area, Format, Item, ItemKind, ProcessItem, Values};
use crate::snapshot::{Snapshot, quality};
use crate::tree::{status_code, timestamp};
use async_trait::async_trait;
use opcua::nodes::DefaultTypeTree;
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::node_manager::{
    DynNodeManager, MonitoredItemRef, NodeManager, NodeManagerBuilder, ReadNode, RequestContext,
    ServerContext,
};
use opcua::server::{CreateMonitoredItem, MonitoredItemHandle, SubscriptionCache};
use opcua::types::{
    AttributeId, DataTypeId, DataValue, DateTime, Identifier, LocalizedText, NodeClass, NodeId,
    QualifiedName, StatusCode, TimestampsToReturn, Variant,
};
use procimg_client::Layout;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use tokio::sync::watch;

/// The namespace URI of the item names.
pub const PNIO_NAMESPACE: &str = "urn:procimg:pnio";

/// The item names of one instance, its controller index `controller`.
pub struct PnioItems {
    ns: u16,
    controller: u8,
    layout: Arc<Layout>,
    snapshots: watch::Receiver<Arc<Snapshot>>,
    /// Monitored items: their node and item, and the value last notified.
    monitored: Mutex<HashMap<MonitoredItemHandle, Monitored>>,
}

struct Monitored {
    node: NodeId,
    item: Item,
    last: Option<(Variant, StatusCode)>,
}

/// Builds [`PnioItems`] into a server.
pub struct PnioItemsBuilder {
    /// The controller index items must name (`CTRL<n>`).
    pub controller: u8,
    /// The image's layout.
    pub layout: Arc<Layout>,
    /// The snapshots.
    pub snapshots: watch::Receiver<Arc<Snapshot>>,
}

impl NodeManagerBuilder for PnioItemsBuilder {
    fn build(self: Box<Self>, context: ServerContext) -> Arc<DynNodeManager> {
        let ns = context
            .type_tree
            .write()
            .namespaces_mut()
            .add_namespace(PNIO_NAMESPACE);
        Arc::new(PnioItems {
            ns,
            controller: self.controller,
            layout: self.layout,
            snapshots: self.snapshots,
            monitored: Mutex::new(HashMap::new()),
        })
    }
}

/// Why an item has no value.
fn unknown() -> StatusCode {
    StatusCode::BadNodeIdUnknown
}

impl PnioItems {
    /// The item a NodeId of this namespace names, if it is one of this instance's.
    fn item(&self, id: &NodeId) -> Result<Item, StatusCode> {
        let Identifier::String(name) = &id.identifier else {
            return Err(unknown());
        };
        let item = Item::parse(name.as_ref()).map_err(|_| unknown())?;
        if item.controller != self.controller {
            return Err(unknown());
        }
        Ok(item)
    }

    /// The submodule whose data holds all of `p`'s bytes.
    fn submodule_of(&self, p: &ProcessItem) -> Option<usize> {
        let (first, len) = p.span();
        let last = u64::from(first) + len as u64;
        self.layout.submodules.iter().position(|e| {
            let (at, n) = match p.area {
                Area::Input => (e.input_address, e.input_length),
                Area::Output => (e.output_address, e.output_length),
            };
            n > 0 && first >= at && last <= u64::from(at) + u64::from(n)
        })
    }

    /// The value and quality of `item` in `snap`.
    fn value(&self, item: &Item, snap: &Snapshot) -> Result<(Variant, StatusCode), StatusCode> {
        match item.kind {
            ItemKind::Mode => Ok((Variant::from(snap.mode().as_u32() as i32), StatusCode::Good)),
            ItemKind::Process(p) => {
                let s = self.submodule_of(&p).ok_or_else(unknown)?;
                let e = self.layout.submodules[s];
                let (first, len) = p.span();
                let (base, bytes) = match p.area {
                    Area::Input => (e.input_address, snap.inputs.get(s)),
                    Area::Output => (e.output_address, snap.outputs.get(s)),
                };
                let at = (first - base) as usize;
                let bytes = bytes
                    .and_then(|b| b.get(at..at + len))
                    .ok_or(StatusCode::BadNotConnected)?;
                let values = p.decode(bytes).map_err(|_| StatusCode::BadInternalError)?;
                let q = quality(snap, &self.layout, s, p.area == Area::Output);
                Ok((variant(&values, p.count.is_some()), status_code(q)))
            }
            // Records are read through the tree's method for now.
            ItemKind::Record(_) => Err(StatusCode::BadNotReadable),
        }
    }

    /// Notifies the monitored items whose value changed in `snap`.
    pub fn notify(&self, snap: &Snapshot, subscriptions: &SubscriptionCache) {
        let time = timestamp(snap.time);
        let mut changes = Vec::new();
        {
            let mut monitored = self.monitored.lock().unwrap_or_else(|e| e.into_inner());
            for m in monitored.values_mut() {
                let now = self
                    .value(&m.item, snap)
                    .unwrap_or_else(|status| (Variant::Empty, status));
                if m.last.as_ref() == Some(&now) {
                    continue;
                }
                m.last = Some(now.clone());
                changes.push((data_value(now, time), m.node.clone()));
            }
        }
        if !changes.is_empty() {
            subscriptions.notify_data_change(
                changes
                    .iter()
                    .map(|(dv, id)| (dv.clone(), id, AttributeId::Value)),
            );
        }
    }

    /// An attribute of `item`'s variable.
    fn attribute(
        &self,
        id: &NodeId,
        item: &Item,
        attribute: AttributeId,
    ) -> Result<Variant, StatusCode> {
        let name = match &id.identifier {
            Identifier::String(s) => s.as_ref().to_owned(),
            _ => String::new(),
        };
        let (data_type, array) = match item.kind {
            ItemKind::Mode => (DataTypeId::Int32, false),
            ItemKind::Record(_) => (DataTypeId::ByteString, false),
            ItemKind::Process(p) => (
                match p.format {
                    Format::Bit => DataTypeId::Boolean,
                    Format::Byte => DataTypeId::Byte,
                    Format::Word => DataTypeId::UInt16,
                    Format::Int => DataTypeId::Int16,
                    Format::DWord => DataTypeId::UInt32,
                    Format::DInt => DataTypeId::Int32,
                    Format::Real => DataTypeId::Float,
                },
                p.count.is_some(),
            ),
        };
        Ok(match attribute {
            AttributeId::NodeId => Variant::from(id.clone()),
            AttributeId::NodeClass => Variant::from(NodeClass::Variable as i32),
            AttributeId::BrowseName => Variant::from(QualifiedName::new(self.ns, name)),
            AttributeId::DisplayName => Variant::from(LocalizedText::new("", &name)),
            AttributeId::DataType => Variant::from(NodeId::from(data_type)),
            AttributeId::ValueRank => Variant::from(if array { 1i32 } else { -1i32 }),
            AttributeId::AccessLevel | AttributeId::UserAccessLevel => Variant::from(1u8),
            AttributeId::MinimumSamplingInterval => Variant::from(0.0f64),
            AttributeId::Historizing => Variant::from(false),
            _ => return Err(StatusCode::BadAttributeIdInvalid),
        })
    }
}

/// `values` as a Variant: a scalar, or an array with `,count`.
fn variant(values: &Values, array: bool) -> Variant {
    fn pick<T: Clone + Into<Variant> + opcua::types::VariantType>(v: &[T], array: bool) -> Variant {
        if array {
            Variant::from(v.to_vec())
        } else {
            v.first().cloned().map_or(Variant::Empty, Into::into)
        }
    }
    match values {
        Values::Bits(v) => pick(v, array),
        Values::Bytes(v) => pick(v, array),
        Values::Words(v) => pick(v, array),
        Values::Ints(v) => pick(v, array),
        Values::DWords(v) => pick(v, array),
        Values::DInts(v) => pick(v, array),
        Values::Reals(v) => pick(v, array),
    }
}

fn data_value((value, status): (Variant, StatusCode), time: DateTime) -> DataValue {
    DataValue {
        value: Some(value),
        status: Some(status),
        source_timestamp: Some(time),
        server_timestamp: Some(DateTime::now()),
        ..Default::default()
    }
}

#[async_trait]
impl NodeManager for PnioItems {
    fn owns_node(&self, id: &NodeId) -> bool {
        id.namespace == self.ns
    }

    fn name(&self) -> &str {
        "procimg-pnio-items"
    }

    fn namespaces_for_user(&self, _context: &RequestContext) -> Vec<NamespaceMetadata> {
        vec![NamespaceMetadata {
            namespace_uri: PNIO_NAMESPACE.to_owned(),
            namespace_index: self.ns,
            is_namespace_subset: Some(false),
            ..Default::default()
        }]
    }

    async fn init(&self, _type_tree: &mut DefaultTypeTree, _context: ServerContext) {}

    async fn read(
        &self,
        _context: &RequestContext,
        _max_age: f64,
        _timestamps: TimestampsToReturn,
        nodes: &mut [&mut ReadNode],
    ) -> Result<(), StatusCode> {
        // One snapshot for the whole call: all its values are of one cycle.
        let snap = self.snapshots.borrow().clone();
        let time = timestamp(snap.time);
        for node in nodes {
            let id = node.node().node_id.clone();
            let attribute = node.node().attribute_id;
            let item = match self.item(&id) {
                Ok(i) => i,
                Err(status) => {
                    node.set_error(status);
                    continue;
                }
            };
            if attribute != AttributeId::Value {
                match self.attribute(&id, &item, attribute) {
                    Ok(v) => node.set_result(DataValue::new_now(v)),
                    Err(status) => node.set_error(status),
                }
                continue;
            }
            match self.value(&item, &snap) {
                Ok(v) => node.set_result(data_value(v, time)),
                Err(status) => node.set_error(status),
            }
        }
        Ok(())
    }

    async fn create_monitored_items(
        &self,
        _context: &RequestContext,
        items: &mut [&mut CreateMonitoredItem],
    ) -> Result<(), StatusCode> {
        let snap = self.snapshots.borrow().clone();
        let time = timestamp(snap.time);
        let mut monitored = self.monitored.lock().unwrap_or_else(|e| e.into_inner());
        for m in items {
            let id = m.item_to_monitor().node_id.clone();
            let item = match self.item(&id) {
                Ok(i) if m.item_to_monitor().attribute_id == AttributeId::Value => i,
                Ok(_) => {
                    m.set_status(StatusCode::BadAttributeIdInvalid);
                    continue;
                }
                Err(status) => {
                    m.set_status(status);
                    continue;
                }
            };
            let now = self
                .value(&item, &snap)
                .unwrap_or_else(|status| (Variant::Empty, status));
            m.set_initial_value(data_value(now.clone(), time));
            m.set_status(StatusCode::Good);
            monitored.insert(
                m.handle(),
                Monitored {
                    node: id,
                    item,
                    last: Some(now),
                },
            );
        }
        Ok(())
    }

    async fn delete_monitored_items(&self, _context: &RequestContext, items: &[&MonitoredItemRef]) {
        let mut monitored = self.monitored.lock().unwrap_or_else(|e| e.into_inner());
        for m in items {
            monitored.remove(&m.handle());
        }
    }
}
