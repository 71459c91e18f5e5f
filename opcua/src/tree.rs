// SPDX-License-Identifier: MIT OR Apache-2.0
//! The browsable address space: `Objects/procimg/<instance>` with the server's status, and
//! per device (in the device role: the station) its state as an enumeration and per
//! submodule (`<slot>.<subslot>`) its data with the providers' and consumers' status. The
//! values are stored in a [`SimpleNodeManager`] and set from each snapshot, only those that
//! changed, in one batch: a Read of the tree sees one cycle.
//!
//! The devices' part follows the snapshots' layout: when procimgd starts anew with another
//! layout, its variables say `BadNodeIdUnknown` to their subscribers once and go, and the
//! new layout's are made (same names, same NodeIds, where devices and submodules stayed).

use crate::items::{Area, Format, Item, ItemKind, Letters, ProcessItem};
use crate::snapshot::{Quality, Snapshot, quality};
use crate::typed::{Catalog, Kind};
use opcua::server::SubscriptionCache;
use opcua::server::address_space::{
    AccessLevel, AddressSpace, DataTypeBuilder, EventNotifier, ObjectBuilder, VariableBuilder,
};
use opcua::server::node_manager::memory::SimpleNodeManager;
use opcua::types::{
    ByteString, DataTypeDefinition, DataTypeId, DataValue, DateTime, EnumDefinition, EnumField,
    LocalizedText, NodeId, ObjectTypeId, QualifiedName, StatusCode, VariableTypeId, Variant,
};
use procimg_client::{ArState, DeviceState, Ioxs, Layout};
use std::collections::HashMap;
use std::time::{SystemTime, UNIX_EPOCH};

/// 100 ns ticks from 1601-01-01 (OPC UA's epoch) to 1970-01-01.
const UNIX_EPOCH_TICKS: i64 = 116_444_736_000_000_000;

/// `t` as an OPC UA time stamp.
pub fn timestamp(t: SystemTime) -> DateTime {
    let since = t.duration_since(UNIX_EPOCH).unwrap_or_default();
    let ticks = i64::try_from(since.as_nanos() / 100).unwrap_or(i64::MAX - UNIX_EPOCH_TICKS);
    DateTime::from(UNIX_EPOCH_TICKS + ticks)
}

/// The OPC UA status code of a [`Quality`].
pub fn status_code(q: Quality) -> StatusCode {
    match q {
        Quality::Good => StatusCode::Good,
        Quality::NotConnected => StatusCode::BadNotConnected,
        Quality::InputsInvalid => StatusCode::BadDeviceFailure,
        Quality::OutputsInvalid => StatusCode::BadOutOfService,
    }
}

/// A value with its status, its source time stamp `time` (its cycle's) and now as the
/// server's.
pub fn data_value((value, status): (Variant, StatusCode), time: DateTime) -> DataValue {
    DataValue {
        value: Some(value),
        status: Some(status),
        source_timestamp: Some(time),
        server_timestamp: Some(DateTime::now()),
        ..Default::default()
    }
}

/// The enumeration DataType of a controller's device states: [`DeviceState::ALL`] from 0.
pub const DEVICE_STATE_TYPE: &str = "DeviceStateEnum";
/// The enumeration DataType of a station's AR: 0 none, then [`ArState::ALL`] from 1.
pub const AR_STATE_TYPE: &str = "ArStateEnum";
/// The word of [`AR_STATE_TYPE`]'s 0.
const NO_AR: &str = "none";

/// What a variable of the tree shows.
#[derive(Clone, Copy, Debug)]
enum Shows {
    Mode,
    CycleTime,
    CycleCount,
    Overruns,
    OpFaults,
    /// A percentile (µs) of a latency of procimgd's cycle.
    Latency(Latency),
    DeviceState(usize),
    Plc,
    PlcRunning,
    Inputs(usize),
    Outputs(usize),
    InputIops(usize),
    InputIocs(usize),
    OutputIops(usize),
    OutputIocs(usize),
    /// A data item of submodule `s`'s data in an area: its offset, length and type.
    Typed(usize, Area, u16, u16, Kind),
    /// A bit of such an item: the item's offset and length, and the bit.
    Bit(usize, Area, u16, u16, u16),
}

