// SPDX-License-Identifier: MIT OR Apache-2.0
//! One station as both of procimg's roles describe it, for the tests that put procimg's
//! controller and procimg's device on the two ends of a veth pair: the device's
//! configuration (`IFACE` its interface, `STATE` its state file, named `fresh-device` until
//! an engineering tool names it) and the controller's (`IFACE`; the station it connects is
//! `pc-device` at 10.47.0.50), in procimg's TOML and as TIA Portal's PN Driver configuration
//! describes it.

/// The station both sides describe: the access point, 8 bytes each way in slot 1 with a
/// parameter record, 4 input bytes in slot 2.
pub const DEVICE_TOML: &str = r#"
role = "device"
network = "IFACE"
[station]
name = "fresh-device"
ip = "10.47.0.50"
vendor_id = 0x0493
device_id = 0x0100
order_number = "PC-DEVICE-TEST"
state_file = "STATE"
[[station.submodule]]
slot = 1
module_ident = 0x10
submodule_ident = 1
input_length = 8
output_length = 8
records = [{ index = 1, length = 4, data = [0, 0, 0, 10] }]
[[station.submodule]]
slot = 2
module_ident = 0x20
submodule_ident = 1
input_length = 4
"#;

/// The same station as the controller's configuration describes it. The watchdog allows
/// 100 frames (100 ms): two cycle threads, their clients and the other tests' servers share
/// two virtual CPUs here, and an AR given up in the middle of an alarm's way would take the
/// alarm with it (the next AR's ModuleDiffBlock says it instead).
pub const CONTROLLER_TOML: &str = r#"
network = "IFACE"
[[device]]
name = "pc-device"
ip = "10.47.0.50"
vendor_id = 0x0493
device_id = 0x0100
watchdog_factor = 100
[[device.submodule]]
slot = 0
subslot = 1
module_ident = 1
submodule_ident = 1
[[device.submodule]]
slot = 0
subslot = 0x8000
module_ident = 1
submodule_ident = 0x8000
[[device.submodule]]
slot = 0
subslot = 0x8001
module_ident = 1
submodule_ident = 0x8001
[[device.submodule]]
slot = 1
subslot = 1
module_ident = 0x10
submodule_ident = 1
input_length = 8
output_length = 8
records = [{ index = 1, data = [0, 0, 0, 7] }]
[[device.submodule]]
slot = 2
subslot = 1
module_ident = 0x20
submodule_ident = 1
input_length = 4
"#;

/// The controller's configuration as a PN Driver configuration (the XML TIA Portal exports,
/// in the format of Siemens' "PROFINET Driver Engineering Interface" manual): the PN Driver
/// `plc-pn-driver` at 10.47.0.1, and the station as [`CONTROLLER_TOML`] has it (the same
/// addresses, record and watchdog). It names no interface: a PN Driver program chooses its
/// adapter.
pub const CONTROLLER_PN_DRIVER_XML: &str =
    include_str!("../../config/tests/data/pn-driver/pc-device.xml");
