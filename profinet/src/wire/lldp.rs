// SPDX-License-Identifier: MIT OR Apache-2.0
//! LLDP (IEEE 802.1AB) LLDPDUs: what a PROFINET device announces on each port and what a
//! PLC's or a switch's LLDP frames carry.
//!
//! The LLDPDU is the Ethernet payload behind EtherType [`ETHERTYPE_LLDP`], sent to
//! [`MULTICAST_NEAREST_BRIDGE`]. It is a chain of TLVs, each with a 16-bit header of a 7-bit
//! type and a 9-bit length, then that many value bytes:
//!
//! ```text
//! Chassis ID(1)  Port ID(2)  TTL(3)  optional TLVs…  End(0, length 0)
//! ```
//!
//! The first three are mandatory and in this order (a receiver drops an LLDPDU without
//! them); [`Repr::parse`] refuses such a PDU. The optional TLVs it decodes are Port
//! Description, System Name, System Description, System Capabilities, Management Address,
//! the PROFINET TLVs PortStatus and ChassisMAC (OUI 00-0E-CF, IEC 61158-6-10) and the IEEE
//! 802.3 MAC/PHY Configuration/Status (OUI 00-12-0F). Every other TLV, and a known one whose
//! value does not decode, is kept as it was ([`TlvRepr::OrgSpecific`], [`TlvRepr::Unknown`]),
//! so parsing never fails on the optional part and emitting a parsed PDU gives its bytes
//! back. Parsing stops at the End TLV; the bytes after it (Ethernet padding) are ignored, and
//! a PDU that ends with the buffer without an End TLV is accepted. [`Repr::emit`] always
//! writes the End TLV.
//!
//! Everything is big-endian. LLDP is not on the real-time path, so [`Repr`] owns its values.

use super::cursor::Writer;
use super::ethernet;
use super::{EmitError, EmitResult, Error, MacAddress, Result, be16, be32};

/// EtherType of LLDP.
pub const ETHERTYPE_LLDP: u16 = 0x88cc;
/// The nearest-bridge group address 01:80:C2:00:00:0E that LLDP frames go to (no bridge
/// forwards it: an LLDP frame reaches the neighbour on the other end of the cable only).
pub const MULTICAST_NEAREST_BRIDGE: MacAddress = MacAddress([0x01, 0x80, 0xc2, 0x00, 0x00, 0x0e]);

/// The PROFIBUS & PROFINET International OUI of the PROFINET TLVs.
pub const OUI_PROFINET: [u8; 3] = [0x00, 0x0e, 0xcf];
/// The IEEE 802.3 OUI of the MAC/PHY Configuration/Status TLV.
pub const OUI_IEEE_802_3: [u8; 3] = [0x00, 0x12, 0x0f];

/// Subtypes of the PROFINET TLVs (IEC 61158-6-10). Only [`PORT_STATUS`](profinet::PORT_STATUS)
/// and [`CHASSIS_MAC`](profinet::CHASSIS_MAC) are decoded; the others are kept as
/// [`TlvRepr::OrgSpecific`].
pub mod profinet {
    /// 1: measured delay values (LLDP_PNIO_DELAY).
    pub const DELAY: u8 = 1;
    /// 2: RTClass2/RTClass3 port status (LLDP_PNIO_PORTSTATUS).
    pub const PORT_STATUS: u8 = 2;
    /// 3: alias (obsolete).
    pub const ALIAS: u8 = 3;
    /// 4: MRP port status (LLDP_PNIO_MRPPORTSTATUS).
    pub const MRP_PORT_STATUS: u8 = 4;
    /// 5: the interface's MAC address (LLDP_PNIO_CHASSIS_MAC).
    pub const CHASSIS_MAC: u8 = 5;
    /// 6: PTCP status (LLDP_PNIO_PTCPSTATUS).
    pub const PTCP_STATUS: u8 = 6;

    /// RTClass2_PortStatus / RTClass3_PortStatus: off (no RT class 2/3 on the port).
    pub const PORT_STATUS_OFF: u16 = 0x0000;
    /// RTClass2_PortStatus: RT class 2 up. RTClass3_PortStatus: RT class 3 up.
    pub const PORT_STATUS_UP: u16 = 0x0002;
    /// RTClass3_PortStatus: RT class 3 running.
    pub const RTCLASS3_RUN: u16 = 0x0004;
}

/// Subtype of the IEEE 802.3 MAC/PHY Configuration/Status TLV.
pub const IEEE_802_3_MAC_PHY: u8 = 1;

