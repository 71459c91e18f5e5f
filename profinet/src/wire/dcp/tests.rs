// SPDX-License-Identifier: MIT OR Apache-2.0
//! The DCP codecs against captured frames of an S7-1515 and p-net, and round trips.
use super::super::ethernet::{ETHERTYPE_PROFINET, Frame};
use super::*;
use crate::test_fixtures::capture;
use proptest::prelude::*;

// The three captures come from the test data of the `pnio` crate 0.1.0
// (core-engineering/pnio-rs, MIT OR Apache-2.0): an S7-1515 talking to the p-net sample
// device. Whole frames from the Ethernet header, trailing Ethernet padding included.

/// S7 DCP Set IP (VLAN tagged, Xid 0x0300012d), 64 bytes.
const SET_REQ: &str = "cm/dcp_set_req";
/// p-net DCP Set Ok, 34 bytes.
const SET_RES: &str = "cm/dcp_set_res";
/// p-net DCP Identify response (Xid 0x0300012c), 144 bytes.
const IDENT_RES: &str = "cm/ident_ok_pnet";

/// The DCP PDU of a captured frame, Ethernet padding included.
fn pdu(frame: &[u8]) -> &[u8] {
    let f = Frame::new_checked(frame).unwrap();
    assert_eq!(f.ethertype(), ETHERTYPE_PROFINET);
    f.payload()
}

/// Parses a capture, checks that the Repr emits back to the PDU without padding.
fn round_trip_capture(frame: &[u8]) -> Repr {
    let bytes = pdu(frame);
    let packet = Packet::new_checked(bytes).unwrap();
    let repr = Repr::parse(&packet).unwrap();
    let len = HEADER_LEN + usize::from(packet.data_length());
    assert_eq!(repr.buffer_len(), len);
    let mut buf = vec![0xa5u8; len];
    repr.emit(&mut buf).unwrap();
    assert_eq!(&buf[..], &bytes[..len]);
    repr
}

#[test]
fn set_request_capture() {
    let repr = round_trip_capture(&capture(SET_REQ));
    assert_eq!(repr.frame_id, FRAME_ID_GET_SET);
    assert_eq!(repr.service_id, ServiceId::Set);
    assert_eq!(repr.service_type, ServiceType::Request);
    assert_eq!(repr.context(), BlockContext::SetRequest);
    assert_eq!(repr.xid, 0x0300_012d);
    assert_eq!(repr.response_delay, 0);
    let ip = [172, 16, 2, 10];
    let mask = [255, 255, 255, 0];
    assert_eq!(
        repr.blocks,
        vec![Block::new(
            QUALIFIER_TEMPORARY,
            BlockRepr::IpParameter {
                ip,
                mask,
                gateway: ip
            }
        )]
    );
    assert_eq!(repr, Repr::set_ip(0x0300_012d, ip, mask, ip, false));
    assert_eq!(repr.ip(), Some((ip, mask, ip)));
}

#[test]
fn set_response_capture() {
    let repr = round_trip_capture(&capture(SET_RES));
    assert_eq!(repr.frame_id, FRAME_ID_GET_SET);
    assert_eq!(repr.service_id, ServiceId::Set);
    assert_eq!(repr.service_type, ServiceType::Success);
    assert_eq!(repr.xid, 0x0300_012d);
    assert_eq!(
        repr.blocks,
        vec![Block::bare(BlockRepr::ControlResponse {
            option: 1,
            suboption: 2,
            error: block_error::OK
        })]
    );
    assert_eq!(repr.set_result().collect::<Vec<_>>(), vec![(1, 2, 0)]);
    // The pad after the last (odd) block is counted in DCPDataLength.
    assert_eq!(
        Packet::new_checked(pdu(&capture(SET_RES)))
            .unwrap()
            .data_length(),
        8
    );
}

