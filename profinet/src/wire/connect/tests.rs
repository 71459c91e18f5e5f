// SPDX-License-Identifier: MIT OR Apache-2.0
//! The Connect codecs against the S7-1515's captured Connect and p-net's answers, the
//! refusals, and round trips.
use super::*;
use crate::iocr_layout::{IocrLayout, SubmoduleIo};
use crate::wire::test_captures::capture_blocks;
use proptest::prelude::*;

// The two frames come from the test data of the `pnio` crate 0.1.0
// (core-engineering/pnio-rs, MIT OR Apache-2.0): an S7-1515 connecting to the p-net sample
// device.

/// S7 Connect request (frame 50, DREP LE): ARBlockReq, 2× IOCRBlockReq,
/// 5× ExpectedSubmoduleBlockReq, AlarmCRBlockReq.
const CONNECT_REQ: &str = "cm/connect_req";

/// p-net Connect response (frame 53, DREP BE): ARBlockRes, 2× IOCRBlockRes, AlarmCRBlockRes,
/// ARServerBlock.
const CONNECT_RES: &str = "cm/connect_res";

/// ModuleDiffBlock of the worked example "record 0xE002" (TV7) of the Siemens manual
/// "PROFINET IO: From PROFIBUS DP to PROFINET IO" (A5E00879152-01, section 6.6): slot 2
/// missing, slot 4 holding a wrong module whose subslot 1 is wrong (0x9000).
static MODULE_DIFF_TV7: [u8; 42] = [
    0x81, 0x04, 0x00, 0x26, 0x01, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00, 0x02,
    0x00, 0x00, 0x88, 0xa1, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x17, 0xff, 0x00, 0x01,
    0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x90, 0x00,
];

/// The captured blocks of one type, whole.
fn captured(bytes: &[u8], t: BlockType) -> Vec<&[u8]> {
    blocks(bytes)
        .map(Result::unwrap)
        .filter(|(h, _)| h.block_type == t)
        .map(|(_, b)| b)
        .collect()
}

fn entries(v: &[(u16, u16, u16)]) -> Vec<IocrEntry> {
    v.iter()
        .map(|&(slot, subslot, frame_offset)| IocrEntry {
            slot,
            subslot,
            frame_offset,
        })
        .collect()
}

