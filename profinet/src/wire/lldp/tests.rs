// SPDX-License-Identifier: MIT OR Apache-2.0
//! The LLDP codec against a hand-built LLDPDU of the kind a PLC sends, malformed PDUs, and
//! round trips.
use super::*;
use proptest::prelude::*;

const MAC: MacAddress = MacAddress([0x00, 0x1b, 0x1b, 0x12, 0x34, 0x56]);

/// An LLDPDU as a PLC port sends it, TLV by TLV (header bytes = type << 9 | length), then
/// Ethernet padding.
static PLC_PDU: &[u8] = &[
    // Chassis ID, 5: locally assigned "plc1".
    0x02, 0x05, 0x07, b'p', b'l', b'c', b'1', //
    // Port ID, 9: locally assigned "port-001".
    0x04, 0x09, 0x07, b'p', b'o', b'r', b't', b'-', b'0', b'0', b'1', //
    // TTL, 2: 20 s.
    0x06, 0x02, 0x00, 0x14, //
    // Port Description, 6.
    0x08, 0x06, b'p', b'o', b'r', b't', b' ', b'1', //
    // System Name, 4.
    0x0a, 0x04, b'p', b'l', b'c', b'1', //
    // System Description, 10.
    0x0c, 0x0a, b'S', b'I', b'M', b'A', b'T', b'I', b'C', b' ', b'S', b'7', //
    // System Capabilities, 4: bridge and station only, station only enabled.
    0x0e, 0x04, 0x00, 0x84, 0x00, 0x80, //
    // Management Address, 12: IPv4 192.168.0.1, ifIndex 1, no OID.
    0x10, 0x0c, 0x05, 0x01, 0xc0, 0xa8, 0x00, 0x01, 0x02, 0x00, 0x00, 0x00, 0x01, 0x00, //
    // PROFINET delay values (subtype 1), 24: kept as it is.
    0xfe, 0x18, 0x00, 0x0e, 0xcf, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x2a, //
    // PROFINET PortStatus, 8: RTClass2 off, RTClass3 off.
    0xfe, 0x08, 0x00, 0x0e, 0xcf, 0x02, 0x00, 0x00, 0x00, 0x00, //
    // PROFINET ChassisMAC, 10.
    0xfe, 0x0a, 0x00, 0x0e, 0xcf, 0x05, 0x00, 0x1b, 0x1b, 0x12, 0x34, 0x56, //
    // IEEE 802.3 MAC/PHY, 9: autoneg supported+enabled, 10/100 HD/FD, 100BASE-TX FD.
    0xfe, 0x09, 0x00, 0x12, 0x0f, 0x01, 0x03, 0x6c, 0x00, 0x00, 0x10, //
    // A TLV of reserved type 9, 2.
    0x12, 0x02, 0xab, 0xcd, //
    // End.
    0x00, 0x00, //
    // Ethernet padding.
    0x00, 0x00, 0x00, 0x00,
];

fn plc_repr() -> Repr {
    let mut delay = vec![0u8; 20];
    delay[19] = 0x2a;
    Repr {
        chassis_id: Id::Local("plc1".into()),
        port_id: Id::Local("port-001".into()),
        ttl: 20,
        tlvs: vec![
            TlvRepr::PortDescription("port 1".into()),
            TlvRepr::SystemName("plc1".into()),
            TlvRepr::SystemDescription("SIMATIC S7".into()),
            TlvRepr::SystemCapabilities {
                capabilities: capability::BRIDGE | capability::STATION_ONLY,
                enabled: capability::STATION_ONLY,
            },
            TlvRepr::ManagementAddress(ManagementAddress::ipv4([192, 168, 0, 1], 1)),
            TlvRepr::OrgSpecific {
                oui: OUI_PROFINET,
                subtype: profinet::DELAY,
                data: delay,
            },
            TlvRepr::ProfinetPortStatus {
                rtclass2: profinet::PORT_STATUS_OFF,
                rtclass3: profinet::PORT_STATUS_OFF,
            },
            TlvRepr::ProfinetChassisMac(MAC),
            TlvRepr::MacPhy(MacPhyStatus::FAST_ETHERNET),
            TlvRepr::Unknown {
                tlv_type: 9,
                data: vec![0xab, 0xcd],
            },
        ],
    }
}

