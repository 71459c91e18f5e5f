// SPDX-License-Identifier: MIT OR Apache-2.0
//! This server as an IO device (`role = "device"`): its identity and what is plugged into it
//! (table `[station]`).
//!
//! The device access point occupies slot 0: its own submodule in subslot 1, the interface
//! in 0x8000 and the port in 0x8001, with the ident numbers of `[station.dap]`. The
//! submodules of `[[station.submodule]]` follow in slots 1 and up. Directions are named from
//! the IO controller's view, as in IO-Base's device interface: the *input* data (I) is
//! what the device provides and the PLC reads, the *output* data (Q) what the PLC writes.

use std::net::Ipv4Addr;
use std::path::PathBuf;

use super::SubmoduleConfig;

/// Subslot of the device access point's own submodule.
pub const DAP_SUBSLOT: u16 = 1;
/// Subslot of the interface submodule.
pub const INTERFACE_SUBSLOT: u16 = 0x8000;
/// Subslot of the (only) port submodule.
pub const PORT_SUBSLOT: u16 = 0x8001;
/// Default ModuleIdentNumber of the device access point.
pub const DEFAULT_DAP_MODULE_IDENT: u32 = 0x0000_0001;
/// Default SubmoduleIdentNumber of the device access point's own submodule.
pub const DEFAULT_DAP_SUBMODULE_IDENT: u32 = 0x0000_0001;
/// Default SubmoduleIdentNumber of the interface submodule.
pub const DEFAULT_INTERFACE_IDENT: u32 = 0x0000_8000;
/// Default SubmoduleIdentNumber of the port submodule.
pub const DEFAULT_PORT_IDENT: u32 = 0x0000_8001;
/// Most slots a station may have after the DAP (as GSDML `PhysicalSlots` allows).
pub const MAX_STATION_SLOT: u16 = 0x7FFF;
/// Most bytes of one IO CR's C_SDU (data, IOPS and IOCS), RT class 1.
pub const MAX_CR_DATA: usize = 1440;
/// Longest parameter record a station submodule may accept.
pub const MAX_RECORD_LENGTH: u16 = 4068;

/// The station (table `[station]`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StationConfig {
    /// NameOfStation at the first start (key `name`); DCP may change it, and a permanent
    /// change is kept in the state file.
    pub name: String,
    /// IP address at the first start (key `ip`), or none until DCP sets one.
    pub ip: Option<Ipv4Addr>,
    /// Subnet mask (key `netmask`, default 255.255.255.0 with an `ip`).
    pub netmask: Ipv4Addr,
    /// Default gateway (key `gateway`, default none: 0.0.0.0).
    pub gateway: Ipv4Addr,
    /// PROFINET VendorID (key `vendor_id`).
    pub vendor_id: u16,
    /// PROFINET DeviceID (key `device_id`).
    pub device_id: u16,
    /// Instance of the device's object UUID (key `instance`, default 1).
    pub instance: u16,
    /// The type of station DCP reports, DeviceVendorValue (key `device_type`, default
    /// `"procimg"`): 1 to 240 visible ASCII characters.
    pub device_type: String,
    /// I&M0 OrderID (key `order_number`): up to 20 visible ASCII characters.
    pub order_number: String,
    /// I&M0 IM_Serial_Number (key `serial_number`): up to 16 visible ASCII characters.
    pub serial_number: String,
    /// I&M0 IM_Hardware_Revision (key `hardware_revision`, default 1).
    pub hardware_revision: u16,
    /// I&M0 IM_Software_Revision (key `software_revision`, default `"V0.1.0"`).
    pub software_revision: SoftwareVersion,
    /// Where the station keeps what must survive a restart: a permanent name or IP set by
    /// DCP, I&M1 to I&M4 (key `state_file`; default none: nothing survives).
    pub state_file: Option<PathBuf>,
    /// Send a DCP Hello at start-up (key `dcp_hello`, default false).
    pub dcp_hello: bool,
    /// Where the station's SNMP goes (key `snmp_agentx`): the AgentX master socket of the
    /// system's SNMP agent (net-snmp's snmpd), whose subagent procimgd becomes.
    pub snmp_agentx: SnmpMaster,
    /// The device access point (table `[station.dap]`).
    pub dap: DapConfig,
    /// Every submodule, the DAP's three first, then `[[station.submodule]]` in configuration
    /// order (a station its program defines: the DAP's only, until the program's tree).
    pub submodules: Vec<StationSubmodule>,
    /// The station's GSDML file when its program defines the tree (key `gsdml`, no
    /// `[[station.submodule]]`): the program's (module, submodule) ident numbers are looked
    /// up there.
    pub program: Option<ProgramStation>,
}