/// The latency percentiles the status shows: the cycle thread's wake-up and work, and the
/// synchronous clients' handshake, since procimgd started.
#[derive(Clone, Copy, Debug)]
enum Latency {
    WakeupP50,
    WakeupP99,
    WakeupMax,
    CycleWorkP99,
    HandshakeP99,
}

/// A variable of the tree: its NodeId and what it shows.
type Var = (NodeId, Shows);

/// The tree's variables and what was last published of them.
pub struct Tree {
    ns: u16,
    instance: String,
    controller: u8,
    /// The GSDML files that type the data.
    catalog: std::sync::Arc<Catalog>,
    /// The hash of the layout the devices' part is made for.
    layout: u64,
    /// The server's status variables.
    status: Vec<Var>,
    /// The devices' variables.
    devices: Vec<Var>,
    /// The devices' nodes (objects and variables), in the order made.
    device_nodes: Vec<NodeId>,
    last: HashMap<NodeId, (Variant, StatusCode)>,
}

/// The string NodeId of the tree's node at `path` (`line/Devices/echo/1.1/Inputs`).
pub fn node_id(ns: u16, path: &str) -> NodeId {
    NodeId::new(ns, path)
}

/// The names of a direction's variables in a role: the data's, and the prefix of its
/// status bytes'. A station's directions are named from the PLC's view, as IO-Base's device
/// interface names them: Q data is what the PLC wrote (the layout's inputs), I data what the
/// station sends it (the layout's outputs).
fn direction_names(device_role: bool, output: bool) -> (&'static str, &'static str) {
    match (device_role, output) {
        (false, false) => ("Inputs", "Input"),
        (false, true) => ("Outputs", "Output"),
        (true, false) => ("QData", "QData"),
        (true, true) => ("IData", "IData"),
    }
}

/// Adds an enumeration DataType `name` with `words` numbered from 0 to `space`.
fn add_enumeration(space: &mut AddressSpace, ns: u16, name: &str, words: &[&str]) {
    let id = node_id(ns, name);
    let fields = words
        .iter()
        .enumerate()
        .map(|(i, w)| EnumField {
            value: i as i64,
            display_name: LocalizedText::new("", w),
            description: LocalizedText::null(),
            name: (*w).into(),
        })
        .collect();
    DataTypeBuilder::new(&id, QualifiedName::new(ns, name), name)
        .subtype_of(DataTypeId::Enumeration)
        .data_type_definition(DataTypeDefinition::Enum(EnumDefinition {
            fields: Some(fields),
        }))
        .insert(space);
    let strings: Vec<LocalizedText> = words.iter().map(|w| LocalizedText::new("", w)).collect();
    VariableBuilder::new(
        &node_id(ns, &format!("{name}/EnumStrings")),
        QualifiedName::new(0, "EnumStrings"),
        "EnumStrings",
    )
    .data_type(DataTypeId::LocalizedText)
    .value_rank(1)
    .value(Variant::from(strings))
    .property_of(id)
    .has_type_definition(VariableTypeId::PropertyType)
    .insert(space);
}

