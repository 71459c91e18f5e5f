// SPDX-License-Identifier: MIT OR Apache-2.0
//! The browsable address space: `Objects/procimg/<instance>` with the server's status, and per
//! device its state and per submodule (`<slot>.<subslot>`) its inputs and outputs with their
//! providers' status. Its values are stored in a [`SimpleNodeManager`] and set from each
//! snapshot, only those that changed, in one batch: a Read sees one cycle.

use crate::snapshot::{Quality, Snapshot, quality};
use opcua::server::SubscriptionCache;
use opcua::server::address_space::{AccessLevel, EventNotifier, ObjectBuilder, VariableBuilder};
use opcua::server::node_manager::memory::SimpleNodeManager;
use opcua::types::{
    ByteString, DataTypeId, DataValue, DateTime, NodeId, ObjectTypeId, QualifiedName, StatusCode,
    Variant,
};
use procimg_client::{Ioxs, Layout};
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

/// What a variable of the tree shows.
#[derive(Clone, Copy, Debug)]
enum Shows {
    Mode,
    CycleTime,
    CycleCount,
    Overruns,
    OpFaults,
    DeviceState(usize),
    Inputs(usize),
    Outputs(usize),
    InputIops(usize),
    InputIocs(usize),
    OutputIops(usize),
    OutputIocs(usize),
}

/// The tree's variables and what was last published of them.
pub struct Tree {
    vars: Vec<(NodeId, Shows)>,
    last: HashMap<NodeId, (Variant, StatusCode)>,
}

/// The string NodeId of the tree's node at `path` (`line/Devices/echo/1.1/Inputs`).
pub fn node_id(ns: u16, path: &str) -> NodeId {
    NodeId::new(ns, path)
}

