// SPDX-License-Identifier: MIT OR Apache-2.0
//! The frames procimg's PROFINET emitters produce, dissected by Wireshark's tshark: nothing
//! malformed, no error-level expert item, and the dissector reads what we meant.

use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::dcp;
use procimg_profinet::wire::ethernet::{self, ETHERTYPE_PROFINET, VlanTag};
use procimg_profinet::wire::rt::{self, data_status};
use procimg_testkit::fixtures::profinet_capture;

const PLC: MacAddress = MacAddress([0x02, 0x00, 0x00, 0x00, 0x00, 0x01]);
const DEVICE: MacAddress = MacAddress([0x02, 0x00, 0x00, 0x00, 0x00, 0x02]);

/// A whole cyclic frame: tagged Ethernet header, FrameID, C_SDU, APDU status.
fn cyclic(frame_id: u16, data: &[u8], cycle_counter: u16, status: u8) -> Vec<u8> {
    let eth = ethernet::Repr {
        dst: DEVICE,
        src: PLC,
        vlan: Some(VlanTag::RT),
        ethertype: ETHERTYPE_PROFINET,
    };
    let repr = rt::Repr {
        frame_id,
        data_length: data.len().max(rt::MIN_DATA_LENGTH),
        cycle_counter,
        data_status: status,
        transfer_status: 0,
    };
    let mut buf = vec![0u8; eth.buffer_len() + repr.buffer_len()];
    eth.emit(&mut buf).unwrap();
    let mut p = rt::Packet::new_unchecked(&mut buf[eth.buffer_len()..], repr.data_length);
    p.data_mut()[..data.len()].copy_from_slice(data);
    repr.emit(&mut p).unwrap();
    buf
}

#[test]
fn cyclic_frames_dissect_clean() {
    let io = [0x80u8, 0x80, 0x80, 0x12, 0x80, 0x80, 0x34, 0x80];
    let frames = vec![
        cyclic(0x8001, &io, 0xb800, data_status::OPERATE),
        cyclic(0x8000, &io, 0xb820, data_status::CLEAR),
        cyclic(0xc001, &[0x80; 300], 0x0020, data_status::OPERATE),
        cyclic(0x8002, &[0u8; 1440], 0x0040, data_status::OPERATE),
    ];
    let d = procimg_testkit::tshark::dissect_clean("cyclic", &frames);
    for (f, want) in d
        .iter()
        .zip(["ID:0x8001", "ID:0x8000", "ID:0xc001", "ID:0x8002"])
    {
        assert_eq!(f.protocol, "PNIO", "{f:?}");
        assert!(f.info.contains(want), "{f:?}");
    }
    assert!(d[0].info.contains("Valid,Primary,Ok,Run"), "{:?}", d[0]);
    assert!(d[1].info.contains("Stop"), "{:?}", d[1]);
    assert!(d[1].info.contains("Len:  40"), "{:?}", d[1]);
}

/// A whole DCP frame (untagged, as the S7 sends Identify) from a DCP Repr.
fn dcp_frame(dst: MacAddress, src: MacAddress, repr: &dcp::Repr) -> Vec<u8> {
    let eth = ethernet::Repr {
        dst,
        src,
        vlan: None,
        ethertype: ETHERTYPE_PROFINET,
    };
    let mut buf = vec![0u8; eth.buffer_len()];
    eth.emit(&mut buf).unwrap();
    buf.extend(repr.to_vec().expect("emits"));
    // Ethernet minimum frame (without FCS).
    if buf.len() < 60 {
        buf.resize(60, 0);
    }
    buf
}

#[test]
fn dcp_frames_dissect_clean() {
    let requests = [
        dcp::Repr::identify_all(0x1000_0001, 0x0080),
        dcp::Repr::identify_by_name(0x1000_0002, 1, "i-device"),
        dcp::Repr::set_ip(
            0x1000_0003,
            [172, 16, 2, 10],
            [255, 255, 255, 0],
            [172, 16, 2, 10],
            false,
        ),
        dcp::Repr::set_name(0x1000_0004, "rt-labs-dev", true),
        dcp::Repr::set_name(0x1000_0005, "odd", false),
        dcp::Repr::signal(0x1000_0006),
        dcp::Repr::get(0x1000_0007, &[(2, 2), (1, 2), (2, 3)]),
    ];
    let mut frames: Vec<Vec<u8>> = requests
        .iter()
        .map(|r| {
            let dst = if r.frame_id == dcp::FRAME_ID_IDENTIFY_REQUEST {
                MacAddress::DCP_IDENTIFY
            } else {
                DEVICE
            };
            dcp_frame(dst, PLC, r)
        })
        .collect();
    // A device's Identify response, as p-net sends it (captures/cm/ident_ok_pnet.hex; test
    // data of the pnio crate 0.1.0, MIT OR Apache-2.0), re-emitted by our codec.
    let ident_ok_pnet = profinet_capture("cm/ident_ok_pnet");
    let response =
        dcp::Repr::parse(&dcp::Packet::new_checked(&ident_ok_pnet[14..]).unwrap()).unwrap();
    frames.push(dcp_frame(PLC, DEVICE, &response));
    let d = procimg_testkit::tshark::dissect_clean("dcp", &frames);
    for f in &d {
        assert_eq!(f.protocol, "PN-DCP", "{f:?}");
    }
    assert!(d[0].info.contains("Ident Req"), "{:?}", d[0]);
    assert!(d[1].info.contains("i-device"), "{:?}", d[1]);
    assert!(d[2].info.contains("Set Req"), "{:?}", d[2]);
    assert!(d[3].info.contains("rt-labs-dev"), "{:?}", d[3]);
    assert!(d[6].info.contains("Get Req"), "{:?}", d[6]);
    assert!(d[7].info.contains("Ident Ok"), "{:?}", d[7]);
}

/// The check itself works: a DCP block that runs past its frame is reported.
#[test]
#[should_panic(expected = "malformed or in error")]
fn the_tshark_check_catches_a_malformed_frame() {
    let mut frame = dcp_frame(
        MacAddress::DCP_IDENTIFY,
        PLC,
        &dcp::Repr::identify_by_name(1, 1, "i-device"),
    );
    // Block length 0x0008 -> 0x00f0: the NameOfStation block now claims 240 bytes.
    frame[14 + 12 + 2..14 + 12 + 4].copy_from_slice(&0x00f0u16.to_be_bytes());
    frame[14 + 10..14 + 12].copy_from_slice(&0x00f4u16.to_be_bytes());
    procimg_testkit::tshark::dissect_clean("malformed", &[frame]);
}