#[test]
fn connect_request_capture() {
    let bytes = &capture_blocks(CONNECT_REQ)[..];
    let req = ConnectRequest::parse(bytes).unwrap();

    let ar = &req.ar;
    assert_eq!(ar.ar_type, AR_TYPE_IOC_SINGLE);
    assert_eq!(
        ar.ar_uuid.to_string(),
        "e5e1aecc-b133-4b4d-b187-cc68b0211ed2"
    );
    assert_eq!(ar.session_key, 2);
    assert_eq!(ar.initiator_mac.to_string(), "ec:1c:5d:61:e7:3f");
    assert_eq!(
        ar.initiator_object_uuid.to_string(),
        "dea00000-6c97-11d1-8271-1064010e002a"
    );
    assert_eq!(ar.ar_properties, ar_properties::ADVANCED);
    assert_eq!(ar.ar_properties, 0x4000_0011);
    assert_eq!(ar.activity_timeout_factor, 200);
    assert_eq!(ar.udp_rt_port, UDP_RT_PORT_NONE);
    assert_eq!(ar.station_name, "plcxbbench.profinetxainterfacexb25fbd");
    // What io_controller describes is what the S7 sends.
    let own = ArBlockReq::io_controller(
        ar.ar_uuid,
        2,
        ar.initiator_mac,
        ar.initiator_object_uuid,
        ar.station_name.clone(),
    );
    assert_eq!(*ar, own);

    assert_eq!(req.iocrs.len(), 2);
    let (input, output) = (&req.iocrs[0], &req.iocrs[1]);
    for (cr, t, r, frame_id) in [
        (input, iocr_type::INPUT, 1, 0x8000),
        (output, iocr_type::OUTPUT, 2, 0x8001),
    ] {
        assert_eq!(
            (cr.iocr_type, cr.iocr_reference, cr.frame_id),
            (t, r, frame_id)
        );
        assert_eq!(cr.lt, LT_PROFINET);
        assert_eq!(cr.rt_class(), iocr_properties::RT_CLASS_2);
        assert_eq!(cr.data_length, 40);
        assert_eq!((cr.send_clock_factor, cr.reduction_ratio), (32, 32));
        assert_eq!(cr.period_ns(), 32_000_000);
        assert_eq!((cr.phase, cr.sequence), (1, 0));
        assert_eq!(cr.frame_send_offset, FRAME_SEND_OFFSET_BEST_EFFORT);
        assert_eq!((cr.watchdog_factor, cr.data_hold_factor), (3, 3));
        assert_eq!(cr.tag_header, TAG_HEADER_PRIO_6);
        assert_eq!(cr.multicast_mac, MacAddress::default());
        assert_eq!(cr.apis.len(), 1);
        assert_eq!(cr.apis[0].api, 0);
    }
    // Input CR: IOPS of the DAP submodules, DI8 data, DIO8 in, echo in; IOCS of the
    // output submodules. The output CR carries the IOCS of those same input data objects, at
    // the same offsets.
    let input_objects = entries(&[
        (0, 1, 0),
        (0, 0x8000, 1),
        (0, 0x8001, 2),
        (1, 1, 3),
        (3, 1, 6),
        (4, 1, 9),
    ]);
    assert_eq!(input.apis[0].data_objects, input_objects);
    assert_eq!(
        input.apis[0].iocs,
        entries(&[(2, 1, 5), (3, 1, 8), (4, 1, 18)])
    );
    assert_eq!(
        output.apis[0].data_objects,
        entries(&[(2, 1, 4), (3, 1, 7), (4, 1, 10)])
    );
    assert_eq!(output.apis[0].iocs, input_objects);

    assert_eq!(req.alarm_cr, AlarmCrBlockReq::io_controller(0));

    // One block per slot: the DAP (interface, port) and the four IO modules.
    let module = |api, slot, module_ident, submodules| ExpectedModule {
        api,
        slot,
        module_ident,
        properties: 0,
        submodules,
    };
    let one = |m| ExpectedSubmoduleBlockReq { modules: vec![m] };
    let expected = vec![
        one(module(
            0,
            0,
            0x1,
            vec![
                ExpectedSubmodule::with_io(1, 0x1, 0, 0),
                ExpectedSubmodule::with_io(0x8000, 0x8000, 0, 0),
                ExpectedSubmodule::with_io(0x8001, 0x8001, 0, 0),
            ],
        )),
        one(module(
            0,
            1,
            0x30,
            vec![ExpectedSubmodule::with_io(1, 0x130, 1, 0)],
        )),
        one(module(
            0,
            2,
            0x31,
            vec![ExpectedSubmodule::with_io(1, 0x131, 0, 1)],
        )),
        one(module(
            0,
            3,
            0x32,
            vec![ExpectedSubmodule::with_io(1, 0x132, 1, 1)],
        )),
        one(module(
            0,
            4,
            0x40,
            vec![ExpectedSubmodule::with_io(1, 0x140, 8, 8)],
        )),
    ];
    assert_eq!(req.expected, expected);
    assert_eq!(
        req.expected[3].modules[0].submodules[0].submodule_type(),
        submodule::TYPE_INPUT_OUTPUT
    );

    // Byte for byte: the whole sequence and every block on its own.
    assert_eq!(req.buffer_len(), bytes.len());
    assert_eq!(req.to_vec().unwrap(), bytes);
    let mut buf = vec![0xa5; bytes.len()];
    req.emit(&mut buf).unwrap();
    assert_eq!(buf, bytes);
    assert_eq!(
        req.ar.to_vec().unwrap(),
        captured(bytes, BlockType::ArBlockReq)[0]
    );
    for (cr, raw) in req
        .iocrs
        .iter()
        .zip(captured(bytes, BlockType::IocrBlockReq))
    {
        assert_eq!(cr.buffer_len(), raw.len());
        let mut out = vec![0xa5u8; raw.len()];
        cr.emit(&mut out).unwrap();
        assert_eq!(out, raw);
    }
    let raw = captured(bytes, BlockType::ExpectedSubmoduleBlockReq);
    for (e, raw) in req.expected.iter().zip(raw) {
        assert_eq!(e.to_vec().unwrap(), raw);
    }
    let raw = captured(bytes, BlockType::AlarmCrBlockReq)[0];
    assert_eq!(req.alarm_cr.to_vec().unwrap(), raw);
}

