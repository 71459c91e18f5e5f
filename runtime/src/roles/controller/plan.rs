// SPDX-License-Identifier: MIT OR Apache-2.0
//! The configuration in the protocol crate's terms: what the controller plans for each
//! device.

use crate::config::{Config, DeviceConfig, Peer, SubmoduleConfig};
use procimg_profinet::controller::plan::{DevicePlan, DeviceSpec, PlanError, SubmoduleSpec};
use procimg_profinet::wire::record::{
    CheckedPeer, INDEX_PD_PORT_DATA_CHECK, PdPortDataCheck, PortCheck,
};

/// The controller's plan of every configured device: the configuration translated into the
/// protocol crate's terms, then planned (send clock, frame layouts, expected submodules).
pub fn plan_devices(config: &Config) -> Result<Vec<DevicePlan>, PlanError> {
    let specs: Vec<DeviceSpec> = config.devices.iter().map(device_spec).collect();
    DevicePlan::all(&specs, config.cycle_ns)
}

/// What the controller needs to know of a configured device.
pub fn device_spec(dev: &DeviceConfig) -> DeviceSpec {
    let mut submodules: Vec<SubmoduleSpec> = dev.submodules.iter().map(submodule_spec).collect();
    // The topology the device's ports are to have: their PDPortDataCheck, written with the
    // other parameter records at connect.
    let mut programmable_ports = Vec::new();
    for peer in &dev.topology {
        let (station, port) = match &peer.peer {
            Peer::Fixed { station, port } => (station, port),
            // Tailoring the IO system writes its check.
            Peer::Programmable => {
                programmable_ports.push(peer.subslot);
                continue;
            }
        };
        let check = PdPortDataCheck {
            slot: 0,
            subslot: peer.subslot,
            checks: vec![PortCheck::Peers(vec![CheckedPeer {
                port_id: port.clone(),
                chassis_id: station.clone(),
            }])],
        };
        let port = submodules
            .iter_mut()
            .find(|s| (s.slot, s.subslot) == (0, peer.subslot));
        // The configuration checked both: a port of the device, names that fit.
        if let (Some(port), Ok(data)) = (port, check.to_vec()) {
            port.records.push((INDEX_PD_PORT_DATA_CHECK, data));
        }
    }
    DeviceSpec {
        name: dev.name.clone(),
        ip: dev.ip,
        vendor_id: dev.vendor_id,
        device_id: dev.device_id,
        instance: dev.instance,
        reduction_ratio: dev.reduction_ratio,
        watchdog_factor: dev.watchdog_factor,
        submodules,
        optional: dev.optional,
        programmable_ports,
    }
}

/// What the controller needs to know of a configured submodule.
pub fn submodule_spec(s: &SubmoduleConfig) -> SubmoduleSpec {
    SubmoduleSpec {
        api: s.api,
        slot: s.slot,
        subslot: s.subslot,
        module_ident: s.module_ident,
        submodule_ident: s.submodule_ident,
        input_length: s.input_length,
        output_length: s.output_length,
        records: s
            .records
            .iter()
            .map(|r| (r.index, r.data.clone()))
            .collect(),
    }
}