#[test]
fn identify_response_capture() {
    let repr = round_trip_capture(&capture(IDENT_RES));
    assert_eq!(repr.frame_id, FRAME_ID_IDENTIFY_RESPONSE);
    assert_eq!(repr.service_id, ServiceId::Identify);
    assert_eq!(repr.service_type, ServiceType::Success);
    assert_eq!(repr.context(), BlockContext::Response);
    assert_eq!(repr.xid, 0x0300_012c);
    assert_eq!(repr.name_of_station(), Some("rt-labs-dev"));
    assert_eq!(repr.device_vendor(), Some("P-Net Sample Application"));
    assert_eq!(repr.device_id(), Some((0x0493, 0x0002)));
    assert_eq!(repr.ip(), Some(([0; 4], [0; 4], [0; 4])));
    assert_eq!(repr.mac(), None);
    let options = vec![
        (1, 2),
        (1, 1),
        (2, 1),
        (2, 2),
        (2, 3),
        (2, 4),
        (2, 5),
        (2, 6),
        (5, 1),
        (5, 2),
        (5, 3),
        (5, 5),
        (5, 6),
        (0xff, 0xff),
    ];
    let expected = vec![
        Block::new(
            0,
            BlockRepr::IpParameter {
                ip: [0; 4],
                mask: [0; 4],
                gateway: [0; 4],
            },
        ),
        Block::new(
            0,
            BlockRepr::DeviceVendor("P-Net Sample Application".into()),
        ),
        Block::new(0, BlockRepr::NameOfStation("rt-labs-dev".into())),
        Block::new(
            0,
            BlockRepr::DeviceId {
                vendor_id: 0x0493,
                device_id: 0x0002,
            },
        ),
        Block::new(
            0,
            BlockRepr::DeviceRole {
                role: 1,
                reserved: 1,
            },
        ),
        Block::new(0, BlockRepr::DeviceOptions(options)),
    ];
    assert_eq!(repr.blocks, expected);
}

#[test]
fn identify_by_name_s7() {
    let repr = Repr::identify_by_name(0x0300_012b, 1, "i-device");
    let mut expected = vec![
        0xfe, 0xfe, 0x05, 0x00, 0x03, 0x00, 0x01, 0x2b, 0x00, 0x01, 0x00, 0x0c, 0x02, 0x02, 0x00,
        0x08,
    ];
    expected.extend_from_slice(b"i-device");
    assert_eq!(repr.to_vec().unwrap(), expected);
    let back = Repr::parse(&Packet::new_checked(&expected[..]).unwrap()).unwrap();
    assert_eq!(back, repr);
    assert_eq!(back.context(), BlockContext::IdentifyFilter);
}

#[test]
fn constructors() {
    let all = Repr::identify_all(7, 0x80).to_vec().unwrap();
    assert_eq!(
        all,
        [
            0xfe, 0xfe, 5, 0, 0, 0, 0, 7, 0, 0x80, 0, 4, 0xff, 0xff, 0, 0
        ]
    );
    // Odd name: DCPBlockLength 2 + 3, one pad counted in DCPDataLength.
    let name = Repr::set_name(1, "abc", true).to_vec().unwrap();
    assert_eq!(
        name,
        [
            0xfe, 0xfd, 4, 0, 0, 0, 0, 1, 0, 0, 0, 10, 2, 2, 0, 5, 0, 1, b'a', b'b', b'c', 0
        ]
    );
    let signal = Repr::signal(2).to_vec().unwrap();
    assert_eq!(
        signal,
        [
            0xfe, 0xfd, 4, 0, 0, 0, 0, 2, 0, 0, 0, 8, 5, 3, 0, 4, 0, 0, 1, 0
        ]
    );
    let get = Repr::get(3, &[code::NAME_OF_STATION, code::IP_PARAMETER])
        .to_vec()
        .unwrap();
    assert_eq!(get, [0xfe, 0xfd, 3, 0, 0, 0, 0, 3, 0, 0, 0, 4, 2, 2, 1, 2]);
}

#[test]
fn factory_reset_uses_the_qualifier() {
    let r = Repr::set(9, Block::new(4, BlockRepr::ResetToFactory(4)));
    let bytes = r.to_vec().unwrap();
    assert_eq!(&bytes[HEADER_LEN..], [5, 6, 0, 2, 0, 4]);
    assert_eq!(Repr::parse(&Packet::new_unchecked(&bytes[..])).unwrap(), r);
}

