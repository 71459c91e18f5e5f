// SPDX-License-Identifier: MIT OR Apache-2.0
//! Whole Ethernet frames: the Ethernet header (tagged or not) and, behind EtherType 0x8892,
//! the cyclic RT frame view (FrameID, C_SDU, APDU status).
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_profinet::wire::ethernet::{self, ETHERTYPE_PROFINET};
use procimg_profinet::wire::rt::{self, FrameIdClass};

fuzz_target!(|data: &[u8]| {
    // Safe on any buffer, checked or not.
    let _ = ethernet::Frame::new_unchecked(data).is_tagged();
    let Ok(frame) = ethernet::Frame::new_checked(data) else {
        return;
    };
    let eth = ethernet::Repr::parse(&frame).expect("a checked frame parses");
    assert_eq!(eth.buffer_len(), frame.header_len());

    // Emitting the header over a copy gives the same bytes: every header bit is in the Repr.
    let mut copy = data.to_vec();
    eth.emit(&mut copy[..eth.buffer_len()])
        .expect("the copy holds the header");
    assert_eq!(copy, data);
    let again = ethernet::Frame::new_checked(&copy[..]).expect("re-emitted header");
    assert_eq!(ethernet::Repr::parse(&again), Ok(eth));
    assert_eq!(again.payload(), frame.payload());

    if eth.ethertype != ETHERTYPE_PROFINET {
        return;
    }
    let pdu = frame.payload();
    // The C_SDU length comes from the IOCR, not the frame: try the smallest one, the one that
    // fills the frame, and one taken from the frame's first byte.
    let lengths = [
        rt::MIN_DATA_LENGTH,
        pdu.len().saturating_sub(6),
        rt::MIN_DATA_LENGTH + usize::from(pdu.first().copied().unwrap_or(0)) * 4,
    ];
    for n in lengths {
        cyclic(pdu, n);
    }
});

fn cyclic(pdu: &[u8], data_length: usize) {
    let p = rt::Packet::new_unchecked(pdu, data_length);
    let Ok(()) = p.check_len() else {
        assert!(rt::Repr::parse(&p).is_err());
        return;
    };
    // Once checked, no getter panics.
    let _ = (p.frame_id(), p.data(), p.cycle_counter(), p.data_status());
    let _ = (p.transfer_status(), p.frame_len());
    let class = FrameIdClass::of(p.frame_id());
    match rt::Repr::parse(&p) {
        Ok(r) => {
            assert!(class.is_cyclic());
            assert_eq!(r.buffer_len(), p.frame_len());
            let _ = r.data_usable();
            let _ = rt::cycle_counter_is_newer(r.cycle_counter, r.frame_id);
            // Emitting over a copy reproduces the frame; the C_SDU is left as it is.
            let mut copy = pdu.to_vec();
            let mut q = rt::Packet::new_unchecked(&mut copy[..], data_length);
            r.emit(&mut q).expect("the copy holds the frame");
            assert_eq!(copy, pdu);
            let back = rt::Packet::new_checked(&copy[..], data_length).expect("re-emitted");
            assert_eq!(rt::Repr::parse(&back), Ok(r));
        }
        Err(_) => assert!(!class.is_cyclic()),
    }
}