#[test]
fn deconstruct() {
    let p = Packet::new_checked(PLC_PDU).unwrap();
    let types: Vec<u8> = p.tlvs().map(|t| t.tlv_type().raw()).collect();
    assert_eq!(types, [1, 2, 3, 4, 5, 6, 7, 8, 127, 127, 127, 127, 9]);
    let r = Repr::parse(&p).unwrap();
    assert_eq!(r, plc_repr());
    assert_eq!(r.system_name(), Some("plc1"));
    assert_eq!(r.management_ipv4(), Some([192, 168, 0, 1]));
    assert_eq!(r.profinet_chassis_mac(), Some(MAC));
    assert_eq!(r.mac_phy(), Some(MacPhyStatus::FAST_ETHERNET));
    assert_eq!(r.chassis_id.local(), Some("plc1"));
    assert_eq!(
        p.to_string(),
        "LLDP chassis=\"plc1\" port=\"port-001\" ttl=20 [Port Description] [System Name] \
         [System Description] [System Capabilities] [Management Address] \
         [Organizationally Specific] [Organizationally Specific] [Organizationally Specific] \
         [Organizationally Specific] [TLV 9]"
    );
}

#[test]
fn construct() {
    let r = plc_repr();
    let len = PLC_PDU.len() - 4;
    assert_eq!(r.buffer_len(), len);
    let mut buf = vec![0xa5u8; len];
    r.emit(&mut buf).unwrap();
    assert_eq!(&buf[..], &PLC_PDU[..len]);
    assert_eq!(
        r.emit(&mut buf[..len - 1]),
        Err(EmitError::BufferTooShort {
            what: "LLDPDU",
            needed: len,
            len: len - 1
        })
    );
    let f = r.frame(MAC).unwrap();
    assert_eq!(&f[..6], &MULTICAST_NEAREST_BRIDGE.0);
    assert_eq!(&f[6..12], &MAC.0);
    assert_eq!(&f[12..14], &[0x88, 0xcc]);
    assert_eq!(&f[14..], &PLC_PDU[..len]);
}

#[test]
fn short_frames_are_padded() {
    let r = Repr {
        chassis_id: Id::MacAddress(MAC),
        port_id: Id::Local("port-001".into()),
        ttl: 20,
        tlvs: Vec::new(),
    };
    let f = r.frame(MAC).unwrap();
    assert_eq!(f.len(), 60);
    let pdu = ethernet::Frame::new_checked(&f[..]).unwrap().payload();
    assert_eq!(
        &pdu[..11],
        &[
            0x02, 0x07, 0x04, 0x00, 0x1b, 0x1b, 0x12, 0x34, 0x56, 0x04, 0x09
        ]
    );
    assert_eq!(Repr::parse(&Packet::new_checked(pdu).unwrap()), Ok(r));
}

#[test]
fn the_mac_subtype_differs_between_chassis_and_port() {
    let r = Repr {
        chassis_id: Id::MacAddress(MAC),
        port_id: Id::MacAddress(MAC),
        ttl: 0,
        tlvs: Vec::new(),
    };
    let v = r.to_vec().unwrap();
    assert_eq!(
        (v[2], v[11]),
        (chassis_subtype::MAC_ADDRESS, port_subtype::MAC_ADDRESS)
    );
    assert_eq!(Repr::parse(&Packet::new_checked(&v[..]).unwrap()), Ok(r));
    // A port ID of subtype 4 (network address) with 6 bytes is no MAC address.
    let mut v = v;
    v[11] = port_subtype::NETWORK_ADDRESS;
    let back = Repr::parse(&Packet::new_checked(&v[..]).unwrap()).unwrap();
    assert_eq!(
        back.port_id,
        Id::Other {
            subtype: 4,
            id: MAC.0.to_vec()
        }
    );
}