#[test]
fn malformed() {
    // Short header, DCPDataLength past the buffer, block past DCPDataLength, odd Get.
    let bad: [&[u8]; 5] = [
        &[0xfe, 0xfe, 5, 0],
        &[0xfe, 0xfe, 5, 0, 0, 0, 0, 1, 0, 0, 0, 4, 0xff, 0xff],
        &[0xfe, 0xfe, 5, 0, 0, 0, 0, 1, 0, 0, 0, 4, 2, 2, 0, 1, b'a'],
        &[0xfe, 0xfd, 3, 0, 0, 0, 0, 1, 0, 0, 0, 3, 2, 2, 1],
        // Response block too short for its BlockInfo.
        &[0xfe, 0xff, 5, 1, 0, 0, 0, 1, 0, 0, 0, 6, 2, 2, 0, 1, 0, 0],
    ];
    for b in bad {
        assert_eq!(Repr::parse(&Packet::new_unchecked(b)), Err(Error));
    }
    // Non-UTF-8 name is kept as Unknown, losslessly.
    let b: &[u8] = &[
        0xfe, 0xfe, 5, 0, 0, 0, 0, 1, 0, 0, 0, 6, 2, 2, 0, 2, 0xff, 0xfe,
    ];
    let r = Repr::parse(&Packet::new_unchecked(b)).unwrap();
    assert_eq!(
        r.blocks[0].value,
        BlockRepr::Unknown {
            option: 2,
            suboption: 2,
            data: vec![0xff, 0xfe]
        }
    );
    assert_eq!(r.to_vec().unwrap(), b);
    // A last odd block without its pad is accepted.
    let b: &[u8] = &[0xfe, 0xfe, 5, 0, 0, 0, 0, 1, 0, 0, 0, 5, 2, 2, 0, 1, b'a'];
    let r = Repr::parse(&Packet::new_unchecked(b)).unwrap();
    assert_eq!(r.name_of_station(), Some("a"));
    // Too short a buffer for emit.
    let r = Repr::identify_all(1, 1);
    let mut buf = vec![0u8; r.buffer_len() - 1];
    assert_eq!(
        r.emit(&mut buf),
        Err(EmitError::BufferTooShort {
            what: "DCP PDU",
            needed: buf.len() + 1,
            len: buf.len()
        })
    );
}

#[test]
fn response_delay() {
    let mac = MacAddress([0, 0x0e, 0xcf, 0, 0x01, 0x2c]); // 0x012c = 300
    assert_eq!(response_delay_ns(mac, 0), 0);
    assert_eq!(response_delay_ns(mac, 1), 0);
    assert_eq!(response_delay_ns(mac, 7), (300 % 7) * 10_000_000);
    assert_eq!(response_delay_ns(mac, 6400), 300 * 10_000_000);
    assert_eq!(response_delay_ns(mac, 6401), 0);
}

fn ip4() -> impl Strategy<Value = [u8; 4]> {
    any::<[u8; 4]>()
}

fn name() -> impl Strategy<Value = String> {
    "[a-z0-9-]{1,60}"
}

/// Any block value that parses back to itself in a context with (`prefixed`) or without
/// a prefix; `Unknown` only with codes this module does not model.
fn block_value() -> impl Strategy<Value = BlockRepr> {
    prop_oneof![
        any::<[u8; 6]>().prop_map(|m| BlockRepr::MacAddress(MacAddress(m))),
        (ip4(), ip4(), ip4()).prop_map(|(ip, mask, gateway)| BlockRepr::IpParameter {
            ip,
            mask,
            gateway
        }),
        (ip4(), ip4(), ip4(), any::<[[u8; 4]; 4]>()).prop_map(|(ip, mask, gateway, dns)| {
            BlockRepr::FullIpSuite {
                ip,
                mask,
                gateway,
                dns,
            }
        }),
        "[ -~]{0,40}".prop_map(BlockRepr::DeviceVendor),
        name().prop_map(BlockRepr::NameOfStation),
        (any::<u16>(), any::<u16>()).prop_map(|(vendor_id, device_id)| BlockRepr::DeviceId {
            vendor_id,
            device_id
        }),
        (any::<u8>(), any::<u8>())
            .prop_map(|(role, reserved)| BlockRepr::DeviceRole { role, reserved }),
        proptest::collection::vec(any::<(u8, u8)>(), 0..20).prop_map(BlockRepr::DeviceOptions),
        name().prop_map(BlockRepr::AliasName),
        (any::<u8>(), any::<u8>()).prop_map(|(high, low)| BlockRepr::DeviceInstance { high, low }),
        Just(BlockRepr::ControlStart),
        Just(BlockRepr::ControlStop),
        any::<u16>().prop_map(BlockRepr::ControlSignal),
        (any::<u8>(), any::<u8>(), any::<u8>()).prop_map(|(option, suboption, error)| {
            BlockRepr::ControlResponse {
                option,
                suboption,
                error,
            }
        }),
        any::<u16>().prop_map(BlockRepr::FactoryReset),
        any::<u16>().prop_map(BlockRepr::ResetToFactory),
        any::<u16>().prop_map(BlockRepr::DeviceInitiative),
        Just(BlockRepr::AllSelector),
        (
            0x80u8..0xff,
            any::<u8>(),
            proptest::collection::vec(any::<u8>(), 0..50)
        )
            .prop_map(|(option, suboption, data)| BlockRepr::Unknown {
                option,
                suboption,
                data
            }),
    ]
}

