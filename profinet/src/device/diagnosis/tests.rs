// SPDX-License-Identifier: MIT OR Apache-2.0
//! Tests of the diagnosis store: its alarms against the p-net device's captured ones (the
//! captures in profinet/tests/fixtures/captures/alarm, test data of the `pnio` crate 0.1.0,
//! MIT OR Apache-2.0), its records against the Siemens manual's worked examples, and the
//! filters and states.

use super::records::{DiagnosisScope, Selection, diagnosis_index};
use super::*;
use crate::test_fixtures::{capture, hex};
use crate::wire::connect::SubmoduleState;
use crate::wire::diagnosis::{CHANNEL_NUMBER_SUBMODULE, ChannelDirection};
use crate::wire::record::DiagnosisData;

/// The p-net sample device's submodule of the captures: API 0, slot 1, subslot 1.
const AT: SubslotAddr = SubslotAddr::new(0, 1, 1);
const MODULE_IDENT: u32 = 0x30;
const SUBMODULE_IDENT: u32 = 0x130;

/// The AlarmNotification block of a captured alarm frame: after Ethernet, VLAN tag and
/// EtherType (18 bytes) and the RTA header with its FrameID (14 bytes).
fn captured_notification(name: &str) -> Vec<u8> {
    let frame = capture(&format!("alarm/{name}"));
    let block = &frame[32..];
    let len = usize::from(u16::from_be_bytes([block[2], block[3]])) + 4;
    block[..len].to_vec()
}

/// The bytes of `alarm` as the device sends it: the submodule's idents, `seq`, and
/// ARDiagnosisState from the store (the captures' AR has this one submodule).
fn sent(store: &DiagnosisStore, alarm: &DiagnosisAlarm, seq: u16) -> Vec<u8> {
    let n = alarm.notification(MODULE_IDENT, SUBMODULE_IDENT, seq, store.has_fault());
    let mut b = vec![0u8; n.buffer_len()];
    n.emit(&mut b).unwrap();
    b
}

/// The extended channel diagnosis of the captures: channel 4, 1 bit, input, ChannelErrorType
/// 1 (short circuit), ExtChannelErrorType 0.
fn channel_4(add_value: u32) -> DiagEntry {
    ChannelDiag::extended(4, 1, 0, add_value)
        .with_data_type(1)
        .with_direction(ChannelDirection::Input)
        .into()
}

#[test]
fn the_captured_p_net_alarms_byte_for_byte() {
    let mut store = DiagnosisStore::new();
    // Seq 0: the fault appears (alarm_diag_notif).
    let a = store.add(AT, channel_4(0)).unwrap();
    assert_eq!(a.len(), 1);
    assert_eq!(
        sent(&store, &a[0], 0),
        captured_notification("alarm_diag_notif")
    );
    // Adding it again changes nothing.
    assert_eq!(store.add(AT, channel_4(0)).unwrap(), vec![]);
    // Seq 1 and 2: its ExtChannelAddValue changes to 1234: the new values appear, the old
    // disappear with others remaining (alarm_diag_update_*).
    let a = store.add(AT, channel_4(1234)).unwrap();
    assert_eq!(a.len(), 2);
    assert_eq!(
        sent(&store, &a[0], 1),
        captured_notification("alarm_diag_update_appears")
    );
    assert_eq!(
        sent(&store, &a[1], 2),
        captured_notification("alarm_diag_update_others_remain")
    );
    assert_eq!(store.entries(AT), &[channel_4(1234)]);
    // Seq 3 and 4 (not captured): manufacturer diagnosis USI 0x1234 appears.
    let usi = GenericDiag::new(0x1234, &[0xde, 0xad]);
    let a = store.add(AT, usi.clone().into()).unwrap();
    assert_eq!(a[0].alarm_type, AlarmType::Diagnosis);
    assert!(a[0].specifier.manufacturer_diagnosis && a[0].specifier.channel_diagnosis);
    assert_eq!(
        a[0].item,
        Some(AlarmItem::Other {
            usi: 0x1234,
            data: vec![0xde, 0xad]
        })
    );
    // Seq 5: it disappears (alarm_diag_usi_disappears).
    let a = store.remove(AT, &DiagKey::Generic { usi: 0x1234 });
    assert_eq!(
        sent(&store, &a[0], 5),
        captured_notification("alarm_diag_usi_disappears")
    );
    // Seq 6: the channel diagnosis disappears, the last one: all disappear, nothing left
    // (alarm_diag_std_remove).
    let a = store.remove(AT, &channel_4(0).key());
    assert_eq!(
        sent(&store, &a[0], 6),
        captured_notification("alarm_diag_std_remove")
    );
    assert!(store.is_empty() && !store.has_fault());
    // Removing what is not there: no alarm.
    assert_eq!(store.remove(AT, &channel_4(0).key()), vec![]);
}

