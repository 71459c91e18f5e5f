// SPDX-License-Identifier: MIT OR Apache-2.0
//! Alarms and diagnosis as an application that keeps them apart sends them: IO-Base's device
//! interface stores a diagnosis (`PNIO_diag_channel_add` and the others) and announces it
//! with an alarm of its own making (`PNIO_diag_alarm_send`), and waits for each alarm's
//! acknowledgement (`PNIO_CBF_REQ_DONE`). [`Device::keep_diagnosis`] changes the store
//! without an alarm, [`Device::raise_diagnosis_alarm`] sends the application's diagnosis
//! alarm, and [`ArSlot::next_alarm_sequence`](super::ArSlot::next_alarm_sequence) tells
//! which AlarmSequenceNumber the next alarm gets, so that the caller can match the
//! controller's AlarmAck ([`Device::alarm_acks`]) to it.

use super::diagnosis::{DiagEntry, DiagKey, DiagnosisError, SubslotAddr};
use super::{Application, Device, DeviceAction};
use crate::wire::alarm::{AlarmNotification, AlarmSpecifier, AlarmType, Priority};
use crate::wire::diagnosis::AlarmItem;

/// A change of the diagnosis store that [`Device::keep_diagnosis`] makes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DiagnosisEdit {
    /// Add the entry, or update the one with the same key.
    Add(DiagEntry),
    /// Remove the entry with this key.
    Remove(DiagKey),
    /// Remove every entry of the submodule.
    Clear,
}

/// Why an application's alarm did not go out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AlarmError {
    /// No AR is in data exchange.
    #[error("no AR is in data exchange: alarms go to the PLC only once its AR has started")]
    NotInDataExchange,
    /// The AR in data exchange does not hold a proper submodule there.
    #[error("the PLC's AR holds no proper submodule at {0}")]
    NotInAr(SubslotAddr),
    /// The UserStructureIdentifier does not fit the alarm.
    #[error("USI {0:#06x} does not fit this alarm")]
    InvalidUsi(u16),
    /// The notification is longer than the AR's MaxAlarmDataLength.
    #[error("the alarm is {len} bytes, more than the {max} the PLC's AR takes")]
    TooLong {
        /// The notification's length.
        len: usize,
        /// The AR's MaxAlarmDataLength.
        max: u16,
    },
}

impl<A: Application> Device<A> {
    /// Changes the diagnosis store of a plugged submodule without announcing it: the records,
    /// the SubmoduleState and the station problem show it at once, the alarm is the caller's
    /// to send ([`raise_diagnosis_alarm`](Self::raise_diagnosis_alarm)). `true` when the
    /// store changed.
    pub fn keep_diagnosis(
        &mut self,
        at: SubslotAddr,
        edit: DiagnosisEdit,
    ) -> Result<bool, DiagnosisError> {
        if !self.plugging.is_plugged(at) {
            return Err(DiagnosisError::UnknownSubmodule(at));
        }
        let alarms = match edit {
            DiagnosisEdit::Add(entry) => self.diagnosis.add(at, entry)?,
            DiagnosisEdit::Remove(key) => self.diagnosis.remove(at, &key),
            DiagnosisEdit::Clear => self.diagnosis.clear(at),
        };
        Ok(!alarms.is_empty())
    }

    /// Sends the application's diagnosis alarm for the submodule at `at`: Diagnosis when it
    /// `appears`; when it disappears, DiagnosisDisappears once nothing is pending on the
    /// submodule any more, else Diagnosis (the item's ChannelProperties tell "disappears").
    /// The item is `usi` with `data` (the bytes after the USI; none with no data, which
    /// announces that all of the submodule's diagnosis is gone); the AlarmSpecifier
    /// follows the store. Returns the alarm's AlarmSequenceNumber.
    #[allow(clippy::too_many_arguments)]
    pub fn raise_diagnosis_alarm(
        &mut self,
        at: SubslotAddr,
        appears: bool,
        usi: u16,
        data: &[u8],
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Result<u16, AlarmError> {
        // 0x8001 (several diagnoses in one alarm) is not the application's to send.
        if usi == 0x8001 || (usi > 0x8003 && usi < 0x9000) {
            return Err(AlarmError::InvalidUsi(usi));
        }
        let alarm_type = if appears || !self.diagnosis.entries(at).is_empty() {
            AlarmType::Diagnosis
        } else {
            AlarmType::DiagnosisDisappears
        };
        let item = (!data.is_empty()).then(|| AlarmItem::parse(usi, data));
        let specifier = self.diagnosis.specifier(at);
        self.raise_alarm(at, Priority::Low, alarm_type, specifier, item, now_ns, out)
    }

    /// Sends an alarm of a proper submodule of the AR in data exchange, numbered with the
    /// AR's next AlarmSequenceNumber, which it returns.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn raise_alarm(
        &mut self,
        at: SubslotAddr,
        priority: Priority,
        alarm_type: AlarmType,
        specifier: AlarmSpecifier,
        item: Option<AlarmItem>,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Result<u16, AlarmError> {
        let ar = self
            .ar
            .current
            .as_ref()
            .filter(|a| a.in_data())
            .ok_or(AlarmError::NotInDataExchange)?;
        let s = ar
            .submodules
            .iter()
            .find(|s| s.proper && s.expected.addr() == at)
            .ok_or(AlarmError::NotInAr(at))?;
        let diagnosis = &self.diagnosis;
        let ar_diagnosis = ar.owned().any(|o| diagnosis.has_fault_at(o));
        let n = AlarmNotification {
            priority,
            alarm_type,
            api: at.api,
            slot: at.slot,
            subslot: at.subslot,
            module_ident: s.expected.module_ident,
            submodule_ident: s.expected.submodule_ident,
            specifier: AlarmSpecifier {
                ar_diagnosis: ar_diagnosis && alarm_type != AlarmType::Process,
                ..specifier
            },
            maintenance: None,
            item,
        };
        let max = ar.alarms.max_data_length;
        if n.buffer_len() > usize::from(max) {
            return Err(AlarmError::TooLong {
                len: n.buffer_len(),
                max,
            });
        }
        let sequence = ar.alarms.sequence;
        self.send_alarm(n, now_ns, out);
        Ok(sequence)
    }
}
