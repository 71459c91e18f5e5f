// SPDX-License-Identifier: MIT OR Apache-2.0
//! Byte-exact examples (the expected bytes written by hand from RFC 2741's layouts) and
//! property tests: every repr round-trips, no input makes a parser panic.

use proptest::prelude::*;

use super::*;

/// Big-endian u32 bytes, for writing expected PDUs.
fn be(v: u32) -> [u8; 4] {
    v.to_be_bytes()
}

fn le(v: u32) -> [u8; 4] {
    v.to_le_bytes()
}

fn cat(parts: &[&[u8]]) -> Vec<u8> {
    parts.concat()
}

#[test]
fn open_in_network_byte_order() {
    let expected = cat(&[
        // version 1, type 1 (Open), flags NETWORK_BYTE_ORDER, reserved
        &[1, 1, 0x10, 0],
        &be(0),  // sessionID
        &be(7),  // transactionID
        &be(1),  // packetID
        &be(20), // payload_length
        // o.timeout 5, reserved
        &[5, 0, 0, 0],
        // o.id: the null OID
        &[0, 0, 0, 0],
        // o.descr: length 8, "procimgd" (no padding needed)
        &be(8),
        b"procimgd",
    ]);
    let repr = PduRepr::new(
        0,
        7,
        1,
        Pdu::Open(Open {
            timeout: 5,
            id: Oid::null(),
            description: b"procimgd".to_vec(),
        }),
    );
    assert_eq!(repr.buffer_len(), expected.len());
    assert_eq!(repr.to_bytes().unwrap(), expected);
    assert_eq!(PduRepr::parse(&expected).unwrap(), repr);
    assert_eq!(frame_len(&expected).unwrap(), Some(expected.len()));
}

#[test]
fn register_range_little_endian_with_prefix_compression() {
    // sysDescr..sysServices as one range registration: 1.3.6.1.2.1.1.[1-7], priority 1.
    let expected = cat(&[
        // version 1, type 3 (Register), no flags: little-endian
        &[1, 3, 0, 0],
        &le(0x0102_0304),
        &le(2),
        &le(3),
        &le(24),
        // r.timeout 0, r.priority 1, r.range_subid 8, reserved
        &[0, 1, 8, 0],
        // r.subtree: n_subid 3, prefix 2 (1.3.6.1.2), include 0, reserved, then 1.1.1
        &[3, 2, 0, 0],
        &le(1),
        &le(1),
        &le(1),
        // r.upper_bound
        &le(7),
    ]);
    let repr = PduRepr {
        byte_order: ByteOrder::Little,
        ..PduRepr::new(
            0x0102_0304,
            2,
            3,
            Pdu::Register(Register {
                timeout: 0,
                priority: 1,
                range_subid: 8,
                subtree: Oid::from([1, 3, 6, 1, 2, 1, 1, 1]),
                upper_bound: Some(7),
            }),
        )
    };
    assert_eq!(repr.to_bytes().unwrap(), expected);
    assert_eq!(PduRepr::parse(&expected).unwrap(), repr);
}

#[test]
fn get_next_with_context_and_include() {
    // The LLDP-MIB, which is not under 1.3.6.1: sent without prefix.
    let expected = cat(&[
        // type 6 (GetNext), flags NETWORK_BYTE_ORDER | NON_DEFAULT_CONTEXT
        &[1, 6, 0x18, 0],
        &be(9),
        &be(10),
        &be(11),
        &be(64),
        // context "ctx", padded to 4
        &be(3),
        b"ctx\0",
        // start 1.0.8802.1.1.2, include 1
        &[6, 0, 1, 0],
        &be(1),
        &be(0),
        &be(8802),
        &be(1),
        &be(1),
        &be(2),
        // end 1.0.8802.1.1.3
        &[6, 0, 0, 0],
        &be(1),
        &be(0),
        &be(8802),
        &be(1),
        &be(1),
        &be(3),
    ]);
    let repr = PduRepr::parse(&expected).unwrap();
    assert_eq!(repr.context.as_deref(), Some(&b"ctx"[..]));
    assert_eq!(
        repr.pdu,
        Pdu::GetNext(vec![SearchRange {
            start: Oid::from([1, 0, 8802, 1, 1, 2]),
            include: true,
            end: Oid::from([1, 0, 8802, 1, 1, 3]),
        }])
    );
    assert_eq!(repr.to_bytes().unwrap(), expected);
}