/// The S7's IOCR data objects are what `IocrLayout::new` computes for the expected
/// submodules, and `from_layout` rebuilds both IOCRBlockReqs byte for byte.
#[test]
fn capture_iocrs_match_the_layout() {
    let req = ConnectRequest::parse(&capture_blocks(CONNECT_REQ)).unwrap();
    let subs: Vec<SubmoduleIo> = req.submodules().collect();
    assert_eq!(subs.len(), 7);
    let layout = IocrLayout::new(&subs).unwrap();
    let input =
        IocrBlockReq::from_layout(iocr_type::INPUT, 1, 0x8000, &layout.input, &subs).unwrap();
    let output =
        IocrBlockReq::from_layout(iocr_type::OUTPUT, 2, 0x8001, &layout.output, &subs).unwrap();
    assert_eq!(input, req.iocrs[0]);
    assert_eq!(output, req.iocrs[1]);
    let req_bytes = capture_blocks(CONNECT_REQ);
    let raw = captured(&req_bytes, BlockType::IocrBlockReq);
    assert_eq!(input.to_vec().unwrap(), raw[0]);
    assert_eq!(output.to_vec().unwrap(), raw[1]);
    // A layout from another submodule list does not build.
    assert_eq!(
        IocrBlockReq::from_layout(iocr_type::INPUT, 1, 0x8000, &layout.input, &subs[..3]),
        Err(EmitError::Inconsistent(
            "the layout names a submodule outside the list"
        ))
    );
}

#[test]
fn connect_response_capture() {
    let bytes = &capture_blocks(CONNECT_RES)[..];
    let res = ConnectResponse::parse(bytes).unwrap();
    assert_eq!(res.ar.ar_type, AR_TYPE_IOC_SINGLE);
    assert_eq!(
        res.ar.ar_uuid.to_string(),
        "e5e1aecc-b133-4b4d-b187-cc68b0211ed2"
    );
    assert_eq!(res.ar.session_key, 2);
    assert_eq!(res.ar.responder_mac.to_string(), "8c:f3:19:cd:19:f8");
    assert_eq!(res.ar.udp_rt_port, UDP_RT_PORT_NONE);
    assert_eq!(
        res.iocrs,
        vec![
            IocrBlockRes {
                iocr_type: iocr_type::INPUT,
                iocr_reference: 1,
                frame_id: 0x8000
            },
            IocrBlockRes {
                iocr_type: iocr_type::OUTPUT,
                iocr_reference: 2,
                frame_id: 0x8001
            },
        ]
    );
    assert_eq!(
        (res.frame_id(1), res.frame_id(2), res.frame_id(3)),
        (Some(0x8000), Some(0x8001), None)
    );
    assert_eq!(
        res.alarm_cr,
        AlarmCrBlockRes {
            alarm_cr_type: ALARM_CR_TYPE,
            local_alarm_reference: 0,
            max_alarm_data_length: 200
        }
    );
    assert_eq!(res.module_diff, None);
    let server = res.ar_server.as_ref().unwrap();
    assert_eq!(server.station_name, "rt-labs-dev");
    assert_eq!(server.buffer_len(), 20, "one pad byte");
    assert!(res.others.is_empty());
    assert_eq!(res.buffer_len(), bytes.len());
    assert_eq!(res.to_vec().unwrap(), bytes);
    let raw = captured(bytes, BlockType::ArServerBlock)[0];
    assert_eq!(server.to_vec().unwrap(), raw);
}

