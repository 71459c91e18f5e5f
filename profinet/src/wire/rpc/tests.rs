// SPDX-License-Identifier: MIT OR Apache-2.0
//! The RPC codecs against captured PDUs of an S7-1515 and p-net, and round trips.

use super::super::BlockHeader;
use super::*;
use proptest::prelude::*;

// The captures below come from the test data of the `pnio` crate 0.1.0
// (core-engineering/pnio-rs, MIT OR Apache-2.0): an S7-1515 talking to the p-net sample
// device. Each names a file in tests/fixtures/captures; the tests read its UDP payload (the
// RPC PDU) with [`rpc_pdu`], so the bytes are kept once, in the capture file.

/// captures/cm/connect_req.hex, bytes 42.. (657 bytes): frame 50: CPU Connect request, DREP LE, 699 bytes (RPC PDU at offset 42)
const CONNECT_REQ: &str = "cm/connect_req";

/// captures/cm/connect_res.hex, bytes 42.. (190 bytes): frame 53: p-net Connect response, DREP BE, 232 bytes (RPC PDU at offset 42)
const CONNECT_RES: &str = "cm/connect_res";

/// captures/cm/write_req.hex, bytes 42.. (444 bytes): frame 54: CPU Write MultipleWrite, DREP LE, 486 bytes
const WRITE_REQ: &str = "cm/write_req";

/// captures/cm/write_res.hex, bytes 42.. (420 bytes): frame 56: p-net Write response, DREP BE, 462 bytes
const WRITE_RES: &str = "cm/write_res";

/// captures/cm/prmend_req.hex, bytes 42.. (132 bytes): frame 57: CPU Control PrmEnd, DREP LE, 174 bytes
const PRMEND_REQ: &str = "cm/prmend_req";

/// captures/cm/prmend_res.hex, bytes 42.. (132 bytes): frame 58: p-net Control PrmEnd Done, DREP BE, 174 bytes
const PRMEND_RES: &str = "cm/prmend_res";

/// captures/cm/appready_req.hex, bytes 42.. (132 bytes): frame 59: p-net -> CPU Control ApplicationReady, DREP BE, 174 bytes (src port 49153)
const APPREADY_REQ: &str = "cm/appready_req";

/// captures/cm/appready_res.hex, bytes 42.. (132 bytes): frame 60: CPU -> p-net ApplicationReady Done, DREP LE, flags1 0x0a, 174 bytes
const APPREADY_RES: &str = "cm/appready_res";

/// captures/alarm/im0_read_req.hex, bytes 42.. (164 bytes): frame 24414 of plan5-alarm.pcapng (2026-08-30): CPU -> p-net, DCE-RPC Read request (opnum 2), IODReadReqHeader slot 0 subslot 1, index 0xAFF0 I&M0, RecordDataLength 0x8000, 206 bytes
const IM0_READ_REQ: &str = "alarm/im0_read_req";

/// captures/alarm/im0_read_req_if.hex, bytes 42.. (164 bytes): frame 24410 of plan5-alarm.pcapng (2026-08-30): CPU -> p-net, Read request I&M0 on the interface submodule slot 0 subslot 0x8000, 206 bytes
const IM0_READ_REQ_IF: &str = "alarm/im0_read_req_if";

/// captures/alarm/im0_read_res.hex, bytes 42.. (224 bytes): frame 24415 of plan5-alarm.pcapng (2026-08-30): p-net -> CPU, DCE-RPC Read response, IODReadResHeader + I&M0 block (60 bytes), p-net identity VendorID 0x0493 OrderID '12345 Abcdefghijk', 266 bytes
const IM0_READ_RES: &str = "alarm/im0_read_res";

/// captures/alarm/im0_read_res_if.hex, bytes 42.. (224 bytes): frame 24411 of plan5-alarm.pcapng (2026-08-30): p-net -> CPU, Read response I&M0 on the interface submodule, 266 bytes
const IM0_READ_RES_IF: &str = "alarm/im0_read_res_if";

use crate::wire::test_captures::rpc_pdu;