#[test]
fn malformed_mandatory_tlvs_are_refused() {
    let parse = |b: &[u8]| Repr::parse(&Packet::new_unchecked(b));
    let good = &PLC_PDU[..22];
    assert!(parse(good).is_ok());
    // Every truncation inside the mandatory TLVs.
    for n in 0..22 {
        assert_eq!(parse(&good[..n]), Err(Error), "{n}");
    }
    // Out of order.
    let mut swapped = good[7..18].to_vec();
    swapped.extend_from_slice(&good[..7]);
    swapped.extend_from_slice(&good[18..]);
    assert_eq!(parse(&swapped), Err(Error));
    // An empty chassis ID (subtype only).
    assert_eq!(
        parse(&[0x02, 0x01, 0x07, 0x04, 0x02, 0x07, b'p']),
        Err(Error)
    );
    // A TTL of 3 bytes.
    let mut ttl3 = good[..18].to_vec();
    ttl3.extend_from_slice(&[0x06, 0x03, 0, 0, 20]);
    assert_eq!(parse(&ttl3), Err(Error));
    // A TLV running past the buffer.
    let mut long = good.to_vec();
    long.extend_from_slice(&[0x08, 0x10, b'x']);
    assert_eq!(parse(&long), Err(Error));
    assert!(Packet::new_checked(&long[..]).is_err());
}

#[test]
fn optional_tlvs_that_do_not_decode_are_kept() {
    let mut b = PLC_PDU[..22].to_vec();
    let odd: &[&[u8]] = &[
        // Port description that is not UTF-8.
        &[0x08, 0x02, 0xff, 0xfe],
        // System capabilities of 3 bytes.
        &[0x0e, 0x03, 0, 0, 0],
        // Management address whose string length runs past the value.
        &[0x10, 0x03, 0x09, 0x01, 0x02],
        // A second chassis ID.
        &[0x02, 0x02, 0x07, b'x'],
        // PROFINET ChassisMAC of 5 bytes.
        &[0xfe, 0x09, 0x00, 0x0e, 0xcf, 0x05, 1, 2, 3, 4, 5],
        // An organizationally specific TLV without room for its subtype.
        &[0xfe, 0x02, 0x00, 0x0e],
    ];
    for t in odd {
        b.extend_from_slice(t);
    }
    let r = Repr::parse(&Packet::new_checked(&b[..]).unwrap()).unwrap();
    assert_eq!(
        r.tlvs,
        vec![
            TlvRepr::Unknown {
                tlv_type: 4,
                data: vec![0xff, 0xfe]
            },
            TlvRepr::Unknown {
                tlv_type: 7,
                data: vec![0, 0, 0]
            },
            TlvRepr::Unknown {
                tlv_type: 8,
                data: vec![0x09, 0x01, 0x02]
            },
            TlvRepr::Unknown {
                tlv_type: 1,
                data: vec![0x07, b'x']
            },
            TlvRepr::OrgSpecific {
                oui: OUI_PROFINET,
                subtype: profinet::CHASSIS_MAC,
                data: vec![1, 2, 3, 4, 5]
            },
            TlvRepr::Unknown {
                tlv_type: 127,
                data: vec![0x00, 0x0e]
            },
        ]
    );
    // Without an End TLV, emitting adds one: the bytes come back with it.
    let mut with_end = b.clone();
    with_end.extend_from_slice(&[0, 0]);
    assert_eq!(r.to_vec().unwrap(), with_end);
}