#[test]
fn response_with_every_value_type() {
    let varbinds = vec![
        VarBind::new([1, 3, 6, 1, 2, 1, 1, 7, 0], Value::Integer(-1)),
        VarBind::new([1, 3, 6, 1, 2, 1, 1, 5, 0], Value::string("abcde")),
        VarBind::new(
            [1, 3, 6, 1, 2, 1, 1, 2, 0],
            Value::ObjectIdentifier(Oid::from([1, 3, 6, 1, 4, 1, 24686])),
        ),
        VarBind::new(
            [1, 3, 6, 1, 2, 1, 4, 20, 1, 1],
            Value::IpAddress([192, 168, 0, 50]),
        ),
        VarBind::new(
            [1, 3, 6, 1, 2, 1, 2, 2, 1, 10, 1],
            Value::Counter32(0xdead_beef),
        ),
        VarBind::new(
            [1, 3, 6, 1, 2, 1, 31, 1, 1, 1, 6, 1],
            Value::Counter64(0x0102_0304_0506_0708),
        ),
        VarBind::new([1, 3, 6, 1, 2, 1, 1, 3, 0], Value::TimeTicks(4242)),
        VarBind::new([1, 3, 6, 1, 2, 1, 1, 99], Value::EndOfMibView),
    ];
    let expected = cat(&[
        &[1, 18, 0x10, 0],
        &be(1),
        &be(2),
        &be(3),
        &be(272),
        // res.sysUpTime 0, res.error 0 (noError), res.index 0
        &be(0),
        &[0, 0, 0, 0],
        // Integer -1: type 2, name 1.3.6.1.2.1.1.7.0 (prefix 2: 1.1.7.0)
        &[0, 2, 0, 0],
        &[4, 2, 0, 0],
        &be(1),
        &be(1),
        &be(7),
        &be(0),
        &be(0xffff_ffff),
        // OctetString "abcde": type 4, 5 octets and 3 bytes of padding
        &[0, 4, 0, 0],
        &[4, 2, 0, 0],
        &be(1),
        &be(1),
        &be(5),
        &be(0),
        &be(5),
        b"abcde\0\0\0",
        // ObjectIdentifier 1.3.6.1.4.1.24686: type 6, value with prefix 4
        &[0, 6, 0, 0],
        &[4, 2, 0, 0],
        &be(1),
        &be(1),
        &be(2),
        &be(0),
        &[2, 4, 0, 0],
        &be(1),
        &be(24686),
        // IpAddress: type 64, an octet string of 4
        &[0, 64, 0, 0],
        &[5, 2, 0, 0],
        &be(1),
        &be(4),
        &be(20),
        &be(1),
        &be(1),
        &be(4),
        &[192, 168, 0, 50],
        // Counter32: type 65
        &[0, 65, 0, 0],
        &[6, 2, 0, 0],
        &be(1),
        &be(2),
        &be(2),
        &be(1),
        &be(10),
        &be(1),
        &be(0xdead_beef),
        // Counter64: type 70, 8 bytes, most significant first
        &[0, 70, 0, 0],
        &[7, 2, 0, 0],
        &be(1),
        &be(31),
        &be(1),
        &be(1),
        &be(1),
        &be(6),
        &be(1),
        &[1, 2, 3, 4, 5, 6, 7, 8],
        // TimeTicks: type 67
        &[0, 67, 0, 0],
        &[4, 2, 0, 0],
        &be(1),
        &be(1),
        &be(3),
        &be(0),
        &be(4242),
        // endOfMibView: type 130, no data
        &[0, 130, 0, 0],
        &[3, 2, 0, 0],
        &be(1),
        &be(1),
        &be(99),
    ]);
    let repr = PduRepr::new(
        1,
        2,
        3,
        Pdu::Response(Response {
            sys_up_time: 0,
            error: ResponseError::NoError,
            index: 0,
            varbinds,
        }),
    );
    assert_eq!(repr.buffer_len(), expected.len());
    assert_eq!(repr.to_bytes().unwrap(), expected);
    assert_eq!(PduRepr::parse(&expected).unwrap(), repr);
}