const OBJECT_DEVICE: &str = "dea00000-6c97-11d1-8271-000100020493";
const OBJECT_CPU: &str = "dea00000-6c97-11d1-8271-1064010e002a";
const IFACE_DEVICE: &str = "dea00001-6c97-11d1-8271-00a02442df7d";
const IFACE_CONTROLLER: &str = "dea00002-6c97-11d1-8271-00a02442df7d";
const ACT_CONNECT: &str = "d2aca1ae-0032-1010-b058-ec1c5d61e73f";
const ACT_READ: &str = "8d6dd76b-0013-1010-9479-ec1c5d61e73c";
const ACT_APPREADY: &str = "14af198a-1234-1056-8079-8cf319cd19f8";

/// What a capture must parse to.
struct Expect {
    capture: &'static str,
    side: Side,
    activity: &'static str,
    sequence_number: u32,
    opnum: u16,
    body_len: u16,
    ndr: Ndr,
    first_block: u16,
}

/// Who sends a PDU of the captures and how: the header fields every PDU of that side has.
#[derive(Clone, Copy)]
struct Side {
    packet_type: PacketType,
    flags1: u8,
    little_endian: bool,
    object: &'static str,
    interface: &'static str,
    server_boot_time: u32,
}

/// The S7 calls the p-net device (Connect, Write, Control, Read): DREP little-endian.
const S7_CALL: Side = Side {
    packet_type: PacketType::Request,
    flags1: flags1::IDEMPOTENT,
    little_endian: true,
    object: OBJECT_DEVICE,
    interface: IFACE_DEVICE,
    server_boot_time: 0,
};

/// p-net answers the S7's call: DREP big-endian, no FACK wanted.
const PNET_ANSWER: Side = Side {
    packet_type: PacketType::Response,
    flags1: flags1::NO_FACK | flags1::IDEMPOTENT,
    little_endian: false,
    ..S7_CALL
};

/// p-net calls the S7's controller interface (ApplicationReady): DREP big-endian.
const PNET_CALL: Side = Side {
    packet_type: PacketType::Request,
    flags1: flags1::IDEMPOTENT,
    little_endian: false,
    object: OBJECT_CPU,
    interface: IFACE_CONTROLLER,
    server_boot_time: 0,
};

/// The S7 answers p-net's call, with its server boot time.
const S7_ANSWER: Side = Side {
    packet_type: PacketType::Response,
    flags1: flags1::LAST_FRAGMENT | flags1::NO_FACK,
    little_endian: true,
    server_boot_time: 0x5156,
    ..PNET_CALL
};

fn request(args_maximum: u32, len: u32) -> Ndr {
    Ndr::Request(NdrRequest {
        args_maximum,
        args_length: len,
        maximum_count: args_maximum,
        offset: 0,
        actual_count: len,
    })
}

fn response(maximum_count: u32, len: u32) -> Ndr {
    Ndr::Response(NdrResponse {
        status: PnioStatus::OK,
        args_length: len,
        maximum_count,
        offset: 0,
        actual_count: len,
    })
}