impl Tree {
    /// Builds the tree of `instance` (CpIndex `controller`) with `layout` into `nm`'s address
    /// space (namespace `ns`), typed where `catalog`'s files describe the data.
    pub fn build(
        nm: &SimpleNodeManager,
        ns: u16,
        (instance, controller): (&str, u8),
        catalog: std::sync::Arc<Catalog>,
        layout: &Layout,
    ) -> Tree {
        let mut tree = Tree {
            ns,
            instance: instance.to_owned(),
            controller,
            catalog,
            layout: layout.hash(),
            status: Vec::new(),
            devices: Vec::new(),
            device_nodes: Vec::new(),
            last: HashMap::new(),
        };
        let mut space = nm.address_space().write();
        let root = node_id(ns, "procimg");
        space.add_folder(
            &root,
            QualifiedName::new(ns, "procimg"),
            "procimg",
            &NodeId::objects_folder_id(),
        );
        let device_words: Vec<&str> = DeviceState::ALL.iter().map(|s| s.as_str()).collect();
        add_enumeration(&mut space, ns, DEVICE_STATE_TYPE, &device_words);
        let ar_words: Vec<&str> = std::iter::once(NO_AR)
            .chain(ArState::ALL.iter().map(|s| s.as_str()))
            .collect();
        add_enumeration(&mut space, ns, AR_STATE_TYPE, &ar_words);
        let top = node_id(ns, instance);
        ObjectBuilder::new(&top, QualifiedName::new(ns, instance), instance)
            .organized_by(root)
            .event_notifier(EventNotifier::SUBSCRIBE_TO_EVENTS)
            .has_type_definition(ObjectTypeId::BaseObjectType)
            .insert(&mut *space);
        let status = node_id(ns, &format!("{instance}/Status"));
        tree.object(&mut space, &status, "Status", &top);
        for (name, data_type, initial, shows) in [
            ("Mode", DataTypeId::String, Variant::from(""), Shows::Mode),
            (
                "CycleTime",
                DataTypeId::Double,
                Variant::from(0.0f64),
                Shows::CycleTime,
            ),
            (
                "CycleCount",
                DataTypeId::UInt64,
                Variant::from(0u64),
                Shows::CycleCount,
            ),
            (
                "Overruns",
                DataTypeId::UInt64,
                Variant::from(0u64),
                Shows::Overruns,
            ),
            (
                "OpFaults",
                DataTypeId::UInt64,
                Variant::from(0u64),
                Shows::OpFaults,
            ),
            (
                "WakeupLatencyP50",
                DataTypeId::Double,
                Variant::from(0.0f64),
                Shows::Latency(Latency::WakeupP50),
            ),
            (
                "WakeupLatencyP99",
                DataTypeId::Double,
                Variant::from(0.0f64),
                Shows::Latency(Latency::WakeupP99),
            ),
            (
                "WakeupLatencyMax",
                DataTypeId::Double,
                Variant::from(0.0f64),
                Shows::Latency(Latency::WakeupMax),
            ),
            (
                "CycleWorkP99",
                DataTypeId::Double,
                Variant::from(0.0f64),
                Shows::Latency(Latency::CycleWorkP99),
            ),
            (
                "HandshakeP99",
                DataTypeId::Double,
                Variant::from(0.0f64),
                Shows::Latency(Latency::HandshakeP99),
            ),
        ] {
            let id = tree.variable(
                &mut space,
                &status,
                format!("{instance}/Status/{name}"),
                (name, data_type.into(), initial),
                None,
            );
            tree.status.push((id, shows));
        }
        let devices = node_id(ns, &format!("{instance}/Devices"));
        tree.object(&mut space, &devices, "Devices", &top);
        // What stays whatever the layout.
        tree.device_nodes.clear();
        tree.lay_out(&mut space, layout);
        drop(space);
        tree
    }

    /// An object `name` at `id`, a component of `parent`.
    fn object(&mut self, space: &mut AddressSpace, id: &NodeId, name: &str, parent: &NodeId) {
        ObjectBuilder::new(id, QualifiedName::new(self.ns, name), name)
            .component_of(parent.clone())
            .has_type_definition(ObjectTypeId::BaseObjectType)
            .insert(space);
        self.device_nodes.push(id.clone());
    }

    /// A read-only variable at `path` below `parent`: its name, DataType and first value,
    /// and a description.
    fn variable(
        &mut self,
        space: &mut AddressSpace,
        parent: &NodeId,
        path: String,
        (name, data_type, initial): (&str, NodeId, Variant),
        description: Option<String>,
    ) -> NodeId {
        let id = node_id(self.ns, &path);
        let mut b = VariableBuilder::new(&id, QualifiedName::new(self.ns, name), name)
            .data_type(data_type)
            .value(initial)
            .access_level(AccessLevel::CURRENT_READ)
            .user_access_level(AccessLevel::CURRENT_READ)
            .component_of(parent.clone());
        if let Some(d) = description {
            b = b.description(LocalizedText::new("", &d));
        }
        b.insert(space);
        self.device_nodes.push(id.clone());
        id
    }

    /// The PNIO item of `format` at `address` (`bit` for bits; `count` values, or one).
    fn item_of(
        &self,
        area: Area,
        (format, address, bit): (Format, u32, u8),
        count: Option<u16>,
    ) -> String {
        Item {
            controller: self.controller,
            kind: ItemKind::Process(ProcessItem {
                area,
                letters: Letters::German,
                format,
                address,
                bit,
                count,
            }),
        }
        .to_string()
    }

