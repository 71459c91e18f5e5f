// SPDX-License-Identifier: MIT OR Apache-2.0
//! A device program's handle on procimgd's station with IO-Base's semantics: it checks the
//! station's ARs and holds its ApplicationReady, turns the station's notifications into
//! the callbacks in the manual's order, keeps the ArNumber and SessionKey of the current AR
//! and checks the calls that name it, lets the program's ApplicationReady go, keeps the
//! program's diagnosis by DiagTag and flashes the LED for a DCP Signal.
//!
//! # Callbacks and when they come
//!
//! For a PLC's Connect:
//!
//! 1. [`ar_check`](DeviceCallbacks::ar_check) with the new ArNumber (1, 2, … per device)
//!    and the Connect's SessionKey;
//! 2. [`check_submodule`](DeviceCallbacks::check_submodule) for each expected submodule
//!    where something other than the expected ident numbers is plugged;
//! 3. the station's AR check is answered accepting once these returned (the manual's way
//!    to refuse is an abort of the AR afterwards);
//! 4. [`ar_info`](DeviceCallbacks::ar_info) with the AR's expected submodules;
//! 5. [`prm_end`](DeviceCallbacks::prm_end) when the station reports the AR
//!    [`ArState::Parameterized`] (the PLC's PrmEnd); the ApplicationReady waits for
//!    [`IoBaseDevice::application_ready`] (procimgd sends it by itself after
//!    [`APP_READY_HOLD_TIMEOUT_MS`](procimg_control::services::APP_READY_HOLD_TIMEOUT_MS));
//! 6. [`in_data`](DeviceCallbacks::in_data) when the station reports [`ArState::Data`];
//! 7. [`apdu_status`](DeviceCallbacks::apdu_status) when the DataStatus of the PLC's
//!    frames changes: RUN or STOP, a station problem, primary or backup (a change before
//!    data exchange right after `in_data`);
//! 8. [`ar_offline`](DeviceCallbacks::ar_offline) when the AR ends after `in_data`, else
//!    [`ar_abort`](DeviceCallbacks::ar_abort). An AR that a new Connect replaced before its
//!    end was reported ends [`ArEndReason::Replaced`]; one whose end this station waited
//!    for in vain [`ArEndReason::Abandoned`]; one the program aborted with the RTA abort
//!    code AbortRequest (IO-Base's `PNIO_AR_REASON_ABORT`).
//!
//! Notifications about an AR whose check this device did not get (one that connected
//! before it was opened) give no callbacks.

use super::callbacks::DeviceCallbacks;
use super::diag_tags::{DiagTagError, DiagTagKind, DiagTags, Position};
use super::end_reason::ArEndReason;
use super::led::{FLASH_HZ, LedFlash};
use super::sessions::{
    ApduStatus, ArId, ArSessions, ProgramAr, Ready, ReadyError, SessionError, Step,
};
use crate::error::{AttachError, ControlError};
use crate::services::{ServiceOptions, Services};
use procimg_control::services::{Notification, StationArCheckJob};
use procimg_control::{ArState, DiagnosisEntry, Refusal};
use procimg_shm_layout::Mode;
use std::os::fd::RawFd;
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// How long an abort waits for the station to report the AR's end; then the device ends
/// it itself ([`ArEndReason::Abandoned`]).
pub const END_WAIT: Duration = Duration::from_secs(5);
/// How long a mode change waits for the one before it to be confirmed (a cycle or two).
pub const MODE_WAIT: Duration = Duration::from_secs(2);

/// Why [`IoBaseDevice::open`] failed.
#[derive(Debug, thiserror::Error)]
pub enum DeviceOpenError {
    /// No services handle on the instance.
    #[error(transparent)]
    Attach(#[from] AttachError),
    /// The instance is an IO controller's.
    #[error(transparent)]
    NotDevice(ControlError),
    /// The station did not let this program check its ARs and hold its ApplicationReady.
    #[error(
        "instance \"{instance}\" did not let this device check its ARs and hold its \
         ApplicationReady (does another program check them?): {cause}"
    )]
    NotChecking {
        /// The instance.
        instance: String,
        /// What the server said.
        cause: ControlError,
    },
}

