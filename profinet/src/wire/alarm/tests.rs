// SPDX-License-Identifier: MIT OR Apache-2.0
//! Tests of the alarm codecs.

use super::super::ethernet::{ETHERTYPE_PROFINET, Frame};
use super::super::rta_pdu::*;
use super::*;
use crate::test_fixtures::hex;
use crate::wire::test_strategies::alarm_item;
use proptest::prelude::*;

// The captures below come from the test data of the `pnio` crate 0.1.0
// (core-engineering/pnio-rs, MIT OR Apache-2.0): an S7-1515 ("CPU") talking to the p-net
// sample device ("dev"), frames of plan5-alarm.pcapng. Hex from the Ethernet header, VLAN
// tagged, trailing Ethernet padding included (the S7 pads with stale bytes).

/// alarm_process_notif.hex: p-net → CPU, high, DATA AlarmNotification Process, USI 0x0010.
const PROCESS_NOTIF: &str = concat!(
    "ec1c5d61e73c8cf319cd19f88100c0008892fc01000000001111fffffffe001d",
    "0001001901000002000000000001000100000030000001300000001001",
);
/// alarm_ack_rta_high_cpu.hex: CPU → p-net, high ACK-RTA for the process notification.
const ACK_RTA_HIGH_CPU: &str = concat!(
    "8cf319cd19f8ec1c5d61e73c8100c0008892fc01000000001301fffeffff0000",
    "0000000000000000000000000000000000000000000000000000000000000000",
);
/// alarm_ack_high_cpu.hex: CPU → p-net, high DATA AlarmAck Process, PNIOStatus OK.
const ACK_HIGH_CPU: &str = concat!(
    "8cf319cd19f8ec1c5d61e73c8100c0008892fc01000000001111ffffffff0016",
    "8001001201000002000000000001000100000000000000000000000000000000",
);
/// alarm_ack_rta_high_dev.hex: p-net → CPU, high ACK-RTA for the CPU's AlarmAck.
const ACK_RTA_HIGH_DEV: &str = "ec1c5d61e73c8cf319cd19f88100c0008892fc01000000001301ffffffff0000";
/// alarm_diag_notif.hex: p-net → CPU, low DATA AlarmNotification Diagnosis, USI 0x8002.
const DIAG_NOTIF: &str = concat!(
    "ec1c5d61e73c8cf319cd19f88100a0008892fe01000000001111fffffffe0028",
    "000200240100000100000000000100010000003000000130a800800200042801",
    "0001000000000000",
);
/// alarm_ack_rta_low_cpu.hex: CPU → p-net, low ACK-RTA for the diagnosis notification.
const ACK_RTA_LOW_CPU: &str = concat!(
    "8cf319cd19f8ec1c5d61e73c8100a0008892fe01000000001301fffeffff0000",
    "0000000000000000000000000000000000000000000000000000000000000000",
);
/// alarm_diag_ack_cpu.hex: CPU → p-net, low DATA AlarmAck Diagnosis, PNIOStatus OK.
const DIAG_ACK_CPU: &str = concat!(
    "8cf319cd19f8ec1c5d61e73c8100a0008892fe01000000001111ffffffff0016",
    "80020012010000010000000000010001a8000000000000000000000000000000",
);
/// alarm_ack_rta_low_dev.hex: p-net → CPU, low ACK-RTA for the CPU's AlarmAck.
const ACK_RTA_LOW_DEV: &str = "ec1c5d61e73c8cf319cd19f88100a0008892fe01000000001301ffffffff0000";
/// alarm_diag_update_appears.hex: p-net → CPU, Diagnosis 0x2801 appears.
const DIAG_UPDATE_APPEARS: &str = concat!(
    "ec1c5d61e73c8cf319cd19f88100a0008892fe010000000011110000ffff0028",
    "000200240100000100000000000100010000003000000130a801800200042801",
    "00010000000004d2",
);
/// alarm_diag_update_others_remain.hex: p-net → CPU, Diagnosis 0x3801 disappears, others
/// remain.
const DIAG_UPDATE_OTHERS_REMAIN: &str = concat!(
    "ec1c5d61e73c8cf319cd19f88100a0008892fe01000000001111000100000028",
    "000200240100000100000000000100010000003000000130a802800200043801",
    "0001000000000000",
);
/// alarm_diag_usi_disappears.hex: p-net → CPU, DiagnosisDisappears, USI 0x1234, no data.
const DIAG_USI_DISAPPEARS: &str = concat!(
    "ec1c5d61e73c8cf319cd19f88100a0008892fe0100000000111100040003001c",
    "000200180100000c00000000000100010000003000000130a8051234",
);
/// alarm_diag_std_remove.hex: p-net → CPU, Diagnosis 0x2001 (all disappear).
const DIAG_STD_REMOVE: &str = concat!(
    "ec1c5d61e73c8cf319cd19f88100a0008892fe01000000001111000500040028",
    "0002002401000001000000000001000100000030000001300006800200042001",
    "00010000000004d2",
);
/// alarm_err_rta_dev.hex: p-net → CPU, ERR-RTA CF 81 FD 00.
const ERR_RTA_DEV: &str = concat!(
    "ec1c5d61e73c8cf319cd19f88100a0008892fe01000000001401000600050004",
    "cf81fd00",
);
/// alarm_err_rta_cpu.hex: CPU → p-net, ERR-RTA CF 81 FD 0B, stale bytes as padding.
const ERR_RTA_CPU: &str = concat!(
    "8cf319cd19f8ec1c5d61e73c8100a0008892fe01000000001401000500050004",
    "cf81fd0b002a010e8004000c010b000000160160cf81fd000000000000000000",
);
/// alarm_err_rta_cpu_removed.hex: CPU → p-net, ERR-RTA CF 81 FD 11 at a TIA download.
const ERR_RTA_CPU_REMOVED: &str = concat!(
    "8cf319cd19f8ec1c5d61e73c8100a0008892fe01000000001401fffefffe0004",
    "cf81fd11002a010e8004000c01110000028006978181fd110000000000000000",
);
/// alarm_err_rta_dev_removed_reply.hex: p-net → CPU, ERR-RTA reply CF 81 FD 11.
const ERR_RTA_DEV_REMOVED_REPLY: &str = concat!(
    "ec1c5d61e73c8cf319cd19f88100a0008892fe01000000001401fffffffe0004",
    "cf81fd11",
);

