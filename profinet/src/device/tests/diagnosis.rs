// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device's diagnosis, identification and I&M records, through [`Device`]: the p-net
//! sample device of the captures in data exchange with the S7, diagnosis added and removed by
//! the application, the alarms it sends compared with the ones p-net sent (captures
//! alarm/alarm_diag_*), and the records read back with built requests.

use super::*;
use crate::wire::alarm::{AlarmNotification, AlarmType};
use crate::wire::connect::{ModuleDiffBlock, SubmoduleState};
use crate::wire::diagnosis::{AlarmItem, ChannelDirection};
use crate::wire::record::{
    DiagnosisData, IdentApi, IdentificationData, IdentificationKind, Im0FilterData, Im1,
    blank_padded,
};
use crate::wire::rta_pdu::{self, RtaHeader, RtaPdu};

/// The extended channel diagnosis of the captures: channel 4 of slot 1 subslot 1, 1 bit,
/// input, short circuit.
fn channel_4(add_value: u32) -> ChannelDiag {
    ChannelDiag::extended(4, 1, 0, add_value)
        .with_data_type(1)
        .with_direction(ChannelDirection::Input)
}

/// The AlarmNotification block p-net sent in a captured alarm frame.
fn captured_block(name: &str) -> Vec<u8> {
    let frame = capture(&format!("alarm/{name}"));
    let len = usize::from(u16::from_be_bytes([frame[34], frame[35]])) + 4;
    frame[32..32 + len].to_vec()
}

/// The RTA PDUs among the frames of `out`, with the block bytes of their notification.
fn alarms_sent(out: &[DeviceAction]) -> Vec<(RtaPdu, Vec<u8>)> {
    frames(out)
        .iter()
        .filter(|f| f[18..20] == [0xfe, 0x01] || f[18..20] == [0xfc, 0x01])
        .map(|f| {
            let pdu = RtaPdu::parse(&rta_pdu::Packet::new_checked(&f[18..]).unwrap()).unwrap();
            let len = usize::from(pdu.header.var_part_len);
            (pdu, f[32..32 + len].to_vec())
        })
        .collect()
}

/// The S7's transport acknowledgement of the DATA-RTA with `h` (as the capture
/// alarm_ack_rta_low_cpu shows it).
pub(super) fn ack_rta(
    dev: &mut Device<TestApp>,
    h: &RtaHeader,
    priority: Priority,
    now: u64,
) -> Vec<DeviceAction> {
    let pdu = RtaPdu::first_ack_of(priority, h);
    let tci = match priority {
        Priority::High => 0xc000,
        Priority::Low => 0xa000,
    };
    let frame = ethernet_frame(PNET_MAC, S7_MAC, Some(tci), &pdu.to_vec().unwrap());
    let mut out = Vec::new();
    dev.on_frame(&frame, now, &mut out);
    out
}

/// The DataStatus of the next input CR frame.
fn next_data_status(dev: &mut Device<TestApp>) -> u8 {
    let mut out = Vec::new();
    loop {
        let t = dev.next_deadline_ns().unwrap();
        dev.poll(t, &mut out);
        if let Some(f) = frames(&out).into_iter().find(|f| f[18..20] == [0x80, 0x00]) {
            return f[62];
        }
    }
}

/// A record client on the S7's RPC socket, counting its sequence numbers.
struct Client {
    seq: u32,
}

impl Client {
    /// Reads `index` of (API 0, `slot`, `subslot`) in the AR (or implicitly, outside it):
    /// the status and the record data.
    fn read(
        &mut self,
        dev: &mut Device<TestApp>,
        implicit: bool,
        (slot, subslot): (u16, u16),
        index: u16,
    ) -> (PnioStatus, Vec<u8>) {
        self.seq += 1;
        let ar = if implicit {
            Uuid::NIL
        } else {
            dev.ar().ar_uuid().unwrap()
        };
        let h = IodHeader::read_request(0, ar, 0, slot, subslot, index, 4096);
        let op = if implicit {
            opnum::READ_IMPLICIT
        } else {
            opnum::READ
        };
        let r = call(
            dev,
            &request(op, ACTIVITY, self.seq, &h.to_bytes(), true),
            100 * MS,
        );
        let (_, data, _) = IodHeader::split(&r.blocks).unwrap();
        (status(&r), data.to_vec())
    }

