// SPDX-License-Identifier: MIT OR Apache-2.0
//! Alarms of the clients' making (`DeviceRequest::StationAlarm`: IO-Base's
//! `PNIO_process_alarm_send`, `PNIO_diag_alarm_send`, `PNIO_ret_of_sub_alarm_send`) sent on
//! the engine, and each one's end: the PLC's AlarmAck, matched by AlarmSequenceNumber, or
//! the AR's end before it, told to the subscriber that sent it.

use super::station::{ImageApplication, StationEvent, state_name};
use procimg_control::{AlarmRefusal, Refusal, StationAlarmKind};
use procimg_profinet::device::{AlarmError, ArState, Device, DeviceAction, SubslotAddr};

/// An alarm a client asked for, as the engine is to send it.
#[derive(Debug)]
pub struct AlarmOrder {
    /// The subscriber its end goes to.
    pub subscriber: u64,
    /// The client's name for it.
    pub tag: u64,
    /// Where.
    pub at: SubslotAddr,
    /// What alarm.
    pub alarm: StationAlarmKind,
    /// The item's USI.
    pub usi: u16,
    /// The item's data.
    pub data: Vec<u8>,
}

/// A sent alarm that waits for its acknowledgement.
struct Waiting {
    sequence: u16,
    subscriber: u64,
    tag: u64,
}

/// The clients' alarms waiting for the PLC's acknowledgement.
#[derive(Default)]
pub struct ClientAlarms {
    waiting: Vec<Waiting>,
    /// The engine's count of AlarmAcks already looked at.
    acks_seen: u64,
}

impl ClientAlarms {
    /// Sends `order` on `device`; it waits for its acknowledgement from now on.
    pub fn send(
        &mut self,
        device: &mut Device<ImageApplication>,
        order: AlarmOrder,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Result<(), Refusal> {
        let AlarmOrder {
            subscriber,
            tag,
            at,
            alarm,
            usi,
            data,
        } = order;
        // The acknowledgements that came before this alarm are not its.
        self.acks_seen = device.alarm_acks().count();
        let sent = match alarm {
            StationAlarmKind::Process => device.send_process_alarm(at, usi, &data, now_ns, out),
            StationAlarmKind::DiagnosisAppears | StationAlarmKind::DiagnosisDisappears => {
                let appears = alarm == StationAlarmKind::DiagnosisAppears;
                device.raise_diagnosis_alarm(at, appears, usi, &data, now_ns, out)
            }
            StationAlarmKind::ReturnOfSubmodule => return_of_submodule(device, at, now_ns, out),
        };
        let sequence = sent.map_err(|e| refusal(device, at, e))?;
        self.waiting.push(Waiting {
            sequence,
            subscriber,
            tag,
        });
        Ok(())
    }

    /// The ends of the waiting alarms: those the PLC acknowledged since the last look, and
    /// all of them when the AR is gone (`ar_ended`).
    pub fn ended(
        &mut self,
        device: &Device<ImageApplication>,
        ar_ended: bool,
    ) -> Vec<StationEvent> {
        let mut events = Vec::new();
        let count = device.alarm_acks().count();
        let new = usize::try_from(count - self.acks_seen).unwrap_or(usize::MAX);
        self.acks_seen = count;
        let acks = device.alarm_acks().list();
        for ack in &acks[acks.len().saturating_sub(new)..] {
            let seq = ack.specifier.sequence_number;
            if let Some(i) = self.waiting.iter().position(|w| w.sequence == seq) {
                let w = self.waiting.remove(i);
                let s = ack.status;
                events.push(StationEvent::AlarmDone {
                    subscriber: w.subscriber,
                    tag: w.tag,
                    status: Some([s.error_code, s.error_decode, s.error_code1, s.error_code2]),
                });
            }
        }
        if ar_ended {
            events.extend(self.waiting.drain(..).map(|w| StationEvent::AlarmDone {
                subscriber: w.subscriber,
                tag: w.tag,
                status: None,
            }));
        }
        events
    }
}

/// A Return of Submodule alarm, with its AlarmSequenceNumber.
fn return_of_submodule(
    device: &mut Device<ImageApplication>,
    at: SubslotAddr,
    now_ns: u64,
    out: &mut Vec<DeviceAction>,
) -> Result<u16, AlarmError> {
    let sequence = device
        .ar()
        .next_alarm_sequence()
        .ok_or(AlarmError::NotInDataExchange)?;
    match device.return_submodule(at, now_ns, out) {
        Ok(Some(_)) => Ok(sequence),
        Ok(None) if device.ar().state() == ArState::Data => Err(AlarmError::NotInAr(at)),
        Ok(None) => Err(AlarmError::NotInDataExchange),
        Err(_) => Err(AlarmError::NotInAr(at)),
    }
}

/// The refusal of an alarm that did not go out.
fn refusal(device: &Device<ImageApplication>, at: SubslotAddr, e: AlarmError) -> Refusal {
    let refused = match e {
        AlarmError::NotInDataExchange => AlarmRefusal::NotInDataExchange,
        AlarmError::NotInAr(_) => AlarmRefusal::NotInAr,
        AlarmError::InvalidUsi(_) => AlarmRefusal::InvalidUsi,
        AlarmError::TooLong { .. } => AlarmRefusal::TooLong,
    };
    Refusal::StationAlarm {
        refused,
        message: format!(
            "no alarm went out for {at}: {e} (the PLC's AR is {})",
            state_name(device.ar().state())
        ),
    }
}