#[test]
fn module_diff_worked_example() {
    let d = ModuleDiffBlock::parse(&MODULE_DIFF_TV7).unwrap();
    assert_eq!(d.apis.len(), 1);
    let m = &d.apis[0].modules;
    assert_eq!(
        (m[0].slot, m[0].module_ident, m[0].state),
        (2, 0x88a1, ModuleState::NoModule)
    );
    assert!(m[0].submodules.is_empty());
    assert_eq!(
        (m[1].slot, m[1].module_ident, m[1].state),
        (4, 0x17ff, ModuleState::WrongModule)
    );
    let subs: Vec<_> = d.submodules().collect();
    assert_eq!(subs, vec![(0, 4, 1, SubmoduleState(0x9000))]);
    let s = subs[0].3;
    assert!(s.format_indicator());
    assert_eq!(s.ident_info(), IdentInfo::Wrong);
    assert_eq!(s.ar_info(), ArInfo::Own);
    assert!(!s.fault() && !s.maintenance_required() && !s.maintenance_demanded());
    assert!(!s.qualified_info());
    assert_eq!(s.add_info(), 0);
    assert!(!s.is_usable());
    assert_eq!(d.to_vec().unwrap(), MODULE_DIFF_TV7);

    // Bit decoding on a made-up state: substitute, ApplicationReady pending, fault, MR.
    let s = SubmoduleState(0x8000 | 1 << 11 | 1 << 7 | 1 << 6 | 1 << 4 | 1);
    assert_eq!(s.ident_info(), IdentInfo::Substitute);
    assert_eq!(s.ar_info(), ArInfo::ApplicationReadyPending);
    assert!(s.fault() && s.maintenance_required() && !s.maintenance_demanded());
    assert_eq!(s.add_info(), 1);
    assert!(!s.is_usable());
    assert!(SubmoduleState(0x8000).is_usable());
    assert!(!SubmoduleState(0).is_usable());
    assert_eq!(SubmoduleState(0xf800).ident_info(), IdentInfo::Unknown(15));
    assert_eq!(SubmoduleState(0x8780).ar_info(), ArInfo::Unknown(15));
    for v in 0..6u16 {
        assert_eq!(u16::from(ModuleState::from(v)), v);
    }
}

#[test]
fn a_submodule_state_reads_as_what_it_means() {
    let said = |raw: u16| SubmoduleState(raw).to_string();
    // TV7's wrong submodule, and a submodule with nothing wrong but its diagnosis.
    assert_eq!(said(0x9000), "a wrong submodule, owned by this AR");
    assert_eq!(
        said(0x8040),
        "the expected submodule, owned by this AR, diagnosis available"
    );
    assert_eq!(
        said(0x8000 | 1 << 11 | 1 << 7 | 1 << 6 | 1 << 4 | 1),
        "a substitute, application ready pending, diagnosis available, maintenance \
         required, takeover not allowed"
    );
    assert_eq!(
        said(0x8000 | 3 << 7),
        "the expected submodule, locked by IO controller"
    );
    assert_eq!(said(0xf800), "reserved IdentInfo 15, owned by this AR");
    assert_eq!(said(0x0040), "SubmoduleState 0x0040 in the old format");
}

#[test]
fn response_with_module_diff_and_other_blocks() {
    let mut res = ConnectResponse::parse(&capture_blocks(CONNECT_RES)).unwrap();
    res.module_diff = Some(ModuleDiffBlock::parse(&MODULE_DIFF_TV7).unwrap());
    // An ARRPCBlockRes-like block the module does not model.
    let other = vec![0x81, 0x07, 0x00, 0x04, 0x01, 0x00, 0x88, 0x94];
    res.others.push((BlockType::ArRpcBlockRes, other.clone()));
    let bytes = res.to_vec().unwrap();
    assert_eq!(bytes.len(), res.buffer_len());
    // Order: ..., AlarmCR, ModuleDiff, others, ARServer.
    let types: Vec<u16> = blocks(&bytes)
        .map(|r| r.unwrap().0.block_type.raw())
        .collect();
    assert_eq!(
        types,
        vec![0x8101, 0x8102, 0x8102, 0x8103, 0x8104, 0x8107, 0x8106]
    );
    assert_eq!(ConnectResponse::parse(&bytes), Ok(res));
}

