// SPDX-License-Identifier: MIT OR Apache-2.0
//! The application's own alarms and the diagnosis it keeps without one: what goes out, the
//! sequence numbers the acknowledgements are matched by, and what is refused.

use super::tests::{MS, alarms, counter_device, to_data};
use super::*;
use crate::device::diagnosis::ChannelDiag;
use crate::wire::alarm::{AlarmType, Priority};

/// The counter device's input submodule (4 bytes in).
const INPUT: SubslotAddr = SubslotAddr::new(0, 1, 1);

#[test]
fn kept_diagnosis_changes_the_store_without_an_alarm() {
    let (mut dev, connect) = counter_device();
    let t = to_data(&mut dev, &connect, 1_000 * MS);
    let entry = DiagEntry::Channel(ChannelDiag::new(0x8000, 0x0006));
    let key = entry.key();
    assert_eq!(
        dev.keep_diagnosis(INPUT, DiagnosisEdit::Add(entry)),
        Ok(true)
    );
    assert!(dev.station_problem());
    assert_eq!(dev.diagnosis().entries(INPUT).len(), 1);
    assert_eq!(
        dev.keep_diagnosis(INPUT, DiagnosisEdit::Remove(key)),
        Ok(true)
    );
    assert_eq!(dev.keep_diagnosis(INPUT, DiagnosisEdit::Clear), Ok(false));
    let mut out = Vec::new();
    dev.poll(t, &mut out);
    assert!(alarms(&out).is_empty());
    assert_eq!(
        dev.keep_diagnosis(SubslotAddr::new(0, 9, 1), DiagnosisEdit::Clear),
        Err(DiagnosisError::UnknownSubmodule(SubslotAddr::new(0, 9, 1)))
    );
}

#[test]
fn the_applications_diagnosis_alarm_carries_its_item_and_follows_the_store() {
    let (mut dev, connect) = counter_device();
    let t = to_data(&mut dev, &connect, 1_000 * MS);
    let entry = DiagEntry::Channel(ChannelDiag::new(0x8000, 0x0006));
    dev.keep_diagnosis(INPUT, DiagnosisEdit::Add(entry.clone()))
        .unwrap();
    // ChannelNumber 0x8000, ChannelProperties appearing, ChannelErrorType 6 (wire break).
    let data = [0x80, 0x00, 0x08, 0x00, 0x00, 0x06];
    let seq = dev.ar().next_alarm_sequence().expect("an AR");
    let mut out = Vec::new();
    assert_eq!(
        dev.raise_diagnosis_alarm(INPUT, true, 0x8000, &data, t, &mut out),
        Ok(seq)
    );
    let a = alarms(&out);
    assert_eq!(a.len(), 1);
    assert_eq!(
        (
            a[0].priority,
            a[0].alarm_type,
            a[0].specifier.sequence_number
        ),
        (Priority::Low, AlarmType::Diagnosis, seq)
    );
    assert!(a[0].specifier.channel_diagnosis && a[0].specifier.submodule_diagnosis);
    assert!(a[0].specifier.ar_diagnosis);
    let item = a[0].item.as_ref().expect("an item");
    assert_eq!(item.usi(), 0x8000);
    assert!(item.diagnosis().is_some(), "the channel item decodes");
    assert_eq!(dev.ar().next_alarm_sequence(), Some(seq + 1));
    // The last entry gone: DiagnosisDisappears, the flags clear.
    dev.keep_diagnosis(INPUT, DiagnosisEdit::Remove(entry.key()))
        .unwrap();
    let mut out = Vec::new();
    // Wait for the first alarm's channel to be free: the transport ack is not sent here,
    // so the second alarm queues; its sequence number is taken all the same.
    let r = dev.raise_diagnosis_alarm(INPUT, false, 0x8000, &[], t + MS, &mut out);
    assert_eq!(r, Ok(seq + 1));
}

#[test]
fn alarms_are_refused_without_data_exchange_or_when_they_do_not_fit() {
    let (mut dev, connect) = counter_device();
    let mut out = Vec::new();
    assert_eq!(
        dev.send_process_alarm(INPUT, 1, &[1, 2], 0, &mut out),
        Err(AlarmError::NotInDataExchange)
    );
    assert_eq!(dev.ar().next_alarm_sequence(), None);
    let t = to_data(&mut dev, &connect, 1_000 * MS);
    assert_eq!(
        dev.send_process_alarm(INPUT, 0x8000, &[], t, &mut out),
        Err(AlarmError::InvalidUsi(0x8000))
    );
    assert_eq!(
        dev.raise_diagnosis_alarm(INPUT, true, 0x8001, &[0; 6], t, &mut out),
        Err(AlarmError::InvalidUsi(0x8001))
    );
    let other = SubslotAddr::new(0, 9, 1);
    assert_eq!(
        dev.send_process_alarm(other, 1, &[], t, &mut out),
        Err(AlarmError::NotInAr(other))
    );
    assert!(matches!(
        dev.send_process_alarm(INPUT, 1, &[0; 400], t, &mut out),
        Err(AlarmError::TooLong { .. })
    ));
    assert!(alarms(&out).is_empty());
    let seq = dev.ar().next_alarm_sequence().unwrap();
    assert_eq!(
        dev.send_process_alarm(INPUT, 1, &[1, 2], t, &mut out),
        Ok(seq)
    );
    let a = alarms(&out);
    assert_eq!(
        (a.len(), a[0].alarm_type, a[0].priority),
        (1, AlarmType::Process, Priority::High)
    );
}