/// Why the program's ApplicationReady did not go.
#[derive(Debug, thiserror::Error)]
pub enum ApplicationReadyError {
    /// Not now, or not this AR.
    #[error(transparent)]
    Refused(#[from] ReadyError),
    /// procimgd did not take it.
    #[error("instance \"{instance}\" did not take the ApplicationReady: {cause}")]
    NotTaken {
        /// The instance.
        instance: String,
        /// What the server said.
        cause: ControlError,
    },
}

/// Why an abort of an AR did not go.
#[derive(Debug, thiserror::Error)]
pub enum AbortError {
    /// Not this AR.
    #[error(transparent)]
    Session(#[from] SessionError),
    /// procimgd did not end the AR.
    #[error("instance \"{instance}\" did not end the AR: {cause}")]
    NotTaken {
        /// The instance.
        instance: String,
        /// What the server said.
        cause: ControlError,
    },
}

/// A device program's handle on the station, with IO-Base's semantics. It may be shared
/// between threads: the notifications are delivered on one, the program's calls come from
/// any.
pub struct IoBaseDevice {
    instance: String,
    services: Mutex<Services>,
    sessions: Mutex<ArSessions>,
    led: Mutex<LedFlash>,
    diag: Mutex<DiagTags>,
}

/// Locks `m`; a panic elsewhere leaves the data as consistent as each step left it.
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl IoBaseDevice {
    /// Opens a services handle named `name` on `instance` and takes the station's AR checks
    /// and ApplicationReady.
    pub fn open(instance: &str, name: &str) -> Result<IoBaseDevice, DeviceOpenError> {
        let services = Services::open(instance, ServiceOptions::new(name))?;
        IoBaseDevice::with_services(services)
    }

    /// As [`open`](Self::open), with a services handle the caller opened.
    pub fn with_services(services: Services) -> Result<IoBaseDevice, DeviceOpenError> {
        let instance = services.control().instance().to_owned();
        services
            .check_ars(true)
            .and_then(|()| services.hold_application_ready(true))
            .map_err(|source| match source {
                ControlError::NotDevice { .. }
                | ControlError::Refused(Refusal::WrongRole { .. }) => {
                    DeviceOpenError::NotDevice(source)
                }
                cause => DeviceOpenError::NotChecking {
                    instance: instance.clone(),
                    cause,
                },
            })?;
        Ok(IoBaseDevice {
            instance,
            services: Mutex::new(services),
            sessions: Mutex::new(ArSessions::new()),
            led: Mutex::new(LedFlash::default()),
            diag: Mutex::new(DiagTags::default()),
        })
    }

    /// The procimgd instance.
    pub fn instance(&self) -> &str {
        &self.instance
    }

    /// The services handle (records, alarms, status), locked.
    pub fn services(&self) -> MutexGuard<'_, Services> {
        lock(&self.services)
    }

    /// The current AR, if one is up.
    pub fn current_ar(&self) -> Option<ProgramAr> {
        lock(&self.sessions).current().cloned()
    }

    /// Whether the current AR takes the program's IO data ([`ProgramAr::takes_data`]),
    /// without a copy of it: the data functions ask this every call, in an isochronous
    /// program inside its STARTOP callback.
    pub fn ar_takes_data(&self) -> bool {
        lock(&self.sessions)
            .current()
            .is_some_and(ProgramAr::takes_data)
    }

    /// Checks the ArNumber and SessionKey of a call; the current AR.
    pub fn check(&self, ar: ArId) -> Result<ProgramAr, SessionError> {
        lock(&self.sessions).check(ar).cloned()
    }

    /// The ArNumber and SessionKey of the AR procimgd names `uuid`, if it is the current one.
    pub fn ar_of(&self, uuid: &str) -> Option<ArId> {
        lock(&self.sessions).by_uuid(uuid).map(|a| a.id)
    }

    /// Delivers every notification that is there, and the end of a DCP Signal's flashing;
    /// returns how many notifications it delivered.
    pub fn poll(&self, program: &mut impl DeviceCallbacks) -> usize {
        self.tick(Instant::now(), program);
        let mut n = 0;
        while let Some(note) = self.try_next() {
            self.deliver(note, program);
            n += 1;
        }
        n
    }

    /// Waits up to `timeout` for a notification (without holding the handle), then
    /// delivers what is there as [`poll`](Self::poll) does.
    pub fn wait(&self, timeout: Duration, program: &mut impl DeviceCallbacks) -> usize {
        let until = self.led_until().map_or(timeout, |t| {
            t.saturating_duration_since(Instant::now()).min(timeout)
        });
        let fd = lock(&self.services).notify_fd();
        procimg_shm_layout::os::wait_readable(
            fd,
            until.as_nanos().min(u128::from(u64::MAX)) as u64,
        );
        self.poll(program)
    }

