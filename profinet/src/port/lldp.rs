// SPDX-License-Identifier: MIT OR Apache-2.0
//! The LLDP announcer of a station's port (a device's or a controller's), sans-IO: what the
//! port tells its neighbour about the station, every 5 s and at once when the station's
//! name, address or naming mode changed.
//!
//! A PROFINET IO device sends per port (IEC 61158-6-10, LLDP as used by PROFINET):
//!
//! ```text
//! Chassis ID  Port ID  TTL 20 s  PROFINET PortStatus  PROFINET ChassisMAC  IEEE 802.3 MAC/PHY
//! [Management Address: IPv4, ifIndex]  End
//! ```
//!
//! in the order p-net sends them, from the port's MAC address to 01:80:C2:00:00:0E. The TTL
//! of 20 s with a 5 s interval is IEC 61158-6-10's (p-net cites 6.3.13.2.2), so a neighbour
//! forgets the port 20 s after its last frame. The Management Address goes out only when
//! the station has an IP address.
//!
//! Where the name goes depends on PDInterfaceAdjust's MultipleInterfaceMode.NameOfDevice
//! ([`NameOfDeviceMode`]), which the controller may write:
//!
//! - 0, the default (Wireshark's PNIO dissector, after IEC 61158-6-10: "PortID of LLDP
//!   contains name of port (Default)"): Chassis ID = NameOfStation, locally assigned, or the
//!   MAC address (subtype 4) while the station has no name; Port ID = the port name
//!   `port-001`, locally assigned. p-net's "legacy" mode sends the same.
//! - 1 ("PortID of LLDP contains name of port and NameOfStation"; the S7-1515 of our
//!   captures writes it in its PDInterfaceAdjust): Port ID = `port-001.<NameOfStation>`
//!   (`port-001.<MAC as 8C-F3-19-CD-19-F8>` without a name, p-net citing PROFINET 2.4
//!   table 335 "LLDP substitutions"); Chassis ID = the SystemIdentification text (the
//!   sysDescr layout of DeviceType, OrderID, serial number, hardware and software
//!   revision), as p-net's "standard" mode sends, or the MAC address when there is none.

use crate::wire::lldp::{self, Id, MacPhyStatus, ManagementAddress, TlvRepr};
use crate::wire::record::Im0;
use crate::wire::{BlockHeader, MacAddress};

/// How often a port announces itself: every 5 s.
pub const TX_INTERVAL_NS: u64 = 5_000_000_000;
/// How long a neighbour keeps what a port announced: 20 s.
pub const TTL_SECONDS: u16 = 20;

/// Where a device's name goes in its LLDP frames: PDInterfaceAdjust's
/// MultipleInterfaceMode.NameOfDevice (bit 0).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum NameOfDeviceMode {
    /// 0, the default: Chassis ID = NameOfStation, Port ID = `port-001`.
    #[default]
    PortName,
    /// 1: Chassis ID = SystemIdentification, Port ID = `port-001.<NameOfStation>`.
    PortAndStationName,
}

impl NameOfDeviceMode {
    /// The mode of a MultipleInterfaceMode value.
    pub const fn from_multiple_interface_mode(v: u32) -> NameOfDeviceMode {
        if v & 1 == 0 {
            NameOfDeviceMode::PortName
        } else {
            NameOfDeviceMode::PortAndStationName
        }
    }
}

/// Record index of PDInterfaceAdjust, written to the interface submodule.
pub const INDEX_PD_INTERFACE_ADJUST: u16 = 0x8071;
/// Block type of PDInterfaceAdjust.
const BLOCK_PD_INTERFACE_ADJUST: u16 = 0x0250;

/// The naming mode a PDInterfaceAdjust record sets: its block (type 0x0250, version 1.0),
/// two padding bytes and MultipleInterfaceMode (u32). `None` for anything else.
pub fn name_of_device_mode(record: &[u8]) -> Option<NameOfDeviceMode> {
    let h = BlockHeader::parse(record).ok()?;
    if h.block_type.raw() != BLOCK_PD_INTERFACE_ADJUST || (h.version_high, h.version_low) != (1, 0)
    {
        return None;
    }
    match h.body(record) {
        [_, _, a, b, c, d] => Some(NameOfDeviceMode::from_multiple_interface_mode(
            u32::from_be_bytes([*a, *b, *c, *d]),
        )),
        _ => None,
    }
}