/// Parses a captured frame's RTA PDU and checks it re-emits to the PDU bytes (padding
/// excluded). Returns the Repr.
fn capture(frame_hex: &str) -> RtaPdu {
    let frame = hex(frame_hex);
    let f = Frame::new_checked(&frame[..]).unwrap();
    assert_eq!(f.ethertype(), ETHERTYPE_PROFINET);
    let bytes = f.payload();
    let packet = Packet::new_checked(bytes).unwrap();
    let pdu = RtaPdu::parse(&packet).unwrap();
    let len = HEADER_LEN + usize::from(packet.var_part_len());
    assert_eq!(pdu.buffer_len(), len);
    let mut buf = vec![0xa5u8; len];
    pdu.emit(&mut buf).unwrap();
    assert_eq!(&buf[..], &bytes[..len]);
    assert_eq!(pdu.header.var_part_len, packet.var_part_len());
    assert_eq!(pdu.header.pdu_type, pdu.body.pdu_type());
    let _ = packet.to_string();
    pdu
}

fn seqs(p: &RtaPdu) -> (u16, u16) {
    (p.header.send_seq, p.header.ack_seq)
}

const fn spec(seq: u16) -> AlarmSpecifier {
    // Bits 11, 13 and 15, as p-net sets them for its diagnosis alarms (0xA8xx).
    AlarmSpecifier {
        sequence_number: seq,
        channel_diagnosis: true,
        manufacturer_diagnosis: false,
        submodule_diagnosis: true,
        ar_diagnosis: true,
    }
}

