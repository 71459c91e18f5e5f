// SPDX-License-Identifier: MIT OR Apache-2.0
//! Connectionless DCE/RPC PDUs (UDP payloads of port 34964): the header view and its round
//! trip in both byte orders, the NDR request and response headers, whole PDUs, and the words
//! for a PNIOStatus.
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_profinet::wire::PnioStatus;
use procimg_profinet::wire::rpc::{
    self, Header, NDR_LEN, Ndr, Packet, PacketType, Pdu, describe, opnum,
};

fuzz_target!(|data: &[u8]| {
    let p = Packet::new_unchecked(data);
    let _ = p.to_string();
    if p.check_len().is_ok() {
        header(data, &p);
    } else {
        assert!(Header::parse(&p).is_err());
        assert!(Pdu::parse(data).is_err());
    }
    if let Ok(pdu) = Pdu::parse(data) {
        whole_pdu(data, &pdu);
    }
    // Any four bytes are a status that can be put in words.
    if let Some(s) = data.get(..4) {
        let _ = describe(PnioStatus::from_bytes([s[0], s[1], s[2], s[3]]));
    }
});

fn header(data: &[u8], p: &Packet<&[u8]>) {
    let h = Header::parse(p).expect("a checked packet parses");
    assert_eq!(usize::from(h.body_len), p.body().len());
    let _ = (
        h.to_string(),
        opnum::name(h.opnum),
        rpc::object_uuid_parts(&h.object),
    );
    let _ = (p.drep(), p.serial(), p.version(), p.fragment_number());
    // Emitting the header over a copy and parsing again gives the same header, in either
    // byte order.
    for little_endian in [h.little_endian, !h.little_endian] {
        let h = Header { little_endian, ..h };
        let mut copy = data.to_vec();
        h.emit(&mut copy).expect("the copy holds the header");
        let q = Packet::new_checked(&copy[..]).expect("emitted headers check");
        assert_eq!(Header::parse(&q), Ok(h));
    }
    // NDR headers in either role and byte order.
    for packet_type in [PacketType::Request, PacketType::Response, h.packet_type] {
        let Ok((ndr, blocks)) = rpc::parse_body(packet_type, h.little_endian, p.body()) else {
            continue;
        };
        assert_eq!(blocks.len() + NDR_LEN, p.body().len());
        let mut buf = [0u8; NDR_LEN];
        ndr.emit(&mut buf, h.little_endian).expect("20 bytes");
        assert_eq!(Ndr::parse(packet_type, &buf, h.little_endian), Ok(ndr));
        assert_eq!(&buf[..], &p.body()[..NDR_LEN]);
        let _ = (
            ndr.is_consistent(blocks.len()),
            ndr.args_length(),
            ndr.maximum_count(),
        );
        if let Some(s) = ndr.status() {
            let _ = rpc::StatusText(s).to_string();
        }
    }
}

fn whole_pdu(data: &[u8], pdu: &Pdu<'_>) {
    assert_eq!(pdu.header.packet_type, pdu.ndr.packet_type());
    // A parsed PDU emits again: identical up to the DREP character and float formats, which
    // the header does not keep and emits as 0.
    let out = pdu.to_vec().expect("a parsed PDU emits");
    assert_eq!(out.len(), pdu.buffer_len());
    let mut expected = data[..pdu.buffer_len()].to_vec();
    expected[4] &= 0xf0;
    expected[5..7].fill(0);
    assert_eq!(out, expected);
    assert_eq!(Pdu::parse(&out).as_ref(), Ok(pdu));
    // The builders make PDUs that parse as what they were given.
    let blocks = pdu.blocks;
    match pdu.ndr {
        Ndr::Request(r) => {
            let v = rpc::emit_request(&pdu.header, r.args_maximum, blocks).expect("emits");
            let back = Pdu::parse(&v).expect("parses");
            assert!(back.ndr.is_consistent(blocks.len()));
            assert_eq!(back.blocks, blocks);
        }
        Ndr::Response(r) => {
            let v =
                rpc::emit_response(&pdu.header, r.status, r.maximum_count, blocks).expect("emits");
            let back = Pdu::parse(&v).expect("parses");
            assert_eq!(back.ndr.status(), Some(r.status));
            assert_eq!(back.blocks, blocks);
        }
    }
}