/// What a port announces about its station.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LldpStation {
    /// NameOfStation (empty when none is set).
    pub name: String,
    /// The interface's MAC address (the ChassisMAC TLV, and the Chassis ID without a name).
    pub mac: MacAddress,
    /// The port's MAC address: the source of the frames.
    pub port_mac: MacAddress,
    /// The IP address; `None` (or 0.0.0.0) sends no Management Address.
    pub ip: Option<[u8; 4]>,
    /// The port number, 1 for `port-001`.
    pub port: u8,
    /// The interface number of the Management Address (the ifIndex of the interface); 1
    /// unless told otherwise.
    pub if_index: u32,
    /// The port's link, for the IEEE 802.3 MAC/PHY TLV; 100BASE-TX full duplex with
    /// auto-negotiation unless told otherwise.
    pub link: MacPhyStatus,
    /// Where the name goes.
    pub mode: NameOfDeviceMode,
    /// The SystemIdentification text, the Chassis ID in
    /// [`NameOfDeviceMode::PortAndStationName`] (see [`system_identification`]).
    pub system_identification: String,
}

impl LldpStation {
    /// A station with one port (`port`, usually 1) whose frames come from `port_mac`; ifIndex
    /// 1, a 100BASE-TX link, the default naming mode, no SystemIdentification.
    pub fn new(
        name: &str,
        mac: MacAddress,
        port_mac: MacAddress,
        ip: Option<[u8; 4]>,
        port: u8,
    ) -> LldpStation {
        LldpStation {
            name: name.into(),
            mac,
            port_mac,
            ip,
            port,
            if_index: 1,
            link: MacPhyStatus::FAST_ETHERNET,
            mode: NameOfDeviceMode::PortName,
            system_identification: String::new(),
        }
    }

    /// The port's name: `port-001` for port 1.
    pub fn port_name(&self) -> String {
        format!("port-{:03}", self.port)
    }

    /// The IP address, if one is set (0.0.0.0 is none).
    fn ip(&self) -> Option<[u8; 4]> {
        self.ip.filter(|ip| *ip != [0; 4])
    }

    /// `text` as a locally assigned identifier, or the MAC address when `text` is empty or
    /// too long for the TLV.
    fn local_or_mac(&self, text: &str) -> Id {
        if text.is_empty() || text.len() > lldp::MAX_STRING_LEN {
            Id::MacAddress(self.mac)
        } else {
            Id::Local(text.into())
        }
    }

    /// The Chassis ID.
    pub fn chassis_id(&self) -> Id {
        match self.mode {
            NameOfDeviceMode::PortName => self.local_or_mac(&self.name),
            NameOfDeviceMode::PortAndStationName => self.local_or_mac(&self.system_identification),
        }
    }

    /// The Port ID.
    pub fn port_id(&self) -> Id {
        let port = self.port_name();
        match self.mode {
            NameOfDeviceMode::PortName => Id::Local(port),
            NameOfDeviceMode::PortAndStationName => {
                let named = format!("{port}.{}", self.name);
                if !self.name.is_empty() && named.len() <= lldp::MAX_STRING_LEN {
                    Id::Local(named)
                } else {
                    let m = self.mac.0;
                    Id::Local(format!(
                        "{port}.{:02X}-{:02X}-{:02X}-{:02X}-{:02X}-{:02X}",
                        m[0], m[1], m[2], m[3], m[4], m[5]
                    ))
                }
            }
        }
    }

    /// The LLDPDU of an announcement.
    pub fn repr(&self) -> lldp::Repr {
        let mut tlvs = vec![
            TlvRepr::ProfinetPortStatus {
                rtclass2: lldp::profinet::PORT_STATUS_OFF,
                rtclass3: lldp::profinet::PORT_STATUS_OFF,
            },
            TlvRepr::ProfinetChassisMac(self.mac),
            TlvRepr::MacPhy(self.link),
        ];
        if let Some(ip) = self.ip() {
            tlvs.push(TlvRepr::ManagementAddress(ManagementAddress::ipv4(
                ip,
                self.if_index,
            )));
        }
        lldp::Repr {
            chassis_id: self.chassis_id(),
            port_id: self.port_id(),
            ttl: TTL_SECONDS,
            tlvs,
        }
    }