/// Parses a capture, checks every field, and re-emits it byte for byte, both from the
/// parsed `Pdu` and from its parts through `emit_request` / `emit_response`.
fn check(e: Expect) -> Vec<u8> {
    let side = e.side;
    let bytes = rpc_pdu(e.capture);
    let p = Packet::new_checked(&bytes[..]).unwrap();
    assert_eq!(p.version(), RPC_VERSION);
    let drep0 = if side.little_endian { 0x10 } else { 0x00 };
    assert_eq!(p.drep(), [drep0, 0, 0]);
    assert_eq!(p.body().len(), usize::from(e.body_len));
    assert_eq!(bytes.len(), HEADER_LEN + usize::from(e.body_len));

    let h = Header::parse(&p).unwrap();
    assert_eq!(h.packet_type, side.packet_type);
    assert_eq!(h.flags1, side.flags1);
    assert_eq!(h.flags2, 0);
    assert_eq!(h.little_endian, side.little_endian);
    assert_eq!(h.serial, 0);
    assert_eq!(h.object.to_string(), side.object);
    assert_eq!(h.interface.to_string(), side.interface);
    assert_eq!(h.activity.to_string(), e.activity);
    assert_eq!(h.server_boot_time, side.server_boot_time);
    assert_eq!(h.interface_version, PNIO_INTERFACE_VERSION);
    assert_eq!(h.sequence_number, e.sequence_number);
    assert_eq!(h.opnum, e.opnum);
    assert_eq!((h.interface_hint, h.activity_hint), (NO_HINT, NO_HINT));
    assert_eq!(h.body_len, e.body_len);
    assert_eq!((h.fragment_number, h.auth_protocol), (0, 0));
    assert_eq!(h.buffer_len(), HEADER_LEN);

    let mut hdr = [0xa5u8; HEADER_LEN];
    h.emit(&mut hdr).unwrap();
    assert_eq!(&hdr[..], &bytes[..HEADER_LEN]);

    let pdu = Pdu::parse(&bytes).unwrap();
    assert_eq!(pdu.header, h);
    assert_eq!(pdu.ndr, e.ndr);
    assert_eq!(pdu.ndr.packet_type(), side.packet_type);
    assert!(pdu.ndr.is_consistent(pdu.blocks.len()));
    assert_eq!(usize::from(e.body_len), NDR_LEN + pdu.blocks.len());
    if let Some(status) = pdu.ndr.status() {
        assert!(status.is_ok());
        assert_eq!(describe(status), "OK");
    }
    // The first block header parses (a Write carries record data between its blocks).
    let first = BlockHeader::parse(pdu.blocks).unwrap();
    assert_eq!(first.block_type.raw(), e.first_block);
    assert_eq!(parse_pdu(&bytes).unwrap(), (h, e.ndr, pdu.blocks));

    // Re-emission: into a dirty buffer of exactly buffer_len bytes, then from the parts.
    assert_eq!(pdu.buffer_len(), bytes.len());
    let mut out = vec![0xa5u8; pdu.buffer_len()];
    pdu.emit(&mut out).unwrap();
    assert_eq!(out, bytes);
    let built = match e.ndr {
        Ndr::Request(r) => emit_request(&h, r.args_maximum, pdu.blocks),
        Ndr::Response(r) => emit_response(&h, r.status, r.maximum_count, pdu.blocks),
    };
    assert_eq!(built.unwrap(), bytes);
    bytes
}

#[test]
fn connect_request_capture() {
    check(Expect {
        capture: CONNECT_REQ,
        side: S7_CALL,
        activity: ACT_CONNECT,
        sequence_number: 0,
        opnum: opnum::CONNECT,
        body_len: 577,
        ndr: request(0x22d, 0x22d),
        first_block: 0x0101,
    });
}

#[test]
fn connect_response_capture() {
    check(Expect {
        capture: CONNECT_RES,
        side: PNET_ANSWER,
        activity: ACT_CONNECT,
        sequence_number: 0,
        opnum: opnum::CONNECT,
        body_len: 110,
        ndr: response(0x22d, 0x5a),
        first_block: 0x8101,
    });
}

#[test]
fn write_request_capture() {
    check(Expect {
        capture: WRITE_REQ,
        side: S7_CALL,
        activity: ACT_CONNECT,
        sequence_number: 1,
        opnum: opnum::WRITE,
        body_len: 364,
        ndr: request(0x158, 0x158),
        first_block: 0x0008,
    });
}

#[test]
fn write_response_capture() {
    check(Expect {
        capture: WRITE_RES,
        side: PNET_ANSWER,
        activity: ACT_CONNECT,
        sequence_number: 1,
        opnum: opnum::WRITE,
        body_len: 340,
        ndr: response(0x158, 0x140),
        first_block: 0x8008,
    });
}

#[test]
fn prmend_request_capture() {
    check(Expect {
        capture: PRMEND_REQ,
        side: S7_CALL,
        activity: ACT_CONNECT,
        sequence_number: 2,
        opnum: opnum::CONTROL,
        body_len: 52,
        ndr: request(0x20, 0x20),
        first_block: 0x0110,
    });
}