/// TV1–TV4 of the Siemens manual: wire breaks on the 1-bit output channels 1 and 0 of slot
/// 2, a short circuit on the input channel 0 of slot 3.
fn manual_store() -> DiagnosisStore {
    let mut store = DiagnosisStore::new();
    let out = |ch| {
        ChannelDiag::new(ch, 6)
            .with_data_type(1)
            .with_direction(ChannelDirection::Output)
    };
    store.add(SubslotAddr::new(0, 2, 1), out(1).into()).unwrap();
    store.add(SubslotAddr::new(0, 2, 1), out(0).into()).unwrap();
    let input = ChannelDiag::new(0, 1)
        .with_data_type(1)
        .with_direction(ChannelDirection::Input);
    store.add(SubslotAddr::new(0, 3, 1), input.into()).unwrap();
    store
}

#[test]
fn records_of_the_manual_examples() {
    let store = manual_store();
    let slot2 = [SubslotAddr::new(0, 2, 1)];
    let tv2 = hex("0010001c01010000000000020001800008008000000148010006000048010006");
    assert_eq!(store.record(Selection::ChannelFaults, slot2).unwrap(), tv2);
    let tv3 = hex("0010001601010000000000030001800008008000000028010001");
    let slot3 = [SubslotAddr::new(0, 3, 1)];
    assert_eq!(store.record(Selection::Everything, slot3).unwrap(), tv3);
    // TV4: the AR-level record 0xE00C over both.
    let both = [slot2[0], slot3[0]];
    let tv4 = [tv2.clone(), tv3].concat();
    assert_eq!(store.record(Selection::Everything, both).unwrap(), tv4);
    // Nothing selected: an empty record.
    assert_eq!(store.record(Selection::AllRequired, both).unwrap(), vec![]);
    assert_eq!(
        store
            .record(Selection::Everything, [SubslotAddr::new(0, 4, 1)])
            .unwrap(),
        vec![]
    );
    // TV1 after the wire break on channel 0 went.
    let mut store = store;
    let a = store.remove(
        slot2[0],
        &ChannelDiag::new(0, 6)
            .with_direction(ChannelDirection::Output)
            .into_key(),
    );
    // Channel 1 still has its fault, channel 0 is free: Disappears.
    let d = a[0].item.as_ref().unwrap().diagnosis().unwrap();
    assert_eq!(d.entries[0].channel_properties.0, 0x5001);
    let tv1 = hex("0010001601010000000000020001800008008000000148010006");
    assert_eq!(store.record(Selection::AllFaults, slot2).unwrap(), tv1);
}

impl ChannelDiag {
    fn into_key(self) -> DiagKey {
        DiagEntry::Channel(self).key()
    }
}

#[test]
fn record_indices() {
    use DiagnosisScope::*;
    use Selection::*;
    for (index, expected) in [
        (0x800a, Some((Subslot, ChannelFaults))),
        (0x800b, Some((Subslot, AllFaults))),
        (0xc00c, Some((Slot, Everything))),
        (0xe010, Some((Ar, ChannelRequired))),
        (0xe011, Some((Ar, ChannelDemanded))),
        (0xf012, Some((Api, AllRequired))),
        (0x8013, Some((Subslot, AllDemanded))),
        (0xf80c, Some((Device, Everything))),
        (0xf80a, None),
        (0x800d, None),
        (0x8000, None),
        (0xaff0, None),
        (0x810a, None),
        (0x000a, None),
    ] {
        assert_eq!(diagnosis_index(index), expected, "{index:#06x}");
    }
}