/// Longest chassis ID, port ID, port description, system name or system description.
pub const MAX_STRING_LEN: usize = 255;
/// The largest value a TLV's 9-bit length holds.
pub const MAX_TLV_LEN: usize = 0x1ff;
/// Bytes of a TLV header.
pub const TLV_HEADER_LEN: usize = 2;
/// Bytes of the OUI and subtype that start an organizationally specific TLV.
const ORG_HEADER_LEN: usize = 4;
/// Longest management address (the address string length holds its subtype too, ≤ 32).
const MAX_MGMT_ADDRESS_LEN: usize = 31;
/// Longest object identifier of a Management Address TLV.
const MAX_OID_LEN: usize = 128;

coded_enum! {
    /// The type of a TLV (7 bits on the wire).
    pub enum TlvType(u8) display "TLV {}" {
        /// 0: end of LLDPDU.
        End = 0 => "End",
        /// 1: chassis ID.
        ChassisId = 1 => "Chassis ID",
        /// 2: port ID.
        PortId = 2 => "Port ID",
        /// 3: time to live.
        Ttl = 3 => "TTL",
        /// 4: port description.
        PortDescription = 4 => "Port Description",
        /// 5: system name.
        SystemName = 5 => "System Name",
        /// 6: system description.
        SystemDescription = 6 => "System Description",
        /// 7: system capabilities.
        SystemCapabilities = 7 => "System Capabilities",
        /// 8: management address.
        ManagementAddress = 8 => "Management Address",
        /// 127: organizationally specific.
        OrganizationallySpecific = 127 => "Organizationally Specific",
    }
}

buffer_view! {
    /// A view of one TLV at the start of a buffer.
    pub struct Tlv;
}

impl<T: AsRef<[u8]>> Tlv<T> {
    /// Checks the buffer holds the header and the value bytes it announces. Bytes after
    /// them (the next TLVs) are allowed.
    pub fn check_len(&self) -> Result<()> {
        let b = self.buffer.as_ref();
        let Some(h) = b.get(..TLV_HEADER_LEN) else {
            return Err(Error);
        };
        let len = usize::from(be16(h) & 0x1ff);
        if b.len() < TLV_HEADER_LEN + len {
            Err(Error)
        } else {
            Ok(())
        }
    }

    fn header(&self) -> u16 {
        be16(&self.buffer.as_ref()[..TLV_HEADER_LEN])
    }

    /// The type (upper 7 bits of the header).
    pub fn tlv_type(&self) -> TlvType {
        // 16 - 9 = 7 bits remain after the shift: the value fits a u8.
        TlvType::from((self.header() >> 9) as u8)
    }

    /// The length of the value (lower 9 bits of the header).
    pub fn length(&self) -> u16 {
        self.header() & 0x1ff
    }

    /// Bytes of the whole TLV, header included.
    pub fn total_len(&self) -> usize {
        TLV_HEADER_LEN + usize::from(self.length())
    }
}

impl<'a, T: AsRef<[u8]> + ?Sized> Tlv<&'a T> {
    /// The value bytes (empty if the buffer is too short, never the case after
    /// `check_len`).
    pub fn value(&self) -> &'a [u8] {
        self.buffer
            .as_ref()
            .get(TLV_HEADER_LEN..self.total_len())
            .unwrap_or(&[])
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Tlv<T> {
    /// Writes the header: `tlv_type` (at most 127) and `length` (at most 511). Values out of
    /// range give [`EmitError::TooLong`]; a buffer shorter than 2 bytes
    /// [`EmitError::BufferTooShort`].
    pub fn set_header(&mut self, tlv_type: TlvType, length: usize) -> EmitResult<()> {
        let h = tlv_header(tlv_type.raw(), length)?;
        let b = self.buffer.as_mut();
        let len = b.len();
        b.get_mut(..TLV_HEADER_LEN)
            .ok_or(EmitError::BufferTooShort {
                what: "LLDP TLV header",
                needed: TLV_HEADER_LEN,
                len,
            })?
            .copy_from_slice(&h.to_be_bytes());
        Ok(())
    }

    /// The value bytes, mutable (empty if the buffer is too short).
    pub fn value_mut(&mut self) -> &mut [u8] {
        let end = self.total_len();
        self.buffer
            .as_mut()
            .get_mut(TLV_HEADER_LEN..end)
            .unwrap_or(&mut [])
    }
}

/// The header of a TLV of this type and value length.
fn tlv_header(tlv_type: u8, length: usize) -> EmitResult<u16> {
    if tlv_type > 127 {
        return Err(EmitError::TooLong {
            field: "LLDP TLV type",
            value: usize::from(tlv_type),
            max: 127,
        });
    }
    let len = u16::try_from(length)
        .ok()
        .filter(|l| usize::from(*l) <= MAX_TLV_LEN)
        .ok_or(EmitError::TooLong {
            field: "LLDP TLV length",
            value: length,
            max: MAX_TLV_LEN,
        })?;
    Ok(u16::from(tlv_type) << 9 | len)
}

buffer_view! {
    /// A view of an LLDPDU (the Ethernet payload).
    pub struct Packet;
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// Checks every TLV up to the End TLV (or the end of the buffer) lies within the buffer.
    pub fn check_len(&self) -> Result<()> {
        let mut b = self.buffer.as_ref();
        while !b.is_empty() {
            let t = Tlv::new_checked(b)?;
            if t.tlv_type() == TlvType::End {
                break;
            }
            b = b.get(t.total_len()..).unwrap_or(&[]);
        }
        Ok(())
    }
}

impl<'a, T: AsRef<[u8]> + ?Sized> Packet<&'a T> {
    /// The TLVs before the End TLV, in order. Stops at a TLV that runs past the buffer
    /// (never the case after `check_len`).
    pub fn tlvs(&self) -> Tlvs<'a> {
        Tlvs {
            rest: self.buffer.as_ref(),
        }
    }
}