#[test]
fn prmend_response_capture() {
    check(Expect {
        capture: PRMEND_RES,
        side: PNET_ANSWER,
        activity: ACT_CONNECT,
        sequence_number: 2,
        opnum: opnum::CONTROL,
        body_len: 52,
        ndr: response(0x20, 0x20),
        first_block: 0x8110,
    });
}

#[test]
fn application_ready_request_capture() {
    check(Expect {
        capture: APPREADY_REQ,
        side: PNET_CALL,
        activity: ACT_APPREADY,
        sequence_number: 0,
        opnum: opnum::CONTROL,
        body_len: 52,
        ndr: request(1340, 0x20),
        first_block: 0x0112,
    });
}

#[test]
fn application_ready_response_capture() {
    check(Expect {
        capture: APPREADY_RES,
        side: S7_ANSWER,
        activity: ACT_APPREADY,
        sequence_number: 0,
        opnum: opnum::CONTROL,
        body_len: 52,
        ndr: response(1340, 0x20),
        first_block: 0x8112,
    });
}

#[test]
fn im0_read_request_captures() {
    for (capture, seq) in [(IM0_READ_REQ, 4), (IM0_READ_REQ_IF, 3)] {
        check(Expect {
            capture,
            side: S7_CALL,
            activity: ACT_READ,
            sequence_number: seq,
            opnum: opnum::READ,
            body_len: 84,
            ndr: request(0x8040, 0x40),
            first_block: 0x0009,
        });
    }
}

#[test]
fn im0_read_response_captures() {
    for (capture, seq) in [(IM0_READ_RES, 4), (IM0_READ_RES_IF, 3)] {
        check(Expect {
            capture,
            side: PNET_ANSWER,
            activity: ACT_READ,
            sequence_number: seq,
            opnum: opnum::READ,
            body_len: 144,
            ndr: response(0x8040, 0x7c),
            first_block: 0x8009,
        });
    }
}

#[test]
fn little_endian_pdu_re_emitted_big_endian() {
    let le = rpc_pdu(CONNECT_REQ);
    let pdu = Pdu::parse(&le).unwrap();
    let be_pdu = Pdu {
        header: Header {
            little_endian: false,
            ..pdu.header
        },
        ..pdu
    };
    let be = be_pdu.to_vec().unwrap();
    assert_eq!(be.len(), le.len());
    assert_eq!(be[4], DREP_BIG_ENDIAN);
    // The object UUID in field order, LengthOfBody 577 and ArgsMaximum 0x22d big-endian.
    assert_eq!(
        &be[8..16],
        &[0xde, 0xa0, 0x00, 0x00, 0x6c, 0x97, 0x11, 0xd1]
    );
    assert_eq!(&be[74..76], &[0x02, 0x41]);
    assert_eq!(&be[80..84], &[0x00, 0x00, 0x02, 0x2d]);
    assert_eq!(&be[100..], &le[100..]);
    let back = Pdu::parse(&be).unwrap();
    assert_eq!(
        back.header,
        Header {
            little_endian: false,
            ..pdu.header
        }
    );
    assert_eq!((back.ndr, back.blocks), (pdu.ndr, pdu.blocks));
    let mut h = Header::parse(&Packet::new_checked(&be[..]).unwrap()).unwrap();
    h.little_endian = true;
    assert_eq!(h, pdu.header);
    // And back to little-endian: the original bytes.
    assert_eq!(Pdu { header: h, ..back }.to_vec().unwrap(), le);
}

