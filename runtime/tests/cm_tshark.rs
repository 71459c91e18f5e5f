// SPDX-License-Identifier: MIT OR Apache-2.0
//! Connection management and alarms through our codecs, checked twice: the S7-1515/p-net
//! exchanges re-emitted by our codecs equal the captured bytes, and frames our codecs build
//! from scratch (a Connect and PrmEnd for the demo's echo device, alarm DATA/ACK/ERR) are
//! dissected by tshark without malformed packets or error-level expert items.

use procimg_testkit::fixtures::profinet_capture as capture;
use procimg_testkit::udp::udp_frame;

use procimg_profinet::iocr_layout::{IocrLayout, SubmoduleIo};
use procimg_profinet::wire::alarm::{AlarmAck, AlarmBlock, Priority};
use procimg_profinet::wire::connect::{
    AlarmCrBlockReq, ArBlockReq, ConnectRequest, ConnectResponse, ExpectedModule,
    ExpectedSubmodule, ExpectedSubmoduleBlockReq, IocrBlockReq,
};
use procimg_profinet::wire::control::ControlBlock;
use procimg_profinet::wire::record::IodHeader;
use procimg_profinet::wire::rpc::{self, Header, Pdu, opnum};
use procimg_profinet::wire::rta_pdu::{self, RtaPdu};
use procimg_profinet::wire::{MacAddress, PnioStatus, Uuid};

/// Re-emits the PNIO blocks of an RPC PDU through the codec for the first block's type.
fn reemit_blocks(blocks: &[u8]) -> Vec<u8> {
    let block_type = u16::from_be_bytes([blocks[0], blocks[1]]);
    match block_type {
        0x0101 => ConnectRequest::parse(blocks).unwrap().to_vec().unwrap(),
        0x8101 => ConnectResponse::parse(blocks).unwrap().to_vec().unwrap(),
        0x0110 | 0x8110 | 0x0112 | 0x8112 | 0x0114 | 0x8114 => {
            let c = ControlBlock::parse(blocks).unwrap();
            let mut out = c.to_bytes().to_vec();
            out.extend_from_slice(&blocks[out.len()..]);
            out
        }
        0x0008 | 0x0009 | 0x8008 | 0x8009 => {
            let h = IodHeader::parse(blocks).unwrap();
            let mut out = h.to_bytes().to_vec();
            out.extend_from_slice(&blocks[out.len()..]);
            out
        }
        t => panic!("no codec for block type {t:04x}"),
    }
}

#[test]
fn captured_cm_exchanges_reemitted_by_our_codecs_equal_the_captures() {
    let names = [
        "cm/connect_req",
        "cm/connect_res",
        "cm/write_req",
        "cm/write_res",
        "cm/prmend_req",
        "cm/prmend_res",
        "cm/appready_req",
        "cm/appready_res",
        "alarm/im0_read_req",
        "alarm/im0_read_res",
    ];
    let mut frames = Vec::new();
    for name in names {
        let frame = capture(name);
        let pdu = Pdu::parse(&frame[42..]).unwrap_or_else(|e| panic!("{name}: {e}"));
        let blocks = reemit_blocks(pdu.blocks);
        assert_eq!(
            blocks, pdu.blocks,
            "{name}: blocks differ after re-emission"
        );
        let again = Pdu {
            header: pdu.header,
            ndr: pdu.ndr,
            blocks: &blocks,
        }
        .to_vec()
        .unwrap();
        let end = 42 + again.len();
        assert_eq!(&frame[42..end], &again[..], "{name}: RPC PDU differs");
        let mut f = frame[..42].to_vec();
        f.extend(again);
        frames.push(f);
    }
    let d = procimg_testkit::tshark::dissect_clean("cm-captured", &frames);
    assert!(d.iter().all(|f| f.protocol.starts_with("PNIO")), "{d:?}");
}

/// The demo's echo device: the DAP (no IO) and 16 bytes in, 16 bytes out.
fn echo_connect(ar_uuid: Uuid) -> ConnectRequest {
    let subs = [
        SubmoduleIo {
            api: 0,
            slot: 0,
            subslot: 1,
            input_length: 0,
            output_length: 0,
        },
        SubmoduleIo {
            api: 0,
            slot: 1,
            subslot: 1,
            input_length: 16,
            output_length: 16,
        },
    ];
    let layout = IocrLayout::new(&subs).unwrap();
    let input = IocrBlockReq::from_layout(1, 1, 0x8000, &layout.input, &subs).unwrap();
    let output = IocrBlockReq::from_layout(2, 2, 0x8001, &layout.output, &subs).unwrap();
    let module = |slot, ident, sub| ExpectedSubmoduleBlockReq {
        modules: vec![ExpectedModule {
            api: 0,
            slot,
            module_ident: ident,
            properties: 0,
            submodules: vec![sub],
        }],
    };
    ConnectRequest {
        ar: ArBlockReq::io_controller(
            ar_uuid,
            1,
            MacAddress([2, 0, 0, 0, 0, 1]),
            rpc::object_uuid(1, 0x0001, 0x0493),
            "procimgd".into(),
        ),
        iocrs: vec![input, output],
        alarm_cr: AlarmCrBlockReq::io_controller(1),
        expected: vec![
            module(
                0,
                0x0000_0001,
                ExpectedSubmodule::with_io(1, 0x0000_0001, 0, 0),
            ),
            module(
                1,
                0x0000_0020,
                ExpectedSubmodule::with_io(1, 0x0000_0001, 16, 16),
            ),
        ],
    }
}