/// The TLVs of an LLDPDU, up to (without) the End TLV.
#[derive(Clone, Debug)]
pub struct Tlvs<'a> {
    rest: &'a [u8],
}

impl<'a> Iterator for Tlvs<'a> {
    type Item = Tlv<&'a [u8]>;

    fn next(&mut self) -> Option<Tlv<&'a [u8]>> {
        let t = Tlv::new_checked(self.rest).ok()?;
        if t.tlv_type() == TlvType::End {
            self.rest = &[];
            return None;
        }
        self.rest = self.rest.get(t.total_len()..).unwrap_or(&[]);
        Some(t)
    }
}

/// Subtypes of the Chassis ID TLV.
pub mod chassis_subtype {
    /// 1: chassis component (entPhysicalAlias).
    pub const CHASSIS_COMPONENT: u8 = 1;
    /// 2: interface alias (ifAlias).
    pub const INTERFACE_ALIAS: u8 = 2;
    /// 3: port component (entPhysicalAlias).
    pub const PORT_COMPONENT: u8 = 3;
    /// 4: MAC address.
    pub const MAC_ADDRESS: u8 = 4;
    /// 5: network address (IANA address family byte, then the address).
    pub const NETWORK_ADDRESS: u8 = 5;
    /// 6: interface name (ifName).
    pub const INTERFACE_NAME: u8 = 6;
    /// 7: locally assigned.
    pub const LOCAL: u8 = 7;
}

/// Subtypes of the Port ID TLV.
pub mod port_subtype {
    /// 1: interface alias (ifAlias).
    pub const INTERFACE_ALIAS: u8 = 1;
    /// 2: port component (entPhysicalAlias).
    pub const PORT_COMPONENT: u8 = 2;
    /// 3: MAC address.
    pub const MAC_ADDRESS: u8 = 3;
    /// 4: network address (IANA address family byte, then the address).
    pub const NETWORK_ADDRESS: u8 = 4;
    /// 5: interface name (ifName).
    pub const INTERFACE_NAME: u8 = 5;
    /// 6: agent circuit ID.
    pub const AGENT_CIRCUIT_ID: u8 = 6;
    /// 7: locally assigned.
    pub const LOCAL: u8 = 7;
}

/// An identifier of the Chassis ID or Port ID TLV: a subtype byte and 1 to 255 bytes.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Id {
    /// A MAC address (chassis subtype 4, port subtype 3).
    MacAddress(MacAddress),
    /// Locally assigned (subtype 7), as text. A PROFINET device's NameOfStation and port
    /// name (`port-001`) are such.
    Local(String),
    /// Any other subtype, or a MAC address subtype whose value is not 6 bytes, or a locally
    /// assigned value that is not UTF-8.
    Other {
        /// The subtype.
        subtype: u8,
        /// The identifier's bytes.
        id: Vec<u8>,
    },
}

impl Id {
    /// Decodes a Chassis ID (`port` false) or Port ID (`port` true) value. Shorter than 2
    /// bytes or longer than 256 is malformed.
    fn parse(v: &[u8], port: bool) -> Result<Id> {
        let (&subtype, id) = v.split_first().ok_or(Error)?;
        if id.is_empty() || id.len() > MAX_STRING_LEN {
            return Err(Error);
        }
        let mac = if port {
            port_subtype::MAC_ADDRESS
        } else {
            chassis_subtype::MAC_ADDRESS
        };
        let text = core::str::from_utf8(id).ok();
        Ok(match (subtype, text) {
            (s, _) if s == mac && id.len() == 6 => Id::MacAddress(MacAddress::from_slice(id)),
            (chassis_subtype::LOCAL, Some(t)) => Id::Local(t.into()),
            _ => Id::Other {
                subtype,
                id: id.to_vec(),
            },
        })
    }

    /// (subtype, bytes) of the value.
    fn parts(&self, port: bool) -> (u8, &[u8]) {
        match self {
            Id::MacAddress(m) if port => (port_subtype::MAC_ADDRESS, &m.0),
            Id::MacAddress(m) => (chassis_subtype::MAC_ADDRESS, &m.0),
            Id::Local(s) => (chassis_subtype::LOCAL, s.as_bytes()),
            Id::Other { subtype, id } => (*subtype, id),
        }
    }