#[test]
fn process_notification() {
    let p = capture(PROCESS_NOTIF);
    assert_eq!(p.priority, Priority::High);
    assert_eq!(
        p.header,
        RtaHeader {
            dst_endpoint: 0,
            src_endpoint: 0,
            pdu_type: PduType::Data,
            version: 1,
            window_size: 1,
            tack: true,
            send_seq: SEQ_INITIAL,
            ack_seq: SEQ_INITIAL_LAST,
            var_part_len: 0x1d,
        }
    );
    let n = p.notification().unwrap();
    let expected = AlarmNotification {
        priority: Priority::High,
        alarm_type: AlarmType::Process,
        api: 0,
        slot: 1,
        subslot: 1,
        module_ident: 0x30,
        submodule_ident: 0x130,
        specifier: AlarmSpecifier::default(),
        maintenance: None,
        item: Some(AlarmItem::Other {
            usi: 0x0010,
            data: vec![0x01],
        }),
    };
    assert_eq!(n, &expected);
    assert_eq!(
        p,
        RtaPdu::data(
            Priority::High,
            0,
            0,
            0xffff,
            0xfffe,
            vec![AlarmBlock::Notification(expected)]
        )
    );
    assert!(p.to_string().starts_with("RTA high DATA"));
}

#[test]
fn ack_rtas() {
    for (hex, priority, send, ack) in [
        (ACK_RTA_HIGH_CPU, Priority::High, 0xfffe, 0xffff),
        (ACK_RTA_HIGH_DEV, Priority::High, 0xffff, 0xffff),
        (ACK_RTA_LOW_CPU, Priority::Low, 0xfffe, 0xffff),
        (ACK_RTA_LOW_DEV, Priority::Low, 0xffff, 0xffff),
    ] {
        let p = capture(hex);
        assert_eq!(p.body, RtaBody::Ack);
        assert_eq!(p.priority, priority);
        assert_eq!(seqs(&p), (send, ack));
        assert!(!p.header.tack);
        assert_eq!(p.header.window_size, 1);
        assert_eq!(p, RtaPdu::ack(priority, 0, 0, send, ack));
    }
}

#[test]
fn alarm_acks() {
    let p = capture(ACK_HIGH_CPU);
    assert_eq!(seqs(&p), (0xffff, 0xffff));
    let a = *p.alarm_ack().unwrap();
    assert_eq!(
        a,
        AlarmAck {
            priority: Priority::High,
            alarm_type: AlarmType::Process,
            api: 0,
            slot: 1,
            subslot: 1,
            specifier: AlarmSpecifier::default(),
            status: PnioStatus::OK,
        }
    );
    let n = capture(PROCESS_NOTIF).notification().cloned().unwrap();
    assert_eq!(AlarmAck::for_notification(&n, PnioStatus::OK), a);

    let p = capture(DIAG_ACK_CPU);
    let a = *p.alarm_ack().unwrap();
    assert_eq!(a.priority, Priority::Low);
    assert_eq!(a.alarm_type, AlarmType::Diagnosis);
    assert_eq!((a.slot, a.subslot), (1, 1));
    assert_eq!(a.specifier, spec(0));
    assert!(a.status.is_ok());
    let n = capture(DIAG_NOTIF).notification().cloned().unwrap();
    assert_eq!(AlarmAck::for_notification(&n, PnioStatus::OK), a);
}