    /// The typed variables of submodule `s`'s data items in `area` (which starts at logical
    /// address `address`), below its data variable `data`.
    fn lay_out_items(
        &mut self,
        space: &mut AddressSpace,
        layout: &Layout,
        (s, area, address): (usize, Area, u32),
        (data, data_path): (&NodeId, &str),
    ) {
        let catalog = self.catalog.clone();
        let mut names = std::collections::HashSet::new();
        for (_, item) in catalog
            .items(layout, s)
            .into_iter()
            .filter(|(a, _)| *a == area)
        {
            let kind = Kind::of(&item.data_type);
            let mut name = item
                .name
                .clone()
                .unwrap_or_else(|| format!("{} {}", item.data_type, item.offset));
            if !names.insert(name.clone()) {
                name = format!("{name} @{}", item.offset);
            }
            let at = address + u32::from(item.offset);
            let description = kind
                .format()
                .map(|f| format!("the item {}", self.item_of(area, (f, at, 0), None)));
            let path = format!("{data_path}/{name}");
            let id = self.variable(
                space,
                data,
                path.clone(),
                (&name, kind.data_type().into(), Variant::Empty),
                description,
            );
            self.devices.push((
                id.clone(),
                Shows::Typed(s, area, item.offset, item.length, kind),
            ));
            for (bit, bit_name) in &item.bits {
                let bit_name = bit_name.clone().unwrap_or_else(|| format!("Bit {bit}"));
                let byte = at + u32::from(item.length) - 1 - u32::from(bit / 8);
                let description = format!(
                    "the item {}",
                    self.item_of(area, (Format::Bit, byte, (bit % 8) as u8), None)
                );
                let bit_id = self.variable(
                    space,
                    &id,
                    format!("{path}/{bit_name}"),
                    (&bit_name, DataTypeId::Boolean.into(), Variant::from(false)),
                    Some(description),
                );
                self.devices
                    .push((bit_id, Shows::Bit(s, area, item.offset, item.length, *bit)));
            }
        }
    }

    /// Makes the devices' part of the tree for `layout`.
    fn lay_out(&mut self, space: &mut AddressSpace, layout: &Layout) {
        let ns = self.ns;
        let instance = self.instance.clone();
        let devices = node_id(ns, &format!("{instance}/Devices"));
        let device_role = layout.is_device();
        let state_type = node_id(
            ns,
            if device_role {
                AR_STATE_TYPE
            } else {
                DEVICE_STATE_TYPE
            },
        );
        for d in 0..layout.devices.len() {
            let name = layout.device_name(d).to_owned();
            let dev_path = format!("{instance}/Devices/{name}");
            let dev = node_id(ns, &dev_path);
            ObjectBuilder::new(&dev, QualifiedName::new(ns, name.as_str()), name.as_str())
                .component_of(devices.clone())
                .has_type_definition(ObjectTypeId::BaseObjectType)
                .event_notifier(EventNotifier::SUBSCRIBE_TO_EVENTS)
                .insert(space);
            self.device_nodes.push(dev.clone());
            let mut vars = vec![(
                "State",
                state_type.clone(),
                Variant::from(0i32),
                Shows::DeviceState(d),
            )];
            if device_role {
                vars.push((
                    "Plc",
                    DataTypeId::String.into(),
                    Variant::from(""),
                    Shows::Plc,
                ));
                vars.push((
                    "PlcRunning",
                    DataTypeId::Boolean.into(),
                    Variant::from(false),
                    Shows::PlcRunning,
                ));
            }
            for (var, data_type, initial, shows) in vars {
                let id = self.variable(
                    space,
                    &dev,
                    format!("{dev_path}/{var}"),
                    (var, data_type, initial),
                    None,
                );
                self.devices.push((id, shows));
            }
            for s in layout.submodules_of(d) {
                let e = layout.submodules[s];
                let sub_name = format!("{}.{}", e.slot, e.subslot);
                let sub_path = format!("{dev_path}/{sub_name}");
                let sub = node_id(ns, &sub_path);
                self.object(space, &sub, &sub_name, &dev);
                // A direction's data and its two status bytes, where it has data.
                let directions = [
                    (
                        e.input_length,
                        e.input_address,
                        Area::Input,
                        [Shows::Inputs(s), Shows::InputIops(s), Shows::InputIocs(s)],
                    ),
                    (
                        e.output_length,
                        e.output_address,
                        Area::Output,
                        [
                            Shows::Outputs(s),
                            Shows::OutputIops(s),
                            Shows::OutputIocs(s),
                        ],
                    ),
                ];
                for (length, address, area, [data, iops, iocs]) in directions {
                    if length == 0 {
                        continue;
                    }
                    let (data_name, prefix) = direction_names(device_role, area == Area::Output);
                    let item = self.item_of(area, (Format::Byte, address, 0), Some(length));
                    let empty = Variant::from(ByteString::from(Vec::<u8>::new()));
                    for (var, data_type, initial, shows, description) in [
                        (
                            data_name.to_owned(),
                            DataTypeId::ByteString,
                            empty,
                            data,
                            Some(format!("the same bytes as the item {item}")),
                        ),
                        (
                            format!("{prefix}IOPS"),
                            DataTypeId::Boolean,
                            Variant::from(false),
                            iops,
                            None,
                        ),
                        (
                            format!("{prefix}IOCS"),
                            DataTypeId::Boolean,
                            Variant::from(false),
                            iocs,
                            None,
                        ),
                    ] {
                        let id = self.variable(
                            space,
                            &sub,
                            format!("{sub_path}/{var}"),
                            (&var, data_type.into(), initial),
                            description,
                        );
                        self.devices.push((id, shows));
                    }
                    let data_path = format!("{sub_path}/{data_name}");
                    let data = node_id(ns, &data_path);
                    self.lay_out_items(space, layout, (s, area, address), (&data, &data_path));
                }
            }
        }
        self.layout = layout.hash();
    }