    /// Bytes of the value (subtype included).
    fn value_len(&self, port: bool) -> usize {
        1 + self.parts(port).1.len()
    }

    fn emit(&self, port: bool, w: &mut Writer<'_>) -> EmitResult<()> {
        let (subtype, id) = self.parts(port);
        let (tlv_type, field) = if port {
            (TlvType::PortId, "LLDP Port ID")
        } else {
            (TlvType::ChassisId, "LLDP Chassis ID")
        };
        if id.is_empty() {
            return Err(EmitError::Inconsistent(
                "an empty LLDP Chassis ID or Port ID",
            ));
        }
        if id.len() > MAX_STRING_LEN {
            return Err(EmitError::TooLong {
                field,
                value: id.len(),
                max: MAX_STRING_LEN,
            });
        }
        w.u16(tlv_header(tlv_type.raw(), 1 + id.len())?)?;
        w.u8(subtype)?;
        w.put(id)
    }

    /// The text of a locally assigned identifier.
    pub fn local(&self) -> Option<&str> {
        match self {
            Id::Local(s) => Some(s),
            _ => None,
        }
    }
}

impl core::fmt::Display for Id {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Id::MacAddress(m) => write!(f, "mac {m}"),
            Id::Local(s) => write!(f, "{s:?}"),
            Id::Other { subtype, id } => write!(f, "subtype {subtype} {id:02x?}"),
        }
    }
}

/// Bits of the System Capabilities TLV.
pub mod capability {
    /// Other.
    pub const OTHER: u16 = 0x0001;
    /// Repeater.
    pub const REPEATER: u16 = 0x0002;
    /// MAC bridge.
    pub const BRIDGE: u16 = 0x0004;
    /// WLAN access point.
    pub const WLAN_ACCESS_POINT: u16 = 0x0008;
    /// Router.
    pub const ROUTER: u16 = 0x0010;
    /// Telephone.
    pub const TELEPHONE: u16 = 0x0020;
    /// DOCSIS cable device.
    pub const DOCSIS: u16 = 0x0040;
    /// Station only (an end station: a PROFINET device with one port).
    pub const STATION_ONLY: u16 = 0x0080;
}

coded_enum! {
    /// How the Management Address TLV numbers the interface.
    pub enum InterfaceNumbering(u8) display "numbering {}" {
        /// 1: unknown.
        Unspecified = 1 => "unknown",
        /// 2: ifIndex.
        IfIndex = 2 => "ifIndex",
        /// 3: system port number.
        SystemPort = 3 => "system port number",
    }
}

/// The IANA address family of an IPv4 management address.
pub const ADDRESS_FAMILY_IPV4: u8 = 1;

/// The Management Address TLV.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ManagementAddress {
    /// IANA address family ([`ADDRESS_FAMILY_IPV4`] for IPv4).
    pub address_subtype: u8,
    /// The address, 1 to 31 bytes.
    pub address: Vec<u8>,
    /// How `interface_number` counts.
    pub interface_subtype: InterfaceNumbering,
    /// The interface the address belongs to.
    pub interface_number: u32,
    /// An object identifier (BER-encoded) of the hardware behind the address, at most 128
    /// bytes; usually empty.
    pub oid: Vec<u8>,
}

impl ManagementAddress {
    /// An IPv4 address of the interface with this ifIndex, without OID.
    pub fn ipv4(ip: [u8; 4], if_index: u32) -> ManagementAddress {
        ManagementAddress {
            address_subtype: ADDRESS_FAMILY_IPV4,
            address: ip.to_vec(),
            interface_subtype: InterfaceNumbering::IfIndex,
            interface_number: if_index,
            oid: Vec::new(),
        }
    }

    /// The address, if it is IPv4.
    pub fn as_ipv4(&self) -> Option<[u8; 4]> {
        if self.address_subtype != ADDRESS_FAMILY_IPV4 {
            return None;
        }
        self.address.as_slice().try_into().ok()
    }

    /// Decodes a value; `None` when its lengths do not add up.
    fn parse(v: &[u8]) -> Option<ManagementAddress> {
        let (&str_len, rest) = v.split_first()?;
        let addr_len = usize::from(str_len).checked_sub(1)?;
        if addr_len == 0 || addr_len > MAX_MGMT_ADDRESS_LEN {
            return None;
        }
        let (&address_subtype, rest) = rest.split_first()?;
        let (address, rest) = rest.split_at_checked(addr_len)?;
        let (&if_subtype, rest) = rest.split_first()?;
        let (number, rest) = rest.split_at_checked(4)?;
        let (&oid_len, oid) = rest.split_first()?;
        if usize::from(oid_len) != oid.len() || oid.len() > MAX_OID_LEN {
            return None;
        }
        Some(ManagementAddress {
            address_subtype,
            address: address.to_vec(),
            interface_subtype: InterfaceNumbering::from(if_subtype),
            interface_number: be32(number),
            oid: oid.to_vec(),
        })
    }