#[test]
fn diagnosis_notifications() {
    let appears = ChannelProperties(0x2801);
    assert_eq!(appears.data_type(), 1);
    assert_eq!(appears.specifier(), ChannelSpecifier::Appears);
    assert_eq!(appears.direction(), ChannelDirection::Input);
    assert!(!appears.accumulative() && !appears.maintenance_required());
    assert_eq!(
        appears,
        ChannelProperties::new(
            1,
            false,
            false,
            false,
            ChannelSpecifier::Appears,
            ChannelDirection::Input
        )
    );
    let cases = [
        (DIAG_NOTIF, (0xffff, 0xfffe), 0x0001, spec(0), 0x2801, 0),
        (
            DIAG_UPDATE_APPEARS,
            (0, 0xffff),
            0x0001,
            spec(1),
            0x2801,
            1234,
        ),
        (
            DIAG_UPDATE_OTHERS_REMAIN,
            (1, 0),
            0x0001,
            spec(2),
            0x3801,
            0,
        ),
        (
            DIAG_STD_REMOVE,
            (5, 4),
            0x0001,
            AlarmSpecifier::from_u16(6),
            0x2001,
            1234,
        ),
    ];
    for (hex, seq, alarm_type, specifier, props, add_value) in cases {
        let p = capture(hex);
        assert_eq!(p.priority, Priority::Low);
        assert_eq!(seqs(&p), seq);
        let n = p.notification().unwrap();
        assert_eq!(n.alarm_type, AlarmType::from(alarm_type));
        assert_eq!((n.api, n.slot, n.subslot), (0, 1, 1));
        assert_eq!((n.module_ident, n.submodule_ident), (0x30, 0x130));
        assert_eq!(n.specifier, specifier);
        assert_eq!(n.maintenance, None);
        let d = n.diagnosis().unwrap();
        assert_eq!(d.format, DiagnosisFormat::Extended);
        assert_eq!(d.usi(), USI_EXT_CHANNEL_DIAGNOSIS);
        assert_eq!(
            d.entries,
            vec![ChannelDiagnosis {
                channel_number: 4,
                channel_properties: ChannelProperties(props),
                channel_error_type: 1,
                ext_channel_error_type: 0,
                ext_channel_add_value: add_value,
                qualifier: 0,
            }]
        );
    }
    let others = ChannelProperties(0x3801).specifier();
    assert_eq!(others, ChannelSpecifier::DisappearsOthersRemain);
    let all = ChannelProperties(0x2001).specifier();
    assert_eq!(all, ChannelSpecifier::AllDisappear);
    let spec6 = AlarmSpecifier::from_u16(6);
    assert_eq!(spec6.sequence_number, 6);
    assert!(!spec6.channel_diagnosis && !spec6.submodule_diagnosis && !spec6.ar_diagnosis);
}

#[test]
fn manufacturer_usi_without_data() {
    let p = capture(DIAG_USI_DISAPPEARS);
    assert_eq!(seqs(&p), (4, 3));
    let n = p.notification().unwrap();
    assert_eq!(n.alarm_type, AlarmType::DiagnosisDisappears);
    assert_eq!(n.specifier, spec(5));
    assert_eq!(
        n.item,
        Some(AlarmItem::Other {
            usi: 0x1234,
            data: vec![]
        })
    );
    assert_eq!(n.diagnosis(), None);
}

#[test]
fn err_rtas() {
    for (hex, seq, code, text) in [
        (
            ERR_RTA_DEV,
            (6, 5),
            AbortCode::Unspecified,
            "abort: unspecified (0x00)",
        ),
        (
            ERR_RTA_CPU,
            (5, 5),
            AbortCode::AlarmIndicationError,
            "abort: AR alarm.ind(err) (0x0b)",
        ),
        (
            ERR_RTA_CPU_REMOVED,
            (0xfffe, 0xfffe),
            AbortCode::ArRemoved,
            "abort: AR removed (0x11)",
        ),
        (
            ERR_RTA_DEV_REMOVED_REPLY,
            (0xffff, 0xfffe),
            AbortCode::ArRemoved,
            "abort: AR removed (0x11)",
        ),
    ] {
        let p = capture(hex);
        assert_eq!(p.priority, Priority::Low);
        assert_eq!(seqs(&p), seq);
        assert_eq!(p.header.var_part_len, 4);
        assert!(!p.header.tack);
        let RtaBody::Err(e) = &p.body else {
            panic!("not an ERR-RTA: {p:?}");
        };
        assert_eq!(e.status.to_bytes()[..3], [0xcf, 0x81, 0xfd]);
        assert!(e.vendor_data.is_empty());
        assert_eq!(e.abort_code(), Some(code));
        assert_eq!(e, &ErrRta::abort(code));
        assert_eq!(e.to_string(), text);
        assert_eq!(
            p,
            RtaPdu::err(Priority::Low, 0, 0, seq.0, seq.1, ErrRta::abort(code))
        );
    }
    assert_eq!(AbortCode::from(0x99).to_string(), "abort code 0x99");
    assert_eq!(
        AbortCode::PdevCheckFailed.to_string(),
        "PDEV check failed (0x24)"
    );
}