#[test]
fn response_status_is_stored_in_drep_order() {
    let status = PnioStatus::from_bytes([0xdb, 0x81, 0x02, 0x09]);
    let ndr = NdrResponse::for_blocks(status, 0x22d, 0);
    let mut b = [0u8; NDR_LEN];
    ndr.emit(&mut b, true).unwrap();
    assert_eq!(&b[..4], &[0x09, 0x02, 0x81, 0xdb]);
    assert_eq!(&b[8..12], &[0x2d, 0x02, 0x00, 0x00]);
    assert_eq!(NdrResponse::parse(&b, true).unwrap(), ndr);
    ndr.emit(&mut b, false).unwrap();
    assert_eq!(&b[..4], &[0xdb, 0x81, 0x02, 0x09]);
    assert_eq!(NdrResponse::parse(&b, false).unwrap(), ndr);
    assert!(ndr.emit(&mut b[..19], false).is_err());
    assert!(NdrResponse::parse(&b[..19], false).is_err());
    assert!(NdrRequest::parse(&b[..0], true).is_err());
}

#[test]
fn reply_echoes_the_call() {
    let req = Pdu::parse(&rpc_pdu(PRMEND_REQ)).unwrap().header;
    let res = Pdu::parse(&rpc_pdu(PRMEND_RES)).unwrap().header;
    let reply = req.reply(0);
    assert_eq!(reply.flags1, REPLY_FLAGS1);
    // p-net answers big-endian with NoFack | Idempotent; otherwise the same header.
    assert_eq!(
        Header {
            little_endian: false,
            flags1: 0x28,
            body_len: 52,
            ..reply
        },
        res
    );
    // The S7 answers with LastFragment | NoFack, little-endian, its boot time.
    let req = Pdu::parse(&rpc_pdu(APPREADY_REQ)).unwrap().header;
    let res = Pdu::parse(&rpc_pdu(APPREADY_RES)).unwrap().header;
    assert_eq!(
        Header {
            little_endian: true,
            body_len: 52,
            ..req.reply(0x5156)
        },
        res
    );
    let fresh = Header::request(
        object_uuid(1, 2, 0x0493),
        DEVICE_INTERFACE,
        req.activity,
        0,
        opnum::CONNECT,
    );
    assert_eq!((fresh.flags1, fresh.interface_version), (0x20, 1));
    assert_eq!(
        fresh.to_string(),
        "DCE/RPC request Connect seq 0 act 14af198a-1234-1056-8079-8cf319cd19f8 BE body 0"
    );
}

#[test]
fn uuids() {
    assert_eq!(object_uuid(1, 2, 0x0493).to_string(), OBJECT_DEVICE);
    assert_eq!(DEVICE_INTERFACE.to_string(), IFACE_DEVICE);
    assert_eq!(CONTROLLER_INTERFACE.to_string(), IFACE_CONTROLLER);
    assert_eq!(
        SUPERVISOR_INTERFACE.to_string(),
        "dea00003-6c97-11d1-8271-00a02442df7d"
    );
    assert_eq!(
        PARAMETER_SERVER_INTERFACE.to_string(),
        "dea00004-6c97-11d1-8271-00a02442df7d"
    );
    assert_eq!(
        EPM_INTERFACE.to_string(),
        "e1af8308-5d1f-11c9-91a4-08002b14a0fa"
    );
    let cpu = Pdu::parse(&rpc_pdu(APPREADY_REQ)).unwrap().header.object;
    assert_eq!(object_uuid_parts(&cpu), Some((0x1064, 0x010e, 0x002a)));
    assert_eq!(object_uuid_parts(&DEVICE_INTERFACE), None);
    assert_eq!(opnum::name(5), Some("ReadImplicit"));
    assert_eq!(opnum::name(6), None);
    for v in 0..=255u8 {
        assert_eq!(u8::from(PacketType::from(v)), v);
    }
}

