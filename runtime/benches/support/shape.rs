// SPDX-License-Identifier: MIT OR Apache-2.0
//! Configurations of a given size: devices, submodules and bytes of IO data, spread evenly.

use procimg_runtime::config::station::{
    DapConfig, SoftwareVersion, StationConfig, StationSubmodule,
};
use procimg_runtime::config::{Config, DeviceConfig, Role, SimBehaviour, SubmoduleConfig};
use procimg_shm_layout::NO_ADDRESS;

/// Cycle time of every benchmark configuration. Long, so that a device's watchdog
/// ([`WATCHDOG_FACTOR`] cycles) never runs out while criterion pauses between samples; the
/// server's work per cycle does not depend on it.
pub const CYCLE_NS: u64 = 32_000_000;

/// The longest data hold time (DataHoldFactor × cycle) a device accepts in a Connect: the
/// standard's limit for RT.
const MAX_DATA_HOLD_NS: u64 = 1_920_000_000;

/// Every device's watchdog factor: the longest watchdog a device accepts at [`CYCLE_NS`]
/// (the devices are brought up by the controller, see `rig::exchanges`).
pub const WATCHDOG_FACTOR: u16 = (MAX_DATA_HOLD_NS / CYCLE_NS) as u16;

/// The size of an IO system.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shape {
    /// Devices.
    pub devices: usize,
    /// Submodules over all devices.
    pub submodules: usize,
    /// Bytes of input data, and as many of output data, over all submodules.
    pub bytes: usize,
}

impl Shape {
    /// Bytes of data of submodule `s` (each direction): `bytes` spread evenly.
    pub fn submodule_len(&self, s: usize) -> usize {
        let (q, r) = (self.bytes / self.submodules, self.bytes % self.submodules);
        q + usize::from(s < r)
    }

    /// Submodules of device `d`: `submodules` spread evenly.
    pub fn device_submodules(&self, d: usize) -> usize {
        let (q, r) = (
            self.submodules / self.devices,
            self.submodules % self.devices,
        );
        q + usize::from(d < r)
    }

    /// Whether every device's IO fits one cyclic frame (1440 bytes of C_SDU: per
    /// submodule its data, its IOPS and the IOCS of the other direction).
    pub fn fits_profinet(&self) -> bool {
        let mut s = 0;
        (0..self.devices).all(|d| {
            let n = self.device_submodules(d);
            let bytes: usize = (s..s + n).map(|i| self.submodule_len(i) + 2).sum();
            s += n;
            bytes <= procimg_profinet::wire::rt::MAX_DATA_LENGTH
        })
    }
}

/// A configuration of `shape` under `instance`: every submodule has inputs and outputs,
/// addresses are assigned in order, one submodule per slot.
pub fn config(instance: &str, shape: Shape) -> Config {
    let mut config = Config::demo();
    config.instance = instance.to_string();
    config.cycle_ns = CYCLE_NS;
    config.opdone_deadline_ns = CYCLE_NS / 2;
    let template = config.devices[0].clone();
    let (mut s, mut address) = (0, 0u32);
    config.devices = (0..shape.devices)
        .map(|d| {
            let submodules = (0..shape.device_submodules(d))
                .map(|i| {
                    let len = shape.submodule_len(s) as u16;
                    s += 1;
                    let at = if len > 0 { address } else { NO_ADDRESS };
                    address += u32::from(len);
                    SubmoduleConfig {
                        api: 0,
                        slot: i as u16 + 1,
                        subslot: 1,
                        module_ident: 0x100,
                        submodule_ident: 0x1,
                        input_length: len,
                        output_length: len,
                        input_address: at,
                        output_address: at,
                        rt_class: 1,
                        records: Vec::new(),
                    }
                })
                .collect();
            DeviceConfig {
                name: format!("bench-{d}"),
                ip: None,
                gsdml: None,
                sim: SimBehaviour::None,
                watchdog_factor: WATCHDOG_FACTOR,
                reduction_ratio: 1,
                submodules,
                ..template.clone()
            }
        })
        .collect();
    config
}

/// `config`'s first device as procimgd's own station (the IO device role), with the same
/// submodules in the same order and no access point: the table the device's end of the
/// device's exchange maps onto.
pub fn as_station(config: &Config) -> Config {
    let d = &config.devices[0];
    Config {
        role: Role::Device,
        devices: Vec::new(),
        station: Some(StationConfig {
            program: None,
            name: d.name.clone(),
            ip: Some(std::net::Ipv4Addr::new(192, 168, 0, 50)),
            netmask: std::net::Ipv4Addr::new(255, 255, 255, 0),
            gateway: std::net::Ipv4Addr::UNSPECIFIED,
            vendor_id: d.vendor_id,
            device_id: d.device_id,
            instance: d.instance,
            device_type: "procimg bench".into(),
            order_number: String::new(),
            serial_number: String::new(),
            hardware_revision: 1,
            software_revision: SoftwareVersion {
                prefix: 'V',
                functional: 0,
                bug_fix: 1,
                internal: 0,
            },
            state_file: None,
            dcp_hello: false,
            snmp_agentx: Default::default(),
            dap: DapConfig::default(),
            submodules: d
                .submodules
                .iter()
                .map(|s| StationSubmodule {
                    submodule: s.clone(),
                    accepts: Vec::new(),
                    im: false,
                    plugged: true,
                })
                .collect(),
        }),
        ..config.clone()
    }
}