#[test]
fn filters_select_by_coding_and_severity() {
    let mut store = DiagnosisStore::new();
    let fault = ChannelDiag::new(1, 0x0002);
    let required = ChannelDiag::extended(CHANNEL_NUMBER_SUBMODULE, 0x8007, 0x8000, 16)
        .with_severity(Severity::MaintenanceRequired);
    let demanded = ChannelDiag::new(2, 0x0004).with_severity(Severity::MaintenanceDemanded);
    let qualified = ChannelDiag::qualified(3, 0x0005, 0, 0, 1 << 28);
    let generic = GenericDiag::new(0x0042, &[1, 2, 3]);
    let generic_required = GenericDiag {
        severity: Severity::MaintenanceRequired,
        ..GenericDiag::new(0x0043, &[])
    };
    for e in [
        DiagEntry::from(fault),
        required.into(),
        demanded.into(),
        qualified.into(),
        generic.clone().into(),
        generic_required.into(),
    ] {
        store.add(AT, e).unwrap();
    }
    let usis = |sel| -> Vec<(u16, usize)> {
        store
            .record_blocks(sel, [AT])
            .iter()
            .map(|b| {
                let n = b.item.diagnosis().map_or(0, |d| d.entries.len());
                (b.item.usi(), n)
            })
            .collect()
    };
    assert_eq!(usis(Selection::ChannelFaults), [(0x8000, 1)]);
    assert_eq!(usis(Selection::AllFaults), [(0x8000, 1), (0x0042, 0)]);
    assert_eq!(usis(Selection::ChannelRequired), [(0x8002, 1)]);
    assert_eq!(usis(Selection::ChannelDemanded), [(0x8000, 1)]);
    assert_eq!(usis(Selection::AllRequired), [(0x8002, 1), (0x0043, 0)]);
    assert_eq!(usis(Selection::AllDemanded), [(0x8000, 1)]);
    assert_eq!(
        usis(Selection::Everything),
        [
            (0x8000, 2),
            (0x8002, 1),
            (0x8003, 1),
            (0x0042, 0),
            (0x0043, 0)
        ]
    );
    // The block headers: a fault among the entries appears, maintenance alone does not.
    let blocks = store.record_blocks(Selection::Everything, [AT]);
    let headers: Vec<u16> = blocks.iter().map(|b| b.channel_properties.0).collect();
    assert_eq!(headers, [0x0800, 0x1000, 0x1000, 0x0800, 0x0a00]);
    assert!(blocks.iter().take(3).all(|b| b.channel_number == 0x8000));
    // The qualified entry keeps its qualifier, both maintenance bits set.
    let q = blocks[2].item.diagnosis().unwrap().entries[0];
    assert_eq!((q.channel_properties.0, q.qualifier), (0x0e00, 1 << 28));
    // The manufacturer data is the block's data.
    assert_eq!(
        blocks[3].item,
        AlarmItem::Other {
            usi: 0x42,
            data: vec![1, 2, 3]
        }
    );
    // The record parses back into the same blocks.
    let bytes = store.record(Selection::Everything, [AT]).unwrap();
    assert_eq!(DiagnosisData::parse_record(&bytes).unwrap(), blocks);

    // States: a fault (the qualified one's qualifier is a fault too), maintenance both ways,
    // qualified diagnosis.
    let s = store.submodule_state(AT);
    let all = SubmoduleState::DIAG_INFO
        | SubmoduleState::MAINTENANCE_REQUIRED
        | SubmoduleState::MAINTENANCE_DEMANDED
        | SubmoduleState::QUALIFIED_INFO;
    assert_eq!(s, all);
    assert_eq!(store.maintenance_status(AT), 0b11 | 1 << 28);
    assert!(store.has_fault_at(AT) && store.has_fault());
    let spec = store.specifier(AT);
    assert!(spec.channel_diagnosis && spec.manufacturer_diagnosis && spec.submodule_diagnosis);
}