#[test]
fn malformed_pdus_are_refused() {
    let good = rpc_pdu(PRMEND_REQ);
    for n in 0..good.len() {
        assert!(Packet::new_checked(&good[..n]).is_err(), "{n} bytes");
        assert!(Pdu::parse(&good[..n]).is_err());
    }
    let mut bad = good.clone();
    bad[0] = 5;
    assert!(Pdu::parse(&bad).is_err(), "RPCVersion 5");
    let mut bad = good.clone();
    bad[4] = 0x20;
    assert!(Pdu::parse(&bad).is_err(), "DREP integer representation 2");
    let mut frag = good.clone();
    frag[2] |= flags1::FRAGMENT;
    assert!(Header::parse(&Packet::new_checked(&frag[..]).unwrap()).is_ok());
    assert!(Pdu::parse(&frag).is_err(), "a fragment");
    let mut ping = good.clone();
    ping[1] = 1;
    assert!(Pdu::parse(&ping).is_err(), "a ping has no NDR header");
    // LengthOfBody 19: the NDR header does not fit the body.
    let mut short = good.clone();
    short[74..76].copy_from_slice(&19u16.to_le_bytes());
    assert!(Pdu::parse(&short).is_err());
    // Bytes after the body are ignored.
    let mut long = good.clone();
    long.extend_from_slice(&[1, 2, 3, 4]);
    let pdu = Pdu::parse(&long).unwrap();
    assert_eq!(pdu.to_vec().unwrap(), good);
    assert_eq!(Packet::new_checked(&long[..]).unwrap().body().len(), 52);
}

#[test]
fn emission_errors() {
    let bytes = rpc_pdu(PRMEND_RES);
    let pdu = Pdu::parse(&bytes).unwrap();
    let mut buf = vec![0u8; pdu.buffer_len() - 1];
    assert!(pdu.emit(&mut buf).is_err());
    assert!(pdu.header.emit(&mut buf[..79]).is_err());
    let mismatched = Pdu {
        ndr: Ndr::Request(NdrRequest::for_blocks(0x20, 32)),
        ..pdu
    };
    assert!(mismatched.to_vec().is_err());
    let fragment = Pdu {
        header: Header {
            flags1: flags1::FRAGMENT,
            ..pdu.header
        },
        ..pdu
    };
    assert!(fragment.to_vec().is_err());
    let big = vec![0u8; usize::from(u16::MAX) - NDR_LEN];
    let v = emit_request(&pdu.header, 0, &big).unwrap();
    assert_eq!(v.len(), HEADER_LEN + usize::from(u16::MAX));
    let too_big = vec![0u8; usize::from(u16::MAX) - NDR_LEN + 1];
    assert!(emit_request(&pdu.header, 0, &too_big).is_err());
    assert!(emit_response(&pdu.header, PnioStatus::OK, 0, &too_big).is_err());
    assert_eq!(NdrRequest::for_blocks(7, usize::MAX).args_length, u32::MAX);
}

#[test]
fn packet_setters_write_in_the_buffer_drep() {
    let mut buf = [0u8; HEADER_LEN + 4];
    let mut p = Packet::new_unchecked(&mut buf[..]);
    p.set_version(RPC_VERSION);
    p.set_drep(true);
    p.set_body_len(4);
    p.set_opnum(opnum::READ_IMPLICIT);
    p.set_serial(0x1234);
    p.set_interface_uuid(&DEVICE_INTERFACE);
    p.body_mut().copy_from_slice(&[1, 2, 3, 4]);
    assert_eq!(p.body(), &[1, 2, 3, 4]);
    assert_eq!((p.serial_high(), p.serial_low()), (0x12, 0x34));
    assert_eq!(&buf[68..70], &[5, 0]);
    assert_eq!(&buf[24..28], &[0x01, 0x00, 0xa0, 0xde]);
    let p = Packet::new_checked(&buf[..]).unwrap();
    assert_eq!(p.interface_uuid(), DEVICE_INTERFACE);
    assert_eq!(p.to_string(), format!("{}", Header::parse(&p).unwrap()));
    assert_eq!(
        Packet::new_unchecked(&buf[..10]).to_string(),
        "DCE/RPC (malformed)"
    );
}

