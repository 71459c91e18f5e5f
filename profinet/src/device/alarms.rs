// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the application reports to the controller: process alarms, and diagnosis, which the
//! device keeps in its [`DiagnosisStore`] (for the records, the SubmoduleStates and the
//! station problem) and announces with diagnosis alarms.
//!
//! Alarms go out only to an AR in data exchange, and only for the submodules it owns; before
//! that the controller learns the diagnosis from the ModuleDiffBlock of the Connect response
//! and of the ApplicationReady, and from the records. The AR's MaxAlarmDataLength bounds every
//! AlarmNotification: a longer one is not sent. The controller's acknowledgements are kept
//! in [`AlarmAcks`].

use super::diagnosis::{
    DiagEntry, DiagKey, DiagnosisAlarm, DiagnosisError, DiagnosisStore, SubslotAddr,
};
use super::iobase_alarms::AlarmError;
use super::{Application, Device, DeviceAction, MAX_KEPT_ACKS};
use crate::wire::alarm::{
    AlarmAck, AlarmBlock, AlarmItem, AlarmNotification, AlarmSpecifier, AlarmType, Priority,
};

/// What a diagnosis change did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DiagnosisChange {
    /// Whether the store changed: false when the same entry was pending already, or there
    /// was nothing to remove.
    pub changed: bool,
    /// Diagnosis alarms handed to the AR's low-priority alarm channel (0 without an AR in
    /// data exchange that owns the submodule).
    pub alarms_sent: usize,
    /// Alarms not sent because they are longer than the AR's MaxAlarmDataLength: the change
    /// is in the store and its records all the same.
    pub alarms_too_long: usize,
}

/// The AlarmAcks the controller sent for the device's alarms.
#[derive(Clone, Debug, Default)]
pub struct AlarmAcks {
    /// The most recent, oldest first.
    list: Vec<AlarmAck>,
    /// AlarmAcks received in all.
    count: u64,
}

impl AlarmAcks {
    /// The AlarmAcks the controller sent, oldest first (the last [`MAX_KEPT_ACKS`]).
    pub fn list(&self) -> &[AlarmAck] {
        &self.list
    }

    /// AlarmAcks the controller sent since the device was made (of which
    /// [`list`](Self::list) keeps the last [`MAX_KEPT_ACKS`]).
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Takes the AlarmAcks an alarm channel received, emptying `acks`.
    pub(super) fn take(&mut self, acks: &mut Vec<AlarmAck>) {
        self.count += acks.len() as u64;
        self.list.append(acks);
        // The most recent ones are what a caller looks at; a long-running device must not
        // grow without bound.
        if self.list.len() > MAX_KEPT_ACKS {
            let excess = self.list.len() - MAX_KEPT_ACKS;
            self.list.drain(..excess);
        }
    }
}