    /// The data of a successful read.
    fn data(&mut self, dev: &mut Device<TestApp>, at: (u16, u16), index: u16) -> Vec<u8> {
        let (s, d) = self.read(dev, false, at, index);
        assert_eq!(s, PnioStatus::OK, "read of {index:#06x}");
        d
    }

    /// Writes `data` to `index` of (API 0, `slot`, `subslot`) in the AR: the status.
    fn write(
        &mut self,
        dev: &mut Device<TestApp>,
        (slot, subslot): (u16, u16),
        index: u16,
        data: &[u8],
    ) -> PnioStatus {
        self.seq += 1;
        let ar = dev.ar().ar_uuid().unwrap();
        let h = IodHeader::write_request(0, ar, 0, slot, subslot, index, data.len() as u32);
        let mut b = h.to_bytes().to_vec();
        b.extend_from_slice(data);
        status(&call(
            dev,
            &request(opnum::WRITE, ACTIVITY, self.seq, &b, true),
            100 * MS,
        ))
    }
}

/// `block` with another sequence number in its AlarmSpecifier (the captures' AR had sent
/// other alarms before).
fn with_sequence(block: &[u8], seq: u16) -> Vec<u8> {
    let mut n = AlarmNotification::parse(block).unwrap();
    n.specifier.sequence_number = seq;
    let mut b = vec![0u8; n.buffer_len()];
    n.emit(&mut b).unwrap();
    b
}