    fn value_len(&self) -> usize {
        // String length, subtype, address, numbering subtype, number, OID length, OID.
        1 + 1 + self.address.len() + 1 + 4 + 1 + self.oid.len()
    }

    fn emit(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        if self.address.is_empty() {
            return Err(EmitError::Inconsistent("an empty LLDP management address"));
        }
        if self.address.len() > MAX_MGMT_ADDRESS_LEN {
            return Err(EmitError::TooLong {
                field: "LLDP management address",
                value: self.address.len(),
                max: MAX_MGMT_ADDRESS_LEN,
            });
        }
        if self.oid.len() > MAX_OID_LEN {
            return Err(EmitError::TooLong {
                field: "LLDP management address OID",
                value: self.oid.len(),
                max: MAX_OID_LEN,
            });
        }
        w.u16(tlv_header(
            TlvType::ManagementAddress.raw(),
            self.value_len(),
        )?)?;
        // Both lengths were checked above: 1 + 31 and 128 fit a byte.
        w.u8(1 + self.address.len() as u8)?;
        w.u8(self.address_subtype)?;
        w.put(&self.address)?;
        w.u8(self.interface_subtype.raw())?;
        w.u32(self.interface_number)?;
        w.u8(self.oid.len() as u8)?;
        w.put(&self.oid)
    }
}

/// The IEEE 802.3 MAC/PHY Configuration/Status TLV: what the port negotiates and runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MacPhyStatus {
    /// Auto-negotiation support/status: [`MacPhyStatus::AUTONEG_SUPPORTED`],
    /// [`MacPhyStatus::AUTONEG_ENABLED`] (other bits reserved, kept).
    pub autoneg: u8,
    /// PMD auto-negotiation advertised capability (the `ADVERTISED_*` bits).
    pub advertised: u16,
    /// Operational MAU type (IETF RFC 4836 dot3MauType, e.g. [`MacPhyStatus::MAU_100BASE_TX_FD`]).
    pub mau_type: u16,
}

impl MacPhyStatus {
    /// Auto-negotiation supported.
    pub const AUTONEG_SUPPORTED: u8 = 0x01;
    /// Auto-negotiation enabled.
    pub const AUTONEG_ENABLED: u8 = 0x02;
    /// Advertised: 10BASE-T half duplex.
    pub const ADVERTISED_10BASE_T: u16 = 0x4000;
    /// Advertised: 10BASE-T full duplex.
    pub const ADVERTISED_10BASE_T_FD: u16 = 0x2000;
    /// Advertised: 100BASE-TX half duplex.
    pub const ADVERTISED_100BASE_TX: u16 = 0x0800;
    /// Advertised: 100BASE-TX full duplex.
    pub const ADVERTISED_100BASE_TX_FD: u16 = 0x0400;
    /// Advertised: 1000BASE-T full duplex.
    pub const ADVERTISED_1000BASE_T_FD: u16 = 0x0001;
    /// MAU type 100BASE-TX full duplex (16), what PROFINET copper ports run.
    pub const MAU_100BASE_TX_FD: u16 = 0x0010;
    /// MAU type 100BASE-FX full duplex (18).
    pub const MAU_100BASE_FX_FD: u16 = 0x0012;
    /// MAU type 1000BASE-T full duplex (30).
    pub const MAU_1000BASE_T_FD: u16 = 0x001e;

    /// A 100BASE-TX port with auto-negotiation on, advertising 10/100 half and full duplex,
    /// running 100 Mbit/s full duplex: a typical PROFINET copper port.
    pub const FAST_ETHERNET: MacPhyStatus = MacPhyStatus {
        autoneg: MacPhyStatus::AUTONEG_SUPPORTED | MacPhyStatus::AUTONEG_ENABLED,
        advertised: MacPhyStatus::ADVERTISED_10BASE_T
            | MacPhyStatus::ADVERTISED_10BASE_T_FD
            | MacPhyStatus::ADVERTISED_100BASE_TX
            | MacPhyStatus::ADVERTISED_100BASE_TX_FD,
        mau_type: MacPhyStatus::MAU_100BASE_TX_FD,
    };

    /// Bytes of the value after the OUI and subtype.
    const LEN: usize = 5;
}