#[test]
fn a_connect_and_prmend_built_from_scratch_dissect_clean() {
    let ar_uuid = Uuid::from_fields(0x1234_5678, 0x9abc, 0x4def, [1, 2, 3, 4, 5, 6, 7, 8]);
    let activity = Uuid::from_fields(0xaaaa_0001, 1, 0x4000, [8, 7, 6, 5, 4, 3, 2, 1]);
    let object = rpc::object_uuid(1, 0x0001, 0x0493);
    let connect = echo_connect(ar_uuid);
    let blocks = connect.to_vec().unwrap();
    // Our own request parses back to itself.
    assert_eq!(ConnectRequest::parse(&blocks).unwrap(), connect);
    let h = Header::request(object, rpc::DEVICE_INTERFACE, activity, 0, opnum::CONNECT);
    let connect_pdu = rpc::emit_request(&h, 1340, &blocks).unwrap();
    let prmend = ControlBlock::prm_end(ar_uuid, 1).to_bytes();
    let h = Header::request(object, rpc::DEVICE_INTERFACE, activity, 1, opnum::CONTROL);
    let prmend_pdu = rpc::emit_request(&h, 1340, &prmend).unwrap();
    let plc = [192, 168, 0, 1];
    let dev = [192, 168, 0, 11];
    let frames = vec![
        udp_frame(plc, dev, 0xc001, rpc::RPC_PORT, &connect_pdu),
        udp_frame(plc, dev, 0xc001, rpc::RPC_PORT, &prmend_pdu),
    ];
    let d = procimg_testkit::tshark::dissect_clean("cm-built", &frames);
    assert_eq!(d[0].protocol, "PNIO-CM");
    assert!(
        d[0].info.contains(
            "Connect request, ARBlockReq, IOCRBlockReq, IOCRBlockReq, ExpectedSubmoduleBlockReq, \
             ExpectedSubmoduleBlockReq, AlarmCRBlockReq"
        ),
        "{d:?}"
    );
    assert!(d[1].info.contains("IODControlReq Prm End"), "{d:?}");
}

#[test]
fn alarm_frames_reemitted_and_built_dissect_clean() {
    let mut frames = Vec::new();
    let mut notification = None;
    for name in [
        "alarm/alarm_process_notif",
        "alarm/alarm_diag_notif",
        "alarm/alarm_ack_rta_high_cpu",
        "alarm/alarm_ack_high_cpu",
        "alarm/alarm_err_rta_cpu",
    ] {
        let frame = capture(name);
        let eth = procimg_profinet::wire::ethernet::Frame::new_checked(&frame[..]).unwrap();
        let at = eth.header_len();
        let pdu = RtaPdu::parse(&rta_pdu::Packet::new_checked(&frame[at..]).unwrap()).unwrap();
        if notification.is_none() {
            notification = pdu.notification().cloned().map(|n| (n, pdu.header));
        }
        let again = pdu.to_vec().unwrap();
        assert_eq!(&frame[at..at + again.len()], &again[..], "{name}");
        let mut f = frame[..at].to_vec();
        f.extend(again);
        frames.push(f);
    }
    // Built from scratch: the controller's AlarmAck for the process alarm, its transport ACK
    // and an abort.
    let (n, h) = notification.expect("a notification among the captures");
    let ack = AlarmAck::for_notification(&n, PnioStatus::OK);
    let data = RtaPdu::first_reply_to(Priority::High, &h, vec![AlarmBlock::Ack(ack)]);
    let tack = RtaPdu::first_ack_of(Priority::High, &h);
    let tagged = |pdu: &RtaPdu| {
        let mut f = vec![
            2, 0, 0, 0, 0, 2, 2, 0, 0, 0, 0, 1, 0x81, 0x00, 0xc0, 0x00, 0x88, 0x92,
        ];
        f.extend(pdu.to_vec().unwrap());
        if f.len() < 60 {
            f.resize(60, 0);
        }
        f
    };
    frames.push(tagged(&data));
    frames.push(tagged(&tack));
    let d = procimg_testkit::tshark::dissect_clean("alarms", &frames);
    assert!(d.iter().all(|f| f.protocol.starts_with("PN")), "{d:?}");
}
