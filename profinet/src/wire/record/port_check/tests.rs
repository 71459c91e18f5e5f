// SPDX-License-Identifier: MIT OR Apache-2.0

use super::*;
use proptest::prelude::*;

#[test]
fn check_peers_with_one_peer() {
    let c = PdPortDataCheck {
        slot: 0,
        subslot: 0x8001,
        checks: vec![PortCheck::Peers(vec![CheckedPeer {
            port_id: "port-001".into(),
            chassis_id: "plc".into(),
        }])],
    };
    let b = c.to_vec().unwrap();
    let want: &[u8] = &[
        0x02, 0x00, 0x00, 0x1c, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x01, // frame
        0x02, 0x0a, 0x00, 0x10, 0x01, 0x00, 0x01, 0x08, b'p', b'o', b'r', b't', b'-', b'0', b'0',
        b'1', 0x03, b'p', b'l', b'c', // CheckPeers: 6 + 14 bytes, aligned already
    ];
    assert_eq!(b, want);
    assert_eq!(PdPortDataCheck::parse(&b).unwrap(), c);
    assert_eq!(c.peers().unwrap()[0].chassis_id, "plc");
    // A name one byte longer: three bytes of padding at the end.
    let longer = PdPortDataCheck {
        checks: vec![PortCheck::Peers(vec![CheckedPeer {
            port_id: "port-001".into(),
            chassis_id: "plc2".into(),
        }])],
        ..c
    };
    let b = longer.to_vec().unwrap();
    assert_eq!((&b[14..16], b.len()), (&[0x00, 0x14][..], 36));
    assert_eq!(&b[32..], &[b'2', 0, 0, 0]);
    assert_eq!(PdPortDataCheck::parse(&b).unwrap(), longer);
}

#[test]
fn adjust_boundaries_and_unknown_sub_blocks() {
    let a = PdPortDataAdjust {
        slot: 0,
        subslot: 0x8001,
        adjusts: vec![
            PortAdjust::PeerToPeerBoundary {
                boundary: PEER_TO_PEER_NO_LLDP,
                properties: 0,
            },
            PortAdjust::DcpBoundary {
                boundary: DCP_BOUNDARY_IDENTIFY | DCP_BOUNDARY_HELLO,
                properties: 0,
            },
            PortAdjust::DomainBoundary {
                ingress: 1,
                egress: Some(2),
                properties: 0,
            },
            PortAdjust::MauType {
                mau_type: 0x10,
                properties: 0,
            },
            PortAdjust::Other(vec![0x02, 0x26, 0x00, 0x08, 0x01, 0x00, 0, 0, 0, 0, 0, 0]),
        ],
    };
    let b = a.to_vec().unwrap();
    assert_eq!(b.len(), 12 + 16 + 16 + 20 + 12 + 12);
    assert_eq!(
        &b[12..20],
        &[0x02, 0x24, 0x00, 0x0c, 0x01, 0x00, 0x00, 0x00]
    );
    let back = PdPortDataAdjust::parse(&b).unwrap();
    assert_eq!(back, a);
    assert_eq!(back.peer_to_peer_boundary(), Some(PEER_TO_PEER_NO_LLDP));
    assert_eq!(back.dcp_boundary(), Some(3));
}

fn check() -> impl Strategy<Value = PortCheck> {
    prop_oneof![
        proptest::collection::vec(("[a-z0-9.-]{0,20}", "[a-z0-9.-]{0,40}"), 0..3).prop_map(|p| {
            PortCheck::Peers(
                p.into_iter()
                    .map(|(port_id, chassis_id)| CheckedPeer {
                        port_id,
                        chassis_id,
                    })
                    .collect(),
            )
        }),
        any::<u32>().prop_map(PortCheck::LineDelay),
        any::<u16>().prop_map(PortCheck::MauType),
        any::<u16>().prop_map(PortCheck::LinkState),
        any::<u16>().prop_map(PortCheck::SyncDifference),
        any::<u16>().prop_map(PortCheck::MauTypeDifference),
    ]
}

fn adjust() -> impl Strategy<Value = PortAdjust> {
    prop_oneof![
        (
            any::<u32>(),
            proptest::option::of(any::<u32>()),
            any::<u16>()
        )
            .prop_map(|(ingress, egress, properties)| PortAdjust::DomainBoundary {
                ingress,
                egress,
                properties
            }),
        (any::<u32>(), any::<u16>()).prop_map(|(boundary, properties)| {
            PortAdjust::MulticastBoundary {
                boundary,
                properties,
            }
        }),
        (any::<u16>(), any::<u16>()).prop_map(|(mau_type, properties)| PortAdjust::MauType {
            mau_type,
            properties
        }),
        (any::<u16>(), any::<u16>())
            .prop_map(|(state, properties)| PortAdjust::LinkState { state, properties }),
        (any::<u32>(), any::<u16>()).prop_map(|(boundary, properties)| {
            PortAdjust::PeerToPeerBoundary {
                boundary,
                properties,
            }
        }),
        (any::<u32>(), any::<u16>()).prop_map(|(boundary, properties)| {
            PortAdjust::DcpBoundary {
                boundary,
                properties,
            }
        }),
    ]
}

proptest! {
    #[test]
    fn checks_round_trip(checks in proptest::collection::vec(check(), 0..5)) {
        let c = PdPortDataCheck { slot: 0, subslot: 0x8001, checks };
        let b = c.to_vec().unwrap();
        prop_assert!(b.len().is_multiple_of(4));
        prop_assert_eq!(PdPortDataCheck::parse(&b).unwrap(), c);
    }

    #[test]
    fn adjusts_round_trip(adjusts in proptest::collection::vec(adjust(), 0..5)) {
        let a = PdPortDataAdjust { slot: 0, subslot: 0x8002, adjusts };
        let b = a.to_vec().unwrap();
        prop_assert!(b.len().is_multiple_of(4));
        prop_assert_eq!(PdPortDataAdjust::parse(&b).unwrap(), a);
    }

    #[test]
    fn the_parsers_take_any_bytes(b in proptest::collection::vec(any::<u8>(), 0..160)) {
        let _ = PdPortDataCheck::parse(&b);
        let _ = PdPortDataAdjust::parse(&b);
        let mut framed = vec![0x02, 0x00, 0x00, (b.len() + 8).min(255) as u8, 0x01, 0x00, 0, 0, 0, 0, 0x80, 0x01];
        framed.extend_from_slice(&b);
        let _ = PdPortDataCheck::parse(&framed);
    }
}
