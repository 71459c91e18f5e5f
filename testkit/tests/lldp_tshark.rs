// SPDX-License-Identifier: MIT OR Apache-2.0
//! Every LLDP frame the device's announcer sends, for stations with and without a name and
//! an address, with the longest names, in both naming modes, and the DCP Hello request,
//! must decode in Wireshark's dissectors without malformed packets or error-level expert
//! items, and tshark must read the chassis ID, port ID and TTL we meant.

use procimg_profinet::device::{Application, Device, DeviceAction, DeviceSetup};
use procimg_profinet::port::lldp::{Announcer, LldpStation, NameOfDeviceMode};
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::lldp::{
    self, Id, MacPhyStatus, ManagementAddress, TlvRepr, capability,
};
use procimg_testkit::tshark::clean_fields;

const MAC: MacAddress = MacAddress([0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8]);
const PORT_MAC: MacAddress = MacAddress([0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf9]);
const IP: [u8; 4] = [172, 16, 2, 10];

/// The fields compared, in this order.
const FIELDS: [&str; 9] = [
    "_ws.col.Protocol",
    "lldp.chassis.subtype",
    "lldp.chassis.id",
    "lldp.chassis.id.mac",
    "lldp.port.subtype",
    "lldp.port.id",
    "lldp.time_to_live",
    "lldp.mgn.addr.ip4",
    "lldp.ieee.802_3.pmd_mau_type",
];

/// A NameOfStation of 240 characters: four labels of 59 and dots.
fn longest_name() -> String {
    let n = ["a", "b", "c", "d"].map(|c| format!("{c}{}", "x".repeat(58)));
    let name = n.join(".");
    assert_eq!(name.len(), 239);
    format!("{name}0")
}

/// The stations announced: named, unnamed, with the longest name, with and without an
/// address, in both naming modes, on several ports, and one on a gigabit link.
fn stations() -> Vec<LldpStation> {
    let long = longest_name();
    let mut all = Vec::new();
    for mode in [
        NameOfDeviceMode::PortName,
        NameOfDeviceMode::PortAndStationName,
    ] {
        for (name, ip, port) in [
            ("rt-labs-dev", Some(IP), 1),
            ("rt-labs-dev", None, 2),
            ("", None, 1),
            ("", Some(IP), 3),
            (long.as_str(), Some(IP), 1),
            (long.as_str(), None, 255),
        ] {
            let mut s = LldpStation::new(name, MAC, PORT_MAC, ip, port);
            s.mode = mode;
            s.if_index = 7;
            s.system_identification = procimg_profinet::port::lldp::system_identification(
                "procimg simulated device",
                &Default::default(),
            );
            all.push(s);
        }
    }
    // Gigabit, no auto-negotiation.
    let mut g = LldpStation::new("gige", MAC, PORT_MAC, Some(IP), 1);
    g.link = MacPhyStatus {
        autoneg: 0,
        advertised: 0,
        mau_type: MacPhyStatus::MAU_1000BASE_T_FD,
    };
    all.push(g);
    all
}

/// How tshark shows a locally assigned chassis ID (a byte field): hex without separators.
/// The port ID is a string field, shown as text.
fn hex(s: &str) -> String {
    s.bytes().map(|b| format!("{b:02x}")).collect()
}

#[test]
fn announcements_decode_in_tshark() {
    let stations = stations();
    let frames: Vec<Vec<u8>> = stations
        .iter()
        .map(|s| Announcer::new(s.clone()).poll(0).expect("an announcement"))
        .collect();
    let read = clean_fields("lldp-announcements", &frames, &FIELDS);
    for (s, got) in stations.iter().zip(&read) {
        let (chassis_subtype, chassis, chassis_mac) = match s.chassis_id() {
            Id::Local(t) => ("7", hex(&t), String::new()),
            Id::MacAddress(m) => ("4", String::new(), m.to_string()),
            other => panic!("unexpected chassis ID {other}"),
        };
        let Id::Local(port) = s.port_id() else {
            panic!("a locally assigned port ID");
        };
        let ip =
            s.ip.map(|a| format!("{}.{}.{}.{}", a[0], a[1], a[2], a[3]))
                .unwrap_or_default();
        let expected = [
            "LLDP".to_string(),
            chassis_subtype.into(),
            chassis,
            chassis_mac,
            "7".into(),
            port,
            "20".into(),
            ip,
            format!("{:#06x}", s.link.mau_type),
        ];
        assert_eq!(got[..], expected[..], "{s:?}");
    }
}