#[test]
fn malformed() {
    let req_bytes = &capture_blocks(CONNECT_REQ)[..];
    let res_bytes = &capture_blocks(CONNECT_RES)[..];
    // Truncated anywhere: an error, never a panic.
    for n in 0..req_bytes.len() {
        assert!(ConnectRequest::parse(&req_bytes[..n]).is_err(), "{n}");
    }
    for n in 0..res_bytes.len() {
        let _ = ConnectResponse::parse(&res_bytes[..n]);
    }
    assert!(ConnectResponse::parse(&res_bytes[..res_bytes.len() - 1]).is_err());
    // Without the ARServerBlock (the last 20 bytes) the response is complete.
    let legacy = ConnectResponse::parse(&res_bytes[..res_bytes.len() - 20]).unwrap();
    assert_eq!(legacy.ar_server, None);
    // Missing or duplicate AR block.
    let ar_len = captured(req_bytes, BlockType::ArBlockReq)[0].len();
    assert!(ConnectRequest::parse(&req_bytes[ar_len..]).is_err());
    let mut twice = req_bytes.to_vec();
    twice.extend_from_slice(&req_bytes[..ar_len]);
    assert!(ConnectRequest::parse(&twice).is_err());
    // An unknown block type in a request.
    let mut unknown = req_bytes.to_vec();
    unknown.extend_from_slice(&[0x01, 0x07, 0x00, 0x04, 0x01, 0x00, 0x88, 0x94]);
    assert!(ConnectRequest::parse(&unknown).is_err());
    // Wrong version, wrong type, trailing bytes in the body.
    let alarm = captured(req_bytes, BlockType::AlarmCrBlockReq)[0];
    let mut b = alarm.to_vec();
    b[5] = 1;
    assert!(AlarmCrBlockReq::parse(&b).is_err());
    assert!(ArBlockReq::parse(alarm).is_err());
    let mut b = alarm.to_vec();
    b[3] += 2;
    b.extend_from_slice(&[0, 0]);
    assert!(AlarmCrBlockReq::parse(&b).is_err());
    // A station name that is not UTF-8.
    let mut b = captured(res_bytes, BlockType::ArServerBlock)[0].to_vec();
    b[8] = 0xff;
    assert!(ArServerBlock::parse(&b).is_err());
    // Four padding bytes are too many.
    let mut b = captured(res_bytes, BlockType::ArServerBlock)[0].to_vec();
    b[3] += 3;
    b.extend_from_slice(&[0, 0, 0]);
    assert!(ArServerBlock::parse(&b).is_err());
    b.truncate(b.len() - 3);
    b[3] -= 3;
    assert!(ArServerBlock::parse(&b).is_ok());
}

#[test]
fn unrepresentable_values_do_not_emit() {
    let req = ConnectRequest::parse(&capture_blocks(CONNECT_REQ)).unwrap();
    let mut short = vec![0u8; req.ar.buffer_len() - 1];
    assert_eq!(
        req.ar.emit(&mut short),
        Err(EmitError::BufferTooShort {
            what: "ARBlockReq",
            needed: short.len() + 1,
            len: short.len()
        })
    );
    let mut short = vec![0u8; req.buffer_len() - 1];
    assert!(req.emit(&mut short).is_err());
    // Data descriptions that do not match the submodule type.
    let mut bad = req.clone();
    bad.expected[0].modules[0].submodules[0].properties = submodule::TYPE_INPUT_OUTPUT;
    let mismatch = Err(EmitError::Inconsistent(
        "an expected submodule's data descriptions do not match its type",
    ));
    assert_eq!(bad.expected[0].to_vec(), mismatch);
    assert_eq!(bad.to_vec(), mismatch);
    // A list longer than its 16-bit count.
    let mut bad = req.clone();
    let e = IocrEntry {
        slot: 1,
        subslot: 1,
        frame_offset: 0,
    };
    bad.iocrs[0].apis[0].iocs = vec![e; 0x1_0000];
    // Its block is over 65 539 bytes too, which is found first.
    let too_long = bad.iocrs[0].to_vec();
    assert!(matches!(too_long, Err(EmitError::TooLong { .. })));
    assert_eq!(bad.to_vec(), too_long);
    // A block longer than 65 539 bytes.
    let mut bad = req;
    bad.iocrs[0].apis[0].iocs = vec![e; 0x3000];
    bad.iocrs[0].apis[0].data_objects = vec![e; 0x3000];
    assert!(matches!(
        bad.iocrs[0].to_vec(),
        Err(EmitError::TooLong {
            field: "BlockLength",
            ..
        })
    ));
    let long = ArServerBlock {
        station_name: "x".repeat(0x1_0000),
    };
    assert!(matches!(
        long.to_vec(),
        Err(EmitError::TooLong {
            field: "BlockLength",
            ..
        })
    ));
}

