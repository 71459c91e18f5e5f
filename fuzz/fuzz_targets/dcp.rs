// SPDX-License-Identifier: MIT OR Apache-2.0
//! DCP PDUs (from the FrameID on, as behind EtherType 0x8892): the packet view, the Repr and
//! its round trip, and the requesting side (`dcp_client`) reading the PDU as an answer.
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_profinet::dcp_client::{Identify, Set};
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::dcp::{self, Packet, Repr};
use procimg_profinet::wire::ethernet::{self, ETHERTYPE_PROFINET};

const CONTROLLER: MacAddress = MacAddress([0x02, 0, 0, 0, 0, 1]);
const DEVICE: MacAddress = MacAddress([0x02, 0, 0, 0, 0, 2]);

fuzz_target!(|data: &[u8]| {
    let p = Packet::new_unchecked(data);
    // Display works on anything, checked or not.
    let _ = p.to_string();
    if let Ok(r) = Repr::parse(&p) {
        round_trip(&p, &r);
        let _ = r.to_string();
        let _ = (
            r.name_of_station(),
            r.device_vendor(),
            r.ip(),
            r.device_id(),
            r.mac(),
        );
        let _ = r.set_result().count();
        let _ = dcp::response_delay_ns(DEVICE, r.response_delay);
    }
    client(data);
});

/// parse → emit → parse gives the same Repr.
fn round_trip(p: &Packet<&[u8]>, r: &Repr) {
    match r.to_vec() {
        Ok(bytes) => {
            assert_eq!(bytes.len(), r.buffer_len());
            // Emission adds at most the pad after an odd last block that parsing tolerated.
            assert!(bytes.len() <= dcp::HEADER_LEN + usize::from(p.data_length()) + 1);
            let q = Packet::new_checked(&bytes[..]).expect("emitted PDUs are whole");
            assert_eq!(usize::from(q.data_length()), bytes.len() - dcp::HEADER_LEN);
            let back = Repr::parse(&q).expect("emitted PDUs parse");
            assert_eq!(&back, r);
        }
        // The only thing a parsed PDU cannot emit: DCPDataLength 65535 ending in an odd block
        // without its pad, which needs one byte more than a u16 counts.
        Err(_) => assert!(r.data_len() > usize::from(u16::MAX)),
    }
}

/// The PDU in a frame from the device to the controller, as `dcp_client` reads answers.
fn client(pdu: &[u8]) {
    let eth = ethernet::Repr {
        dst: CONTROLLER,
        src: DEVICE,
        vlan: None,
        ethertype: ETHERTYPE_PROFINET,
    };
    let mut frame = vec![0u8; eth.buffer_len()];
    eth.emit(&mut frame).expect("sized for the header");
    frame.extend_from_slice(pdu);
    // Answer the transaction the PDU names, so that the client looks further than the Xid.
    let xid = Packet::new_checked(pdu).map_or(0, |p| p.xid());
    let mut identify = Identify::new(xid);
    if identify.on_frame(&frame) {
        assert_eq!(identify.devices().len(), 1);
        assert!(!identify.on_frame(&frame), "a device is listed once");
    }
    let set = Set::ip(
        xid,
        DEVICE,
        [192, 168, 0, 2],
        [255, 255, 255, 0],
        [0; 4],
        false,
    );
    if let Some(outcome) = set.on_frame(&frame) {
        let _ = outcome.to_string();
    }
    let _ = Set::name(xid, DEVICE, "fuzz", true).on_frame(&frame);
}