#[test]
fn diagnosis_alarms_match_p_nets_and_the_records_follow() {
    let (mut dev, t) = pnet_in_data(TestApp::None);
    let mut client = Client { seq: 0 };
    assert!(!dev.station_problem());
    assert_eq!(next_data_status(&mut dev), data_status::OPERATE);

    // The fault appears: the first low-priority DATA-RTA, p-net's notification byte for byte.
    let mut out = Vec::new();
    let c = dev
        .add_diagnosis(0, 1, 1, channel_4(0), t, &mut out)
        .unwrap();
    assert_eq!(
        c,
        DiagnosisChange {
            changed: true,
            alarms_sent: 1,
            alarms_too_long: 0
        }
    );
    let sent = alarms_sent(&out);
    assert_eq!(sent.len(), 1);
    let (pdu, block) = &sent[0];
    assert_eq!(pdu.priority, Priority::Low);
    assert_eq!((pdu.header.send_seq, pdu.header.ack_seq), (0xffff, 0xfffe));
    assert!(pdu.header.tack);
    assert_eq!(block, &captured_block("alarm_diag_notif"));
    // The station problem shows in the DataStatus (0x15: primary, valid, run, problem).
    assert!(dev.station_problem());
    assert_eq!(next_data_status(&mut dev), 0x15);

    // The add value changes: two alarms; the second waits for the first's transport ACK.
    out.clear();
    let c = dev
        .add_diagnosis(0, 1, 1, channel_4(1234), t, &mut out)
        .unwrap();
    assert_eq!((c.changed, c.alarms_sent), (true, 2));
    let sent = alarms_sent(&out);
    assert_eq!(sent.len(), 0, "the first DATA-RTA is not confirmed yet");
    let out = ack_rta(&mut dev, &pdu.header, Priority::Low, t + MS);
    let sent = alarms_sent(&out);
    assert_eq!(sent.len(), 1);
    assert_eq!(sent[0].1, captured_block("alarm_diag_update_appears"));
    let out = ack_rta(&mut dev, &sent[0].0.header, Priority::Low, t + 2 * MS);
    let sent = alarms_sent(&out);
    assert_eq!(sent[0].1, captured_block("alarm_diag_update_others_remain"));
    let last = sent[0].0.header;
    // The same again: nothing changes, nothing is sent.
    let mut out = Vec::new();
    let c = dev
        .add_diagnosis(0, 1, 1, channel_4(1234), t, &mut out)
        .unwrap();
    assert_eq!(c, DiagnosisChange::default());
    assert!(out.is_empty());

    // The records: channel and all codings at every level, nothing for maintenance.
    let expected = DiagnosisData::record_to_vec(&[DiagnosisData {
        version: crate::wire::record::RecordVersion::V1_1,
        api: 0,
        slot: 1,
        subslot: 1,
        channel_number: 0x8000,
        channel_properties: crate::wire::diagnosis::ChannelProperties(0x0800),
        item: AlarmItem::parse(
            0x8002,
            &crate::test_fixtures::hex("0004 2801 0001 0000 000004d2"),
        ),
    }])
    .unwrap();
    for (at, index) in [
        ((1, 1), 0x800a),
        ((1, 1), 0x800b),
        ((1, 1), 0x800c),
        ((1, 7), 0xc00a),
        ((0, 1), 0xe00c),
        ((0, 1), 0xf00b),
        ((0, 0), 0xf80c),
    ] {
        assert_eq!(client.data(&mut dev, at, index), expected, "{index:#06x}");
    }
    for index in [0x8010, 0x8011, 0x8012, 0x8013] {
        assert_eq!(client.data(&mut dev, (1, 1), index), vec![], "{index:#06x}");
    }
    // Another subslot has none; an unknown one is refused.
    assert_eq!(client.data(&mut dev, (2, 1), 0x800c), vec![]);
    assert_eq!(
        client.read(&mut dev, false, (9, 1), 0x800c).0,
        PnioStatus::from_bytes([0xde, 0x80, 0xb2, 0])
    );
    // The ModuleDiffBlock lists the submodule: as expected, with diagnosis.
    let diff = ModuleDiffBlock::parse(&client.data(&mut dev, (0, 1), 0xe002)).unwrap();
    let subs: Vec<_> = diff.submodules().collect();
    let state = SubmoduleState(SubmoduleState::FORMAT_INDICATOR | SubmoduleState::DIAG_INFO);
    assert_eq!(subs, vec![(0, 1, 1, state)]);
    assert!(state.is_usable() && state.fault());

    // It disappears: the last one, so all disappear (p-net's alarm_diag_std_remove).
    let mut out = Vec::new();
    let k = DiagEntry::from(channel_4(0)).key();
    let c = dev
        .remove_diagnosis(0, 1, 1, &k, t + 3 * MS, &mut out)
        .unwrap();
    assert_eq!((c.changed, c.alarms_sent), (true, 1));
    let out = ack_rta(&mut dev, &last, Priority::Low, t + 4 * MS);
    let sent = alarms_sent(&out);
    assert_eq!(
        sent[0].1,
        with_sequence(&captured_block("alarm_diag_std_remove"), 3)
    );
    assert!(!dev.station_problem());
    assert_eq!(next_data_status(&mut dev), data_status::OPERATE);
    assert_eq!(client.data(&mut dev, (1, 1), 0x800c), vec![]);
    assert_eq!(client.data(&mut dev, (0, 1), 0xe002), vec![]);
    // Nothing left to remove.
    let mut out = Vec::new();
    let c = dev.remove_diagnosis(0, 1, 1, &k, t, &mut out).unwrap();
    assert!(!c.changed && out.is_empty());
}