fn uuid() -> impl Strategy<Value = Uuid> {
    any::<[u8; 16]>().prop_map(Uuid)
}

fn mac() -> impl Strategy<Value = MacAddress> {
    any::<[u8; 6]>().prop_map(MacAddress)
}

fn name() -> impl Strategy<Value = String> {
    "[a-z0-9.-]{0,64}"
}

fn ar_block_req() -> impl Strategy<Value = ArBlockReq> {
    (
        (any::<u16>(), uuid(), any::<u16>(), mac(), uuid()),
        (any::<u32>(), any::<u16>(), any::<u16>(), name()),
    )
        .prop_map(|((t, ar, key, m, obj), (props, tf, port, n))| ArBlockReq {
            ar_type: t,
            ar_uuid: ar,
            session_key: key,
            initiator_mac: m,
            initiator_object_uuid: obj,
            ar_properties: props,
            activity_timeout_factor: tf,
            udp_rt_port: port,
            station_name: n,
        })
}

fn entry() -> impl Strategy<Value = IocrEntry> {
    any::<(u16, u16, u16)>().prop_map(|(slot, subslot, frame_offset)| IocrEntry {
        slot,
        subslot,
        frame_offset,
    })
}

fn iocr_block_req() -> impl Strategy<Value = IocrBlockReq> {
    let api = (
        any::<u32>(),
        proptest::collection::vec(entry(), 0..8),
        proptest::collection::vec(entry(), 0..8),
    )
        .prop_map(|(api, data_objects, iocs)| IocrApi {
            api,
            data_objects,
            iocs,
        });
    (
        any::<[u16; 12]>(),
        any::<(u32, u32)>(),
        mac(),
        proptest::collection::vec(api, 0..3),
    )
        .prop_map(|(w, (props, fso), m, apis)| IocrBlockReq {
            iocr_type: w[0],
            iocr_reference: w[1],
            lt: w[2],
            iocr_properties: props,
            data_length: w[3],
            frame_id: w[4],
            send_clock_factor: w[5],
            reduction_ratio: w[6],
            phase: w[7],
            sequence: w[8],
            frame_send_offset: fso,
            watchdog_factor: w[9],
            data_hold_factor: w[10],
            tag_header: w[11],
            multicast_mac: m,
            apis,
        })
}

fn alarm_cr_block_req() -> impl Strategy<Value = AlarmCrBlockReq> {
    (any::<[u16; 8]>(), any::<u32>()).prop_map(|(w, p)| AlarmCrBlockReq {
        alarm_cr_type: w[0],
        lt: w[1],
        properties: p,
        rta_timeout_factor: w[2],
        rta_retries: w[3],
        local_alarm_reference: w[4],
        max_alarm_data_length: w[5],
        tag_header_high: w[6],
        tag_header_low: w[7],
    })
}

fn expected_block() -> impl Strategy<Value = ExpectedSubmoduleBlockReq> {
    let dd = any::<(u16, u16, u8, u8)>().prop_map(|(direction, length, c, p)| DataDescription {
        direction,
        length,
        length_iocs: c,
        length_iops: p,
    });
    let sub = (any::<u16>(), any::<u32>(), any::<u16>()).prop_flat_map(move |(ss, id, p)| {
        proptest::collection::vec(dd.clone(), ExpectedSubmodule::description_count(p)).prop_map(
            move |data_descriptions| ExpectedSubmodule {
                subslot: ss,
                submodule_ident: id,
                properties: p,
                data_descriptions,
            },
        )
    });
    let module = (
        any::<u32>(),
        any::<u16>(),
        any::<u32>(),
        any::<u16>(),
        proptest::collection::vec(sub, 0..4),
    )
        .prop_map(
            |(api, slot, module_ident, properties, submodules)| ExpectedModule {
                api,
                slot,
                module_ident,
                properties,
                submodules,
            },
        );
    proptest::collection::vec(module, 0..3)
        .prop_map(|modules| ExpectedSubmoduleBlockReq { modules })
}