#[test]
fn maintenance_alarms_carry_the_maintenance_status() {
    let mut store = DiagnosisStore::new();
    // TV11's port diagnosis: FO power budget, 1.6 dB, maintenance required.
    let port = SubslotAddr::new(0, 0, 0x8001);
    let budget = ChannelDiag::extended(CHANNEL_NUMBER_SUBMODULE, 0x8007, 0x8000, 16)
        .with_severity(Severity::MaintenanceRequired);
    let a = store.add(port, budget.into()).unwrap();
    assert_eq!(a[0].maintenance, Some(MaintenanceItem { status: 1 }));
    let n = a[0].notification(0x363, 1, 4, false);
    // TV11 carries the same MaintenanceItem and entry (its AlarmType is a port data change
    // and its specifier has no flags: the manual's device reports it that way).
    let tv11 = hex(concat!(
        "000200320100000e0000000000008001000003630000000100048100",
        "0f0000080100000000000001800280000a008007800000000010",
    ));
    let mut ours = vec![0u8; n.buffer_len()];
    n.emit(&mut ours).unwrap();
    assert_eq!(ours[26..], tv11[26..]);
    assert_eq!(ours.len(), tv11.len());
    // ChannelDiagnosis pending, no fault: bit 11 and the sequence number.
    assert_eq!(u16::from_be_bytes([ours[24], ours[25]]), 0x0804);
    // Not a fault: no station problem, no SubmoduleDiagnosisState.
    assert!(!store.has_fault() && !a[0].specifier.submodule_diagnosis);
    assert_eq!(
        store.submodule_state(port),
        SubmoduleState::MAINTENANCE_REQUIRED
    );
    // It goes: the last one, so all disappear with the maintenance bits cleared; the item
    // says nothing is required any more.
    let a = store.remove(port, &DiagEntry::from(budget).key());
    assert_eq!(a[0].maintenance, Some(MaintenanceItem { status: 0 }));
    let d = a[0].item.as_ref().unwrap().diagnosis().unwrap();
    assert_eq!(d.entries[0].channel_properties.0, 0x0000);
}

#[test]
fn removing_keeps_others_remain_and_clearing_sends_one_alarm() {
    let mut store = DiagnosisStore::new();
    let a = ChannelDiag::new(5, 1);
    let b = ChannelDiag::new(5, 2);
    let c = ChannelDiag::new(6, 1);
    for e in [a, b, c] {
        store.add(AT, e.into()).unwrap();
    }
    let props = |alarms: &[DiagnosisAlarm]| {
        let d = alarms[0].item.as_ref().unwrap().diagnosis().unwrap();
        d.entries[0].channel_properties.specifier()
    };
    let r = store.remove(AT, &DiagEntry::from(a).key());
    assert_eq!(props(&r), ChannelSpecifier::DisappearsOthersRemain);
    assert_eq!(r[0].alarm_type, AlarmType::Diagnosis);
    let r = store.remove(AT, &DiagEntry::from(b).key());
    assert_eq!(props(&r), ChannelSpecifier::Disappears);
    assert!(r[0].specifier.submodule_diagnosis);
    // Clearing: one DiagnosisDisappears without an item, nothing left.
    let r = store.clear(AT);
    assert_eq!(
        r,
        vec![DiagnosisAlarm {
            at: AT,
            alarm_type: AlarmType::DiagnosisDisappears,
            specifier: AlarmSpecifier::default(),
            maintenance: None,
            item: None,
        }]
    );
    let n = r[0].notification(1, 2, 3, false);
    assert_eq!(n.buffer_len(), 26);
    assert!(store.is_empty());
    assert_eq!(store.clear(AT), vec![]);
}

