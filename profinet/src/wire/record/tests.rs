// SPDX-License-Identifier: MIT OR Apache-2.0
//! Tests of the record codecs.

use super::*;
use crate::test_fixtures::hex;
use proptest::prelude::*;

// The captures below come from the test data of the `pnio` crate 0.1.0
// (core-engineering/pnio-rs, MIT OR Apache-2.0): an S7-1515 talking to the p-net sample
// device. Only the blocks part of each frame: from byte 142 (Ethernet 14 + IPv4 20 +
// UDP 8 + RPC header 80 + NDR header 20) to the end.

/// alarm/im0_read_req.hex: Read request, slot 0 subslot 1, index 0xAFF0, up to 0x8000 bytes.
const IM0_READ_REQ: &str = concat!(
    "0009003c01000006ef796d60ef2b9946b39e8531f5b7f9660000000000000001",
    "0000aff000008000000000000000000000000000000000000000000000000000",
);
/// alarm/im0_read_res.hex: p-net's Read response with its I&M0 block.
const IM0_READ_RES: &str = concat!(
    "8009003c01000006ef796d60ef2b9946b39e8531f5b7f9660000000000000001",
    "0000aff00000003c000000000000000000000000000000000000000000000000",
    "00200038010004933132333435204162636465666768696a6b20202030303720",
    "2020202020202020202020200003560002000000123456780101000e",
);
/// alarm/im0_read_req_if.hex: Read request of I&M0 on the interface submodule 0x8000.
const IM0_READ_REQ_IF: &str = concat!(
    "0009003c01000005ef796d60ef2b9946b39e8531f5b7f9660000000000008000",
    "0000aff000008000000000000000000000000000000000000000000000000000",
);
/// alarm/im0_read_res_if.hex: the response to it.
const IM0_READ_RES_IF: &str = concat!(
    "8009003c01000005ef796d60ef2b9946b39e8531f5b7f9660000000000008000",
    "0000aff00000003c000000000000000000000000000000000000000000000000",
    "00200038010004933132333435204162636465666768696a6b20202030303720",
    "2020202020202020202020200003560002000000123456780101000e",
);
/// cm/write_req.hex: the S7's WriteMultiple (PDInterfaceAdjust 0x8071, user records
/// 123, 124 and 125).
const WRITE_REQ: &str = concat!(
    "0008003c01000000e5e1aeccb1334b4db187cc68b0211ed2ffffffffffffffff",
    "0000e04000000118000000000000000000000000000000000000000000000000",
    "0008003c01000001e5e1aeccb1334b4db187cc68b0211ed20000000000008000",
    "000080710000000c000000000000000000000000000000000000000000000000",
    "0250000801000000000000010008003c01000002e5e1aeccb1334b4db187cc68",
    "b0211ed200000000000300010000007b00000004000000000000000000000000",
    "000000000000000000000000000000010008003c01000003e5e1aeccb1334b4d",
    "b187cc68b0211ed200000000000300010000007c000000040000000000000000",
    "00000000000000000000000000000000000000020008003c01000004e5e1aecc",
    "b1334b4db187cc68b0211ed200000000000400010000007d0000000400000000",
    "000000000000000000000000000000000000000000000002",
);
/// cm/write_res.hex: p-net's response to it.
const WRITE_RES: &str = concat!(
    "8008003c01000000e5e1aeccb1334b4db187cc68b0211ed2ffffffffffffffff",
    "0000e04000000000000000000000000000000000000000000000000000000000",
    "8008003c01000001e5e1aeccb1334b4db187cc68b0211ed20000000000008000",
    "0000807100000000000000000000000000000000000000000000000000000000",
    "8008003c01000002e5e1aeccb1334b4db187cc68b0211ed20000000000030001",
    "0000007b00000000000000000000000000000000000000000000000000000000",
    "8008003c01000003e5e1aeccb1334b4db187cc68b0211ed20000000000030001",
    "0000007c00000000000000000000000000000000000000000000000000000000",
    "8008003c01000004e5e1aeccb1334b4db187cc68b0211ed20000000000040001",
    "0000007d00000000000000000000000000000000000000000000000000000000",
);