#[test]
fn sequence_numbers() {
    assert_eq!(next_seq(0xffff), 0);
    assert_eq!(next_seq(0xfffe), 0xffff);
    assert_eq!(next_seq(0), 1);
    assert_eq!(next_seq(0x7ffe), 0x7fff);
    assert_eq!(next_seq(0x7fff), 0);

    // The low channel of the capture, from both ends.
    let mut dev = RtaSequence::new();
    let mut cpu = RtaSequence::new();
    // p-net's first diagnosis DATA.
    let notif = capture(DIAG_NOTIF);
    assert_eq!(seqs(&notif), (dev.send_seq(), dev.last_received()));
    assert_eq!(cpu.receive(notif.header.send_seq), Received::New);
    // The CPU's ACK-RTA confirms it.
    let ack = capture(ACK_RTA_LOW_CPU);
    assert_eq!(seqs(&ack), (cpu.last_sent(), cpu.last_received()));
    assert!(dev.confirms(ack.header.ack_seq));
    dev.confirm();
    // The CPU's AlarmAck DATA, and p-net's ACK-RTA for it.
    let data = capture(DIAG_ACK_CPU);
    assert_eq!(seqs(&data), (cpu.send_seq(), cpu.last_received()));
    assert_eq!(dev.receive(data.header.send_seq), Received::New);
    assert_eq!(dev.classify(data.header.send_seq), Received::Duplicate);
    let ack = capture(ACK_RTA_LOW_DEV);
    assert_eq!(seqs(&ack), (dev.last_sent(), dev.last_received()));
    assert!(cpu.confirms(ack.header.ack_seq));
    cpu.confirm();
    // p-net's next DATA, then (after the CPU's next AlarmAck) the one after it.
    let next = capture(DIAG_UPDATE_APPEARS);
    assert_eq!(seqs(&next), (dev.send_seq(), dev.last_received()));
    assert_eq!(cpu.receive(next.header.send_seq), Received::New);
    dev.confirm();
    assert_eq!(dev.receive(cpu.send_seq()), Received::New);
    cpu.confirm();
    let next = capture(DIAG_UPDATE_OTHERS_REMAIN);
    assert_eq!(seqs(&next), (dev.send_seq(), dev.last_received()));
    assert_eq!(cpu.receive(5), Received::OutOfOrder);
    assert_eq!(cpu.receive(0), Received::Duplicate);
    assert_eq!(cpu.receive(1), Received::New);
}

/// AINFO examples of the Siemens manual (records-diagnosis.md TV10, TV11): channel
/// diagnosis 0x8000, and a MaintenanceItem followed by extended channel diagnosis.
#[test]
fn manual_examples() {
    let tv10 = hex(concat!(
        "0002001e0100000100000000001000010000",
        "8ad800000000a854800000002805",
        "0006"
    ));
    let n = AlarmNotification::parse(&tv10).unwrap();
    assert_eq!(n.alarm_type, AlarmType::Diagnosis);
    assert_eq!((n.slot, n.subslot, n.module_ident), (0x10, 1, 0x8ad8));
    assert_eq!(n.specifier.sequence_number, 84);
    assert_eq!(n.specifier, spec(84));
    let d = n.diagnosis().unwrap();
    assert_eq!(d.format, DiagnosisFormat::Channel);
    assert_eq!(
        d.entries,
        vec![ChannelDiagnosis::new(0, ChannelProperties(0x2805), 6)]
    );
    assert_eq!(d.entries[0].channel_properties.data_type(), 5);
    let mut out = vec![0u8; n.buffer_len()];
    n.emit(&mut out).unwrap();
    assert_eq!(out, tv10);

    let tv11 = hex(concat!(
        "000200320100000e0000000000008001",
        "000003630000000100048100",
        "0f0000080100000000000001",
        "800280000a008007800000000010",
    ));
    let n = AlarmNotification::parse(&tv11).unwrap();
    assert_eq!(n.alarm_type, AlarmType::PortDataChange);
    assert_eq!((n.slot, n.subslot), (0, 0x8001));
    assert_eq!(n.specifier, AlarmSpecifier::from_u16(4));
    let m = n.maintenance.unwrap();
    assert!(m.maintenance_required() && !m.maintenance_demanded());
    let d = n.diagnosis().unwrap();
    assert_eq!(d.format, DiagnosisFormat::Extended);
    let e = d.entries[0];
    assert_eq!(e.channel_number, CHANNEL_NUMBER_SUBMODULE);
    assert!(e.channel_properties.maintenance_required());
    assert_eq!(e.channel_properties.specifier(), ChannelSpecifier::Appears);
    assert_eq!(
        (
            e.channel_error_type,
            e.ext_channel_error_type,
            e.ext_channel_add_value
        ),
        (0x8007, 0x8000, 16)
    );
    let mut out = vec![0u8; n.buffer_len()];
    n.emit(&mut out).unwrap();
    assert_eq!(out, tv11);
}

