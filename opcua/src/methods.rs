// SPDX-License-Identifier: MIT OR Apache-2.0
//! The instance object's methods: `ReadRecord` (any session), `WriteRecord`, `SetMode` and
//! `ActivateDevice` (writers only: [`WRITER_METHODS`], enforced by the authenticator).

use crate::records::{self, Job};
use crate::snapshot::Snapshot;
use opcua::server::address_space::MethodBuilder;
use opcua::server::node_manager::memory::SimpleNodeManager;
use opcua::types::{Argument, ByteString, DataTypeId, NodeId, QualifiedName, StatusCode, Variant};
use procimg_client::access::{self, Space};
use procimg_client::{ControlHandle, Mode, ServiceOptions, Services};
use std::sync::{Arc, Mutex, mpsc};
use std::time::Duration;
use tokio::sync::watch;

/// The methods only a writer's session may call (by the end of their NodeId).
pub const WRITER_METHODS: [&str; 3] = ["/WriteRecord", "/SetMode", "/ActivateDevice"];

/// How long a device's activation may take to be confirmed.
const ACTIVATION_TIMEOUT: Duration = Duration::from_secs(5);

fn argument(name: &str, data_type: DataTypeId, description: &str) -> Argument {
    Argument {
        name: name.into(),
        data_type: data_type.into(),
        value_rank: -1,
        array_dimensions: None,
        description: description.into(),
    }
}

/// Adds the methods to `instance`'s object in `nm` (namespace `ns`), their records (of the
/// newest snapshot's layout) carried out through `records`.
pub fn add(
    nm: &SimpleNodeManager,
    ns: u16,
    instance: &str,
    snapshots: watch::Receiver<Arc<Snapshot>>,
    records: mpsc::Sender<Job>,
) {
    let top = NodeId::new(ns, instance);
    let id = |name: &str| NodeId::new(ns, format!("{instance}/{name}"));
    let addr = argument(
        "Address",
        DataTypeId::UInt32,
        "a logical input address (or diagnostic address) of the submodule",
    );
    let index = argument("Index", DataTypeId::UInt16, "the record index");
    {
        let mut space = nm.address_space().write();
        for (name, inputs, outputs) in [
            (
                "ReadRecord",
                vec![
                    addr.clone(),
                    index.clone(),
                    argument("Length", DataTypeId::UInt32, "the most bytes to read"),
                ],
                vec![argument(
                    "Data",
                    DataTypeId::ByteString,
                    "the record's data",
                )],
            ),
            (
                "WriteRecord",
                vec![
                    addr.clone(),
                    index.clone(),
                    argument("Data", DataTypeId::ByteString, "the record's data"),
                ],
                vec![],
            ),
            (
                "SetMode",
                vec![argument(
                    "Mode",
                    DataTypeId::String,
                    "OFFLINE, CLEAR or OPERATE",
                )],
                vec![],
            ),
            (
                "ActivateDevice",
                vec![
                    argument("Device", DataTypeId::String, "the device's name"),
                    argument(
                        "Active",
                        DataTypeId::Boolean,
                        "true: activate it; false: deactivate it",
                    ),
                ],
                vec![],
            ),
        ] {
            let method = id(name);
            let mut b = MethodBuilder::new(&method, QualifiedName::new(ns, name), name)
                .component_of(top.clone())
                .executable(true)
                .user_executable(true)
                .input_args(&mut *space, &id(&format!("{name}/InputArguments")), &inputs);
            if !outputs.is_empty() {
                b = b.output_args(
                    &mut *space,
                    &id(&format!("{name}/OutputArguments")),
                    &outputs,
                );
            }
            b.insert(&mut *space);
        }
    }
    let records = Arc::new(Mutex::new(records));
    let target_of = {
        let snapshots = snapshots.clone();
        move |args: &[Variant]| -> Result<procimg_client::RecordTarget, StatusCode> {
            let (Some(Variant::UInt32(address)), Some(Variant::UInt16(index))) =
                (args.first(), args.get(1))
            else {
                return Err(StatusCode::BadTypeMismatch);
            };
            let layout = snapshots.borrow().layout.clone();
            let s = access::find_module(&layout.submodules, Space::Input, *address)
                .ok_or(StatusCode::BadNodeIdUnknown)?;
            records::target(&layout, s, *index).ok_or(StatusCode::BadNodeIdUnknown)
        }
    };
    let refused = |why: String| {
        tracing::info!("record method refused: {why}");
        StatusCode::BadCommunicationError
    };
    {
        let records = records.clone();
        let target_of = target_of.clone();
        nm.inner()
            .add_method_callback(id("ReadRecord"), move |args: &[Variant]| {
                let target = target_of(args)?;
                let Some(Variant::UInt32(max_len)) = args.get(2) else {
                    return Err(StatusCode::BadTypeMismatch);
                };
                let max_len = *max_len;
                let data = records::blocking(&records, |reply| Job::Read {
                    target,
                    max_len,
                    reply,
                })
                .map_err(refused)?;
                Ok(vec![Variant::from(ByteString::from(data))])
            });
    }
    nm.inner()
        .add_method_callback(id("WriteRecord"), move |args: &[Variant]| {
            let target = target_of(args)?;
            let Some(Variant::ByteString(data)) = args.get(2) else {
                return Err(StatusCode::BadTypeMismatch);
            };
            let data = data.value.clone().unwrap_or_default();
            records::blocking(&records, |reply| Job::Write {
                target,
                data,
                reply,
            })
            .map_err(refused)?;
            Ok(vec![])
        });
    {
        let instance = instance.to_owned();
        nm.inner()
            .add_method_callback(id("ActivateDevice"), move |args: &[Variant]| {
                let (Some(Variant::String(name)), Some(Variant::Boolean(active))) =
                    (args.first(), args.get(1))
                else {
                    return Err(StatusCode::BadTypeMismatch);
                };
                let active = *active;
                let layout = snapshots.borrow().layout.clone();
                let device = layout
                    .device(name.as_ref())
                    .ok_or(StatusCode::BadNodeIdUnknown)? as u32;
                let activate = || {
                    let mut s =
                        Services::open(&instance, ServiceOptions::new("procimg-opcua activate"))
                            .map_err(|e| e.to_string())?;
                    s.activate_confirmed(device, active, ACTIVATION_TIMEOUT)
                        .map_err(|e| e.to_string())
                };
                let done = records::blocking_call(activate);
                done.map(|()| vec![]).map_err(|why| {
                    tracing::info!("activation of device {name} refused: {why}");
                    StatusCode::BadInvalidState
                })
            });
    }
    let instance = instance.to_owned();
    nm.inner()
        .add_method_callback(id("SetMode"), move |args: &[Variant]| {
            let Some(Variant::String(mode)) = args.first() else {
                return Err(StatusCode::BadTypeMismatch);
            };
            let mode: Mode = mode
                .as_ref()
                .parse()
                .map_err(|_| StatusCode::BadOutOfRange)?;
            let set = || {
                ControlHandle::open(&instance, "procimg-opcua mode")
                    .map_err(|e| e.to_string())
                    .and_then(|c| c.set_mode(mode).map_err(|e| e.to_string()))
            };
            let done = records::blocking_call(set);
            done.map(|()| vec![]).map_err(|why| {
                tracing::info!("mode change to {mode} refused: {why}");
                StatusCode::BadInvalidState
            })
        });
}