/// ARUUID of the I&M0 reads.
const READ_AR: Uuid = Uuid::from_fields(
    0xef79_6d60,
    0xef2b,
    0x9946,
    [0xb3, 0x9e, 0x85, 0x31, 0xf5, 0xb7, 0xf9, 0x66],
);
/// ARUUID of the WriteMultiple.
const WRITE_AR: Uuid = Uuid::from_fields(
    0xe5e1_aecc,
    0xb133,
    0x4b4d,
    [0xb1, 0x87, 0xcc, 0x68, 0xb0, 0x21, 0x1e, 0xd2],
);

/// Splits the header off `b` and checks it re-emits to its 64 bytes.
fn header(b: &[u8]) -> (IodHeader, &[u8], &[u8]) {
    let (h, data, rest) = IodHeader::split(b).unwrap();
    assert_eq!(h.to_bytes()[..], b[..IOD_HEADER_LEN]);
    (h, data, rest)
}

#[test]
fn im0_read_requests() {
    for (hex_str, seq, subslot) in [(IM0_READ_REQ, 6, 1), (IM0_READ_REQ_IF, 5, 0x8000)] {
        let b = hex(hex_str);
        let (h, data, rest) = header(&b);
        assert!(data.is_empty() && rest.is_empty());
        let expected = IodHeader::read_request(seq, READ_AR, 0, 0, subslot, INDEX_IM0, 0x8000);
        assert_eq!(h, expected);
        assert_eq!(h.kind, IodKind::ReadReq);
        assert_eq!(h.target_ar_uuid, Uuid::NIL);
    }
}

#[test]
fn im0_read_responses() {
    for (req, res) in [
        (IM0_READ_REQ, IM0_READ_RES),
        (IM0_READ_REQ_IF, IM0_READ_RES_IF),
    ] {
        let req = IodHeader::parse(&hex(req)).unwrap();
        let b = hex(res);
        let (h, data, rest) = header(&b);
        assert!(rest.is_empty());
        assert_eq!(h.kind, IodKind::ReadRes);
        assert_eq!(h, req.response(IM0_LEN as u32));
        assert_eq!((h.add_value1, h.add_value2), (0, 0));
        assert_eq!(data.len(), IM0_LEN);

        let im0 = Im0::parse(data).unwrap();
        let expected = Im0 {
            vendor_id: 0x0493,
            order_id: blank_padded("12345 Abcdefghijk").unwrap(),
            serial_number: blank_padded("007").unwrap(),
            hardware_revision: 3,
            software_revision: SoftwareRevision {
                prefix: b'V',
                functional_enhancement: 0,
                bug_fix: 2,
                internal_change: 0,
            },
            revision_counter: 0,
            profile_id: 0x1234,
            profile_specific_type: 0x5678,
            im_version: (1, 1),
            im_supported: 0x000e,
        };
        assert_eq!(im0, expected);
        assert_eq!(im0.order_id_str(), Some("12345 Abcdefghijk"));
        assert_eq!(im0.serial_number_str(), Some("007"));
        assert_eq!(im0.software_revision.to_string(), "V0.2.0");
        assert!(im0.supports(1) && im0.supports(2) && im0.supports(3));
        assert!(!im0.supports(0) && !im0.supports(4) && !im0.supports(16));
        assert_eq!(im0.to_bytes()[..], data[..]);
    }
}