#[test]
fn invalid_entries_and_limits() {
    let mut store = DiagnosisStore::new();
    let invalid = |e: DiagEntry| {
        let mut s = DiagnosisStore::new();
        matches!(s.add(AT, e), Err(DiagnosisError::InvalidEntry(_))) && s.is_empty()
    };
    let mut ext_in_plain = ChannelDiag::new(1, 1);
    ext_in_plain.ext_error_type = 0x8000;
    assert!(invalid(ext_in_plain.into()));
    assert!(invalid(ChannelDiag::new(0x8001, 1).into()));
    assert!(invalid(ChannelDiag::new(1, 1).with_data_type(8).into()));
    assert!(invalid(
        ChannelDiag::new(0x8000, 1).with_data_type(1).into()
    ));
    assert!(invalid(
        ChannelDiag::new(1, 1)
            .with_direction(ChannelDirection::Unknown(5))
            .into()
    ));
    assert!(invalid(
        ChannelDiag::new(1, 1)
            .with_severity(Severity::Qualified(1 << 8))
            .into()
    ));
    assert!(invalid(
        ChannelDiag::qualified(1, 1, 0, 0, 0b11 << 8).into()
    ));
    assert!(invalid(ChannelDiag::qualified(1, 1, 0, 0, 1).into()));
    let mut not_qualified = ChannelDiag::qualified(1, 1, 0, 0, 1 << 8);
    not_qualified.severity = Severity::Fault;
    assert!(invalid(not_qualified.into()));
    assert!(invalid(GenericDiag::new(0x8000, &[]).into()));
    assert!(invalid(GenericDiag::new(1, &[0; 1405]).into()));
    assert!(invalid(
        GenericDiag {
            severity: Severity::Qualified(1 << 30),
            ..GenericDiag::new(1, &[])
        }
        .into()
    ));
    for ch in 0..MAX_ENTRIES_PER_SUBMODULE as u16 {
        store.add(AT, ChannelDiag::new(ch, 1).into()).unwrap();
    }
    assert_eq!(
        store.add(AT, ChannelDiag::new(100, 1).into()),
        Err(DiagnosisError::TooManyEntries(AT))
    );
    // An update is no new entry.
    let update = ChannelDiag::new(0, 1).with_severity(Severity::MaintenanceDemanded);
    assert_eq!(store.add(AT, update.into()).unwrap().len(), 2);
    assert_eq!(
        DiagnosisError::TooManyEntries(AT).to_string(),
        "slot 1 subslot 0x0001 holds 64 diagnosis entries already"
    );
    store.retain(|a| a != AT);
    assert!(store.is_empty());
}

proptest::proptest! {
    /// Whatever is added and removed, the alarms' specifiers and the states agree with what
    /// is pending, every record parses, and removing everything leaves nothing.
    #[test]
    fn the_store_stays_consistent(ops in proptest::collection::vec((0u8..4, 0u16..4, 0u8..4), 0..40)) {
        let mut store = DiagnosisStore::new();
        for (op, ch, sev) in ops {
            let severity = match sev {
                0 => Severity::Fault,
                1 => Severity::MaintenanceRequired,
                2 => Severity::MaintenanceDemanded,
                _ => Severity::Qualified(1 << (3 + u32::from(ch) * 7)),
            };
            let entry: DiagEntry = match (op, sev) {
                (3, 3) => GenericDiag::new(ch, &[ch as u8]).into(),
                (3, _) => GenericDiag { severity, ..GenericDiag::new(ch, &[]) }.into(),
                (_, 3) => ChannelDiag::qualified(ch, 1, 0, 0, 1 << (3 + u32::from(ch) * 7)).into(),
                _ => ChannelDiag::new(ch, 1).with_severity(severity).into(),
            };
            let alarms = if op == 1 {
                store.remove(AT, &entry.key())
            } else if op == 2 && ch == 0 {
                store.clear(AT)
            } else {
                store.add(AT, entry).unwrap()
            };
            for a in &alarms {
                proptest::prop_assert_eq!(a.specifier, store.specifier(AT));
            }
            let fault = store.entries(AT).iter().any(|e| e.severity().is_fault());
            proptest::prop_assert_eq!(store.has_fault(), fault);
            proptest::prop_assert_eq!(
                store.submodule_state(AT) & SubmoduleState::DIAG_INFO != 0,
                fault
            );
            let record = store.record(Selection::Everything, [AT]).unwrap();
            let blocks = DiagnosisData::parse_record(&record).unwrap();
            let listed: usize = blocks
                .iter()
                .map(|b| b.item.diagnosis().map_or(1, |d| d.entries.len()))
                .sum();
            proptest::prop_assert_eq!(listed, store.entries(AT).len());
        }
        let keys: Vec<DiagKey> = store.entries(AT).iter().map(DiagEntry::key).collect();
        for k in keys {
            proptest::prop_assert_eq!(store.remove(AT, &k).len(), 1);
        }
        proptest::prop_assert!(store.is_empty());
    }
}