    /// Tells the subscribers of the devices' variables that they went, and removes them.
    fn retire(&mut self, nm: &SimpleNodeManager, subscriptions: &SubscriptionCache) {
        let gone = data_value(
            (Variant::Empty, StatusCode::BadNodeIdUnknown),
            DateTime::now(),
        );
        let _ = nm.set_values(
            subscriptions,
            self.devices.iter().map(|(id, _)| (id, None, gone.clone())),
        );
        let mut space = nm.address_space().write();
        for id in self.device_nodes.drain(..).rev() {
            space.delete(&id, true);
        }
        for (id, _) in self.devices.drain(..) {
            self.last.remove(&id);
        }
    }

    /// Sets the variables that changed in `snap`, in one batch; first makes the devices'
    /// part anew if `snap` is of another layout.
    pub fn publish(
        &mut self,
        nm: &SimpleNodeManager,
        subscriptions: &SubscriptionCache,
        snap: &Snapshot,
    ) {
        if snap.layout.hash() != self.layout {
            tracing::info!(
                "instance {:?} has another layout ({:016x}): its devices' nodes are made anew",
                self.instance,
                snap.layout.hash()
            );
            self.retire(nm, subscriptions);
            let mut space = nm.address_space().write();
            self.lay_out(&mut space, &snap.layout);
        }
        let time = timestamp(snap.time);
        let mut changed = Vec::new();
        for (id, shows) in self.status.iter().chain(&self.devices) {
            let (value, status) = value_of(*shows, snap);
            if matches!(self.last.get(id), Some((v, st)) if *v == value && *st == status) {
                continue;
            }
            self.last.insert(id.clone(), (value.clone(), status));
            changed.push((id, data_value((value, status), time)));
        }
        if changed.is_empty() {
            return;
        }
        // Only the tree's own variables are set: an unknown one would stop the batch.
        if let Err(e) = nm.set_values(
            subscriptions,
            changed.into_iter().map(|(id, dv)| (id, None, dv)),
        ) {
            tracing::warn!("the address space refused the image's values: {e}");
        }
    }
}

fn ioxs(x: Ioxs) -> Variant {
    Variant::from(x == Ioxs::Good)
}

/// The number of a state in its enumeration ([`DEVICE_STATE_TYPE`], [`AR_STATE_TYPE`]).
fn state_number(snap: &Snapshot, d: usize) -> i32 {
    let position = |found: Option<usize>| found.map_or(0, |i| i as i32);
    match &snap.report.station {
        Some(station) => station.ar.as_ref().map_or(0, |a| {
            1 + position(ArState::ALL.iter().position(|s| *s == a.state))
        }),
        None => position(
            snap.report
                .devices
                .get(d)
                .and_then(|x| DeviceState::ALL.iter().position(|s| *s == x.state)),
        ),
    }
}