#[test]
fn manufacturer_diagnosis_clearing_and_limits() {
    let (mut dev, t) = pnet_in_data(TestApp::None);
    let mut client = Client { seq: 0 };
    // A manufacturer fault and a maintenance demand on slot 1, then its USI disappears
    // (p-net's alarm_diag_usi_disappears, but for the maintenance entry that remains).
    let mut out = Vec::new();
    dev.add_diagnosis(0, 1, 1, GenericDiag::new(0x1234, &[1, 2]), t, &mut out)
        .unwrap();
    let first = alarms_sent(&out).remove(0);
    assert_eq!(
        first.0.notification().unwrap().alarm_type,
        AlarmType::Diagnosis
    );
    let demand = channel_4(0).with_severity(Severity::MaintenanceDemanded);
    dev.add_diagnosis(0, 1, 1, demand, t, &mut out).unwrap();
    let k = DiagKey::Generic { usi: 0x1234 };
    dev.remove_diagnosis(0, 1, 1, &k, t, &mut out).unwrap();
    let out = ack_rta(&mut dev, &first.0.header, Priority::Low, t + MS);
    let second = alarms_sent(&out).remove(0);
    let n = second.0.notification().unwrap();
    assert_eq!(n.maintenance.map(|m| m.status), Some(2), "demanded");
    let out = ack_rta(&mut dev, &second.0.header, Priority::Low, t + 2 * MS);
    let third = alarms_sent(&out).remove(0);
    let n = third.0.notification().unwrap();
    assert_eq!(n.alarm_type, AlarmType::DiagnosisDisappears);
    assert_eq!(
        n.item,
        Some(AlarmItem::Other {
            usi: 0x1234,
            data: vec![]
        })
    );
    // No fault left: ChannelDiagnosis only, no station problem.
    assert_eq!(n.specifier.to_u16() & 0xf800, 0x0800);
    assert!(!dev.station_problem());
    // The maintenance demand is in the DMQS and maintenance records, not in the faults.
    assert_eq!(client.data(&mut dev, (1, 1), 0x800b), vec![]);
    assert_eq!(client.data(&mut dev, (1, 1), 0x8011).len(), 32);
    assert_eq!(
        client.data(&mut dev, (1, 1), 0x8011),
        client.data(&mut dev, (1, 1), 0x800c)
    );
    let diff = ModuleDiffBlock::parse(&client.data(&mut dev, (0, 1), 0xe002)).unwrap();
    let (_, _, _, state) = diff.submodules().next().unwrap();
    assert!(state.maintenance_demanded() && !state.fault());

    // Clearing: one DiagnosisDisappears without an item.
    let c = dev.clear_diagnosis(0, 1, 1, t, &mut Vec::new()).unwrap();
    assert_eq!((c.changed, c.alarms_sent), (true, 1));
    let out = ack_rta(&mut dev, &third.0.header, Priority::Low, t + 3 * MS);
    let cleared = alarms_sent(&out).remove(0);
    let n = cleared.0.notification().unwrap();
    assert_eq!(
        (n.alarm_type, n.item.clone()),
        (AlarmType::DiagnosisDisappears, None)
    );
    assert_eq!(cleared.1.len(), 26);
    assert!(dev.diagnosis().is_empty());

    // Data too long for the AR's MaxAlarmDataLength (200): stored, readable, not sent.
    let mut out = Vec::new();
    let big = GenericDiag::new(7, &[0x55; 300]);
    let c = dev.add_diagnosis(0, 2, 1, big, t, &mut out).unwrap();
    assert_eq!(
        c,
        DiagnosisChange {
            changed: true,
            alarms_sent: 0,
            alarms_too_long: 1
        }
    );
    assert!(out.is_empty());
    let record = client.data(&mut dev, (2, 1), 0x800b);
    assert_eq!(record.len(), 20 + 300);
    assert!(dev.station_problem());
    // Unknown submodules and invalid entries change nothing.
    assert_eq!(
        dev.add_diagnosis(0, 9, 1, ChannelDiag::new(0, 1), t, &mut out),
        Err(DiagnosisError::UnknownSubmodule(SubslotAddr::new(0, 9, 1)))
    );
    assert!(matches!(
        dev.add_diagnosis(0, 1, 1, ChannelDiag::new(0x9000, 1), t, &mut out),
        Err(DiagnosisError::InvalidEntry(_))
    ));
    assert!(out.is_empty());
}