#[test]
fn emit_refuses_what_the_wire_cannot_hold() {
    let base = Repr {
        chassis_id: Id::Local("plc1".into()),
        port_id: Id::Local("port-001".into()),
        ttl: 20,
        tlvs: Vec::new(),
    };
    let with = |f: &dyn Fn(&mut Repr)| {
        let mut r = base.clone();
        f(&mut r);
        r.to_vec()
    };
    assert!(matches!(
        with(&|r| r.chassis_id = Id::Local(String::new())),
        Err(EmitError::Inconsistent(_))
    ));
    assert_eq!(
        with(&|r| r.port_id = Id::Local("p".repeat(256))),
        Err(EmitError::TooLong {
            field: "LLDP Port ID",
            value: 256,
            max: 255
        })
    );
    assert!(with(&|r| r.chassis_id = Id::Local("c".repeat(255))).is_ok());
    assert!(matches!(
        with(&|r| r.tlvs.push(TlvRepr::SystemName("n".repeat(256)))),
        Err(EmitError::TooLong { max: 255, .. })
    ));
    assert!(matches!(
        with(&|r| r.tlvs.push(TlvRepr::Unknown {
            tlv_type: 0,
            data: vec![]
        })),
        Err(EmitError::Inconsistent(_))
    ));
    assert!(matches!(
        with(&|r| r.tlvs.push(TlvRepr::Unknown {
            tlv_type: 128,
            data: vec![]
        })),
        Err(EmitError::TooLong { max: 127, .. })
    ));
    assert!(matches!(
        with(&|r| r.tlvs.push(TlvRepr::Unknown {
            tlv_type: 9,
            data: vec![0; 512]
        })),
        Err(EmitError::TooLong { max: 511, .. })
    ));
    assert!(matches!(
        with(&|r| r.tlvs.push(TlvRepr::OrgSpecific {
            oui: [1, 2, 3],
            subtype: 1,
            data: vec![0; 508]
        })),
        Err(EmitError::TooLong { max: 511, .. })
    ));
    let mut m = ManagementAddress::ipv4([10, 0, 0, 1], 1);
    m.oid = vec![0; 129];
    assert!(matches!(
        with(&|r| r.tlvs.push(TlvRepr::ManagementAddress(m.clone()))),
        Err(EmitError::TooLong { max: 128, .. })
    ));
    m.oid.clear();
    m.address.clear();
    assert!(matches!(
        with(&|r| r.tlvs.push(TlvRepr::ManagementAddress(m.clone()))),
        Err(EmitError::Inconsistent(_))
    ));
}

#[test]
fn tlv_view_setters() {
    let mut buf = [0u8; 6];
    let mut t = Tlv::new_unchecked(&mut buf[..]);
    t.set_header(TlvType::Ttl, 2).unwrap();
    t.value_mut().copy_from_slice(&[0, 20]);
    assert_eq!(&buf[..4], &[0x06, 0x02, 0x00, 0x14]);
    let t = Tlv::new_checked(&buf[..4]).unwrap();
    assert_eq!(
        (t.tlv_type(), t.length(), t.value()),
        (TlvType::Ttl, 2, &[0, 20][..])
    );
    assert!(Tlv::new_checked(&buf[..3]).is_err());
    let mut short = [0u8; 1];
    assert!(
        Tlv::new_unchecked(&mut short[..])
            .set_header(TlvType::End, 0)
            .is_err()
    );
}

fn text(max: usize) -> impl Strategy<Value = String> {
    proptest::string::string_regex(&format!("[ -~]{{0,{max}}}")).unwrap()
}

fn id(port: bool) -> impl Strategy<Value = Id> {
    let mac = if port {
        port_subtype::MAC_ADDRESS
    } else {
        chassis_subtype::MAC_ADDRESS
    };
    prop_oneof![
        any::<[u8; 6]>().prop_map(|m| Id::MacAddress(MacAddress(m))),
        text(255)
            .prop_filter("not empty", |s| !s.is_empty())
            .prop_map(Id::Local),
        (
            any::<u8>().prop_filter("not MAC or local", move |s| *s != mac && *s != 7),
            proptest::collection::vec(any::<u8>(), 1..=255)
        )
            .prop_map(|(subtype, id)| Id::Other { subtype, id }),
        // A MAC subtype of another length, a locally assigned one that is not UTF-8.
        proptest::collection::vec(any::<u8>(), 7..=255)
            .prop_map(move |id| Id::Other { subtype: mac, id }),
        Just(Id::Other {
            subtype: 7,
            id: vec![0xff]
        }),
    ]
}