#[test]
fn write_multiple_request() {
    let b = hex(WRITE_REQ);
    let (outer, data, rest) = header(&b);
    assert!(rest.is_empty());
    assert!(outer.is_write_multiple());
    assert_eq!(outer, IodHeader::write_multiple(0, WRITE_AR, 280));
    assert_eq!(data.len(), 280);

    let writes = split_write_multiple(data).unwrap();
    let expected: [(u16, u16, u16, u16, &[u8]); 4] = [
        (
            1,
            0,
            0x8000,
            0x8071,
            &[0x02, 0x50, 0, 8, 1, 0, 0, 0, 0, 0, 0, 1],
        ),
        (2, 3, 1, 123, &[0, 0, 0, 1]),
        (3, 3, 1, 124, &[0, 0, 0, 2]),
        (4, 4, 1, 125, &[0, 0, 0, 2]),
    ];
    assert_eq!(writes.len(), expected.len());
    for ((h, d), (seq, slot, subslot, index, bytes)) in writes.iter().zip(expected) {
        let len = bytes.len() as u32;
        let e = IodHeader::write_request(seq, WRITE_AR, 0, slot, subslot, index, len);
        assert_eq!(h, &e);
        assert_eq!(*d, bytes);
    }
    assert_eq!(write_multiple_len(&writes), data.len());
    assert_eq!(join_write_multiple_to_vec(&writes).unwrap(), data);
    let mut out = outer.to_bytes().to_vec();
    out.extend_from_slice(&join_write_multiple_to_vec(&writes).unwrap());
    assert_eq!(out, b);
}

#[test]
fn write_multiple_response() {
    let b = hex(WRITE_RES);
    let (outer, writes) = split_write_multiple_response(&b).unwrap();
    assert_eq!(outer.kind, IodKind::WriteRes);
    assert!(outer.is_write_multiple());
    assert!(outer.status.is_ok());
    // p-net answers RecordDataLength 0 everywhere.
    let req = hex(WRITE_REQ);
    let (req_outer, data, _) = IodHeader::split(&req).unwrap();
    assert_eq!(outer, req_outer.response(0));
    let requests = split_write_multiple(data).unwrap();
    assert_eq!(writes.len(), requests.len());
    for (res, (req, _)) in writes.iter().zip(&requests) {
        assert_eq!(res, &req.response(0));
    }
    let mut out = outer.to_bytes().to_vec();
    for w in &writes {
        out.extend_from_slice(&w.to_bytes());
    }
    assert_eq!(out, b);
}

#[test]
fn write_multiple_padding() {
    let a = IodHeader::write_request(1, WRITE_AR, 0, 1, 1, 100, 3);
    let b = IodHeader::write_request(2, WRITE_AR, 0, 1, 1, 101, 5);
    let writes: [(IodHeader, &[u8]); 2] = [(a, &[1, 2, 3]), (b, &[4, 5, 6, 7, 8])];
    let joined = join_write_multiple_to_vec(&writes).unwrap();
    assert_eq!(joined.len(), 68 + 72);
    assert_eq!(&joined[64..68], &[1, 2, 3, 0]);
    assert_eq!(&joined[68..70], &[0x00, 0x08]);
    assert_eq!(&joined[132..140], &[4, 5, 6, 7, 8, 0, 0, 0]);
    assert_eq!(split_write_multiple(&joined).unwrap(), writes.to_vec());
    // Without the padding after the last write.
    assert_eq!(
        split_write_multiple(&joined[..137]).unwrap(),
        writes.to_vec()
    );
    // A length that does not match the data, a response header, a short buffer.
    let bad: [(IodHeader, &[u8]); 1] = [(a, &[1, 2])];
    assert!(matches!(
        join_write_multiple_to_vec(&bad),
        Err(EmitError::Inconsistent(_))
    ));
    let bad: [(IodHeader, &[u8]); 1] = [(a.response(3), &[1, 2, 3])];
    assert!(matches!(
        join_write_multiple_to_vec(&bad),
        Err(EmitError::Inconsistent(_))
    ));
    let mut short = [0u8; 67];
    assert_eq!(
        join_write_multiple(&writes[..1], &mut short),
        Err(EmitError::BufferTooShort {
            what: "WriteMultiple",
            needed: 68,
            len: 67
        })
    );
    // A write running past the data.
    assert_eq!(split_write_multiple(&joined[..130]), Err(Error));
}

