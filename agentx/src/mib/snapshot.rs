// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the MIB serves, as plain data: the runtime fills a [`Snapshot`] from its station,
//! ports and LLDP neighbours, and the subagent answers every request from one.

use std::net::Ipv4Addr;

/// The station as the SNMP manager sees it at one moment.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Snapshot {
    /// sysDescr: product, order number, serial number, hardware and software versions.
    pub sys_descr: String,
    /// sysObjectID; empty serves zeroDotZero (0.0).
    pub sys_object_id: Vec<u32>,
    /// sysUpTime: hundredths of a second since the agent (procimgd's SNMP part) started.
    /// Take a snapshot per request and this is current.
    pub sys_up_time_centis: u32,
    /// sysContact.
    pub sys_contact: String,
    /// sysName: the NameOfStation of a PROFINET station.
    pub sys_name: String,
    /// sysLocation: the I&M1 location tag of a PROFINET station.
    pub sys_location: String,
    /// sysServices (0 to 127): 78 for a PROFINET device (layers 2, 3, 4 and 7).
    pub sys_services: u8,
    /// The LLDP-MIB and LLDP-EXT-PNO-MIB data.
    pub lldp: LldpView,
}

/// The LLDP agent's data (IEEE 802.1AB-2005 LLDP-MIB, and the PROFINET extension).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LldpView {
    /// The local system (lldpLocalSystemData's scalars).
    pub local: LocalSystem,
    /// The local ports (lldpLocPortTable, lldpXPnoLocTable).
    pub ports: Vec<LocalPort>,
    /// The local management addresses (lldpLocManAddrTable); usually the interface's IPv4
    /// address, none while it has none.
    pub management_addresses: Vec<ManagementAddress>,
    /// The neighbours (lldpRemTable, lldpRemManAddrTable, lldpXPnoRemTable).
    pub remotes: Vec<RemoteSystem>,
    /// The counters (lldpStatistics); `None` serves none.
    pub statistics: Option<Statistics>,
}

/// A chassis ID with its subtype (LldpChassisIdSubtype).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ChassisId {
    /// 4 = MAC address, 7 = locally assigned (1 to 7).
    pub subtype: u8,
    /// The ID's bytes as the LLDP TLV carries them.
    pub id: Vec<u8>,
}

impl ChassisId {
    /// Subtype 4, macAddress.
    pub fn mac(mac: [u8; 6]) -> ChassisId {
        ChassisId {
            subtype: 4,
            id: mac.to_vec(),
        }
    }

    /// Subtype 7, local: a PROFINET station's NameOfStation.
    pub fn local(text: &str) -> ChassisId {
        ChassisId {
            subtype: 7,
            id: text.as_bytes().to_vec(),
        }
    }
}

/// A port ID with its subtype (LldpPortIdSubtype).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PortId {
    /// 3 = MAC address, 7 = locally assigned (1 to 7).
    pub subtype: u8,
    /// The ID's bytes as the LLDP TLV carries them.
    pub id: Vec<u8>,
}

impl PortId {
    /// Subtype 3, macAddress.
    pub fn mac(mac: [u8; 6]) -> PortId {
        PortId {
            subtype: 3,
            id: mac.to_vec(),
        }
    }

    /// Subtype 7, local: `port-001` or `port-001.<NameOfStation>`.
    pub fn local(text: &str) -> PortId {
        PortId {
            subtype: 7,
            id: text.as_bytes().to_vec(),
        }
    }
}

/// System capabilities in the LLDP TLV's bit order: bit 0 other, 1 repeater, 2 bridge,
/// 3 WLAN access point, 4 router, 5 telephone, 6 DOCSIS cable device, 7 station only.
/// The MIB's BITS value numbers them from the first octet's most significant bit, which
/// the MIB view does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Capabilities {
    /// What the system can do.
    pub supported: u16,
    /// What it does.
    pub enabled: u16,
}

impl Capabilities {
    /// Bit 7: an end station, what a PROFINET device without a switch is.
    pub const STATION_ONLY: u16 = 1 << 7;
    /// Bit 2: a bridge (a device with an integrated switch).
    pub const BRIDGE: u16 = 1 << 2;
}

/// lldpLocalSystemData's scalars.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LocalSystem {
    /// lldpLocChassisIdSubtype and lldpLocChassisId.
    pub chassis_id: ChassisId,
    /// lldpLocSysName.
    pub sys_name: String,
    /// lldpLocSysDesc.
    pub sys_desc: String,
    /// lldpLocSysCapSupported and lldpLocSysCapEnabled.
    pub capabilities: Capabilities,
}

/// A row of lldpLocPortTable (and of lldpXPnoLocTable with `pno`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LocalPort {
    /// lldpLocPortNum, the index (1 to 4096): 1 for `port-001`.
    pub num: u32,
    /// lldpLocPortIdSubtype and lldpLocPortId.
    pub id: PortId,
    /// lldpLocPortDesc (the ifDescr of the port).
    pub description: String,
    /// lldpXPnoLocTable's row; `None` serves none for this port.
    pub pno: Option<PnoPort>,
}