#[test]
fn qualified_diagnosis_round_trip() {
    let entry = ChannelDiagnosis {
        channel_number: 3,
        channel_properties: ChannelProperties(0x4801),
        channel_error_type: 6,
        ext_channel_error_type: 0x8001,
        ext_channel_add_value: 0x0102_0304,
        qualifier: 1 << 27,
    };
    let n = AlarmNotification {
        priority: Priority::Low,
        alarm_type: AlarmType::Diagnosis,
        api: 0,
        slot: 2,
        subslot: 1,
        module_ident: 7,
        submodule_ident: 8,
        specifier: spec(9),
        maintenance: None,
        item: Some(AlarmItem::Diagnosis(Diagnosis {
            format: DiagnosisFormat::Qualified,
            entries: vec![entry, entry],
        })),
    };
    assert_eq!(n.buffer_len(), 6 + 20 + 2 + 32);
    let mut out = vec![0u8; n.buffer_len()];
    n.emit(&mut out).unwrap();
    assert_eq!(&out[26..28], &[0x80, 0x03]);
    assert_eq!(AlarmNotification::parse(&out).unwrap(), n);
    // A diagnosis USI with a partial entry stays raw.
    assert_eq!(
        AlarmItem::parse(USI_CHANNEL_DIAGNOSIS, &[0, 1, 2]),
        AlarmItem::Other {
            usi: USI_CHANNEL_DIAGNOSIS,
            data: vec![0, 1, 2]
        }
    );
}

#[test]
fn malformed() {
    let ok = hex(ACK_RTA_HIGH_DEV);
    let pdu = &ok[18..];
    // Truncated headers.
    for n in 0..HEADER_LEN {
        assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&pdu[..n])), Err(Error));
    }
    // Not an alarm FrameID.
    let mut b = pdu.to_vec();
    b[0..2].copy_from_slice(&0xfefeu16.to_be_bytes());
    assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&b[..])), Err(Error));
    // Unknown PDU type.
    let mut b = pdu.to_vec();
    b[6] = 0x15;
    assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&b[..])), Err(Error));
    // ACK with a VarPart; VarPartLen past the buffer.
    let mut b = pdu.to_vec();
    b[13] = 2;
    assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&b[..])), Err(Error));
    b.extend_from_slice(&[0, 0]);
    assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&b[..])), Err(Error));
    // ERR shorter than its status.
    let err = hex(ERR_RTA_DEV);
    let mut b = err[18..].to_vec();
    b[13] = 3;
    assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&b[..])), Err(Error));
    // DATA whose block runs past VarPartLen.
    let data = hex(PROCESS_NOTIF);
    let mut b = data[18..].to_vec();
    b[13] -= 1;
    assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&b[..])), Err(Error));
    // A notification with one stray byte after the specifier.
    let mut n = hex("0001001701000002000000000001000100000030000001300000ff");
    assert_eq!(AlarmNotification::parse(&n), Err(Error));
    n[3] = 0x16;
    assert!(AlarmNotification::parse(&n).is_ok());
    // An AlarmAck of the wrong length.
    let mut a = hex(ACK_HIGH_CPU)[32..54].to_vec();
    assert!(AlarmAck::parse(&a).is_ok());
    a[3] = 0x11;
    assert_eq!(AlarmAck::parse(&a), Err(Error));
    // Emit into short buffers.
    let p = capture(PROCESS_NOTIF);
    let mut buf = vec![0u8; p.buffer_len() - 1];
    let short = p.emit(&mut buf).unwrap_err();
    assert_eq!(
        short,
        EmitError::BufferTooShort {
            what: "RTA PDU",
            needed: buf.len() + 1,
            len: buf.len()
        }
    );
    assert_eq!(
        short.to_string(),
        format!(
            "buffer of {} bytes, the RTA PDU needs {}",
            buf.len(),
            buf.len() + 1
        )
    );
    assert_eq!(RtaHeader::parse(&[0; 11]), Err(Error));
    assert!(matches!(
        p.header.emit(&mut [0; 11]),
        Err(EmitError::BufferTooShort { needed: 12, .. })
    ));
}