fn module_diff() -> impl Strategy<Value = ModuleDiffBlock> {
    let sub =
        any::<(u16, u32, u16)>().prop_map(|(subslot, submodule_ident, s)| ModuleDiffSubmodule {
            subslot,
            submodule_ident,
            state: SubmoduleState(s),
        });
    let module = (
        any::<(u16, u32, u16)>(),
        proptest::collection::vec(sub, 0..3),
    )
        .prop_map(|((slot, module_ident, s), submodules)| ModuleDiffModule {
            slot,
            module_ident,
            state: ModuleState::from(s),
            submodules,
        });
    let api = (any::<u32>(), proptest::collection::vec(module, 0..3))
        .prop_map(|(api, modules)| ModuleDiffApi { api, modules });
    proptest::collection::vec(api, 0..3).prop_map(|apis| ModuleDiffBlock { apis })
}

fn connect_request() -> impl Strategy<Value = ConnectRequest> {
    (
        ar_block_req(),
        proptest::collection::vec(iocr_block_req(), 0..3),
        alarm_cr_block_req(),
        proptest::collection::vec(expected_block(), 0..3),
    )
        .prop_map(|(ar, iocrs, alarm_cr, expected)| ConnectRequest {
            ar,
            iocrs,
            alarm_cr,
            expected,
        })
}

fn connect_response() -> impl Strategy<Value = ConnectResponse> {
    let ar = (any::<u16>(), uuid(), any::<u16>(), mac(), any::<u16>()).prop_map(
        |(ar_type, ar_uuid, session_key, responder_mac, udp_rt_port)| ArBlockRes {
            ar_type,
            ar_uuid,
            session_key,
            responder_mac,
            udp_rt_port,
        },
    );
    let iocr =
        any::<(u16, u16, u16)>().prop_map(|(iocr_type, iocr_reference, frame_id)| IocrBlockRes {
            iocr_type,
            iocr_reference,
            frame_id,
        });
    let alarm = any::<(u16, u16, u16)>().prop_map(|(t, r, l)| AlarmCrBlockRes {
        alarm_cr_type: t,
        local_alarm_reference: r,
        max_alarm_data_length: l,
    });
    let other = (
        0x8107u16..0x8110,
        proptest::collection::vec(any::<u8>(), 0..12),
    )
        .prop_map(|(t, body)| {
            let mut b = t.to_be_bytes().to_vec();
            b.extend_from_slice(&(body.len() as u16 + 2).to_be_bytes());
            b.extend_from_slice(&[1, 0]);
            b.extend_from_slice(&body);
            (BlockType::from_raw(t), b)
        });
    (
        ar,
        proptest::collection::vec(iocr, 0..3),
        alarm,
        proptest::option::of(module_diff()),
        proptest::option::of(name().prop_map(|station_name| ArServerBlock { station_name })),
        proptest::collection::vec(other, 0..2),
    )
        .prop_map(
            |(ar, iocrs, alarm_cr, module_diff, ar_server, others)| ConnectResponse {
                ar,
                iocrs,
                alarm_cr,
                module_diff,
                ar_server,
                others,
            },
        )
}

/// Every block parser on the same bytes.
fn parse_all(b: &[u8]) {
    let _ = ArBlockReq::parse(b);
    let _ = IocrBlockReq::parse(b);
    let _ = AlarmCrBlockReq::parse(b);
    let _ = ExpectedSubmoduleBlockReq::parse(b);
    let _ = ArBlockRes::parse(b);
    let _ = IocrBlockRes::parse(b);
    let _ = AlarmCrBlockRes::parse(b);
    let _ = ArServerBlock::parse(b);
    let _ = ModuleDiffBlock::parse(b);
    let _ = ConnectRequest::parse(b);
    let _ = ConnectResponse::parse(b);
}