impl Tree {
    /// Builds the tree of `instance` with `layout` into `nm`'s address space (namespace `ns`).
    pub fn build(nm: &SimpleNodeManager, ns: u16, instance: &str, layout: &Layout) -> Tree {
        let mut vars = Vec::new();
        let mut space = nm.address_space().write();
        let root = node_id(ns, "procimg");
        let browse = |name: &str| QualifiedName::new(ns, name);
        space.add_folder(
            &root,
            browse("procimg"),
            "procimg",
            &NodeId::objects_folder_id(),
        );
        let top = node_id(ns, instance);
        ObjectBuilder::new(&top, browse(instance), instance)
            .organized_by(root)
            .event_notifier(EventNotifier::SUBSCRIBE_TO_EVENTS)
            .has_type_definition(ObjectTypeId::BaseObjectType)
            .insert(&mut *space);
        let object = |space: &mut opcua::server::address_space::AddressSpace,
                      id: &NodeId,
                      name: &str,
                      parent: &NodeId| {
            ObjectBuilder::new(id, QualifiedName::new(ns, name), name)
                .component_of(parent.clone())
                .has_type_definition(ObjectTypeId::BaseObjectType)
                .insert(space);
        };
        let mut variable = |space: &mut opcua::server::address_space::AddressSpace,
                            parent: &NodeId,
                            path: String,
                            name: &str,
                            data_type: DataTypeId,
                            initial: Variant,
                            shows: Shows| {
            let id = node_id(ns, &path);
            VariableBuilder::new(&id, QualifiedName::new(ns, name), name)
                .data_type(data_type)
                .value(initial)
                .access_level(AccessLevel::CURRENT_READ)
                .user_access_level(AccessLevel::CURRENT_READ)
                .component_of(parent.clone())
                .insert(space);
            vars.push((id, shows));
        };
        let status = node_id(ns, &format!("{instance}/Status"));
        object(&mut space, &status, "Status", &top);
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
        ] {
            variable(
                &mut space,
                &status,
                format!("{instance}/Status/{name}"),
                name,
                data_type,
                initial,
                shows,
            );
        }
        let devices = node_id(ns, &format!("{instance}/Devices"));
        object(&mut space, &devices, "Devices", &top);
        for d in 0..layout.devices.len() {
            let name = layout.device_name(d).to_owned();
            let dev_path = format!("{instance}/Devices/{name}");
            let dev = node_id(ns, &dev_path);
            ObjectBuilder::new(&dev, QualifiedName::new(ns, name.as_str()), name.as_str())
                .component_of(devices.clone())
                .has_type_definition(ObjectTypeId::BaseObjectType)
                .event_notifier(EventNotifier::SUBSCRIBE_TO_EVENTS)
                .insert(&mut *space);
            variable(
                &mut space,
                &dev,
                format!("{dev_path}/State"),
                "State",
                DataTypeId::String,
                Variant::from(""),
                Shows::DeviceState(d),
            );
            for s in layout.submodules_of(d) {
                let e = layout.submodules[s];
                let sub_name = format!("{}.{}", e.slot, e.subslot);
                let sub_path = format!("{dev_path}/{sub_name}");
                let sub = node_id(ns, &sub_path);
                object(&mut space, &sub, &sub_name, &dev);
                let empty = || Variant::from(ByteString::from(Vec::<u8>::new()));
                // A direction's data and its two status bytes, where it has data.
                let directions = [
                    (
                        e.input_length > 0,
                        "Input",
                        Shows::Inputs(s),
                        Shows::InputIops(s),
                        Shows::InputIocs(s),
                    ),
                    (
                        e.output_length > 0,
                        "Output",
                        Shows::Outputs(s),
                        Shows::OutputIops(s),
                        Shows::OutputIocs(s),
                    ),
                ];
                for (_, dir, data, iops, iocs) in directions.into_iter().filter(|d| d.0) {
                    for (name, data_type, initial, shows) in [
                        (format!("{dir}s"), DataTypeId::ByteString, empty(), data),
                        (
                            format!("{dir}IOPS"),
                            DataTypeId::Boolean,
                            Variant::from(false),
                            iops,
                        ),
                        (
                            format!("{dir}IOCS"),
                            DataTypeId::Boolean,
                            Variant::from(false),
                            iocs,
                        ),
                    ] {
                        variable(
                            &mut space,
                            &sub,
                            format!("{sub_path}/{name}"),
                            &name,
                            data_type,
                            initial,
                            shows,
                        );
                    }
                }
            }
        }
        drop(space);
        Tree {
            vars,
            last: HashMap::new(),
        }
    }

    /// Sets the variables that changed in `snap`, in one batch.
    pub fn publish(
        &mut self,
        nm: &SimpleNodeManager,
        subscriptions: &SubscriptionCache,
        layout: &Layout,
        snap: &Snapshot,
    ) {
        let time = timestamp(snap.time);
        let mut changed = Vec::new();
        for (id, shows) in &self.vars {
            let (value, status) = value_of(*shows, layout, snap);
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

/// The value and status of a variable in `snap`.
fn value_of(shows: Shows, layout: &Layout, snap: &Snapshot) -> (Variant, StatusCode) {
    let r = &snap.report;
    let good = StatusCode::Good;
    let data = |bytes: Option<&Vec<u8>>, q: Quality| {
        let b = bytes.cloned().unwrap_or_default();
        (Variant::from(ByteString::from(b)), status_code(q))
    };
    let st = |s: usize| snap.status.get(s).copied();
    match shows {
        Shows::Mode => (Variant::from(snap.mode().name()), good),
        Shows::CycleTime => (Variant::from(r.cycle_ns as f64 / 1e6), good),
        Shows::CycleCount => (Variant::from(snap.cycle), good),
        Shows::Overruns => (Variant::from(r.overruns), good),
        Shows::OpFaults => (Variant::from(r.opfaults), good),
        Shows::DeviceState(d) => {
            let state = match &r.station {
                Some(station) => station
                    .ar
                    .as_ref()
                    .map_or_else(|| "no AR".to_owned(), |a| a.state.to_string()),
                None => r
                    .devices
                    .get(d)
                    .map_or_else(String::new, |x| x.state.to_string()),
            };
            (Variant::from(state), good)
        }
        Shows::Inputs(s) => data(snap.inputs.get(s), quality(snap, layout, s, false)),
        Shows::Outputs(s) => data(snap.outputs.get(s), quality(snap, layout, s, true)),
        Shows::InputIops(s) => st(s)
            .map_or((Variant::from(false), StatusCode::BadNotConnected), |x| {
                (ioxs(x.input_remote), good)
            }),
        Shows::InputIocs(s) => st(s)
            .map_or((Variant::from(false), StatusCode::BadNotConnected), |x| {
                (ioxs(x.input_local), good)
            }),
        Shows::OutputIops(s) => st(s)
            .map_or((Variant::from(false), StatusCode::BadNotConnected), |x| {
                (ioxs(x.output_local), good)
            }),
        Shows::OutputIocs(s) => st(s)
            .map_or((Variant::from(false), StatusCode::BadNotConnected), |x| {
                (ioxs(x.output_remote), good)
            }),
    }
}