/// One optional TLV (after the TTL, before the End TLV).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum TlvRepr {
    /// 4: port description, at most 255 bytes.
    PortDescription(String),
    /// 5: system name, at most 255 bytes.
    SystemName(String),
    /// 6: system description, at most 255 bytes.
    SystemDescription(String),
    /// 7: system capabilities ([`capability`] bits).
    SystemCapabilities {
        /// What the system can do.
        capabilities: u16,
        /// What of it is enabled.
        enabled: u16,
    },
    /// 8: management address.
    ManagementAddress(ManagementAddress),
    /// PROFINET PortStatus (OUI 00-0E-CF, subtype 2).
    ProfinetPortStatus {
        /// RTClass2_PortStatus ([`profinet::PORT_STATUS_OFF`], [`profinet::PORT_STATUS_UP`]).
        rtclass2: u16,
        /// RTClass3_PortStatus: bits 0–2 the state, bit 12 preamble length, bit 13
        /// fragmentation.
        rtclass3: u16,
    },
    /// PROFINET ChassisMAC (OUI 00-0E-CF, subtype 5): the interface's MAC address.
    ProfinetChassisMac(MacAddress),
    /// IEEE 802.3 MAC/PHY Configuration/Status (OUI 00-12-0F, subtype 1).
    MacPhy(MacPhyStatus),
    /// Any other organizationally specific TLV (127), or one of the above whose value has
    /// another length; at most 507 bytes of `data`.
    OrgSpecific {
        /// The organisation.
        oui: [u8; 3],
        /// Its subtype.
        subtype: u8,
        /// The bytes after the subtype.
        data: Vec<u8>,
    },
    /// Any other TLV, or a known one whose value does not decode (a text that is not UTF-8
    /// or longer than 255 bytes, lengths that do not add up, a mandatory TLV again); at
    /// most 511 bytes of `data`. Its type is never 0 (End).
    Unknown {
        /// The TLV type, 1 to 127.
        tlv_type: u8,
        /// The value bytes.
        data: Vec<u8>,
    },
}

impl TlvRepr {
    /// Decodes a TLV after the mandatory ones. Never fails: what does not decode becomes
    /// `Unknown` or `OrgSpecific`.
    fn parse(tlv_type: u8, v: &[u8]) -> TlvRepr {
        let text = |v: &[u8]| {
            core::str::from_utf8(v)
                .ok()
                .filter(|s| s.len() <= MAX_STRING_LEN)
                .map(String::from)
        };
        let decoded = match TlvType::from(tlv_type) {
            TlvType::PortDescription => text(v).map(TlvRepr::PortDescription),
            TlvType::SystemName => text(v).map(TlvRepr::SystemName),
            TlvType::SystemDescription => text(v).map(TlvRepr::SystemDescription),
            TlvType::SystemCapabilities if v.len() == 4 => Some(TlvRepr::SystemCapabilities {
                capabilities: be16(&v[0..2]),
                enabled: be16(&v[2..4]),
            }),
            TlvType::ManagementAddress => {
                ManagementAddress::parse(v).map(TlvRepr::ManagementAddress)
            }
            TlvType::OrganizationallySpecific => TlvRepr::parse_org(v),
            _ => None,
        };
        decoded.unwrap_or_else(|| TlvRepr::Unknown {
            tlv_type,
            data: v.to_vec(),
        })
    }

    /// Decodes an organizationally specific value; `None` when it has no OUI and subtype.
    fn parse_org(v: &[u8]) -> Option<TlvRepr> {
        let (head, d) = v.split_at_checked(ORG_HEADER_LEN)?;
        let oui = [head[0], head[1], head[2]];
        let subtype = head[3];
        Some(match (oui, subtype, d.len()) {
            (OUI_PROFINET, profinet::PORT_STATUS, 4) => TlvRepr::ProfinetPortStatus {
                rtclass2: be16(&d[0..2]),
                rtclass3: be16(&d[2..4]),
            },
            (OUI_PROFINET, profinet::CHASSIS_MAC, 6) => {
                TlvRepr::ProfinetChassisMac(MacAddress::from_slice(d))
            }
            (OUI_IEEE_802_3, IEEE_802_3_MAC_PHY, MacPhyStatus::LEN) => {
                TlvRepr::MacPhy(MacPhyStatus {
                    autoneg: d[0],
                    advertised: be16(&d[1..3]),
                    mau_type: be16(&d[3..5]),
                })
            }
            _ => TlvRepr::OrgSpecific {
                oui,
                subtype,
                data: d.to_vec(),
            },
        })
    }

    /// The TLV type.
    pub fn tlv_type(&self) -> TlvType {
        match self {
            TlvRepr::PortDescription(_) => TlvType::PortDescription,
            TlvRepr::SystemName(_) => TlvType::SystemName,
            TlvRepr::SystemDescription(_) => TlvType::SystemDescription,
            TlvRepr::SystemCapabilities { .. } => TlvType::SystemCapabilities,
            TlvRepr::ManagementAddress(_) => TlvType::ManagementAddress,
            TlvRepr::ProfinetPortStatus { .. }
            | TlvRepr::ProfinetChassisMac(_)
            | TlvRepr::MacPhy(_)
            | TlvRepr::OrgSpecific { .. } => TlvType::OrganizationallySpecific,
            TlvRepr::Unknown { tlv_type, .. } => TlvType::from(*tlv_type),
        }
    }