/// A management address (lldpLocManAddrTable, lldpRemManAddrTable): an IPv4 address and
/// the interface it belongs to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ManagementAddress {
    /// The address (subtype ipV4).
    pub ipv4: Ipv4Addr,
    /// ...ManAddrIfSubtype: 1 unknown, 2 ifIndex, 3 systemPortNumber.
    pub if_subtype: u8,
    /// ...ManAddrIfId: the interface's number in that numbering.
    pub if_id: u32,
    /// ...ManAddrOID; empty serves no value for it.
    pub object_id: Vec<u32>,
}

impl ManagementAddress {
    /// An address on the interface of ifIndex `if_index`, without an OID.
    pub fn on_if_index(ipv4: Ipv4Addr, if_index: u32) -> ManagementAddress {
        ManagementAddress {
            ipv4,
            if_subtype: 2,
            if_id: if_index,
            object_id: Vec::new(),
        }
    }
}

/// A neighbour: a row of lldpRemTable, with its rows of lldpRemManAddrTable and
/// lldpXPnoRemTable.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RemoteSystem {
    /// lldpRemTimeMark: sysUpTime (hundredths of a second) when the entry last changed.
    pub time_mark: u32,
    /// lldpRemLocalPortNum: the local port it was heard on.
    pub local_port: u32,
    /// lldpRemIndex: the agent's number for this neighbour (1 to 2147483647).
    pub index: u32,
    /// lldpRemChassisIdSubtype and lldpRemChassisId.
    pub chassis_id: ChassisId,
    /// lldpRemPortIdSubtype and lldpRemPortId.
    pub port_id: PortId,
    /// lldpRemPortDesc; `None` when the neighbour sent no Port Description.
    pub port_description: Option<String>,
    /// lldpRemSysName; `None` when it sent no System Name.
    pub sys_name: Option<String>,
    /// lldpRemSysDesc; `None` when it sent no System Description.
    pub sys_desc: Option<String>,
    /// lldpRemSysCapSupported and lldpRemSysCapEnabled; `None` when it sent no System
    /// Capabilities.
    pub capabilities: Option<Capabilities>,
    /// Its management addresses.
    pub management_addresses: Vec<ManagementAddress>,
    /// What its PROFINET TLVs said (lldpXPnoRemTable); `None` serves no row.
    pub pno: Option<PnoPort>,
}

/// lldpXPnoLocPortStatusRT2 / lldpXPnoRemPortStatusRT2.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RtClass2Status {
    /// off(0).
    #[default]
    Off,
    /// configured(1).
    Configured,
    /// running(2).
    Running,
}

/// lldpXPnoLocPortStatusRT3 / lldpXPnoRemPortStatusRT3.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RtClass3Status {
    /// off(0).
    #[default]
    Off,
    /// configured(1).
    Configured,
    /// up(2).
    Up,
    /// down(3).
    Down,
    /// running(4).
    Running,
}

/// A row of lldpXPnoLocTable or lldpXPnoRemTable (LLDP-EXT-PNO-MIB, 2006 revision): the
/// delays and port status a PROFINET port announces.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PnoPort {
    /// ...LPDValue: the line propagation delay, ns.
    pub line_delay_ns: u32,
    /// ...PortTxDValue: the port's transmit delay, ns.
    pub tx_delay_ns: u32,
    /// ...PortRxDValue: the port's receive delay, ns.
    pub rx_delay_ns: u32,
    /// ...PortStatusRT2.
    pub rt_class2: RtClass2Status,
    /// ...PortStatusRT3.
    pub rt_class3: RtClass3Status,
    /// ...PortNoS: the NameOfStation (of this station, or of the neighbour).
    pub name_of_station: String,
}

/// lldpStatistics.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Statistics {
    /// lldpStatsRemTablesLastChangeTime: sysUpTime (hundredths of a second) of the last
    /// change of the neighbour tables.
    pub rem_tables_last_change: u32,
    /// lldpStatsRemTablesInserts.
    pub rem_tables_inserts: u32,
    /// lldpStatsRemTablesDeletes.
    pub rem_tables_deletes: u32,
    /// lldpStatsRemTablesDrops.
    pub rem_tables_drops: u32,
    /// lldpStatsRemTablesAgeouts.
    pub rem_tables_ageouts: u32,
    /// lldpStatsTxPortTable and lldpStatsRxPortTable, one row per port.
    pub ports: Vec<PortStatistics>,
}

/// A port's LLDP counters.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PortStatistics {
    /// The port number (lldpStatsTxPortNum, lldpStatsRxPortNum).
    pub num: u32,
    /// lldpStatsTxPortFramesTotal.
    pub tx_frames: u32,
    /// lldpStatsRxPortFramesDiscardedTotal.
    pub rx_frames_discarded: u32,
    /// lldpStatsRxPortFramesErrors.
    pub rx_frames_errors: u32,
    /// lldpStatsRxPortFramesTotal.
    pub rx_frames: u32,
    /// lldpStatsRxPortTLVsDiscardedTotal.
    pub rx_tlvs_discarded: u32,
    /// lldpStatsRxPortTLVsUnrecognizedTotal.
    pub rx_tlvs_unrecognized: u32,
    /// lldpStatsRxPortAgeoutsTotal.
    pub rx_ageouts: u32,
}