    /// The descriptor that becomes readable when a notification arrives, for a caller that
    /// waits on more than this handle (then calls [`poll`](Self::poll)).
    pub fn notify_fd(&self) -> RawFd {
        lock(&self.services).notify_fd()
    }

    /// When [`poll`](Self::poll) has something to do without a notification: the end of a
    /// DCP Signal's flashing.
    pub fn next_deadline(&self) -> Option<Instant> {
        self.led_until()
    }

    fn try_next(&self) -> Option<Notification> {
        lock(&self.services).try_next()
    }

    fn led_until(&self) -> Option<Instant> {
        lock(&self.led).until()
    }

    /// Ends the flashing of a DCP Signal whose time is over at `now`.
    pub fn tick(&self, now: Instant, program: &mut impl DeviceCallbacks) {
        let over = lock(&self.led).over(now);
        if over {
            program.led_flash_stop();
        }
    }

    /// Turns one notification of the station into the callbacks it means.
    pub fn deliver(&self, n: Notification, program: &mut impl DeviceCallbacks) {
        match n {
            Notification::StationArCheck { check, .. } => self.new_ar(&check, program),
            Notification::StationAr { state, ar_uuid, .. } => {
                self.progress(&ar_uuid, state, program)
            }
            Notification::StationArEnded {
                ar_uuid,
                aborted,
                planned,
                abort_code,
                ..
            } => {
                let ended = lock(&self.sessions).end(&ar_uuid);
                if let Some(ar) = ended {
                    end(
                        &ar,
                        ArEndReason::reported(abort_code, aborted, planned),
                        program,
                    );
                }
            }
            Notification::StationPlcRunning {
                running,
                station_problem,
                backup,
            } => {
                let status = ApduStatus {
                    running,
                    station_problem,
                    backup,
                };
                let now = lock(&self.sessions).plc_status(status);
                if let Some(ar) = now {
                    program.apdu_status(ar, status);
                }
            }
            Notification::StationPlugParameterized { api, slot, subslot } => {
                let ar = lock(&self.sessions).plug_parameterized();
                if let Some(ar) = ar {
                    program.prm_end(ar, Some((api, slot, subslot)));
                }
            }
            Notification::StationRecord { job, .. } => {
                let ar = self.ar_of(&job.ar_uuid);
                program.record(ar, &job);
            }
            Notification::StationAlarmDone { tag, status, .. } => program.alarm_done(tag, status),
            Notification::StationBlink => {
                let started = lock(&self.led).signal(Instant::now());
                if started {
                    program.led_flash_start(FLASH_HZ);
                }
            }
            Notification::StationIdentity {
                factory_reset: true,
                ..
            }
            | Notification::StopRequest { .. } => program.stop_request(),
            _ => {}
        }
    }

    /// A PLC's Connect: `AR_CHECK_IND`, `CHECK_IND` per mismatch, the answer, `AR_INFO_IND`.
    fn new_ar(&self, check: &StationArCheckJob, program: &mut impl DeviceCallbacks) {
        let (ar, replaced) = lock(&self.sessions).begin(check.session_key, &check.ar_uuid);
        if let Some(old) = replaced {
            end(&old, ArEndReason::Replaced, program);
        }
        program.ar_check(ar, check);
        for e in &check.expected {
            match e.plugged {
                Some(plugged) if plugged != (e.module_ident, e.submodule_ident) => {
                    program.check_submodule(ar, e, plugged)
                }
                _ => {}
            }
        }
        // Accepting: the manual's refusal is an abort after the callbacks. An answer that
        // does not arrive is taken as accepted by the station after its timeout.
        let _ = lock(&self.services).answer_ar_check(check, Ok(()));
        program.ar_info(ar, check);
    }

    /// The station reports the AR `uuid` at `state`.
    fn progress(&self, uuid: &str, state: ArState, program: &mut impl DeviceCallbacks) {
        let step = lock(&self.sessions).advance(uuid, state);
        match step {
            Some(Step::PrmEnd(ar)) => program.prm_end(ar, None),
            Some(Step::InData(ar, status)) => {
                program.in_data(ar);
                if let Some(status) = status {
                    program.apdu_status(ar, status);
                }
            }
            None => {}
        }
    }