    /// The Ethernet frame of an announcement (at least 60 bytes). `None` only if the
    /// LLDPDU does not encode, which the identifiers above rule out.
    pub fn frame(&self) -> Option<Vec<u8>> {
        self.repr().frame(self.port_mac).ok()
    }
}

/// The SystemIdentification of a device: DeviceType (25 characters), OrderID (20), serial
/// number (16), hardware revision (5 digits) and software revision (prefix and 3 × 3
/// digits), each left-aligned or right-aligned in its width and separated by a blank, as
/// IEC 61158-6-10 lays out sysDescr and p-net sends it.
/// Control characters (the NULs of an unset I&M0 field) become blanks.
pub fn system_identification(device_type: &str, im0: &Im0) -> String {
    let printable = |c: char| if c.is_control() { ' ' } else { c };
    let text = |b: &[u8], n: usize| {
        let s: String = String::from_utf8_lossy(b)
            .chars()
            .map(printable)
            .take(n)
            .collect();
        format!("{:<n$}", s.trim_end())
    };
    let sw = &im0.software_revision;
    format!(
        "{} {} {} {:>5} {}{:>3}{:>3}{:>3}",
        text(device_type.as_bytes(), 25),
        text(&im0.order_id, 20),
        text(&im0.serial_number, 16),
        im0.hardware_revision,
        printable(char::from(sw.prefix)),
        sw.functional_enhancement,
        sw.bug_fix,
        sw.internal_change,
    )
}

/// Sends a port's announcements: the first at the first [`poll`](Self::poll), then every
/// [`TX_INTERVAL_NS`], and at once after a change of what it announces.
#[derive(Clone, Debug)]
pub struct Announcer {
    station: LldpStation,
    /// When the next announcement is due; 0 = at the next poll.
    due_ns: u64,
}

impl Announcer {
    /// An announcer whose first announcement is due at once.
    pub fn new(station: LldpStation) -> Announcer {
        Announcer { station, due_ns: 0 }
    }

    /// What it announces.
    pub fn station(&self) -> &LldpStation {
        &self.station
    }

    /// Changes what it announces; announces at once if that changed anything.
    pub fn update(&mut self, change: impl FnOnce(&mut LldpStation)) {
        let before = self.station.clone();
        change(&mut self.station);
        if self.station != before {
            self.announce_now();
        }
    }

    /// A new NameOfStation (empty for none); announces at once if it differs.
    pub fn set_name(&mut self, name: &str) {
        if self.station.name != name {
            self.update(|s| s.name = name.into());
        }
    }

    /// A new IP address (`None` for none); announces at once if it differs.
    pub fn set_ip(&mut self, ip: Option<[u8; 4]>) {
        self.update(|s| s.ip = ip);
    }

    /// Where the name goes; announces at once if it differs.
    pub fn set_mode(&mut self, mode: NameOfDeviceMode) {
        self.update(|s| s.mode = mode);
    }

    /// Makes the next [`poll`](Self::poll) announce.
    pub fn announce_now(&mut self) {
        self.due_ns = 0;
    }

    /// The announcement frame when one is due at `now_ns`; the next is then due
    /// [`TX_INTERVAL_NS`] later.
    pub fn poll(&mut self, now_ns: u64) -> Option<Vec<u8>> {
        if now_ns < self.due_ns {
            return None;
        }
        self.due_ns = now_ns.saturating_add(TX_INTERVAL_NS);
        self.station.frame()
    }