#[test]
fn prefix_compression_edges() {
    let encode = |oid: &[u32]| {
        let repr = PduRepr::new(0, 0, 0, Pdu::RemoveAgentCaps(Oid::from(oid)));
        repr.to_bytes().unwrap()[20..].to_vec()
    };
    // 1.3.6.1.4 exactly: prefix 4 and nothing after it.
    assert_eq!(encode(&[1, 3, 6, 1, 4]), [0, 4, 0, 0]);
    // 1.3.6.1.0.5 and 1.3.6.1.256: the fifth subidentifier cannot be a prefix byte.
    assert_eq!(encode(&[1, 3, 6, 1, 0, 5])[..4], [6, 0, 0, 0]);
    assert_eq!(encode(&[1, 3, 6, 1, 256])[..4], [5, 0, 0, 0]);
    // 1.3.6.1: too short for a prefix.
    assert_eq!(encode(&[1, 3, 6, 1])[..4], [4, 0, 0, 0]);
}

#[test]
fn test_set_and_cleanup_and_close() {
    let cleanup = cat(&[&[1, 11, 0x10, 0], &be(5), &be(6), &be(7), &be(0)]);
    assert_eq!(PduRepr::parse(&cleanup).unwrap().pdu, Pdu::CleanupSet);
    let close = PduRepr::new(
        5,
        0,
        8,
        Pdu::Close(Close {
            reason: CloseReason::Shutdown,
        }),
    );
    assert_eq!(
        close.to_bytes().unwrap(),
        cat(&[
            &[1, 2, 0x10, 0],
            &be(5),
            &be(0),
            &be(8),
            &be(4),
            &[5, 0, 0, 0]
        ])
    );
}

#[test]
fn malformed_headers_and_payloads() {
    let ping = cat(&[&[1, 13, 0x10, 0], &be(1), &be(2), &be(3), &be(0)]);
    assert_eq!(frame_len(&ping[..19]), Ok(None));
    let mut v2 = ping.clone();
    v2[0] = 2;
    assert_eq!(frame_len(&v2), Err(ParseError::Version(2)));
    let mut odd = ping.clone();
    odd[19] = 3;
    assert_eq!(frame_len(&odd), Err(ParseError::PayloadAlignment(3)));
    let mut unknown = ping.clone();
    unknown[1] = 99;
    assert_eq!(PduRepr::parse(&unknown), Err(ParseError::PduType(99)));
    // A Ping with 4 bytes of payload: trailing bytes.
    let mut long_ping = ping.clone();
    long_ping[19] = 4;
    long_ping.extend_from_slice(&[0; 4]);
    assert_eq!(
        PduRepr::parse(&long_ping),
        Err(ParseError::TrailingBytes(PduType::Ping))
    );
    // A Close with its payload cut: the declared length does not match what is given.
    let close = cat(&[&[1, 2, 0x10, 0], &be(5), &be(0), &be(8), &be(4), &[5, 0]]);
    assert_eq!(
        PduRepr::parse(&close),
        Err(ParseError::Length {
            expected: 24,
            given: 22
        })
    );
    // A context on a Response is refused when writing.
    let mut response = PduRepr::new(
        0,
        0,
        0,
        Pdu::Response(Response {
            sys_up_time: 0,
            error: ResponseError::NoError,
            index: 0,
            varbinds: vec![],
        }),
    );
    response.context = Some(b"x".to_vec());
    assert_eq!(
        response.to_bytes(),
        Err(EmitError::ContextNotCarried(PduType::Response))
    );
    // A buffer too short to emit into.
    let mut short = [0u8; 10];
    assert!(matches!(
        PduRepr::new(0, 0, 0, Pdu::Ping).emit(&mut short),
        Err(EmitError::BufferTooShort {
            needed: 20,
            got: 10
        })
    ));
}