/// A station its program defines: the GSDML file its tree is checked against.
#[derive(Clone, Debug)]
pub struct ProgramStation {
    /// The GSDML file (key `gsdml`, relative to the configuration file's directory).
    pub gsdml: PathBuf,
    /// The ID of its device access point (key `gsdml_dap`, default the file's first).
    pub dap: String,
    /// The file as read when the configuration was checked.
    pub file: std::sync::Arc<crate::gsdml::Gsdml>,
    /// The index of the device access point in `file.daps`.
    pub dap_index: usize,
}

/// Two are the same when they name the same file and device access point (the file's
/// contents are read from it).
impl PartialEq for ProgramStation {
    fn eq(&self, other: &Self) -> bool {
        (&self.gsdml, &self.dap) == (&other.gsdml, &other.dap)
    }
}

impl Eq for ProgramStation {}

/// The AgentX master a station's SNMP subagent attaches to (key `snmp_agentx`).
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub enum SnmpMaster {
    /// Left out: the agent's standard socket (`/var/agentx/master`) on a real interface,
    /// none on the simulated network.
    #[default]
    Standard,
    /// `"off"`: no SNMP.
    Off,
    /// A socket path, `unix:PATH` or `tcp:HOST:PORT`.
    At(String),
}

impl StationConfig {
    /// The plain submodule descriptions, in table order.
    pub fn submodule_configs(&self) -> impl Iterator<Item = &SubmoduleConfig> {
        self.submodules.iter().map(|s| &s.submodule)
    }

    /// Its tree after the device access point, as a program would define it
    /// ([`crate::define_station`]): places and ident numbers.
    pub fn tree(&self) -> Vec<crate::PlannedSubmodule> {
        self.submodule_configs()
            .filter(|s| s.slot > 0)
            .map(|s| crate::PlannedSubmodule {
                api: s.api,
                slot: s.slot,
                subslot: s.subslot,
                module_ident: s.module_ident,
                submodule_ident: s.submodule_ident,
            })
            .collect()
    }
}

/// I&M0's software revision: a prefix letter and three numbers, e.g. `V1.2.0`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SoftwareVersion {
    /// `V` official release, `R` revision, `P` prototype, `U` under test, `T` test device.
    pub prefix: char,
    /// Functional enhancement.
    pub functional: u8,
    /// Bug fix.
    pub bug_fix: u8,
    /// Internal change.
    pub internal: u8,
}

impl core::fmt::Display for SoftwareVersion {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let SoftwareVersion {
            prefix,
            functional,
            bug_fix,
            internal,
        } = self;
        write!(f, "{prefix}{functional}.{bug_fix}.{internal}")
    }
}

/// The device access point's ident numbers (table `[station.dap]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DapConfig {
    /// ModuleIdentNumber of slot 0 (key `module_ident`).
    pub module_ident: u32,
    /// SubmoduleIdentNumber of subslot 1 (key `submodule_ident`).
    pub submodule_ident: u32,
    /// SubmoduleIdentNumber of the interface, subslot 0x8000 (key `interface_ident`).
    pub interface_ident: u32,
    /// SubmoduleIdentNumber of the port, subslot 0x8001 (key `port_ident`).
    pub port_ident: u32,
}

impl Default for DapConfig {
    fn default() -> Self {
        DapConfig {
            module_ident: DEFAULT_DAP_MODULE_IDENT,
            submodule_ident: DEFAULT_DAP_SUBMODULE_IDENT,
            interface_ident: DEFAULT_INTERFACE_IDENT,
            port_ident: DEFAULT_PORT_IDENT,
        }
    }
}

/// One submodule of the station.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StationSubmodule {
    /// Where it is plugged, its ident numbers, IO lengths and logical addresses
    /// (`records` is empty: see [`accepts`](Self::accepts)).
    pub submodule: SubmoduleConfig,
    /// The parameter records the PLC may write (key `records`), by index.
    pub accepts: Vec<AcceptedRecord>,
    /// Whether the submodule has I&M data of its own (key `im`; default: only the DAP's
    /// own submodule, which speaks for the whole device).
    pub im: bool,
    /// Whether it is plugged when procimgd starts (key `plugged`, default true). A
    /// submodule not plugged at start keeps its place in the image and waits for a client
    /// to plug it (the managing client of the IO-Base device API, GOAL's and GS20-PN's
    /// "add item"); the PLC sees it missing until then.
    pub plugged: bool,
}

/// A parameter record a station submodule accepts (an element of its `records`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AcceptedRecord {
    /// Record index, 0x0000 to 0x7FFF (key `index`).
    pub index: u16,
    /// Its length in bytes (key `length`): a write of another length is refused.
    pub length: u16,
    /// What a read returns before the PLC wrote it (key `data`, default zeros).
    pub initial: Vec<u8>,
}
