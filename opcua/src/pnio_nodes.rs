// SPDX-License-Identifier: MIT OR Apache-2.0
//! The PNIO item names as string NodeIds of namespace [`PNIO_NAMESPACE`], beside the
//! browsable tree: any item [`Item::parse`] reads is a variable, resolved when it is read or
//! monitored, from the newest snapshot (so an image of any size costs no nodes). A Read takes
//! one snapshot for all its items: they are of one cycle.

use crate::auth::Sessions;
use crate::items::{Area, Format, Item, ItemKind, MAX_ITEM_BYTES, ProcessItem, RecordItem, Values};
use crate::records::{self, Job};
use crate::snapshot::{Pace, Snapshot, quality};
use crate::tree::{data_value, status_code, timestamp};
use crate::users::Users;
use crate::writer::{Write, WriteRefusal};
use async_trait::async_trait;
use opcua::nodes::DefaultTypeTree;
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::node_manager::{
    DynNodeManager, MonitoredItemRef, MonitoredItemUpdateRef, NodeManager, NodeManagerBuilder,
    ReadNode, RequestContext, ServerContext, WriteNode,
};
use opcua::server::{CreateMonitoredItem, MonitoredItemHandle, SubscriptionCache};
use opcua::types::{
    AttributeId, DataTypeId, DataValue, DiagnosticInfo, Identifier, LocalizedText, MonitoringMode,
    NodeClass, NodeId, QualifiedName, StatusCode, TimestampsToReturn, UAString, Variant,
};
use procimg_client::access::{self, Space};
use procimg_client::{Layout, RecordTarget};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, mpsc};
use std::time::{Duration, Instant};
use tokio::sync::watch;

/// The namespace URI of the item names.
pub const PNIO_NAMESPACE: &str = "urn:procimg:pnio";

/// The item names of one instance, its controller index `controller`.
pub struct PnioItems {
    ns: u16,
    controller: u8,
    snapshots: watch::Receiver<Arc<Snapshot>>,
    /// Monitored items: their node and item, and the value last notified.
    monitored: Mutex<HashMap<MonitoredItemHandle, Monitored>>,
    /// Who may write.
    users: Arc<Users>,
    /// Where writes go.
    writer: Mutex<mpsc::Sender<Write>>,
    /// Where record jobs go.
    records: Mutex<mpsc::Sender<Job>>,
    /// The feed's pace, set from the monitored items' sampling intervals.
    pace: Arc<Pace>,
}

struct Monitored {
    node: NodeId,
    item: Item,
    last: Option<(Variant, StatusCode)>,
    /// Its sampling interval (zero: every image).
    interval: Duration,
    /// When it is sampled next.
    due: Instant,
    /// Sampled at all (its monitoring mode is not Disabled).
    sampling: bool,
}

/// A sampling interval in ms as the server revised it; zero or less (the subscription's, or
/// as fast as possible) samples every image.
fn interval(ms: f64) -> Duration {
    if ms.is_finite() && ms > 0.0 {
        Duration::from_secs_f64(ms / 1e3)
    } else {
        Duration::ZERO
    }
}

/// Builds [`PnioItems`] into a server.
pub struct PnioItemsBuilder {
    /// The controller index items must name (`CTRL<n>`).
    pub controller: u8,
    /// The snapshots.
    pub snapshots: watch::Receiver<Arc<Snapshot>>,
    /// Who may write.
    pub users: Arc<Users>,
    /// Where writes go.
    pub writer: mpsc::Sender<Write>,
    /// Where record jobs go.
    pub records: mpsc::Sender<Job>,
    /// The feed's pace, which the monitored items set.
    pub pace: Arc<Pace>,
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
            snapshots: self.snapshots,
            monitored: Mutex::new(HashMap::new()),
            users: self.users,
            writer: Mutex::new(self.writer),
            records: Mutex::new(self.records),
            pace: self.pace,
        })
    }
}