/// A block as `parse` would return it in `ctx`.
fn block(ctx: BlockContext) -> impl Strategy<Value = Block> {
    (any::<u16>(), block_value()).prop_map(move |(prefix, value)| {
        let (o, s) = value.code();
        let prefix = match value {
            _ if !ctx.has_prefix(o, s) => 0,
            BlockRepr::FactoryReset(q) | BlockRepr::ResetToFactory(q) => q,
            _ => prefix,
        };
        Block { prefix, value }
    })
}

fn service() -> impl Strategy<Value = (ServiceId, ServiceType, BlockContext)> {
    use ServiceId::*;
    use ServiceType::*;
    prop_oneof![
        Just((Identify, Request, BlockContext::IdentifyFilter)),
        Just((Set, Request, BlockContext::SetRequest)),
        Just((Get, Request, BlockContext::GetRequest)),
        Just((Hello, Request, BlockContext::Response)),
        Just((Identify, Success, BlockContext::Response)),
        Just((Get, Success, BlockContext::Response)),
        Just((Set, Success, BlockContext::Response)),
        Just((Set, NotSupported, BlockContext::Response)),
        (7u8..).prop_map(|v| (ServiceId::Unknown(v), Request, BlockContext::IdentifyFilter)),
        (6u8..).prop_map(|v| (Get, ServiceType::Unknown(v), BlockContext::Response)),
    ]
}

fn repr() -> impl Strategy<Value = Repr> {
    (service(), any::<u16>(), any::<u32>(), any::<u16>()).prop_flat_map(
        |((service_id, service_type, ctx), frame_id, xid, response_delay)| {
            let blocks = if ctx == BlockContext::GetRequest {
                proptest::collection::vec(
                    any::<(u8, u8)>().prop_map(|(option, suboption)| {
                        Block::bare(BlockRepr::Requested { option, suboption })
                    }),
                    0..20,
                )
                .boxed()
            } else {
                proptest::collection::vec(block(ctx), 0..8).boxed()
            };
            blocks.prop_map(move |blocks| Repr {
                frame_id,
                service_id,
                service_type,
                xid,
                response_delay,
                blocks,
            })
        },
    )
}

proptest! {
    #[test]
    fn parse_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..1500)) {
        let p = Packet::new_unchecked(&bytes[..]);
        if let Ok(r) = Repr::parse(&p) {
            // What parses emits again, to the same length or one pad more.
            let v = r.to_vec().unwrap();
            prop_assert!(v.len() <= HEADER_LEN + usize::from(p.data_length()) + 1);
        }
        let _ = p.to_string();
    }

    #[test]
    fn parse_never_panics_on_plausible_blocks(
        sid in 0u8..8,
        st in prop_oneof![Just(0u8), Just(1u8), Just(5u8)],
        blocks in proptest::collection::vec(any::<u8>(), 0..300),
    ) {
        let mut bytes = vec![0xfe, 0xfd, sid, st, 0, 0, 0, 1, 0, 0];
        bytes.extend_from_slice(&(blocks.len() as u16).to_be_bytes());
        bytes.extend_from_slice(&blocks);
        let _ = Repr::parse(&Packet::new_unchecked(&bytes[..]));
    }

    #[test]
    fn round_trip(r in repr()) {
        let bytes = r.to_vec().unwrap();
        prop_assert_eq!(bytes.len(), r.buffer_len());
        let p = Packet::new_checked(&bytes[..]).unwrap();
        prop_assert_eq!(usize::from(p.data_length()) % 2, 0);
        let back = Repr::parse(&p).unwrap();
        prop_assert_eq!(back, r);
    }
}