proptest! {
    #[test]
    fn parse_never_panics(b in proptest::collection::vec(any::<u8>(), 0..600)) {
        parse_all(&b);
    }

    #[test]
    fn parse_never_panics_on_plausible_blocks(
        t in prop::sample::select(vec![
            0x0101u16, 0x0102, 0x0103, 0x0104, 0x8101, 0x8102, 0x8103, 0x8104, 0x8106,
        ]),
        body in proptest::collection::vec(any::<u8>(), 0..200),
        small in any::<bool>(),
    ) {
        // A valid header over random content; small counts make deep parses likely.
        let mut body = body;
        if small {
            for (i, b) in body.iter_mut().enumerate() {
                if i % 2 == 0 { *b = 0; } else { *b &= 3; }
            }
        }
        let mut b = t.to_be_bytes().to_vec();
        b.extend_from_slice(&(body.len() as u16 + 2).to_be_bytes());
        b.extend_from_slice(&[1, 0]);
        b.extend_from_slice(&body);
        parse_all(&b);
    }

    #[test]
    fn mutated_captures_never_panic(
        at in 0usize..557,
        v in any::<u8>(),
        cut in 0usize..600,
    ) {
        for frame in [CONNECT_REQ, CONNECT_RES] {
            let mut b = capture_blocks(frame);
            if let Some(x) = b.get_mut(at) { *x = v; }
            b.truncate(cut);
            parse_all(&b);
        }
    }

    #[test]
    fn ar_block_req_round_trip(ar in ar_block_req()) {
        let b = ar.to_vec().unwrap();
        prop_assert_eq!(b.len(), ar.buffer_len());
        prop_assert_eq!(ArBlockReq::parse(&b), Ok(ar));
    }

    #[test]
    fn iocr_block_req_round_trip(cr in iocr_block_req()) {
        let b = cr.to_vec().unwrap();
        prop_assert_eq!(b.len(), cr.buffer_len());
        prop_assert_eq!(IocrBlockReq::parse(&b), Ok(cr));
    }

    #[test]
    fn expected_and_module_diff_round_trip(e in expected_block(), d in module_diff()) {
        prop_assert_eq!(ExpectedSubmoduleBlockReq::parse(&e.to_vec().unwrap()), Ok(e));
        prop_assert_eq!(ModuleDiffBlock::parse(&d.to_vec().unwrap()), Ok(d));
    }

    #[test]
    fn connect_request_round_trip(req in connect_request()) {
        let b = req.to_vec().unwrap();
        prop_assert_eq!(b.len(), req.buffer_len());
        prop_assert_eq!(ConnectRequest::parse(&b), Ok(req));
    }

    #[test]
    fn connect_response_round_trip(res in connect_response()) {
        let b = res.to_vec().unwrap();
        prop_assert_eq!(b.len(), res.buffer_len());
        let parsed = ConnectResponse::parse(&b).unwrap();
        prop_assert_eq!(&parsed, &res);
        if let Some(s) = &parsed.ar_server {
            prop_assert_eq!(s.buffer_len() % 4, 0);
        }
    }

    #[test]
    fn from_layout_round_trips(lens in proptest::collection::vec((0u16..16, 0u16..16), 0..12)) {
        let subs: Vec<SubmoduleIo> = lens
            .iter()
            .enumerate()
            .map(|(i, &(input_length, output_length))| SubmoduleIo {
                api: (i % 2) as u32,
                slot: i as u16,
                subslot: 1,
                input_length,
                output_length,
            })
            .collect();
        let l = IocrLayout::new(&subs).unwrap();
        for (t, cr) in [(iocr_type::INPUT, &l.input), (iocr_type::OUTPUT, &l.output)] {
            let b = IocrBlockReq::from_layout(t, t, 0x8000 + t, cr, &subs).unwrap();
            let n: usize = b.apis.iter().map(|a| a.data_objects.len()).sum();
            prop_assert_eq!(n, cr.objects.len());
            let n: usize = b.apis.iter().map(|a| a.iocs.len()).sum();
            prop_assert_eq!(n, cr.iocs.len());
            prop_assert_eq!(IocrBlockReq::parse(&b.to_vec().unwrap()), Ok(b));
        }
    }
}