    /// Bytes of the value (without the TLV header).
    fn value_len(&self) -> usize {
        match self {
            TlvRepr::PortDescription(s)
            | TlvRepr::SystemName(s)
            | TlvRepr::SystemDescription(s) => s.len(),
            TlvRepr::SystemCapabilities { .. } => 4,
            TlvRepr::ManagementAddress(m) => m.value_len(),
            TlvRepr::ProfinetPortStatus { .. } => ORG_HEADER_LEN + 4,
            TlvRepr::ProfinetChassisMac(_) => ORG_HEADER_LEN + 6,
            TlvRepr::MacPhy(_) => ORG_HEADER_LEN + MacPhyStatus::LEN,
            TlvRepr::OrgSpecific { data, .. } => ORG_HEADER_LEN.saturating_add(data.len()),
            TlvRepr::Unknown { data, .. } => data.len(),
        }
    }

    /// Bytes of the TLV, header included.
    pub fn buffer_len(&self) -> usize {
        TLV_HEADER_LEN.saturating_add(self.value_len())
    }

    fn emit(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        let text = |w: &mut Writer<'_>, t: TlvType, field: &'static str, s: &str| {
            if s.len() > MAX_STRING_LEN {
                return Err(EmitError::TooLong {
                    field,
                    value: s.len(),
                    max: MAX_STRING_LEN,
                });
            }
            w.u16(tlv_header(t.raw(), s.len())?)?;
            w.put(s.as_bytes())
        };
        let org = |w: &mut Writer<'_>, oui: [u8; 3], subtype: u8, len: usize| {
            w.u16(tlv_header(
                TlvType::OrganizationallySpecific.raw(),
                ORG_HEADER_LEN.saturating_add(len),
            )?)?;
            w.put(&oui)?;
            w.u8(subtype)
        };
        match self {
            TlvRepr::PortDescription(s) => {
                text(w, TlvType::PortDescription, "LLDP port description", s)
            }
            TlvRepr::SystemName(s) => text(w, TlvType::SystemName, "LLDP system name", s),
            TlvRepr::SystemDescription(s) => {
                text(w, TlvType::SystemDescription, "LLDP system description", s)
            }
            TlvRepr::SystemCapabilities {
                capabilities,
                enabled,
            } => {
                w.u16(tlv_header(TlvType::SystemCapabilities.raw(), 4)?)?;
                w.u16(*capabilities)?;
                w.u16(*enabled)
            }
            TlvRepr::ManagementAddress(m) => m.emit(w),
            TlvRepr::ProfinetPortStatus { rtclass2, rtclass3 } => {
                org(w, OUI_PROFINET, profinet::PORT_STATUS, 4)?;
                w.u16(*rtclass2)?;
                w.u16(*rtclass3)
            }
            TlvRepr::ProfinetChassisMac(m) => {
                org(w, OUI_PROFINET, profinet::CHASSIS_MAC, 6)?;
                w.put(&m.0)
            }
            TlvRepr::MacPhy(s) => {
                org(w, OUI_IEEE_802_3, IEEE_802_3_MAC_PHY, MacPhyStatus::LEN)?;
                w.u8(s.autoneg)?;
                w.u16(s.advertised)?;
                w.u16(s.mau_type)
            }
            TlvRepr::OrgSpecific { oui, subtype, data } => {
                org(w, *oui, *subtype, data.len())?;
                w.put(data)
            }
            TlvRepr::Unknown { tlv_type, data } => {
                if *tlv_type == TlvType::End.raw() {
                    return Err(EmitError::Inconsistent(
                        "an LLDP TLV of type 0 (End) with a value",
                    ));
                }
                w.u16(tlv_header(*tlv_type, data.len())?)?;
                w.put(data)
            }
        }
    }
}

/// A parsed LLDPDU.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Repr {
    /// Chassis ID (mandatory, first).
    pub chassis_id: Id,
    /// Port ID (mandatory, second).
    pub port_id: Id,
    /// Time to live in seconds (mandatory, third); 0 withdraws the sender's information.
    pub ttl: u16,
    /// The optional TLVs, in order, without the End TLV.
    pub tlvs: Vec<TlvRepr>,
}

