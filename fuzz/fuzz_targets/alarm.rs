// SPDX-License-Identifier: MIT OR Apache-2.0
//! RTA PDUs (from the FrameID on, as behind EtherType 0x8892): DATA, ACK, NACK and ERR with
//! their round trips, and the blocks a DATA-RTA carries (AlarmNotification with maintenance
//! and diagnosis items, AlarmAck, others) on their own.
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_profinet::wire::alarm::{AlarmAck, AlarmBlock, AlarmItem, AlarmNotification};
use procimg_profinet::wire::common::blocks;
use procimg_profinet::wire::rta_pdu::{
    ErrRta, HEADER_LEN, Packet, RTA_HEADER_LEN, RtaHeader, RtaPdu,
};

fuzz_target!(|data: &[u8]| {
    let p = Packet::new_unchecked(data);
    let _ = p.to_string();
    if let Ok(pdu) = RtaPdu::parse(&p) {
        rta_pdu(&p, &pdu);
    }
    // The header alone, after the FrameID.
    if let Ok(h) = RtaHeader::parse(data.get(2..).unwrap_or(&[])) {
        let mut buf = [0u8; RTA_HEADER_LEN];
        h.emit(&mut buf).expect("12 bytes");
        assert_eq!(RtaHeader::parse(&buf), Ok(h));
    }
    // The blocks alone: at the start of the input, and where a VarPart would start.
    for b in [data, data.get(HEADER_LEN..).unwrap_or(&[])] {
        alarm_blocks(b);
    }
    if let Ok(e) = ErrRta::parse(data) {
        let _ = (e.to_string(), e.abort_code());
        assert_eq!(e.buffer_len(), data.len());
    }
});

fn rta_pdu(p: &Packet<&[u8]>, pdu: &RtaPdu) {
    let _ = (pdu.to_string(), pdu.notification(), pdu.alarm_ack());
    // Reserved bits and block versions are normalised, nothing else: the PDU emits to the
    // same length and parses back to the same value.
    let v = pdu.to_vec().expect("a parsed PDU emits");
    assert_eq!(v.len(), HEADER_LEN + usize::from(p.var_part_len()));
    assert_eq!(v.len(), pdu.buffer_len());
    let q = Packet::new_checked(&v[..]).expect("emitted PDUs are whole");
    assert_eq!(RtaPdu::parse(&q).as_ref(), Ok(pdu));
}

fn alarm_blocks(data: &[u8]) {
    if let Ok(n) = AlarmNotification::parse(data) {
        notification(&n);
    }
    if let Ok(a) = AlarmAck::parse(data) {
        let mut buf = [0u8; AlarmAck::LEN];
        a.emit(&mut buf).expect("AlarmAck::LEN bytes");
        assert_eq!(AlarmAck::parse(&buf), Ok(a));
    }
    for (_, block) in blocks(data).map_while(Result::ok) {
        if let Ok(b) = AlarmBlock::parse(block) {
            assert_eq!(b.buffer_len(), block.len());
        }
    }
}

fn notification(n: &AlarmNotification) {
    let _ = (
        n.alarm_type.to_string(),
        n.specifier.to_u16(),
        n.diagnosis(),
    );
    if let Some(m) = &n.maintenance {
        let _ = (m.maintenance_required(), m.maintenance_demanded());
    }
    if let Some(item) = &n.item {
        // Item data never fails to parse: it is diagnosis or kept as it is.
        if let AlarmItem::Other { usi, data } = item {
            assert_eq!(&AlarmItem::parse(*usi, data), item);
        }
        if let Some(d) = item.diagnosis() {
            for e in &d.entries {
                let p = e.channel_properties;
                let _ = (
                    p.specifier(),
                    p.direction(),
                    p.data_type(),
                    p.accumulative(),
                );
            }
        }
    }
    let mut buf = vec![0u8; n.buffer_len()];
    n.emit(&mut buf).expect("buffer_len bytes");
    assert_eq!(AlarmNotification::parse(&buf).as_ref(), Ok(n));
}
