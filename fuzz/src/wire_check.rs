// SPDX-License-Identifier: MIT OR Apache-2.0
//! What our own code puts on the wire must parse with our own parsers, whatever it was fed:
//! a controller or simulated device that answers garbage with a malformed frame is a bug even
//! when nothing panics.

use procimg_nic::MAX_FRAME;
use procimg_profinet::wire::ethernet::{self, ETHERTYPE_PROFINET};
use procimg_profinet::wire::rpc::{self, Header, PacketType};
use procimg_profinet::wire::rt::{self, FrameIdClass};
use procimg_profinet::wire::rta_pdu::{self, RtaPdu};
use procimg_profinet::wire::{MacAddress, dcp, lldp};

/// Checks an Ethernet frame `who` sent: at most [`MAX_FRAME`] bytes, a whole Ethernet header,
/// EtherType 0x8892, and a PDU that parses as what its FrameID says (DCP, RTA) or, for
/// cyclic frames, is long enough for the smallest C_SDU and the APDU status; or EtherType
/// 0x88CC and an LLDPDU that parses (a device's announcements).
pub fn emitted_frame(who: &str, frame: &[u8]) {
    assert!(
        frame.len() <= MAX_FRAME,
        "{who} sent a frame of {} bytes",
        frame.len()
    );
    let eth = ethernet::Frame::new_checked(frame)
        .unwrap_or_else(|_| panic!("{who} sent a frame without a whole Ethernet header"));
    if eth.ethertype() == lldp::ETHERTYPE_LLDP {
        let pdu = eth.payload();
        let p = lldp::Packet::new_checked(pdu)
            .unwrap_or_else(|_| panic!("{who} sent a truncated LLDPDU: {pdu:02x?}"));
        if let Err(e) = lldp::Repr::parse(&p) {
            panic!("{who} sent an LLDPDU that does not parse ({e}): {pdu:02x?}");
        }
        return;
    }
    assert_eq!(
        eth.ethertype(),
        ETHERTYPE_PROFINET,
        "{who} sent a frame that is not PROFINET"
    );
    assert_ne!(eth.src(), MacAddress::default(), "{who} sent from MAC 0");
    let pdu = eth.payload();
    let frame_id = match pdu {
        [hi, lo, ..] => u16::from_be_bytes([*hi, *lo]),
        _ => panic!("{who} sent a PROFINET frame without a FrameID"),
    };
    match FrameIdClass::of(frame_id) {
        FrameIdClass::Dcp => {
            let p = dcp::Packet::new_checked(pdu)
                .unwrap_or_else(|_| panic!("{who} sent a truncated DCP PDU: {pdu:02x?}"));
            if let Err(e) = dcp::Repr::parse(&p) {
                panic!("{who} sent a DCP PDU that does not parse ({e}): {pdu:02x?}");
            }
        }
        FrameIdClass::AlarmHigh | FrameIdClass::AlarmLow => {
            let p = rta_pdu::Packet::new_checked(pdu)
                .unwrap_or_else(|_| panic!("{who} sent a truncated RTA PDU: {pdu:02x?}"));
            if let Err(e) = RtaPdu::parse(&p) {
                panic!("{who} sent an RTA PDU that does not parse ({e}): {pdu:02x?}");
            }
        }
        class if class.is_cyclic() => assert!(
            pdu.len() >= 2 + rt::MIN_DATA_LENGTH + 4,
            "{who} sent a cyclic frame of {} bytes",
            pdu.len()
        ),
        class => panic!("{who} sent FrameID {frame_id:#06x} ({class:?})"),
    }
}

/// Checks a UDP payload `who` sent: a whole connectionless RPC PDU, and for an unfragmented
/// request or response the NDR header.
pub fn emitted_datagram(who: &str, payload: &[u8]) {
    let p = rpc::Packet::new_checked(payload)
        .unwrap_or_else(|_| panic!("{who} sent a malformed RPC PDU: {payload:02x?}"));
    let h = Header::parse(&p).expect("checked");
    if matches!(h.packet_type, PacketType::Request | PacketType::Response) && !h.is_fragment() {
        assert!(
            rpc::Pdu::parse(payload).is_ok(),
            "{who} sent a {} without a whole NDR header: {payload:02x?}",
            h.packet_type
        );
    }
}