    /// When the next announcement is due (0: at the next poll).
    pub fn next_deadline_ns(&self) -> u64 {
        self.due_ns
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::ethernet;
    use crate::wire::record::SoftwareRevision;

    const MAC: MacAddress = MacAddress([0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8]);
    const S: u64 = 1_000_000_000;

    fn station() -> LldpStation {
        LldpStation::new("rt-labs-dev", MAC, MAC, Some([172, 16, 2, 10]), 1)
    }

    /// The announcement of `station()`, computed by hand from the TLV layouts.
    #[rustfmt::skip]
    static ANNOUNCEMENT: [u8; 92] = [
        // Ethernet: to 01:80:C2:00:00:0E from the port, EtherType 0x88CC.
        0x01, 0x80, 0xc2, 0x00, 0x00, 0x0e, 0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8, 0x88, 0xcc,
        // Chassis ID (type 1 << 9 | 12): locally assigned "rt-labs-dev".
        0x02, 0x0c, 0x07, b'r', b't', b'-', b'l', b'a', b'b', b's', b'-', b'd', b'e', b'v',
        // Port ID (2 << 9 | 9): locally assigned "port-001".
        0x04, 0x09, 0x07, b'p', b'o', b'r', b't', b'-', b'0', b'0', b'1',
        // TTL (3 << 9 | 2): 20 s.
        0x06, 0x02, 0x00, 0x14,
        // PROFINET PortStatus (127 << 9 | 8): OUI 00-0E-CF, subtype 2, RTClass2/3 off.
        0xfe, 0x08, 0x00, 0x0e, 0xcf, 0x02, 0x00, 0x00, 0x00, 0x00,
        // PROFINET ChassisMAC (127 << 9 | 10): subtype 5, the interface MAC.
        0xfe, 0x0a, 0x00, 0x0e, 0xcf, 0x05, 0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8,
        // IEEE 802.3 MAC/PHY (127 << 9 | 9): OUI 00-12-0F, subtype 1, autoneg supported and
        // enabled, advertised 10BASE-T HD/FD + 100BASE-TX HD/FD, MAU 16 (100BASE-TX FD).
        0xfe, 0x09, 0x00, 0x12, 0x0f, 0x01, 0x03, 0x6c, 0x00, 0x00, 0x10,
        // Management Address (8 << 9 | 12): string length 5, IPv4 172.16.2.10, ifIndex 1,
        // no OID.
        0x10, 0x0c, 0x05, 0x01, 0xac, 0x10, 0x02, 0x0a, 0x02, 0x00, 0x00, 0x00, 0x01, 0x00,
        // End.
        0x00, 0x00,
    ];

    #[test]
    fn one_announcement_byte_for_byte() {
        assert_eq!(station().frame().unwrap(), ANNOUNCEMENT);
    }

    #[test]
    fn the_announcement_parses_back() {
        let eth = ethernet::Frame::new_checked(&ANNOUNCEMENT[..]).unwrap();
        assert_eq!(eth.ethertype(), lldp::ETHERTYPE_LLDP);
        assert_eq!(eth.dst(), lldp::MULTICAST_NEAREST_BRIDGE);
        let r = lldp::Repr::parse(&lldp::Packet::new_checked(eth.payload()).unwrap()).unwrap();
        assert_eq!(r, station().repr());
        assert_eq!(r.chassis_id, Id::Local("rt-labs-dev".into()));
        assert_eq!(r.port_id, Id::Local("port-001".into()));
        assert_eq!(r.ttl, 20);
        assert_eq!(r.management_ipv4(), Some([172, 16, 2, 10]));
        assert_eq!(r.profinet_chassis_mac(), Some(MAC));
        assert_eq!(r.mac_phy(), Some(MacPhyStatus::FAST_ETHERNET));
    }

    #[test]
    fn without_name_or_address() {
        let s = LldpStation::new("", MAC, MacAddress([2, 0, 0, 0, 0, 1]), None, 2);
        let f = s.frame().unwrap();
        assert_eq!(
            f.len(),
            14 + 9 + 11 + 4 + 10 + 12 + 11 + 2,
            "no management address"
        );
        assert_eq!(&f[6..12], &[2, 0, 0, 0, 0, 1], "from the port's MAC");
        let eth = ethernet::Frame::new_checked(&f[..]).unwrap();
        let r = lldp::Repr::parse(&lldp::Packet::new_checked(eth.payload()).unwrap()).unwrap();
        assert_eq!(r.chassis_id, Id::MacAddress(MAC));
        assert_eq!(r.port_id, Id::Local("port-002".into()));
        assert_eq!(r.management_ipv4(), None);
        // 0.0.0.0 is no address either.
        let s = LldpStation {
            ip: Some([0; 4]),
            ..s
        };
        assert_eq!(s.repr().management_ipv4(), None);
    }

    #[test]
    fn name_of_device_modes() {
        let mut s = station();
        s.mode = NameOfDeviceMode::PortAndStationName;
        assert_eq!(s.port_id(), Id::Local("port-001.rt-labs-dev".into()));
        assert_eq!(
            s.chassis_id(),
            Id::MacAddress(MAC),
            "no SystemIdentification"
        );
        s.system_identification = "sysid".into();
        assert_eq!(s.chassis_id(), Id::Local("sysid".into()));
        s.name.clear();
        assert_eq!(s.port_id(), Id::Local("port-001.8C-F3-19-CD-19-F8".into()));
        // The longest name fits the port ID.
        s.name = "a".repeat(240);
        assert_eq!(s.port_id(), Id::Local(format!("port-001.{}", s.name)));
        assert!(s.frame().is_some());
        assert_eq!(
            NameOfDeviceMode::from_multiple_interface_mode(1),
            NameOfDeviceMode::PortAndStationName
        );
        assert_eq!(
            NameOfDeviceMode::from_multiple_interface_mode(0xfffe),
            NameOfDeviceMode::PortName
        );
    }

    #[test]
    fn pd_interface_adjust() {
        // The S7-1515's PDInterfaceAdjust of the captures (cm/write_req).
        let s7 = [0x02, 0x50, 0x00, 0x08, 0x01, 0x00, 0, 0, 0, 0, 0, 1];
        assert_eq!(
            name_of_device_mode(&s7),
            Some(NameOfDeviceMode::PortAndStationName)
        );
        let mut zero = s7;
        zero[11] = 0;
        assert_eq!(name_of_device_mode(&zero), Some(NameOfDeviceMode::PortName));
        let mut other = s7;
        other[1] = 0x51;
        assert_eq!(name_of_device_mode(&other), None);
        assert_eq!(name_of_device_mode(&s7[..11]), None);
    }

    #[test]
    fn system_identification_layout() {
        let im0 = Im0 {
            vendor_id: 0x0493,
            order_id: *b"12345 Abcdefghijk   ",
            serial_number: *b"007             ",
            hardware_revision: 3,
            software_revision: SoftwareRevision {
                prefix: b'V',
                functional_enhancement: 0,
                bug_fix: 2,
                internal_change: 0,
            },
            revision_counter: 0,
            profile_id: 0,
            profile_specific_type: 0,
            im_version: (1, 1),
            im_supported: 0,
        };
        let s = system_identification("P-Net Sample Application", &im0);
        assert_eq!(
            s,
            "P-Net Sample Application  12345 Abcdefghijk    007                  3 V  0  2  0"
        );
        assert_eq!(s.len(), 25 + 1 + 20 + 1 + 16 + 1 + 5 + 1 + 10);
        // An unset I&M0 (NULs) gives blanks, never a control character.
        let blank = system_identification("x", &Im0::default());
        assert_eq!(blank.len(), 80);
        assert!(blank.starts_with("x ") && blank.ends_with("    0    0  0  0"));
        assert!(!blank.chars().any(char::is_control));
    }

    #[test]
    fn every_five_seconds_and_at_once_after_a_change() {
        let mut a = Announcer::new(station());
        assert_eq!(a.next_deadline_ns(), 0);
        assert!(a.poll(7 * S).is_some(), "the first at once");
        assert_eq!(a.next_deadline_ns(), 12 * S);
        assert!(a.poll(12 * S - 1).is_none());
        assert!(a.poll(12 * S).is_some());
        assert_eq!(a.next_deadline_ns(), 17 * S);
        // The same name again changes nothing.
        a.set_name("rt-labs-dev");
        assert_eq!(a.next_deadline_ns(), 17 * S);
        a.set_name("other");
        assert_eq!(a.next_deadline_ns(), 0);
        let f = a.poll(13 * S).unwrap();
        assert!(f.windows(5).any(|w| w == b"other"));
        assert_eq!(a.next_deadline_ns(), 18 * S);
        a.set_ip(Some([172, 16, 2, 10]));
        assert_eq!(a.next_deadline_ns(), 18 * S, "same address");
        a.set_ip(None);
        assert_eq!(a.next_deadline_ns(), 0);
        a.poll(14 * S).unwrap();
        a.set_mode(NameOfDeviceMode::PortAndStationName);
        assert_eq!(a.next_deadline_ns(), 0);
        assert_eq!(a.station().mode, NameOfDeviceMode::PortAndStationName);
    }
}