#[test]
fn malformed() {
    let b = hex(IM0_READ_RES);
    for n in 0..IOD_HEADER_LEN {
        assert_eq!(IodHeader::parse(&b[..n]), Err(Error));
    }
    // Record data past the end.
    assert_eq!(IodHeader::split(&b[..b.len() - 1]), Err(Error));
    // Wrong body length, unknown block type.
    let mut bad = b.clone();
    bad[3] = 0x3b;
    assert_eq!(IodHeader::parse(&bad), Err(Error));
    let mut bad = b.clone();
    bad[1] = 0x0a;
    assert_eq!(IodHeader::parse(&bad), Err(Error));
    // I&M0 of the wrong length or type.
    let im0 = &b[IOD_HEADER_LEN..];
    assert_eq!(Im0::parse(&im0[..IM0_LEN - 1]), Err(Error));
    let mut bad = im0.to_vec();
    bad[1] = 0x21;
    assert_eq!(Im0::parse(&bad), Err(Error));
    // Emit into short buffers.
    let h = IodHeader::parse(&b).unwrap();
    assert!(matches!(
        h.emit(&mut [0u8; IOD_HEADER_LEN - 1]),
        Err(EmitError::BufferTooShort { needed: 64, .. })
    ));
    let i = Im0::parse(im0).unwrap();
    assert!(matches!(
        i.emit(&mut [0u8; IM0_LEN - 1]),
        Err(EmitError::BufferTooShort { needed: 60, .. })
    ));
    // A response of nothing.
    assert_eq!(split_write_multiple_response(&[]), Err(Error));
    // Blank padding.
    assert_eq!(blank_padded::<4>("ab"), Ok(*b"ab  "));
    assert_eq!(blank_padded::<2>("abc"), Err(Error));
    assert_eq!(blank_padded::<4>("a\u{e9}"), Err(Error));
}

#[test]
fn record_errors() {
    let e = RecordError::from_status(PnioStatus::from_bytes([0xde, 0x80, 0xb0, 0x00])).unwrap();
    assert_eq!(e, RecordError::read(RecordErrorCode::InvalidIndex, 0));
    assert_eq!(e.code.class(), ErrorClass::Access);
    assert_eq!(
        e.to_string(),
        "record read error: access: invalid index (ErrorCode2 0x00)"
    );
    let e = RecordError::write(RecordErrorCode::ResourceBusy, 7);
    assert_eq!(e.status().to_bytes(), [0xdf, 0x80, 0xc2, 0x07]);
    assert_eq!(RecordError::from_status(e.status()), Some(e));
    assert_eq!(
        e.to_string(),
        "record write error: resource: resource busy (ErrorCode2 0x07)"
    );
    let text = |code1: u8| RecordErrorCode::from(code1).to_string();
    assert_eq!(text(0xa9), "application: feature not supported");
    assert_eq!(text(0xab), "application: user specific (0xab)");
    assert_eq!(text(0xa4), "application: reserved (0xa4)");
    assert_eq!(text(0xbf), "access: user specific (0xbf)");
    assert_eq!(text(0xc5), "resource: reserved (0xc5)");
    assert_eq!(text(0xc8), "resource: user specific (0xc8)");
    assert_eq!(text(0xd1), "user specific (0xd1)");
    assert_eq!(text(0x12), "reserved (0x12)");
    // Not PNIORW: a Connect error, success.
    let connect = PnioStatus::from_bytes([0xdb, 0x81, 0x01, 0x04]);
    assert_eq!(RecordError::from_status(connect), None);
    assert_eq!(RecordError::from_status(PnioStatus::OK), None);
}

fn uuid() -> impl Strategy<Value = Uuid> {
    any::<[u8; 16]>().prop_map(Uuid)
}

fn iod_header() -> impl Strategy<Value = IodHeader> {
    let kind = prop_oneof![
        Just(IodKind::WriteReq),
        Just(IodKind::ReadReq),
        Just(IodKind::WriteRes),
        Just(IodKind::ReadRes),
    ];
    (
        kind,
        any::<(u16, u32, u16, u16, u16, u32)>(),
        uuid(),
        uuid(),
        any::<(u16, u16, u32)>(),
    )
        .prop_map(
            |(kind, (seq, api, slot, subslot, index, len), ar, target, (a1, a2, s))| {
                let mut h = IodHeader::request(kind, seq, ar, api, slot, subslot, index, len);
                if kind == IodKind::ReadReq {
                    h.target_ar_uuid = target;
                }
                if !kind.is_request() {
                    h.add_value1 = a1;
                    h.add_value2 = a2;
                }
                if kind == IodKind::WriteRes {
                    h.status = PnioStatus::from_u32(s);
                }
                h
            },
        )
}