/// An LLDPDU with every TLV the codec decodes, as a PLC or a switch sends them, and some it
/// keeps raw.
#[test]
fn every_tlv_of_the_codec_decodes_in_tshark() {
    let r = lldp::Repr {
        chassis_id: Id::MacAddress(MAC),
        port_id: Id::MacAddress(PORT_MAC),
        ttl: 120,
        tlvs: vec![
            TlvRepr::PortDescription("Siemens, SIMATIC S7, CPU 1515, port 1".into()),
            TlvRepr::SystemName("plc1".into()),
            TlvRepr::SystemDescription("SIMATIC S7-1500".into()),
            TlvRepr::SystemCapabilities {
                capabilities: capability::BRIDGE | capability::STATION_ONLY,
                enabled: capability::STATION_ONLY,
            },
            TlvRepr::ManagementAddress(ManagementAddress::ipv4(IP, 1)),
            TlvRepr::ProfinetPortStatus {
                rtclass2: lldp::profinet::PORT_STATUS_UP,
                rtclass3: lldp::profinet::PORT_STATUS_OFF,
            },
            TlvRepr::ProfinetChassisMac(MAC),
            TlvRepr::MacPhy(MacPhyStatus::FAST_ETHERNET),
            // PROFINET measured delays: five u32 of zero (not measured).
            TlvRepr::OrgSpecific {
                oui: lldp::OUI_PROFINET,
                subtype: lldp::profinet::DELAY,
                data: vec![0; 20],
            },
        ],
    };
    let frame = r.frame(PORT_MAC).unwrap();
    let read = clean_fields(
        "lldp-codec",
        &[frame],
        &[
            "lldp.chassis.id.mac",
            "lldp.port.id.mac",
            "lldp.time_to_live",
            "lldp.tlv.system.name",
            "lldp.tlv.system.desc",
            "lldp.mgn.addr.ip4",
            "lldp.profinet.rtc2_port_status",
            "lldp.ieee.802_3.pmd_mau_type",
        ],
    );
    assert_eq!(
        read[0],
        [
            MAC.to_string(),
            PORT_MAC.to_string(),
            "120".into(),
            "plc1".into(),
            "SIMATIC S7-1500".into(),
            "172.16.2.10".into(),
            "0x0002".into(),
            "0x0010".into(),
        ]
    );
}

/// An application that leaves the inputs alone.
struct Idle;

impl Application for Idle {
    fn fill_inputs(&mut self, _: u64, _: &mut [u8], _: &[u8], _: &[u8], _: bool) {}
}

/// What a device puts on the link at start-up with LLDP and Hello on: the Hello request and
/// the first announcement.
#[test]
fn a_devices_start_up_decodes_in_tshark() {
    let mut frames = Vec::new();
    for (name, ip) in [
        ("rt-labs-dev", Some(IP)),
        ("", None),
        (longest_name().as_str(), Some(IP)),
    ] {
        let mut dev = Device::new(DeviceSetup {
            name: name.into(),
            mac: MAC,
            ip,
            vendor_id: 0x0493,
            device_id: 0x0002,
            instance: 1,
            submodules: Vec::new(),
            application: Idle,
            im0: Default::default(),
        });
        dev.station_mut().set_hello(true);
        let mut out = Vec::new();
        dev.poll(0, &mut out);
        assert_eq!(out.len(), 2, "the Hello and the announcement");
        frames.extend(out.into_iter().map(|a| match a {
            DeviceAction::Frame(f) => f,
            other => panic!("only frames at start-up: {other:?}"),
        }));
    }
    let read = clean_fields(
        "device-start-up",
        &frames,
        &[
            "_ws.col.Protocol",
            "pn_dcp.service_id",
            "pn_dcp.suboption_device_nameofstation",
            "pn_dcp.deviceinitiative_value",
            "lldp.port.id",
        ],
    );
    let protocols: Vec<&str> = read.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(
        protocols,
        ["PN-DCP", "LLDP", "PN-DCP", "LLDP", "PN-DCP", "LLDP"]
    );
    assert_eq!(read[0][1..4], ["6", "rt-labs-dev", "1"]);
    assert_eq!(read[1][4], "port-001");
    assert_eq!(read[4][2], longest_name());
}