#[test]
fn diagnosis_before_the_ar_is_in_the_module_diff_and_the_records() {
    let mut dev = pnet_device(TestApp::None);
    let mut out = Vec::new();
    // No AR: the store takes it, no alarm goes out.
    let required = channel_4(0).with_severity(Severity::MaintenanceRequired);
    let c = dev.add_diagnosis(0, 1, 1, required, 0, &mut out).unwrap();
    assert_eq!((c.changed, c.alarms_sent), (true, 0));
    dev.add_diagnosis(0, 2, 1, ChannelDiag::new(0x8000, 0x0011), 0, &mut out)
        .unwrap();
    assert!(out.is_empty());
    // The Connect response's ModuleDiffBlock lists both, as the proper submodules they are.
    let r = call(&mut dev, &rpc_pdu("cm/connect_req"), 0);
    assert_eq!(status(&r), PnioStatus::OK);
    let res = ConnectResponse::parse(&r.blocks).unwrap();
    let diff = res.module_diff.expect("a ModuleDiffBlock");
    let fi = SubmoduleState::FORMAT_INDICATOR;
    assert_eq!(
        diff.submodules().collect::<Vec<_>>(),
        vec![
            (
                0,
                1,
                1,
                SubmoduleState(fi | SubmoduleState::MAINTENANCE_REQUIRED)
            ),
            (0, 2, 1, SubmoduleState(fi | SubmoduleState::DIAG_INFO)),
        ]
    );
    assert!(
        diff.apis[0]
            .modules
            .iter()
            .all(|m| m.state == ModuleState::ProperModule)
    );
    // The ApplicationReady carries it as it is then: slot 2's fault went meanwhile.
    call(&mut dev, &rpc_pdu("cm/write_req"), MS);
    let k = DiagEntry::from(ChannelDiag::new(0x8000, 0x0011)).key();
    dev.remove_diagnosis(0, 2, 1, &k, MS, &mut out).unwrap();
    assert!(out.is_empty(), "no alarm before data exchange");
    call(&mut dev, &rpc_pdu("cm/prmend_req"), 2 * MS);
    dev.poll(2 * MS + APP_READY_DELAY_NS, &mut out);
    let app = parse_reply(&datagrams(&out)[0].2);
    let control_len = crate::wire::control::BLOCK_LEN;
    let diff = ModuleDiffBlock::parse(&app.blocks[control_len..]).unwrap();
    assert_eq!(diff.submodules().count(), 1);
}

#[test]
fn identification_records() {
    let (mut dev, _) = pnet_in_data(TestApp::None);
    let mut client = Client { seq: 0 };
    let plugged: Vec<_> = pnet_submodules()
        .iter()
        .map(|s| (s.api, s.slot, s.module_ident, s.subslot, s.submodule_ident))
        .collect();
    let ident = |b: Vec<u8>| IdentificationData::parse(&b).unwrap();
    // The AR expects what is plugged (the connect capture made both).
    let e = ident(client.data(&mut dev, (0, 1), 0xe000));
    assert_eq!(e.kind, IdentificationKind::Expected);
    assert_eq!(IdentApi::flatten(&e.apis).collect::<Vec<_>>(), plugged);
    let mut sorted = plugged.clone();
    sorted.sort_by_key(|&(api, slot, _, subslot, _)| (api, slot, subslot));
    for index in [0xe001, 0xf000] {
        let r = ident(client.data(&mut dev, (0, 1), index));
        assert_eq!(r.kind, IdentificationKind::Real);
        assert_eq!(IdentApi::flatten(&r.apis).collect::<Vec<_>>(), sorted);
    }
    // One subslot, one slot.
    let one = ident(client.data(&mut dev, (1, 1), 0x8000));
    assert_eq!(
        IdentApi::flatten(&one.apis).collect::<Vec<_>>(),
        [(0, 1, 0x30, 1, 0x130)]
    );
    let slot0 = ident(client.data(&mut dev, (0, 0x8001), 0xc001));
    assert!(IdentApi::flatten(&slot0.apis).all(|(_, slot, ..)| slot == 0));
    assert_eq!(slot0.apis[0].modules[0].submodules.len(), 3);
    // Unknown places are refused; without the AR its records are a state conflict.
    let invalid = PnioStatus::from_bytes([0xde, 0x80, 0xb2, 0]);
    assert_eq!(client.read(&mut dev, false, (9, 1), 0x8001).0, invalid);
    assert_eq!(client.read(&mut dev, false, (9, 0), 0xc000).0, invalid);
    let conflict = PnioStatus::from_bytes([0xde, 0x80, 0xb5, 0]);
    assert_eq!(client.read(&mut dev, true, (0, 1), 0xe000).0, conflict);
    assert_eq!(client.read(&mut dev, true, (0, 1), 0xe002).0, conflict);
    // The real configuration reads without the AR, the AR's diagnosis is empty.
    let (s, d) = client.read(&mut dev, true, (0, 1), 0xf000);
    assert_eq!((s, ident(d).apis.len()), (PnioStatus::OK, 1));
    assert_eq!(
        client.read(&mut dev, true, (0, 1), 0xe00c),
        (PnioStatus::OK, vec![])
    );
    // No difference, no ModuleDiffBlock.
    assert_eq!(client.data(&mut dev, (0, 1), 0xe002), vec![]);
}