    /// The program is ready for AR `ar` (after its `PRM_END_IND`): procimgd sends the
    /// ApplicationReady, with the submodules in `not_ready` reported "application ready
    /// pending" until the program's Return of Submodule alarm for each. After a
    /// `PRM_END_IND` of a submodule plugged in data exchange, lets that one's
    /// PlugApplicationReady go.
    pub fn application_ready(
        &self,
        ar: ArId,
        not_ready: &[Position],
    ) -> Result<(), ApplicationReadyError> {
        let ready = lock(&self.sessions).ready(ar)?;
        let sent = lock(&self.services).application_ready_except(not_ready);
        sent.map_err(|cause| {
            if ready == Ready::Ar {
                lock(&self.sessions).not_ready(ar);
            }
            ApplicationReadyError::NotTaken {
                instance: self.instance.clone(),
                cause,
            }
        })
    }

    /// Ends AR `ar` from the station's side (IO-Base's `PNIO_device_ar_abort`): an ERR-RTA
    /// with AbortRequest goes to the PLC, and the notifications are delivered until the end
    /// was reported (`AR_ABORT_IND` or `AR_OFFLINE_IND`, reason `PNIO_AR_REASON_ABORT`), at
    /// most [`END_WAIT`]. The station stays on the wire: the PLC may connect again at once,
    /// with a new AR.
    pub fn abort(&self, ar: ArId, program: &mut impl DeviceCallbacks) -> Result<(), AbortError> {
        let uuid = self.check(ar)?.uuid;
        let asked = lock(&self.services).abort_ar(&uuid);
        match asked {
            // Ended meanwhile: its end is reported all the same.
            Ok(()) | Err(ControlError::Refused(Refusal::ArGone { .. })) => {}
            Err(cause) => {
                return Err(AbortError::NotTaken {
                    instance: self.instance.clone(),
                    cause,
                });
            }
        }
        self.until_ended(&uuid, END_WAIT, program);
        Ok(())
    }

    /// Takes the station to `mode` (OFFLINE: no PLC connects, and the AR ends; OPERATE:
    /// PLCs may connect), once the change asked for before it is confirmed (within
    /// [`MODE_WAIT`]).
    pub fn set_mode(&self, mode: Mode) -> Result<(), ControlError> {
        let until = Instant::now() + MODE_WAIT;
        loop {
            let r = lock(&self.services).control().set_mode(mode);
            match r {
                Err(ControlError::Refused(Refusal::ModeChangePending { .. }))
                    if Instant::now() < until =>
                {
                    std::thread::sleep(Duration::from_millis(5));
                }
                r => return r,
            }
        }
    }

    /// Delivers the station's notifications until the AR `uuid` has ended (its callback
    /// given) or `timeout` passed; then, if it is still current, ends it
    /// ([`ArEndReason::Abandoned`]).
    pub fn until_ended(&self, uuid: &str, timeout: Duration, program: &mut impl DeviceCallbacks) {
        let until = Instant::now() + timeout;
        let current = || lock(&self.sessions).by_uuid(uuid).is_some();
        while current() {
            let left = until.saturating_duration_since(Instant::now());
            if left.is_zero() {
                break;
            }
            self.wait(left, program);
        }
        let left = lock(&self.sessions).end(uuid);
        if let Some(ar) = left {
            end(&ar, ArEndReason::Abandoned, program);
        }
    }

    /// Adds the program's diagnosis entry with `tag` to the submodule at `at`, without an
    /// alarm.
    pub fn add_diagnosis(
        &self,
        at: Position,
        tag: u16,
        kind: DiagTagKind,
        entry: DiagnosisEntry,
    ) -> Result<(), DiagTagError> {
        let mut diag = lock(&self.diag);
        diag.add(&lock(&self.services), at, tag, kind, entry)
    }

    /// Removes the program's entry with `tag` (0: every one of `kind`) from the submodule at
    /// `at`.
    pub fn remove_diagnosis(
        &self,
        at: Position,
        tag: u16,
        kind: DiagTagKind,
    ) -> Result<(), DiagTagError> {
        let mut diag = lock(&self.diag);
        diag.remove(&lock(&self.services), at, tag, kind)
    }

    /// Gives the station's AR checks and ApplicationReady back (dropping the device does
    /// too; this says it at once).
    pub fn close(&self) {
        let services = lock(&self.services);
        let _ = services.check_ars(false);
        let _ = services.hold_application_ready(false);
    }
}

/// Gives `AR_OFFLINE_IND` (after data exchange began) or `AR_ABORT_IND` for `ar`.
fn end(ar: &ProgramAr, reason: ArEndReason, program: &mut impl DeviceCallbacks) {
    if ar.phase == super::sessions::ArPhase::InData {
        program.ar_offline(ar.id, reason);
    } else {
        program.ar_abort(ar.id, reason);
    }
}