impl<A: Application> Device<A> {
    /// Raises a process alarm (high priority, manufacturer-specific USI 0x0000–0x7FFF with
    /// `data`) for a submodule of the AR in data exchange. `false` when there is no such AR
    /// or submodule, the USI is not manufacturer-specific, or the notification is longer than
    /// the AR's MaxAlarmDataLength (at most 200 bytes; a longer one would not fit what the
    /// controller accepts, or even one frame). The controller's AlarmAck shows up in
    /// [`alarm_acks`](Self::alarm_acks).
    #[allow(clippy::too_many_arguments)]
    pub fn raise_process_alarm(
        &mut self,
        api: u32,
        slot: u16,
        subslot: u16,
        usi: u16,
        data: &[u8],
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> bool {
        let at = SubslotAddr::new(api, slot, subslot);
        self.send_process_alarm(at, usi, data, now_ns, out).is_ok()
    }

    /// [`raise_process_alarm`](Self::raise_process_alarm), saying why it did not go out, or
    /// with the alarm's AlarmSequenceNumber.
    pub fn send_process_alarm(
        &mut self,
        at: SubslotAddr,
        usi: u16,
        data: &[u8],
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Result<u16, AlarmError> {
        if usi >= 0x8000 {
            return Err(AlarmError::InvalidUsi(usi));
        }
        let item = Some(AlarmItem::Other {
            usi,
            data: data.to_vec(),
        });
        let specifier = AlarmSpecifier::default();
        self.raise_alarm(
            at,
            Priority::High,
            AlarmType::Process,
            specifier,
            item,
            now_ns,
            out,
        )
    }

    /// Numbers `n` with the AR's next AlarmSequenceNumber and sends it on the channel of
    /// its priority; an abort the channel reports ends the AR. Nothing without an AR.
    pub(super) fn send_alarm(
        &mut self,
        mut n: AlarmNotification,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) {
        let mac = self.station.id.mac;
        let Some(ar) = self.ar.current.as_mut() else {
            return;
        };
        n.specifier.sequence_number = ar.alarms.sequence;
        ar.alarms.sequence = (ar.alarms.sequence + 1) & AlarmSpecifier::SEQUENCE_MASK;
        let priority = n.priority;
        let block = vec![AlarmBlock::Notification(n)];
        if let Some(a) = ar.alarms.send(priority, block, mac, now_ns, out) {
            self.end_ar(a.code);
        }
    }

    /// The pending diagnosis.
    pub fn diagnosis(&self) -> &DiagnosisStore {
        &self.diagnosis
    }

    /// Whether a fault is pending on any submodule: the station problem, which the
    /// DataStatus of the input CR reports (StationProblemIndicator 0).
    pub fn station_problem(&self) -> bool {
        self.diagnosis.has_fault()
    }

    /// Adds a diagnosis entry to a plugged submodule, or updates the pending one with the same
    /// [`key`](DiagEntry::key), and sends the diagnosis alarms that announce it when an AR in
    /// data exchange owns the submodule. An unknown submodule or an invalid entry change
    /// nothing.
    #[allow(clippy::too_many_arguments)]
    pub fn add_diagnosis(
        &mut self,
        api: u32,
        slot: u16,
        subslot: u16,
        entry: impl Into<DiagEntry>,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Result<DiagnosisChange, DiagnosisError> {
        let at = self.plugged_at(api, slot, subslot)?;
        let alarms = self.diagnosis.add(at, entry.into())?;
        Ok(self.send_diagnosis(alarms, now_ns, out))
    }

    /// Removes the diagnosis entry with `key` from a plugged submodule and sends the alarm
    /// that announces it; nothing changes (and no alarm goes out) when no such entry is
    /// pending.
    #[allow(clippy::too_many_arguments)]
    pub fn remove_diagnosis(
        &mut self,
        api: u32,
        slot: u16,
        subslot: u16,
        key: &DiagKey,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Result<DiagnosisChange, DiagnosisError> {
        let at = self.plugged_at(api, slot, subslot)?;
        let alarms = self.diagnosis.remove(at, key);
        Ok(self.send_diagnosis(alarms, now_ns, out))
    }

    /// Removes every diagnosis entry of a plugged submodule, announced by one
    /// DiagnosisDisappears alarm without an item.
    pub fn clear_diagnosis(
        &mut self,
        api: u32,
        slot: u16,
        subslot: u16,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Result<DiagnosisChange, DiagnosisError> {
        let at = self.plugged_at(api, slot, subslot)?;
        let alarms = self.diagnosis.clear(at);
        Ok(self.send_diagnosis(alarms, now_ns, out))
    }

    /// Where a plugged submodule is; [`DiagnosisError::UnknownSubmodule`] if none is there.
    fn plugged_at(&self, api: u32, slot: u16, subslot: u16) -> Result<SubslotAddr, DiagnosisError> {
        let at = SubslotAddr::new(api, slot, subslot);
        if self.plugging.is_plugged(at) {
            Ok(at)
        } else {
            Err(DiagnosisError::UnknownSubmodule(at))
        }
    }

    /// Sends `alarms` to the AR if it is in data exchange and owns their submodule.
    pub(super) fn send_diagnosis(
        &mut self,
        alarms: Vec<DiagnosisAlarm>,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> DiagnosisChange {
        let mut change = DiagnosisChange {
            changed: !alarms.is_empty(),
            ..DiagnosisChange::default()
        };
        let mac = self.station.id.mac;
        let Some(ar) = self.ar.current.as_mut().filter(|a| a.in_data()) else {
            return change;
        };
        // ARDiagnosisState: a fault on a submodule the AR owns, after the change.
        let diagnosis = &self.diagnosis;
        let ar_fault = ar.owned().any(|at| diagnosis.has_fault_at(at));
        let mut abort = None;
        for alarm in alarms {
            let Some(s) = ar
                .submodules
                .iter()
                .find(|s| s.proper && s.expected.addr() == alarm.at)
            else {
                continue;
            };
            let e = s.expected;
            let n = alarm.notification(
                e.module_ident,
                e.submodule_ident,
                ar.alarms.sequence,
                ar_fault,
            );
            if n.buffer_len() > usize::from(ar.alarms.max_data_length) {
                change.alarms_too_long += 1;
                continue;
            }
            ar.alarms.sequence = (ar.alarms.sequence + 1) & AlarmSpecifier::SEQUENCE_MASK;
            let block = vec![AlarmBlock::Notification(n)];
            change.alarms_sent += 1;
            abort = ar.alarms.send(Priority::Low, block, mac, now_ns, out);
            if abort.is_some() {
                break;
            }
        }
        if let Some(a) = abort {
            self.end_ar(a.code);
        }
        change
    }
}