fn tlv() -> impl Strategy<Value = TlvRepr> {
    let mgmt = (
        any::<u8>(),
        proptest::collection::vec(any::<u8>(), 1..=31),
        any::<u8>(),
        any::<u32>(),
        proptest::collection::vec(any::<u8>(), 0..=128),
    )
        .prop_map(
            |(address_subtype, address, s, interface_number, oid)| ManagementAddress {
                address_subtype,
                address,
                interface_subtype: InterfaceNumbering::from(s),
                interface_number,
                oid,
            },
        );
    let known_org = |oui: [u8; 3], subtype: u8, len: usize| {
        (oui == OUI_PROFINET && subtype == profinet::PORT_STATUS && len == 4)
            || (oui == OUI_PROFINET && subtype == profinet::CHASSIS_MAC && len == 6)
            || (oui == OUI_IEEE_802_3 && subtype == IEEE_802_3_MAC_PHY && len == 5)
    };
    prop_oneof![
        text(255).prop_map(TlvRepr::PortDescription),
        text(255).prop_map(TlvRepr::SystemName),
        text(255).prop_map(TlvRepr::SystemDescription),
        any::<(u16, u16)>().prop_map(|(capabilities, enabled)| TlvRepr::SystemCapabilities {
            capabilities,
            enabled
        }),
        mgmt.prop_map(TlvRepr::ManagementAddress),
        any::<(u16, u16)>()
            .prop_map(|(rtclass2, rtclass3)| TlvRepr::ProfinetPortStatus { rtclass2, rtclass3 }),
        any::<[u8; 6]>().prop_map(|m| TlvRepr::ProfinetChassisMac(MacAddress(m))),
        any::<(u8, u16, u16)>().prop_map(|(autoneg, advertised, mau_type)| {
            TlvRepr::MacPhy(MacPhyStatus {
                autoneg,
                advertised,
                mau_type,
            })
        }),
        (
            prop_oneof![Just(OUI_PROFINET), Just(OUI_IEEE_802_3), any::<[u8; 3]>()],
            0u8..8,
            proptest::collection::vec(any::<u8>(), 0..=507)
        )
            .prop_filter("not a decoded one", move |(o, s, d)| !known_org(
                *o,
                *s,
                d.len()
            ))
            .prop_map(|(oui, subtype, data)| TlvRepr::OrgSpecific { oui, subtype, data }),
        (9u8..127, proptest::collection::vec(any::<u8>(), 0..=511))
            .prop_map(|(tlv_type, data)| TlvRepr::Unknown { tlv_type, data }),
        (1u8..4, proptest::collection::vec(any::<u8>(), 0..=40))
            .prop_map(|(tlv_type, data)| TlvRepr::Unknown { tlv_type, data }),
    ]
}

fn repr() -> impl Strategy<Value = Repr> {
    (
        id(false),
        id(true),
        any::<u16>(),
        proptest::collection::vec(tlv(), 0..6),
    )
        .prop_map(|(chassis_id, port_id, ttl, tlvs)| Repr {
            chassis_id,
            port_id,
            ttl,
            tlvs,
        })
}

proptest! {
    #[test]
    fn parse_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..1500)) {
        let p = Packet::new_unchecked(&bytes[..]);
        let _ = p.tlvs().count();
        if let Ok(r) = Repr::parse(&p) {
            // What parses emits, and parses back the same.
            let v = r.to_vec().unwrap();
            let again = Repr::parse(&Packet::new_checked(&v[..]).unwrap()).unwrap();
            prop_assert_eq!(again, r);
        }
        let _ = p.to_string();
    }

    #[test]
    fn parse_never_panics_behind_valid_mandatory_tlvs(
        tail in proptest::collection::vec(any::<u8>(), 0..600),
    ) {
        let mut bytes = PLC_PDU[..22].to_vec();
        bytes.extend_from_slice(&tail);
        let p = Packet::new_unchecked(&bytes[..]);
        if let Ok(r) = Repr::parse(&p) {
            let v = r.to_vec().unwrap();
            // The bytes come back up to the End TLV.
            prop_assert_eq!(&v[..v.len() - 2], &bytes[..v.len() - 2]);
        }
    }

    #[test]
    fn round_trip(r in repr()) {
        let bytes = r.to_vec().unwrap();
        prop_assert_eq!(bytes.len(), r.buffer_len());
        let p = Packet::new_checked(&bytes[..]).unwrap();
        prop_assert_eq!(Repr::parse(&p).unwrap(), r);
    }
}