/// The bytes of a data item of submodule `s` in `snap`.
fn item_bytes(snap: &Snapshot, s: usize, area: Area, offset: u16, length: u16) -> Option<&[u8]> {
    let data = match area {
        Area::Input => snap.inputs.get(s)?,
        Area::Output => snap.outputs.get(s)?,
    };
    data.get(usize::from(offset)..usize::from(offset) + usize::from(length))
}

/// The value and status of a variable in `snap`.
fn value_of(shows: Shows, snap: &Snapshot) -> (Variant, StatusCode) {
    let r = &snap.report;
    let good = StatusCode::Good;
    let data = |bytes: Option<&Vec<u8>>, q: Quality| {
        let b = bytes.cloned().unwrap_or_default();
        (Variant::from(ByteString::from(b)), status_code(q))
    };
    let st = |s: usize| snap.status.get(s).copied();
    let ar = r.station.as_ref().and_then(|s| s.ar.as_ref());
    let bad = |v: Variant| (v, StatusCode::BadNotConnected);
    match shows {
        Shows::Mode => (Variant::from(snap.mode().name()), good),
        Shows::CycleTime => (Variant::from(r.cycle_ns as f64 / 1e6), good),
        Shows::CycleCount => (Variant::from(snap.cycle), good),
        Shows::Overruns => (Variant::from(r.overruns), good),
        Shows::OpFaults => (Variant::from(r.opfaults), good),
        Shows::Latency(which) => {
            let ns = match which {
                Latency::WakeupP50 => r.wakeup_latency.p50_ns,
                Latency::WakeupP99 => r.wakeup_latency.p99_ns,
                Latency::WakeupMax => r.wakeup_latency.max_ns,
                Latency::CycleWorkP99 => r.cycle_work.p99_ns,
                Latency::HandshakeP99 => r.handshake_round_trip.p99_ns,
            };
            (Variant::from(ns as f64 / 1e3), good)
        }
        Shows::DeviceState(d) => (Variant::from(state_number(snap, d)), good),
        Shows::Plc => match ar {
            Some(a) if a.controller_name.is_empty() => {
                (Variant::from(a.controller_mac.as_str()), good)
            }
            Some(a) => (
                Variant::from(format!("{} ({})", a.controller_name, a.controller_mac)),
                good,
            ),
            None => bad(Variant::from("")),
        },
        Shows::PlcRunning => match ar.and_then(|a| a.plc_running) {
            Some(running) => (Variant::from(running), good),
            None => bad(Variant::from(false)),
        },
        Shows::Typed(s, area, offset, length, kind) => {
            let q = status_code(quality(snap, s, area == Area::Output));
            match item_bytes(snap, s, area, offset, length).and_then(|b| kind.decode(b)) {
                Some(v) => (v, q),
                None => bad(Variant::Empty),
            }
        }
        Shows::Bit(s, area, offset, length, n) => {
            let q = status_code(quality(snap, s, area == Area::Output));
            match item_bytes(snap, s, area, offset, length).and_then(|b| crate::typed::bit(b, n)) {
                Some(v) => (Variant::from(v), q),
                None => bad(Variant::from(false)),
            }
        }
        Shows::Inputs(s) => data(snap.inputs.get(s), quality(snap, s, false)),
        Shows::Outputs(s) => data(snap.outputs.get(s), quality(snap, s, true)),
        Shows::InputIops(s) => {
            st(s).map_or(bad(Variant::from(false)), |x| (ioxs(x.input_remote), good))
        }
        Shows::InputIocs(s) => {
            st(s).map_or(bad(Variant::from(false)), |x| (ioxs(x.input_local), good))
        }
        Shows::OutputIops(s) => {
            st(s).map_or(bad(Variant::from(false)), |x| (ioxs(x.output_local), good))
        }
        Shows::OutputIocs(s) => {
            st(s).map_or(bad(Variant::from(false)), |x| (ioxs(x.output_remote), good))
        }
    }
}
