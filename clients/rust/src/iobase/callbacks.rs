// SPDX-License-Identifier: MIT OR Apache-2.0
//! What a device program is told, one method per IO-Base device callback. Every method has
//! an empty default: a program implements those it needs. [`IoBaseDevice`] calls them on
//! the thread that delivers the station's notifications, never with one of its locks held,
//! so a method may call back into the device (ApplicationReady, diagnosis, alarms).
//!
//! [`IoBaseDevice`]: super::IoBaseDevice

use super::diag_tags::Position;
use super::end_reason::ArEndReason;
use super::sessions::{ApduStatus, ArId};
use procimg_control::services::{ExpectedSubmodule, StationArCheckJob, StationRecordJob};

/// The device callbacks of IO-Base (`PNIO_CBF_*`), in Rust.
#[allow(unused_variables)]
pub trait DeviceCallbacks {
    /// `AR_CHECK_IND`: a PLC connects; `ar` is the ArNumber and SessionKey its calls name.
    /// The Connect is accepted once the callbacks of the check returned: a program that
    /// refuses it aborts the AR afterwards ([`IoBaseDevice::abort`](super::IoBaseDevice)).
    fn ar_check(&mut self, ar: ArId, check: &StationArCheckJob) {}

    /// `CHECK_IND`: the PLC expects other ident numbers than `plugged` (module, submodule)
    /// at a position where something is plugged (a position with nothing is the station's
    /// own report).
    fn check_submodule(&mut self, ar: ArId, expected: &ExpectedSubmodule, plugged: (u32, u32)) {}

    /// `AR_INFO_IND`: the AR's submodules as the PLC expects them (`check.expected`) and its
    /// IO CRs (`check.crs`: RT class, timing, FrameIDs, where each submodule's data sits).
    fn ar_info(&mut self, ar: ArId, check: &StationArCheckJob) {}

    /// `PRM_END_IND`: the PLC ended its parameters, of the AR (`submodule` none) or of one
    /// submodule plugged in data exchange. The ApplicationReady waits for
    /// [`IoBaseDevice::application_ready`](super::IoBaseDevice::application_ready).
    fn prm_end(&mut self, ar: ArId, submodule: Option<Position>) {}

    /// `AR_INDATA_IND`: data exchange.
    fn in_data(&mut self, ar: ArId) {}

    /// `APDU_STATUS_IND`: the DataStatus of the PLC's frames changed (RUN or STOP, a
    /// station problem, primary or backup); a change before data exchange comes right after
    /// [`in_data`](Self::in_data).
    fn apdu_status(&mut self, ar: ArId, status: ApduStatus) {}

    /// `AR_ABORT_IND`: the AR ended before data exchange.
    fn ar_abort(&mut self, ar: ArId, reason: ArEndReason) {}

    /// `AR_OFFLINE_IND`: the AR ended after data exchange began.
    fn ar_offline(&mut self, ar: ArId, reason: ArEndReason) {}

    /// `START_LED_FLASH`: an engineering tool's DCP Signal; flash at `hz`.
    fn led_flash_start(&mut self, hz: u32) {}

    /// `STOP_LED_FLASH`: the Signal's time is over.
    fn led_flash_stop(&mut self) {}

    /// `CP_STOP_REQ`: a DCP reset to factory took the station's name and address, or the
    /// server is to restart (a configuration download, a reset); the program is to close
    /// the device (and may open it again) outside the callback.
    fn stop_request(&mut self) {}

    /// `REC_READ` / `REC_WRITE`: the PLC reads or writes a record of a submodule whose
    /// records the program took; answer it with the services handle
    /// ([`IoBaseDevice::services`](super::IoBaseDevice::services)).
    fn record(&mut self, ar: Option<ArId>, job: &StationRecordJob) {}

    /// `REQ_DONE` of an alarm: the PLC's AlarmAck status (all zero: accepted), or none when
    /// the AR ended first.
    fn alarm_done(&mut self, tag: u64, status: Option<[u8; 4]>) {}
}
