// SPDX-License-Identifier: MIT OR Apache-2.0
//! The examples are blocks Wireshark 4.0 decodes without an expert item (checked with
//! tshark on read responses that carry them); the round trips cover the rest.

use super::*;
use proptest::prelude::*;

fn hex(s: &str) -> Vec<u8> {
    s.split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).unwrap())
        .collect()
}

#[test]
fn pd_interface_data_real_pads_the_name_to_four_bytes() {
    let b = PdInterfaceDataReal {
        chassis_id: "dev-1".into(),
        mac: MacAddress([0x02, 0, 0, 0, 0, 0x02]),
        ip: [192, 168, 0, 2],
        mask: [255, 255, 255, 0],
        gateway: [0; 4],
    };
    let want = hex(
        "02 40 00 1c 01 00 05 64 65 76 2d 31 02 00 00 00 00 02 00 00 \
         c0 a8 00 02 ff ff ff 00 00 00 00 00",
    );
    assert_eq!(b.to_vec().unwrap(), want);
    assert_eq!(PdInterfaceDataReal::parse(&want).unwrap(), b);
}

#[test]
fn pd_port_data_real_with_one_peer() {
    let b = PdPortDataReal {
        slot: 0,
        subslot: 0x8001,
        own_port_id: "port-001".into(),
        peers: vec![PeerReal {
            port_id: "port-002".into(),
            chassis_id: "switch-a".into(),
            line_delay: 0,
            mac: MacAddress([0x02, 0, 0, 0, 0, 0x99]),
        }],
        mau_type: 0x0010,
        domain_boundary: 0,
        multicast_boundary: 0,
        port_state: PORT_STATE_FORWARDING,
        link: LINK_UP,
        media_type: MEDIA_COPPER,
    };
    let want = hex("02 0f 00 48 01 00 00 00 00 00 80 01 08 70 6f 72 \
         74 2d 30 30 31 01 00 00 08 70 6f 72 74 2d 30 30 \
         32 08 73 77 69 74 63 68 2d 61 00 00 00 00 00 00 \
         02 00 00 00 00 99 00 00 00 10 00 00 00 00 00 00 \
         00 00 00 00 05 01 00 00 00 00 00 01");
    assert_eq!(b.to_vec().unwrap(), want);
    assert_eq!(PdPortDataReal::parse(&want).unwrap(), b);
    let lonely = PdPortDataReal {
        peers: Vec::new(),
        own_port_id: "port-002".into(),
        ..b
    };
    assert_eq!(lonely.to_vec().unwrap().len(), 44);
}

#[test]
fn pd_port_statistic_versions() {
    let s = PdPortStatistic {
        counter_status: Some(0x000c),
        in_octets: 100,
        out_octets: 200,
        in_discards: 0,
        out_discards: 0,
        in_errors: 1,
        out_errors: 2,
    };
    let b = s.to_vec().unwrap();
    assert_eq!(&b[..8], &[0x02, 0x51, 0x00, 0x1c, 0x01, 0x01, 0x00, 0x0c]);
    assert_eq!(PdPortStatistic::parse(&b).unwrap(), s);
    let v10 = PdPortStatistic {
        counter_status: None,
        ..s
    };
    let b = v10.to_vec().unwrap();
    assert_eq!(&b[4..8], &[0x01, 0x00, 0x00, 0x00]);
    assert_eq!(PdPortStatistic::parse(&b).unwrap(), v10);
}

#[test]
fn multiple_block_header_wraps_aligned_blocks_only() {
    let inner = PdPortStatistic::default().to_vec().unwrap();
    let m = MultipleBlockHeader {
        api: 0,
        slot: 0,
        subslot: 0x8000,
        blocks: inner.clone(),
    };
    let b = m.to_vec().unwrap();
    assert_eq!(
        &b[..16],
        &hex("04 00 00 2c 01 00 00 00 00 00 00 00 00 00 80 00")
    );
    assert_eq!(MultipleBlockHeader::parse(&b).unwrap(), m);
    let odd = MultipleBlockHeader {
        blocks: vec![0; 3],
        ..m
    };
    assert!(odd.to_vec().is_err());
}

fn text(max: usize) -> impl Strategy<Value = String> {
    proptest::collection::vec(0x20u8..0x7f, 0..max).prop_map(|b| String::from_utf8(b).unwrap())
}

proptest! {
    #[test]
    fn pd_port_data_real_round_trips(
        own in text(40),
        peers in proptest::collection::vec((text(30), text(60), any::<u32>(), any::<[u8; 6]>()), 0..3),
        mau in any::<u16>(), port_state in any::<u8>(), link in any::<u8>(), media in any::<u32>(),
    ) {
        let b = PdPortDataReal {
            slot: 0,
            subslot: 0x8001,
            own_port_id: own,
            peers: peers.into_iter().map(|(p, c, d, m)| PeerReal {
                port_id: p, chassis_id: c, line_delay: d, mac: MacAddress(m),
            }).collect(),
            mau_type: mau,
            domain_boundary: 1,
            multicast_boundary: 2,
            port_state,
            link,
            media_type: media,
        };
        let v = b.to_vec().unwrap();
        prop_assert!(v.len().is_multiple_of(4));
        prop_assert_eq!(PdPortDataReal::parse(&v).unwrap(), b);
    }

    #[test]
    fn pd_interface_data_real_round_trips(name in text(240), mac in any::<[u8; 6]>(), ip in any::<[u8; 4]>()) {
        let b = PdInterfaceDataReal { chassis_id: name, mac: MacAddress(mac), ip, mask: [255, 255, 0, 0], gateway: ip };
        let v = b.to_vec().unwrap();
        prop_assert!(v.len().is_multiple_of(4));
        prop_assert_eq!(PdInterfaceDataReal::parse(&v).unwrap(), b);
    }

    #[test]
    fn the_parsers_take_any_bytes(b in proptest::collection::vec(any::<u8>(), 0..120)) {
        let _ = PdInterfaceDataReal::parse(&b);
        let _ = PdPortDataReal::parse(&b);
        let _ = PdPortStatistic::parse(&b);
        let _ = MultipleBlockHeader::parse(&b);
    }
}