#[test]
fn status_descriptions() {
    let d = |b: [u8; 4]| describe(PnioStatus::from_bytes(b));
    assert_eq!(d([0, 0, 0, 0]), "OK");
    assert_eq!(
        d([0xdb, 0x81, 0x02, 0x09]),
        "Connect refused: IOCRBlockReq field 9 (FrameID)"
    );
    assert_eq!(
        d([0xdb, 0x81, 0x02, 0x11]),
        "Connect refused: IOCRBlockReq field 17 (IOCRTagHeader)"
    );
    assert_eq!(
        d([0xdb, 0x81, 0x01, 0x09]),
        "Connect refused: ARBlockReq field 9 (ARProperties)"
    );
    assert_eq!(
        d([0xdb, 0x81, 0x04, 0x0a]),
        "Connect refused: AlarmCRBlockReq field 10 (MaxAlarmDataLength)"
    );
    assert_eq!(
        d([0xdb, 0x81, 0x03, 0x00]),
        "Connect refused: ExpectedSubmoduleBlockReq field 0 (BlockType)"
    );
    assert_eq!(
        d([0xdb, 0x81, 0x07, 0x63]),
        "Connect refused: ARRPCBlockReq field 99"
    );
    assert_eq!(
        d([0xdb, 0x81, 0x40, 0x04]),
        "Connect refused: CMRPC: out of AR resources"
    );
    assert_eq!(
        d([0xdb, 0x81, 0x40, 0x07]),
        "Connect refused: CMRPC code 0x07"
    );
    assert_eq!(
        d([0xdb, 0x81, 0x3d, 0x00]),
        "Connect refused: device CM state machine (CMDEV), code 0x00"
    );
    assert_eq!(
        d([0xde, 0x80, 0xb0, 0x00]),
        "Read failed: access: invalid index"
    );
    assert_eq!(
        d([0xdf, 0x80, 0xb6, 0x05]),
        "Write failed: access: access denied, user code 0x05"
    );
    assert_eq!(
        d([0xde, 0x80, 0xa9, 0x00]),
        "Read failed: application: feature not supported"
    );
    assert_eq!(
        d([0xde, 0x80, 0xc3, 0x00]),
        "Read failed: resource: resource unavailable"
    );
    assert_eq!(
        d([0xde, 0x80, 0xbe, 0x00]),
        "Read failed: access error 0xbe"
    );
    assert_eq!(d([0xdf, 0x80, 0x12, 0x00]), "Write failed: ErrorCode1 0x12");
    assert_eq!(
        d([0xde, 0x81, 0x08, 0x0a]),
        "Read failed: faulty record, field 10"
    );
    assert_eq!(
        d([0xcf, 0x81, 0xfd, 0x05]),
        "RTA error: AR abort: consumer data hold timer expired"
    );
    assert_eq!(
        d([0xcf, 0x81, 0xfd, 0x0b]),
        "RTA error: AR abort: alarm indication with error"
    );
    assert_eq!(
        d([0xcf, 0x81, 0xfd, 0x77]),
        "RTA error: AR abort, code 0x77"
    );
    assert_eq!(
        d([0xdd, 0x82, 0x12, 0x34]),
        "Control refused: manufacturer specific 0x12 0x34"
    );
    assert_eq!(
        d([0xdc, 0x81, 0x55, 0x01]),
        "Release refused: ErrorCode1 0x55, ErrorCode2 0x01"
    );
    assert_eq!(
        d([0x42, 0x17, 0x01, 0x02]),
        "ErrorCode 0x42: ErrorDecode 0x17, ErrorCode1 0x01, ErrorCode2 0x02"
    );
    assert_eq!(
        StatusText(PnioStatus::from_u32(0xda81_0000)).to_string(),
        "AlarmAck failed: ErrorCode1 0x00, ErrorCode2 0x00"
    );
}

fn any_header() -> impl Strategy<Value = Header> {
    (
        (
            any::<u8>(),
            any::<u8>(),
            any::<u8>(),
            any::<bool>(),
            any::<u16>(),
        ),
        (any::<[u8; 16]>(), any::<[u8; 16]>(), any::<[u8; 16]>()),
        (any::<u32>(), any::<u32>(), any::<u32>(), any::<u16>()),
        (
            any::<u16>(),
            any::<u16>(),
            any::<u16>(),
            any::<u16>(),
            any::<u8>(),
        ),
    )
        .prop_map(
            |(
                (packet_type, flags1, flags2, little_endian, serial),
                (object, interface, activity),
                (server_boot_time, interface_version, sequence_number, opnum),
                (interface_hint, activity_hint, body_len, fragment_number, auth_protocol),
            )| Header {
                packet_type: PacketType::from(packet_type),
                flags1,
                flags2,
                little_endian,
                serial,
                object: Uuid(object),
                interface: Uuid(interface),
                activity: Uuid(activity),
                server_boot_time,
                interface_version,
                sequence_number,
                opnum,
                interface_hint,
                activity_hint,
                body_len,
                fragment_number,
                auth_protocol,
            },
        )
}

