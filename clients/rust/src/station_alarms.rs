// SPDX-License-Identifier: MIT OR Apache-2.0
//! A device program's own alarms, acknowledged one by one (IO-Base's
//! `PNIO_process_alarm_send`, `PNIO_diag_alarm_send` and `PNIO_ret_of_sub_alarm_send` with
//! `PNIO_CBF_REQ_DONE`), and diagnosis kept without an alarm (`PNIO_diag_channel_add` and
//! the others), through a [`Services`] handle: each alarm names a tag, and the PLC's
//! AlarmAck comes back to the handle as a
//! [`Notification::StationAlarmDone`](crate::Notification::StationAlarmDone) with it.
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use procimg_client::{Notification, ServiceOptions, Services, StationAlarmKind};
//! use std::time::Duration;
//! let mut services = Services::open("procimg", ServiceOptions::new("alarms"))?;
//! services.send_alarm((0, 1, 1), StationAlarmKind::Process, 0x0001, &[0xbe, 0xef], 7)?;
//! while let Some(n) = services.next(Duration::from_secs(1)) {
//!     if let Notification::StationAlarmDone { tag: 7, status, .. } = n {
//!         println!("acknowledged: {status:?}");
//!         break;
//!     }
//! }
//! # Ok(()) }
//! ```

use crate::ControlError;
use crate::services::Services;
use procimg_control::{DeviceRequest, StationAlarmKind, StationDiagnosisChange};

impl Services {
    /// Sends an alarm of the station's submodule (`api`, `slot`, `subslot`) to the PLC's AR
    /// in data exchange: `usi` and `data` are its item (the bytes after the
    /// UserStructureIdentifier; no data, no item). `Ok` once it went out; the PLC's
    /// acknowledgement (or the AR's end before it) comes as
    /// [`Notification::StationAlarmDone`](crate::Notification::StationAlarmDone) with `tag`.
    /// Refused (`Refusal::StationAlarm`) without data exchange, for a submodule the AR does
    /// not hold, a USI that does not fit, or an alarm longer than the AR takes.
    pub fn send_alarm(
        &self,
        (api, slot, subslot): (u32, u16, u16),
        alarm: StationAlarmKind,
        usi: u16,
        data: &[u8],
        tag: u64,
    ) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationAlarm {
            subscriber: self.id(),
            tag,
            api,
            slot,
            subslot,
            alarm,
            usi,
            data: data.to_vec(),
        })
    }

    /// Changes the station's diagnosis without an alarm: the records, the SubmoduleState and
    /// the station problem show it, the alarm is [`send_alarm`](Self::send_alarm)'s.
    pub fn keep_diagnosis(&self, change: StationDiagnosisChange) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationDiagnosis {
            change,
            silent: true,
        })
    }
}