impl Repr {
    /// Parses an LLDPDU (checking its length first). Missing or malformed mandatory TLVs
    /// (Chassis ID, Port ID, TTL as the first three, identifiers of 1 to 255 bytes, a TTL of
    /// 2 bytes) give [`Error`]; optional TLVs that do not decode are kept as
    /// [`TlvRepr::Unknown`] or [`TlvRepr::OrgSpecific`].
    pub fn parse<T: AsRef<[u8]> + ?Sized>(packet: &Packet<&T>) -> Result<Repr> {
        packet.check_len()?;
        let mut tlvs = packet.tlvs();
        let mut mandatory = |t: TlvType| {
            tlvs.next()
                .filter(|tlv| tlv.tlv_type() == t)
                .map(|tlv| tlv.value())
                .ok_or(Error)
        };
        let chassis_id = Id::parse(mandatory(TlvType::ChassisId)?, false)?;
        let port_id = Id::parse(mandatory(TlvType::PortId)?, true)?;
        let ttl = match mandatory(TlvType::Ttl)? {
            v @ [_, _] => be16(v),
            _ => return Err(Error),
        };
        let tlvs = tlvs
            .map(|t| TlvRepr::parse(t.tlv_type().raw(), t.value()))
            .collect();
        Ok(Repr {
            chassis_id,
            port_id,
            ttl,
            tlvs,
        })
    }

    /// Bytes of the LLDPDU, End TLV included.
    pub fn buffer_len(&self) -> usize {
        let mandatory = 3 * TLV_HEADER_LEN
            + self.chassis_id.value_len(false)
            + self.port_id.value_len(true)
            + 2;
        self.tlvs
            .iter()
            .fold(mandatory, |n, t| n.saturating_add(t.buffer_len()))
            .saturating_add(TLV_HEADER_LEN)
    }

    /// Writes the LLDPDU into the first [`buffer_len`](Self::buffer_len) bytes of `buf`.
    /// Never panics: a short buffer, an empty identifier, a value over its length limit or
    /// an `Unknown` TLV of type 0 or above 127 give [`EmitError`], and nothing is written
    /// truncated.
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        let total = self.buffer_len();
        let len = buf.len();
        let pdu = buf.get_mut(..total).ok_or(EmitError::BufferTooShort {
            what: "LLDPDU",
            needed: total,
            len,
        })?;
        let mut w = Writer::new("LLDPDU", pdu);
        self.chassis_id.emit(false, &mut w)?;
        self.port_id.emit(true, &mut w)?;
        w.u16(tlv_header(TlvType::Ttl.raw(), 2)?)?;
        w.u16(self.ttl)?;
        self.tlvs.iter().try_for_each(|t| t.emit(&mut w))?;
        w.u16(tlv_header(TlvType::End.raw(), 0)?)?;
        w.finish()
    }

    /// The LLDPDU as a new vector of [`buffer_len`](Self::buffer_len) bytes.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b))
    }

    /// The whole Ethernet frame from `src` to [`MULTICAST_NEAREST_BRIDGE`], untagged, padded
    /// to 60 bytes (without FCS).
    pub fn frame(&self, src: MacAddress) -> EmitResult<Vec<u8>> {
        let eth = ethernet::Repr {
            dst: MULTICAST_NEAREST_BRIDGE,
            src,
            vlan: None,
            ethertype: ETHERTYPE_LLDP,
        };
        Ok(eth.frame(&self.to_vec()?, 60))
    }

    /// The text of the first System Name TLV.
    pub fn system_name(&self) -> Option<&str> {
        self.tlvs.iter().find_map(|t| match t {
            TlvRepr::SystemName(s) => Some(s.as_str()),
            _ => None,
        })
    }

    /// The first IPv4 management address.
    pub fn management_ipv4(&self) -> Option<[u8; 4]> {
        self.tlvs.iter().find_map(|t| match t {
            TlvRepr::ManagementAddress(m) => m.as_ipv4(),
            _ => None,
        })
    }

    /// The MAC address of the first PROFINET ChassisMAC TLV.
    pub fn profinet_chassis_mac(&self) -> Option<MacAddress> {
        self.tlvs.iter().find_map(|t| match t {
            TlvRepr::ProfinetChassisMac(m) => Some(*m),
            _ => None,
        })
    }

    /// The first IEEE 802.3 MAC/PHY Configuration/Status TLV.
    pub fn mac_phy(&self) -> Option<MacPhyStatus> {
        self.tlvs.iter().find_map(|t| match t {
            TlvRepr::MacPhy(s) => Some(*s),
            _ => None,
        })
    }
}

impl core::fmt::Display for Repr {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "LLDP chassis={} port={} ttl={}",
            self.chassis_id, self.port_id, self.ttl
        )?;
        for t in &self.tlvs {
            write!(f, " [{}]", t.tlv_type())?;
        }
        Ok(())
    }
}

impl<T: AsRef<[u8]>> core::fmt::Display for Packet<T> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match Repr::parse(&Packet::new_unchecked(self.buffer.as_ref())) {
            Ok(r) => write!(f, "{r}"),
            Err(_) => f.write_str("LLDP (malformed)"),
        }
    }
}

#[cfg(test)]
mod tests;