fn header() -> impl Strategy<Value = RtaHeader> {
    (
        any::<(u16, u16, u16, u16, u16)>(),
        0u8..16,
        0u8..16,
        0u8..16,
        any::<bool>(),
    )
        .prop_map(
            |((dst, src, send, ack, len), ty, version, window, tack)| RtaHeader {
                dst_endpoint: dst,
                src_endpoint: src,
                pdu_type: PduType::from(ty),
                version,
                window_size: window,
                tack,
                send_seq: send,
                ack_seq: ack,
                var_part_len: len,
            },
        )
}

fn priority() -> impl Strategy<Value = Priority> {
    prop_oneof![Just(Priority::High), Just(Priority::Low)]
}

fn alarm_ack() -> impl Strategy<Value = AlarmAck> {
    (
        priority(),
        any::<(u16, u32, u16, u16, u32)>(),
        0u16..0x800,
        any::<u16>(),
    )
        .prop_map(
            |(priority, (ty, api, slot, subslot, status), seq, flags)| AlarmAck {
                priority,
                alarm_type: AlarmType::from(ty),
                api,
                slot,
                subslot,
                specifier: AlarmSpecifier::from_u16((flags & 0xb800) | seq),
                status: PnioStatus::from_u32(status),
            },
        )
}

fn notification() -> impl Strategy<Value = AlarmNotification> {
    (
        priority(),
        any::<(u16, u32, u16, u16, u32, u32)>(),
        0u16..0x800,
        any::<u16>(),
        proptest::option::of(any::<u32>()),
        proptest::option::of(alarm_item(0..5)),
    )
        .prop_map(
            |(priority, (ty, api, slot, subslot, module, submodule), seq, flags, m, item)| {
                AlarmNotification {
                    priority,
                    alarm_type: AlarmType::from(ty),
                    api,
                    slot,
                    subslot,
                    module_ident: module,
                    submodule_ident: submodule,
                    specifier: AlarmSpecifier::from_u16((flags & 0xb800) | seq),
                    maintenance: m.map(|status| MaintenanceItem { status }),
                    item,
                }
            },
        )
}

fn pdu() -> impl Strategy<Value = RtaPdu> {
    let block = prop_oneof![
        notification().prop_map(AlarmBlock::Notification),
        alarm_ack().prop_map(AlarmBlock::Ack),
    ];
    let body = prop_oneof![
        proptest::collection::vec(block, 0..3).prop_map(RtaBody::Data),
        Just(RtaBody::Ack),
        Just(RtaBody::Nack),
        (any::<u32>(), proptest::collection::vec(any::<u8>(), 0..8)).prop_map(
            |(s, vendor_data)| RtaBody::Err(ErrRta {
                status: PnioStatus::from_u32(s),
                vendor_data
            })
        ),
    ];
    (priority(), any::<(u16, u16, u16, u16)>(), body).prop_map(
        |(priority, (dst, src, send, ack), body)| RtaPdu::new(priority, dst, src, send, ack, body),
    )
}