/// The fastest sampling interval of the items sampled now.
fn fastest(monitored: &HashMap<MonitoredItemHandle, Monitored>) -> Option<Duration> {
    monitored
        .values()
        .filter(|m| m.sampling)
        .map(|m| m.interval)
        .min()
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

    /// The submodule of `layout` whose data holds all of `p`'s bytes.
    fn submodule_of(layout: &Layout, p: &ProcessItem) -> Option<usize> {
        let (first, len) = p.span();
        let s = access::find(&layout.submodules, space(p.area), first)?;
        let e = &layout.submodules[s];
        let (at, n) = match p.area {
            Area::Input => (e.input_address, e.input_length),
            Area::Output => (e.output_address, e.output_length),
        };
        (u64::from(first) + len as u64 <= u64::from(at) + u64::from(n)).then_some(s)
    }

    /// The record a record item names in `layout`: of the submodule IO-Base's record jobs
    /// would name by its address.
    fn record_target(layout: &Layout, r: &RecordItem) -> Option<RecordTarget> {
        let s = access::find_module(&layout.submodules, space(r.area), r.address)?;
        records::target(layout, s, r.index)
    }

    /// Sends a record job and waits for its answer.
    async fn record_job<T>(
        &self,
        job: impl FnOnce(tokio::sync::oneshot::Sender<Result<T, String>>) -> Job,
    ) -> Result<T, (StatusCode, Option<String>)> {
        let (reply, answer) = tokio::sync::oneshot::channel();
        self.records
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .send(job(reply))
            .map_err(|_| (StatusCode::BadServerHalted, None))?;
        match answer.await {
            Ok(Ok(v)) => Ok(v),
            Ok(Err(why)) => Err((StatusCode::BadCommunicationError, Some(why))),
            Err(_) => Err((StatusCode::BadServerHalted, None)),
        }
    }

    /// Reads the record a record item names in `layout`.
    async fn read_record(
        &self,
        layout: &Layout,
        r: &RecordItem,
    ) -> Result<Variant, (StatusCode, Option<String>)> {
        let target = Self::record_target(layout, r).ok_or((StatusCode::BadNodeIdUnknown, None))?;
        let max_len = u32::from(r.length.unwrap_or(MAX_ITEM_BYTES as u16));
        let data = self
            .record_job(|reply| Job::Read {
                target,
                max_len,
                reply,
            })
            .await?;
        Ok(Variant::from(opcua::types::ByteString::from(data)))
    }

    /// The value and quality of `item` in `snap`.
    fn value(&self, item: &Item, snap: &Snapshot) -> Result<(Variant, StatusCode), StatusCode> {
        match item.kind {
            ItemKind::Mode => Ok((Variant::from(snap.mode().as_u32() as i32), StatusCode::Good)),
            ItemKind::Process(p) => {
                let s = Self::submodule_of(&snap.layout, &p).ok_or_else(unknown)?;
                let e = snap.layout.submodules[s];
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
                let q = quality(snap, s, p.area == Area::Output);
                Ok((variant(&values, p.count.is_some()), status_code(q)))
            }
            // Read as jobs (see `read_record`), never from a snapshot.
            ItemKind::Record(_) => Err(StatusCode::BadNotSupported),
        }
    }

    /// Notifies the monitored items due for a sample whose value changed in `snap`: an item
    /// is looked at once per sampling interval, not once per image.
    pub fn notify(&self, snap: &Snapshot, subscriptions: &SubscriptionCache) {
        let time = timestamp(snap.time);
        let mut changes = Vec::new();
        let at = Instant::now();
        {
            let mut monitored = self.monitored.lock().unwrap_or_else(|e| e.into_inner());
            for m in monitored.values_mut() {
                if !m.sampling || at < m.due {
                    continue;
                }
                // The next sample on the interval's grid, never in a burst after a stall.
                m.due = (m.due + m.interval).max(at);
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

    /// One write: the outputs an item names, in a submodule the session holds (claimed
    /// here if nobody does).
    async fn write_one(
        &self,
        context: &RequestContext,
        may_write: bool,
        w: &opcua::server::node_manager::ParsedWriteValue,
    ) -> Result<(), (StatusCode, Option<String>)> {
        let item = self.item(&w.node_id).map_err(|s| (s, None))?;
        // The layout and outputs the write is resolved against.
        let snap = self.snapshots.borrow().clone();
        if w.attribute_id != AttributeId::Value {
            return Err((StatusCode::BadNotWritable, None));
        }
        if !may_write {
            return Err((
                StatusCode::BadUserAccessDenied,
                Some("writes need a session of a user with the writer role".to_owned()),
            ));
        }
        let p = match item.kind {
            ItemKind::Process(p) => p,
            ItemKind::Record(r) => {
                let target = Self::record_target(&snap.layout, &r)
                    .ok_or((StatusCode::BadNodeIdUnknown, None))?;
                let Some(Variant::ByteString(data)) = w.value.value.as_ref() else {
                    return Err((
                        StatusCode::BadTypeMismatch,
                        Some(format!("{item} takes a ByteString")),
                    ));
                };
                let data = data.value.clone().unwrap_or_default();
                return self
                    .record_job(|reply| Job::Write {
                        target,
                        data,
                        reply,
                    })
                    .await;
            }
            ItemKind::Mode => return Err((StatusCode::BadNotWritable, None)),
        };
        if p.area != Area::Output {
            return Err((
                StatusCode::BadNotWritable,
                Some("inputs are the devices' to write".to_owned()),
            ));
        }
        let s = Self::submodule_of(&snap.layout, &p).ok_or((StatusCode::BadNodeIdUnknown, None))?;
        let value = w
            .value
            .value
            .as_ref()
            .ok_or((StatusCode::BadTypeMismatch, None))?;
        let values = values_from(&p, value).ok_or((
            StatusCode::BadTypeMismatch,
            Some(format!(
                "{item} takes {} {:?} value(s)",
                p.values(),
                p.format
            )),
        ))?;
        // Bits keep their neighbours: the bytes start as they went out last.
        let (first, len) = p.span();
        let e = snap.layout.submodules[s];
        let at = (first - e.output_address) as usize;
        let mut bytes = snap
            .outputs
            .get(s)
            .and_then(|b| b.get(at..at + len))
            .map(<[u8]>::to_vec)
            .unwrap_or_else(|| vec![0; len]);
        p.encode(&values, &mut bytes)
            .map_err(|e| (StatusCode::BadTypeMismatch, Some(e.to_string())))?;
        let session = Arc::downgrade(&context.session);
        let (reply, outcome) = tokio::sync::oneshot::channel();
        let job = Write {
            session: context.session_id,
            alive: Box::new(move || session.upgrade().is_some_and(|s| s.read().is_activated())),
            layout: snap.layout.hash(),
            submodule: s,
            address: first,
            bytes,
            reply,
        };
        self.writer
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .send(job)
            .map_err(|_| (StatusCode::BadServerHalted, None))?;
        match outcome.await {
            Ok(Ok(())) => Ok(()),
            Ok(Err(WriteRefusal::Gone)) => Err((
                StatusCode::BadNodeIdUnknown,
                Some("procimgd started anew with another layout".to_owned()),
            )),
            Ok(Err(WriteRefusal::Held(holder))) => Err((
                StatusCode::BadResourceUnavailable,
                Some(format!("the outputs are held by {holder}")),
            )),
            Ok(Err(WriteRefusal::Failed(why))) => {
                Err((StatusCode::BadCommunicationError, Some(why)))
            }
            Err(_) => Err((StatusCode::BadServerHalted, None)),
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
            AttributeId::AccessLevel | AttributeId::UserAccessLevel => {
                // CurrentRead, and CurrentWrite for outputs and records.
                let output = matches!(item.kind, ItemKind::Process(p) if p.area == Area::Output)
                    || matches!(item.kind, ItemKind::Record(_));
                Variant::from(if output { 3u8 } else { 1u8 })
            }
            AttributeId::MinimumSamplingInterval => Variant::from(0.0f64),
            AttributeId::Historizing => Variant::from(false),
            _ => return Err(StatusCode::BadAttributeIdInvalid),
        })
    }
}

/// The values a written Variant holds for `p`: a scalar of its format, or with `,count` an
/// array of as many.
fn values_from(p: &ProcessItem, v: &Variant) -> Option<Values> {
    let scalars: Vec<&Variant> = match (v, p.count) {
        (Variant::Array(a), Some(_)) => a.values.iter().collect(),
        (Variant::Array(_), None) | (_, Some(_)) => return None,
        (scalar, None) => vec![scalar],
    };
    macro_rules! all {
        ($variant:ident, $values:ident) => {
            scalars
                .iter()
                .map(|x| match x {
                    Variant::$variant(y) => Some(*y),
                    _ => None,
                })
                .collect::<Option<Vec<_>>>()
                .map(Values::$values)
        };
    }
    let values = match p.format {
        Format::Bit => all!(Boolean, Bits),
        Format::Byte => all!(Byte, Bytes),
        Format::Word => all!(UInt16, Words),
        Format::Int => all!(Int16, Ints),
        Format::DWord => all!(UInt32, DWords),
        Format::DInt => all!(Int32, DInts),
        Format::Real => all!(Float, Reals),
    }?;
    (values.len() == p.values()).then_some(values)
}

/// The client's address space of an item's area.
fn space(area: Area) -> Space {
    match area {
        Area::Input => Space::Input,
        Area::Output => Space::Output,
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
            if let ItemKind::Record(r) = item.kind {
                match self.read_record(&snap.layout, &r).await {
                    Ok(v) => node.set_result(DataValue::new_now(v)),
                    Err((status, why)) => {
                        node.set_error(status);
                        if let Some(why) = why {
                            node.set_diagnostic_info(DiagnosticInfo {
                                additional_info: Some(UAString::from(why)),
                                ..Default::default()
                            });
                        }
                    }
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

    async fn write(
        &self,
        context: &RequestContext,
        nodes: &mut [&mut WriteNode],
    ) -> Result<(), StatusCode> {
        let may_write = Sessions::may_write(&self.users, &context.token);
        for node in nodes {
            let outcome = self.write_one(context, may_write, node.value()).await;
            match outcome {
                Ok(()) => node.set_status(StatusCode::Good),
                Err((status, why)) => {
                    node.set_status(status);
                    if let Some(why) = why {
                        node.set_diagnostic_info(DiagnosticInfo {
                            additional_info: Some(UAString::from(why)),
                            ..Default::default()
                        });
                    }
                }
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
                Ok(Item {
                    kind: ItemKind::Record(_),
                    ..
                }) => {
                    // A record is a job on the device, not a value of the image.
                    m.set_status(StatusCode::BadNotSupported);
                    continue;
                }
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
                    interval: interval(m.sampling_interval()),
                    due: Instant::now(),
                    sampling: m.monitoring_mode() != MonitoringMode::Disabled,
                },
            );
        }
        self.pace.set(fastest(&monitored));
        Ok(())
    }

    async fn modify_monitored_items(
        &self,
        _context: &RequestContext,
        items: &[&MonitoredItemUpdateRef],
    ) {
        let mut monitored = self.monitored.lock().unwrap_or_else(|e| e.into_inner());
        for m in items {
            if let Some(x) = monitored.get_mut(&m.handle()) {
                x.interval = interval(m.update().revised_sampling_interval);
            }
        }
        self.pace.set(fastest(&monitored));
    }

    async fn set_monitoring_mode(
        &self,
        _context: &RequestContext,
        mode: MonitoringMode,
        items: &[&MonitoredItemRef],
    ) {
        let mut monitored = self.monitored.lock().unwrap_or_else(|e| e.into_inner());
        for m in items {
            if let Some(x) = monitored.get_mut(&m.handle()) {
                x.sampling = mode != MonitoringMode::Disabled;
            }
        }
        self.pace.set(fastest(&monitored));
    }

    async fn delete_monitored_items(&self, _context: &RequestContext, items: &[&MonitoredItemRef]) {
        let mut monitored = self.monitored.lock().unwrap_or_else(|e| e.into_inner());
        for m in items {
            monitored.remove(&m.handle());
        }
        self.pace.set(fastest(&monitored));
    }
}