#[test]
fn oid_text() {
    let oid: Oid = ".1.3.6.1.2.1.1.5.0".parse().unwrap();
    assert_eq!(oid, Oid::from([1, 3, 6, 1, 2, 1, 1, 5, 0]));
    assert_eq!(oid.to_string(), "1.3.6.1.2.1.1.5.0");
    assert_eq!("".parse::<Oid>(), Ok(Oid::null()));
    assert!("1.x.3".parse::<Oid>().is_err());
    assert!("1..3".parse::<Oid>().is_err());
}

// Strategies for the round trips.

fn oid() -> impl Strategy<Value = Oid> {
    prop_oneof![
        prop::collection::vec(any::<u32>(), 0..12).prop_map(Oid::new),
        // Internet OIDs, which compress.
        (1u32..300, prop::collection::vec(any::<u32>(), 0..8))
            .prop_map(|(p, rest)| Oid::from([1, 3, 6, 1, p]).child(&rest)),
    ]
}

fn octets() -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(any::<u8>(), 0..13)
}

fn value() -> impl Strategy<Value = Value> {
    prop_oneof![
        any::<i32>().prop_map(Value::Integer),
        octets().prop_map(Value::OctetString),
        Just(Value::Null),
        oid().prop_map(Value::ObjectIdentifier),
        any::<[u8; 4]>().prop_map(Value::IpAddress),
        any::<u32>().prop_map(Value::Counter32),
        any::<u32>().prop_map(Value::Gauge32),
        any::<u32>().prop_map(Value::TimeTicks),
        octets().prop_map(Value::Opaque),
        any::<u64>().prop_map(Value::Counter64),
        Just(Value::NoSuchObject),
        Just(Value::NoSuchInstance),
        Just(Value::EndOfMibView),
    ]
}

fn varbinds() -> impl Strategy<Value = Vec<VarBind>> {
    prop::collection::vec(
        (oid(), value()).prop_map(|(name, value)| VarBind { name, value }),
        0..5,
    )
}

fn ranges() -> impl Strategy<Value = Vec<SearchRange>> {
    prop::collection::vec(
        (oid(), any::<bool>(), oid()).prop_map(|(start, include, end)| SearchRange {
            start,
            include,
            end,
        }),
        0..5,
    )
}

fn registration() -> impl Strategy<Value = (u8, u8, Oid, Option<u32>)> {
    (any::<u8>(), any::<u8>(), oid(), any::<u32>()).prop_map(|(priority, range, subtree, ub)| {
        (priority, range, subtree, (range != 0).then_some(ub))
    })
}