fn im0() -> impl Strategy<Value = Im0> {
    (
        any::<(u16, [u8; 20], [u8; 16], u16, [u8; 4])>(),
        any::<(u16, u16, u16, (u8, u8), u16)>(),
    )
        .prop_map(
            |((vendor, order, serial, hw, sw), (rc, pid, pst, v, sup))| Im0 {
                vendor_id: vendor,
                order_id: order,
                serial_number: serial,
                hardware_revision: hw,
                software_revision: SoftwareRevision {
                    prefix: sw[0],
                    functional_enhancement: sw[1],
                    bug_fix: sw[2],
                    internal_change: sw[3],
                },
                revision_counter: rc,
                profile_id: pid,
                profile_specific_type: pst,
                im_version: v,
                im_supported: sup,
            },
        )
}

proptest! {
    #[test]
    fn parse_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        if let Ok(h) = IodHeader::parse(&bytes) {
            prop_assert_eq!(h.buffer_len(), IOD_HEADER_LEN);
        }
        let _ = IodHeader::split(&bytes);
        let _ = Im0::parse(&bytes);
        let _ = split_write_multiple(&bytes);
        let _ = split_write_multiple_response(&bytes);
        if let Ok(i) = Im0::parse(&bytes) {
            let _ = (i.order_id_str(), i.serial_number_str(), i.software_revision.to_string());
        }
    }

    #[test]
    fn parse_never_panics_on_plausible_headers(
        block_type in prop_oneof![Just(8u16), Just(9u16), Just(0x8008u16), Just(0x8009u16)],
        body in proptest::collection::vec(any::<u8>(), 60..61),
        tail in proptest::collection::vec(any::<u8>(), 0..200),
    ) {
        let mut b = block_type.to_be_bytes().to_vec();
        b.extend_from_slice(&[0, 0x3c]);
        b.extend_from_slice(&body);
        b.extend_from_slice(&tail);
        let h = IodHeader::parse(&b).unwrap();
        prop_assert_eq!(IodHeader::parse(&h.to_bytes()).unwrap(), h);
        let _ = IodHeader::split(&b);
        let _ = split_write_multiple(&b);
    }

    #[test]
    fn record_errors_never_panic(v in any::<u32>()) {
        let s = PnioStatus::from_u32(v);
        if let Some(e) = RecordError::from_status(s) {
            prop_assert_eq!(e.status(), s);
            let _ = e.to_string();
        }
    }

    #[test]
    fn iod_header_round_trip(h in iod_header()) {
        let bytes = h.to_bytes();
        prop_assert_eq!(IodHeader::parse(&bytes).unwrap(), h);
    }

    #[test]
    fn im0_round_trip(i in im0()) {
        prop_assert_eq!(Im0::parse(&i.to_bytes()).unwrap(), i);
    }

    #[test]
    fn write_multiple_round_trip(
        writes in proptest::collection::vec(
            (iod_header(), proptest::collection::vec(any::<u8>(), 0..12)),
            0..5,
        ),
    ) {
        let writes: Vec<(IodHeader, Vec<u8>)> = writes
            .into_iter()
            .map(|(mut h, d)| {
                h = IodHeader::write_request(
                    h.seq_number, h.ar_uuid, h.api, h.slot, h.subslot, h.index, d.len() as u32,
                );
                (h, d)
            })
            .collect();
        let refs: Vec<(IodHeader, &[u8])> =
            writes.iter().map(|(h, d)| (*h, d.as_slice())).collect();
        let joined = join_write_multiple_to_vec(&refs).unwrap();
        prop_assert_eq!(joined.len() % WRITE_MULTIPLE_ALIGN, 0);
        prop_assert_eq!(joined.len(), write_multiple_len(&refs));
        prop_assert_eq!(split_write_multiple(&joined).unwrap(), refs);
    }
}