#[test]
fn im_records_are_kept_by_the_device() {
    let (mut dev, _) = pnet_in_data(TestApp::None);
    let mut client = Client { seq: 0 };
    // Blanks until written.
    let blank = Im1::default().to_bytes().to_vec();
    assert_eq!(client.data(&mut dev, (0, 1), 0xaff1), blank);
    let im1 = Im1 {
        tag_function: blank_padded("pressure sensor 7").unwrap(),
        tag_location: blank_padded("production hall 3").unwrap(),
    };
    assert_eq!(
        client.write(&mut dev, (0, 1), 0xaff1, &im1.to_bytes()),
        PnioStatus::OK
    );
    assert_eq!(client.data(&mut dev, (0, 1), 0xaff1), im1.to_bytes());
    assert_eq!(dev.station().im_records().im1, im1);
    assert_eq!(dev.station().im_write_count(), 1);
    // I&M2–4 too; another length, another block, I&M0: refused.
    let mut im4 = dev.station().im_records().im4;
    im4.signature[0] = 0x42;
    assert_eq!(
        client.write(&mut dev, (0, 1), 0xaff4, &im4.to_bytes()),
        PnioStatus::OK
    );
    assert_eq!(
        client.write(&mut dev, (0, 1), 0xaff2, &[0; 21]),
        PnioStatus::from_bytes([0xdf, 0x80, 0xb1, 0])
    );
    assert_eq!(
        client.write(&mut dev, (0, 1), 0xaff3, &im1.to_bytes()),
        PnioStatus::from_bytes([0xdf, 0x80, 0xb8, 0])
    );
    assert_eq!(dev.station().im_write_count(), 2);
    // They outlast the AR, and a runtime can put back what it stored.
    let kept = *dev.station().im_records();
    assert_eq!(kept.im4, im4);
    let mut other = pnet_device(TestApp::None);
    other.station_mut().set_im_records(kept);
    assert_eq!(other.station().im_records(), &kept);
    // I&M0FilterData: the access point carries the device's I&M, read even at subslot 0.
    let (s, d) = client.read(&mut dev, true, (0, 0), 0xf840);
    assert_eq!(s, PnioStatus::OK);
    let f = Im0FilterData::parse(&d).unwrap();
    let dap = pnet_submodules()
        .into_iter()
        .min_by_key(|s| (s.api, s.slot, s.subslot))
        .unwrap();
    let expected = IdentApi::group([(0, 0, dap.module_ident, dap.subslot, dap.submodule_ident)]);
    assert_eq!(
        (&f.submodules, &f.modules, &f.device),
        (&expected, &expected, &expected)
    );
}
