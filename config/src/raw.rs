// SPDX-License-Identifier: MIT OR Apache-2.0
//! The configuration file as written, before validation: every value that is checked later
//! keeps its span, so errors can name its line.

use serde::Deserialize;
use toml::Spanned;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawConfig {
    pub role: Option<Spanned<String>>,
    pub instance: Option<Spanned<String>>,
    pub cycle_time: Option<Spanned<String>>,
    pub opdone_deadline: Option<Spanned<String>>,
    pub late_client_policy: Option<Spanned<String>>,
    pub send_outputs: Option<Spanned<String>>,
    pub start_mode: Option<Spanned<String>>,
    pub network: Option<Spanned<String>>,
    pub cycle_thread: Option<RawCycleThread>,
    pub access: Option<RawAccess>,
    #[serde(default)]
    pub device: Vec<Spanned<RawDevice>>,
    pub station: Option<Spanned<RawStation>>,
    pub interface: Option<Spanned<RawInterface>>,
}

/// `[interface]`: the controller's own PROFINET interface (`role = "controller"`).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawInterface {
    pub station_name: Option<Spanned<String>>,
    pub name_by_program: Option<bool>,
    pub address_by_program: Option<bool>,
    pub check_link: Option<bool>,
    pub diagnostic_address: Option<Spanned<u32>>,
    pub port_diagnostic_address: Option<Spanned<u32>>,
    pub type_of_station: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawCycleThread {
    pub cpu: Option<Spanned<usize>>,
    pub priority: Option<Spanned<u8>>,
    pub status_priority: Option<Spanned<u8>>,
    pub lock_memory: Option<bool>,
    pub prefault_all: Option<bool>,
    pub opdone_wait: Option<Spanned<String>>,
    pub opdone_spin: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawAccess {
    pub mode: Option<Spanned<String>>,
    pub group: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawDevice {
    pub name: Spanned<String>,
    pub ip: Option<Spanned<String>>,
    pub vendor_id: Option<Spanned<u16>>,
    pub device_id: Option<Spanned<u16>>,
    pub gsdml: Option<Spanned<String>>,
    pub dap: Option<Spanned<String>>,
    pub instance: Option<u16>,
    /// Any integer: out of range, the message gives the key's own range.
    pub reduction_ratio: Option<Spanned<i64>>,
    /// Any integer: out of range, the message gives the key's own range.
    pub watchdog_factor: Option<Spanned<i64>>,
    pub sim: Option<Spanned<String>>,
    pub optional: Option<bool>,
    #[serde(default)]
    pub submodule: Vec<Spanned<RawSubmodule>>,
    #[serde(default)]
    pub topology: Vec<Spanned<RawTopology>>,
}

/// An element of a device's `topology`: the neighbour one of its ports is to have.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawTopology {
    pub subslot: Option<Spanned<u16>>,
    pub station: Option<Spanned<String>>,
    pub port: Option<Spanned<String>>,
    pub programmable: Option<Spanned<bool>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawSubmodule {
    pub api: Option<Spanned<u32>>,
    pub slot: Spanned<u16>,
    pub subslot: Option<Spanned<u16>>,
    pub module: Option<Spanned<String>>,
    pub submodule: Option<Spanned<String>>,
    pub module_ident: Option<Spanned<u32>>,
    pub submodule_ident: Option<Spanned<u32>>,
    pub input_length: Option<Spanned<u16>>,
    pub output_length: Option<Spanned<u16>>,
    pub input_address: Option<Spanned<u32>>,
    pub output_address: Option<Spanned<u32>>,
    pub diagnostic_address: Option<Spanned<u32>>,
    pub rt_class: Option<Spanned<u8>>,
    /// `None` when left out (then a GSDML module's records apply), `Some(vec![])` for
    /// `records = []`.
    pub records: Option<Vec<RawRecord>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawRecord {
    pub index: u16,
    pub data: Vec<u8>,
}

/// `[station]`: this server as an IO device (`role = "device"`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawStation {
    pub name: Spanned<String>,
    pub ip: Option<Spanned<String>>,
    pub netmask: Option<Spanned<String>>,
    pub gateway: Option<Spanned<String>>,
    pub vendor_id: Option<Spanned<u16>>,
    pub device_id: Option<Spanned<u16>>,
    pub gsdml: Option<Spanned<String>>,
    pub gsdml_dap: Option<Spanned<String>>,
    pub instance: Option<Spanned<u16>>,
    pub device_type: Option<Spanned<String>>,
    pub order_number: Option<Spanned<String>>,
    pub serial_number: Option<Spanned<String>>,
    pub hardware_revision: Option<Spanned<u16>>,
    pub software_revision: Option<Spanned<String>>,
    pub state_file: Option<Spanned<String>>,
    pub dcp_hello: Option<bool>,
    pub snmp_agentx: Option<Spanned<String>>,
    pub dap: Option<Spanned<RawDap>>,
    #[serde(default)]
    pub submodule: Vec<Spanned<RawStationSubmodule>>,
}

/// `[station.dap]`: the device access point in slot 0.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawDap {
    pub module_ident: Option<Spanned<u32>>,
    pub submodule_ident: Option<Spanned<u32>>,
    pub interface_ident: Option<Spanned<u32>>,
    pub port_ident: Option<Spanned<u32>>,
}

/// An entry of `[[station.submodule]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawStationSubmodule {
    pub api: Option<Spanned<u32>>,
    pub slot: Spanned<u16>,
    pub subslot: Option<Spanned<u16>>,
    pub module_ident: Spanned<u32>,
    pub submodule_ident: Spanned<u32>,
    pub input_length: Option<Spanned<u16>>,
    pub output_length: Option<Spanned<u16>>,
    pub input_address: Option<Spanned<u32>>,
    pub output_address: Option<Spanned<u32>>,
    pub diagnostic_address: Option<Spanned<u32>>,
    pub im: Option<bool>,
    pub plugged: Option<bool>,
    #[serde(default)]
    pub records: Vec<Spanned<RawAcceptedRecord>>,
}

/// An element of a station submodule's `records`: a parameter record it accepts.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawAcceptedRecord {
    pub index: Spanned<u16>,
    pub length: Spanned<u16>,
    pub data: Option<Spanned<Vec<u8>>>,
}