proptest! {
    #[test]
    fn parse_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let p = Packet::new_unchecked(&bytes[..]);
        if let Ok(r) = RtaPdu::parse(&p) {
            // What parses emits again, to the same length (reserved bits and block
            // versions are normalised).
            let v = r.to_vec().unwrap();
            prop_assert_eq!(v.len(), HEADER_LEN + usize::from(p.var_part_len()));
        }
        let _ = p.to_string();
        let _ = RtaHeader::parse(&bytes);
        let _ = AlarmNotification::parse(&bytes);
        let _ = AlarmAck::parse(&bytes);
        let _ = AlarmBlock::parse(&bytes);
        let _ = ErrRta::parse(&bytes);
    }

    #[test]
    fn parse_never_panics_on_plausible_pdus(
        frame_id in prop_oneof![Just(FRAME_ID_ALARM_HIGH), Just(FRAME_ID_ALARM_LOW)],
        pdu_type in 0u8..6,
        block_type in prop_oneof![Just(1u16), Just(2u16), Just(0x8001u16), Just(0x8002u16)],
        body in proptest::collection::vec(any::<u8>(), 0..80),
    ) {
        let mut b = frame_id.to_be_bytes().to_vec();
        b.extend_from_slice(&[0, 0, 0, 0, 0x10 | pdu_type, 0x11, 0, 0, 0, 0]);
        let var_len = body.len() + 4;
        b.extend_from_slice(&(var_len as u16).to_be_bytes());
        b.extend_from_slice(&block_type.to_be_bytes());
        b.extend_from_slice(&(body.len() as u16).to_be_bytes());
        b.extend_from_slice(&body);
        if let Ok(r) = RtaPdu::parse(&Packet::new_unchecked(&b[..])) {
            prop_assert_eq!(r.to_vec().unwrap().len(), b.len());
        }
    }

    #[test]
    fn diagnosis_decoding_never_panics(
        usi in 0x7ffeu16..0x8005,
        data in proptest::collection::vec(any::<u8>(), 0..64),
    ) {
        let item = AlarmItem::parse(usi, &data);
        prop_assert_eq!(item.buffer_len(), data.len() + 2);
    }

    #[test]
    fn rta_header_round_trip(h in header()) {
        let mut buf = [0u8; RTA_HEADER_LEN];
        h.emit(&mut buf).unwrap();
        prop_assert_eq!(RtaHeader::parse(&buf).unwrap(), h);
        // The view reads the same fields.
        let mut full = [0u8; HEADER_LEN];
        full[2..].copy_from_slice(&buf);
        let p = Packet::new_unchecked(&full[..]);
        prop_assert_eq!(
            (p.dst_endpoint(), p.src_endpoint(), p.pdu_type(), p.version()),
            (h.dst_endpoint, h.src_endpoint, h.pdu_type, h.version)
        );
        prop_assert_eq!(
            (p.window_size(), p.tack(), p.send_seq(), p.ack_seq(), p.var_part_len()),
            (h.window_size, h.tack, h.send_seq, h.ack_seq, h.var_part_len)
        );
        // And the setters write them.
        let mut other = [0u8; HEADER_LEN];
        let mut q = Packet::new_unchecked(&mut other[..]);
        q.set_dst_endpoint(h.dst_endpoint);
        q.set_src_endpoint(h.src_endpoint);
        q.set_pdu_type(h.pdu_type, h.version);
        q.set_add_flags(h.window_size, h.tack);
        q.set_send_seq(h.send_seq);
        q.set_ack_seq(h.ack_seq);
        q.set_var_part_len(h.var_part_len);
        prop_assert_eq!(&other[2..], &buf[..]);
    }

    #[test]
    fn alarm_ack_round_trip(a in alarm_ack()) {
        let mut buf = [0u8; AlarmAck::LEN];
        a.emit(&mut buf).unwrap();
        prop_assert_eq!(AlarmAck::parse(&buf).unwrap(), a);
    }

    #[test]
    fn notification_round_trip(n in notification()) {
        let mut buf = vec![0u8; n.buffer_len()];
        n.emit(&mut buf).unwrap();
        prop_assert_eq!(AlarmNotification::parse(&buf).unwrap(), n);
    }

    #[test]
    fn pdu_round_trip(p in pdu()) {
        let bytes = p.to_vec().unwrap();
        prop_assert_eq!(bytes.len(), p.buffer_len());
        let back = RtaPdu::parse(&Packet::new_checked(&bytes[..]).unwrap()).unwrap();
        prop_assert_eq!(back, p);
    }

    #[test]
    fn sequence_numbers_stay_in_range(n in any::<u16>()) {
        let m = next_seq(n);
        prop_assert!(m <= SEQ_MAX || (n == SEQ_INITIAL_LAST && m == SEQ_INITIAL));
    }
}