fn pdu() -> impl Strategy<Value = Pdu> {
    prop_oneof![
        (any::<u8>(), oid(), octets()).prop_map(|(timeout, id, description)| Pdu::Open(Open {
            timeout,
            id,
            description
        })),
        any::<u8>().prop_map(|r| Pdu::Close(Close {
            reason: CloseReason::from_raw(r)
        })),
        (any::<u8>(), registration()).prop_map(
            |(timeout, (priority, range_subid, subtree, upper_bound))| {
                Pdu::Register(Register {
                    timeout,
                    priority,
                    range_subid,
                    subtree,
                    upper_bound,
                })
            }
        ),
        registration().prop_map(|(priority, range_subid, subtree, upper_bound)| {
            Pdu::Unregister(Unregister {
                priority,
                range_subid,
                subtree,
                upper_bound,
            })
        }),
        ranges().prop_map(Pdu::Get),
        ranges().prop_map(Pdu::GetNext),
        (any::<u16>(), any::<u16>(), ranges()).prop_map(
            |(non_repeaters, max_repetitions, ranges)| {
                Pdu::GetBulk(GetBulk {
                    non_repeaters,
                    max_repetitions,
                    ranges,
                })
            }
        ),
        varbinds().prop_map(Pdu::TestSet),
        Just(Pdu::CommitSet),
        Just(Pdu::UndoSet),
        Just(Pdu::CleanupSet),
        varbinds().prop_map(Pdu::Notify),
        Just(Pdu::Ping),
        varbinds().prop_map(Pdu::IndexAllocate),
        varbinds().prop_map(Pdu::IndexDeallocate),
        (oid(), octets())
            .prop_map(|(id, description)| Pdu::AddAgentCaps(AddAgentCaps { id, description })),
        oid().prop_map(Pdu::RemoveAgentCaps),
        (any::<u32>(), any::<u16>(), any::<u16>(), varbinds()).prop_map(
            |(sys_up_time, e, index, varbinds)| {
                Pdu::Response(Response {
                    sys_up_time,
                    error: ResponseError::from_raw(e),
                    index,
                    varbinds,
                })
            }
        ),
    ]
}

fn pdu_repr() -> impl Strategy<Value = PduRepr> {
    (
        any::<bool>(),
        0u8..8,
        any::<[u32; 3]>(),
        prop::option::of(octets()),
        pdu(),
    )
        .prop_map(
            |(big, flags, [session_id, transaction_id, packet_id], context, pdu)| PduRepr {
                byte_order: if big {
                    ByteOrder::Big
                } else {
                    ByteOrder::Little
                },
                flags: Flags(flags),
                session_id,
                transaction_id,
                packet_id,
                context: context.filter(|_| pdu.pdu_type().carries_context()),
                pdu,
            },
        )
}

proptest! {
    #[test]
    fn every_repr_round_trips(repr in pdu_repr()) {
        let bytes = repr.to_bytes().unwrap();
        prop_assert_eq!(bytes.len(), repr.buffer_len());
        prop_assert_eq!(frame_len(&bytes).unwrap(), Some(bytes.len()));
        prop_assert_eq!(PduRepr::parse(&bytes).unwrap(), repr);
    }

    #[test]
    fn no_input_makes_the_parsers_panic(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        let _ = frame_len(&bytes);
        let _ = PduRepr::parse(&bytes);
        let _ = Header::new_checked(&bytes[..]).map(|h| HeaderRepr::parse(&h));
    }

    #[test]
    fn a_valid_header_over_random_payloads_does_not_panic(
        pdu_type in 0u8..20,
        flags in any::<u8>(),
        payload in prop::collection::vec(any::<u8>(), 0..40).prop_map(|mut p| { p.truncate(p.len() / 4 * 4); p }),
    ) {
        let mut bytes = vec![1, pdu_type, flags, 0];
        bytes.extend_from_slice(&[0; 12]);
        let len = u32::try_from(payload.len()).unwrap();
        if flags & 0x10 != 0 {
            bytes.extend_from_slice(&len.to_be_bytes());
        } else {
            bytes.extend_from_slice(&len.to_le_bytes());
        }
        bytes.extend_from_slice(&payload);
        let _ = PduRepr::parse(&bytes);
    }

    #[test]
    fn a_truncated_pdu_is_an_error_not_a_panic(repr in pdu_repr(), cut in any::<prop::sample::Index>()) {
        let bytes = repr.to_bytes().unwrap();
        let at = cut.index(bytes.len());
        prop_assert!(PduRepr::parse(&bytes[..at]).is_err());
    }
}