/// Runs every parser and getter on `bytes`; must never panic.
fn exercise(bytes: &[u8]) {
    let p = Packet::new_unchecked(bytes);
    let _ = p.to_string();
    if p.check_len().is_ok() {
        let h = Header::parse(&p).unwrap();
        assert_eq!(usize::from(h.body_len), p.body().len());
        let _ = (p.drep(), p.serial(), p.version(), h.to_string());
        if let Ok((ndr, _)) = parse_body(h.packet_type, h.little_endian, p.body()) {
            let _ = ndr.status().map(describe);
        }
    }
    if let Ok(pdu) = Pdu::parse(bytes) {
        // Identical up to the DREP character and float formats, which emit as 0.
        let out = pdu.to_vec().unwrap();
        let mut expected = bytes[..pdu.buffer_len()].to_vec();
        expected[4] &= 0xf0;
        expected[5..7].fill(0);
        assert_eq!(out, expected);
    }
    let _ = parse_pdu(bytes);
}

proptest! {
    #[test]
    fn parsing_arbitrary_bytes_never_panics(
        mut bytes in proptest::collection::vec(any::<u8>(), 0..1600),
        shape in any::<bool>(),
        little_endian in any::<bool>(),
        body_slack in 0usize..4,
    ) {
        exercise(&bytes);
        // Mostly valid headers too, to reach the NDR and block code.
        if shape && bytes.len() >= HEADER_LEN {
            bytes[0] = RPC_VERSION;
            bytes[1] &= 0x03;
            bytes[4] = if little_endian { 0x10 } else { 0x00 };
            let body = (bytes.len() - HEADER_LEN).saturating_sub(body_slack);
            let body = u16::try_from(body).unwrap();
            let b = if little_endian { body.to_le_bytes() } else { body.to_be_bytes() };
            bytes[74..76].copy_from_slice(&b);
            exercise(&bytes);
        }
    }

    #[test]
    fn header_round_trips_in_both_dreps(h in any_header()) {
        for little_endian in [false, true] {
            let h = Header { little_endian, ..h };
            let mut buf = vec![0xa5u8; HEADER_LEN + usize::from(h.body_len)];
            h.emit(&mut buf).unwrap();
            let p = Packet::new_checked(&buf[..]).unwrap();
            prop_assert_eq!(Header::parse(&p).unwrap(), h);
        }
    }

    #[test]
    fn pdu_round_trips(
        h in any_header(),
        is_request in any::<bool>(),
        words in any::<[u32; 5]>(),
        blocks in proptest::collection::vec(any::<u8>(), 0..300),
    ) {
        let ndr = if is_request {
            Ndr::Request(NdrRequest {
                args_maximum: words[0],
                args_length: words[1],
                maximum_count: words[2],
                offset: words[3],
                actual_count: words[4],
            })
        } else {
            Ndr::Response(NdrResponse {
                status: PnioStatus::from_u32(words[0]),
                args_length: words[1],
                maximum_count: words[2],
                offset: words[3],
                actual_count: words[4],
            })
        };
        let header = Header {
            packet_type: ndr.packet_type(),
            flags1: h.flags1 & !flags1::FRAGMENT,
            body_len: u16::try_from(NDR_LEN + blocks.len()).unwrap(),
            ..h
        };
        let pdu = Pdu { header, ndr, blocks: &blocks };
        let bytes = pdu.to_vec().unwrap();
        prop_assert_eq!(Pdu::parse(&bytes).unwrap(), pdu);
        let _ = describe(PnioStatus::from_u32(words[0]));
    }
}
