// SPDX-License-Identifier: MIT OR Apache-2.0
//! The worker thread of one controller: waits for the server's notifications and for
//! diagnosis requests, and calls the program's callbacks, one at a time.
//!
//! It waits in `poll` on the notification descriptor and its own eventfd without holding any
//! lock, takes the notifications under the services lock, and calls the callbacks with no
//! lock held, so the API (including the IO-data functions a callback may call) never waits
//! for a callback.

use super::{ActivationJob, DiagJob, ReconfigJob, RecordJob, Shared, build};
use crate::iobase::callbacks::CallbackTable;
use crate::iobase::errors::{
    PNIO_ERR_DEV_ACT_NOT_ALLOWED, PNIO_ERR_INVALID_PORT, PNIO_ERR_INVALID_STATION,
    PNIO_ERR_NO_FW_COMMUNICATION, PNIO_ERR_PRM_ADD, PNIO_ERR_PRM_INVALIDARG, PNIO_OK,
};
use crate::iobase::sync::lock;
use crate::iobase::types::{
    PNIO_ADDR, PNIO_ADDR_u, PNIO_CBE_ALARM_IND, PNIO_CBE_CP_STOP_REQ, PNIO_CBE_CTRL_DIAG_CONF,
    PNIO_CBE_DEV_ACT_CONF, PNIO_CBE_IOSYSTEM_RECONFIG, PNIO_CBE_PRM, PNIO_CBE_PRM_ALARM_IND,
    PNIO_CBE_PRM_CTRL_DIAG_CONF, PNIO_CBE_PRM_DEV_ACT_CONF, PNIO_CBE_PRM_IOSYS_CONF,
    PNIO_CBE_PRM_LED_FLASH, PNIO_CBE_PRM_REC_READ_CONF, PNIO_CBE_PRM_REC_WRITE_CONF,
    PNIO_CBE_REC_READ_CONF, PNIO_CBE_REC_WRITE_CONF, PNIO_CBE_START_LED_FLASH,
    PNIO_CBE_STOP_LED_FLASH, PNIO_CBE_TYPE, PNIO_CTRL_ALARM_DATA,
    PNIO_CTRL_DIAG_CONFIG_IOROUTER_PRESENT, PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO,
    PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE_LIST, PNIO_CTRL_DIAG_CONFIG_SUBMODULE_LIST,
    PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC, PNIO_CTRL_DIAG_DEVICE_STATE,
    PNIO_CTRL_DIAG_GET_COMM_COUNTER_DATA, PNIO_CTRL_DIAG_RESET_COMM_COUNTERS, PNIO_DA_FALSE,
    PNIO_DA_TRUE, PNIO_ERR_STAT, PNIO_REF,
};
use procimg_client::iobase::FLASH_HZ;
use procimg_client::{
    AlarmReport, DeviceDiagnosis, DeviceState, Notification, RecordConfirmation, TailoringRefusal,
};
use std::os::fd::RawFd;
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

/// How often, while jobs wait for their confirmation, the worker looks whether the server
/// they were sent to still runs.
const LIVENESS_PERIOD: Duration = Duration::from_millis(500);

/// How long one wait lasts at most: notifications whose wake-up came before their sample
/// was visible, and job timeouts, are looked at after this.
const POLL: Duration = Duration::from_millis(100);

/// Notifications taken in one go, so that a flood does not delay stop or diagnosis.
const BATCH: usize = 64;

/// Where the answer of a read points when there is no data: a valid, non-NULL address.
static NO_DATA: [u8; 4] = [0; 4];

/// The worker's loop, until stop; then unsubscribes.
pub(super) fn run(shared: Arc<Shared>) {
    let notify_fd = shared.with_services(|s| s.notify_fd());
    let mut last_liveness = Instant::now();
    while !stopping(&shared) {
        let mut busy = expire(&shared);
        led_over(&shared);
        if last_liveness.elapsed() >= LIVENESS_PERIOD {
            last_liveness = Instant::now();
            busy |= orphaned(&shared);
        }
        busy |= diagnose(&shared);
        let batch = take_notifications(&shared);
        busy |= !batch.is_empty();
        for n in batch {
            if stopping(&shared) {
                break;
            }
            handle(&shared, n);
        }
        if !busy {
            wait(notify_fd, shared.wake.fd());
            shared.wake.clear();
        }
    }
    // Unsubscribe here, on the thread that used the handle last; the API calls find `None`
    // from now on.
    let services = lock(&shared.services).take();
    drop(services);
}

fn stopping(shared: &Shared) -> bool {
    shared.stop.load(Ordering::Acquire)
}

/// Waits until a descriptor is readable or [`POLL`] passed (a negative descriptor, no
/// services handle, is ignored).
fn wait(notify_fd: Option<RawFd>, wake_fd: RawFd) {
    let poll_ns = POLL.as_nanos() as u64;
    procimg_shm_layout::os::wait_any_readable([wake_fd, notify_fd.unwrap_or(-1)], poll_ns);
}

fn take_notifications(shared: &Shared) -> Vec<Notification> {
    shared
        .with_services(|s| std::iter::from_fn(|| s.try_next()).take(BATCH).collect())
        .unwrap_or_default()
}

fn handle(shared: &Shared, n: Notification) {
    match n {
        Notification::Record { confirmation, .. } => record_done(shared, &confirmation),
        Notification::Alarm(a) => alarm(shared, &a),
        Notification::DeviceFailure { device, .. } => {
            set_up(shared, device, false);
            station_alarm(shared, device, true)
        }
        Notification::DeviceReturn { device, .. } => {
            set_up(shared, device, true);
            station_alarm(shared, device, false)
        }
        Notification::DeviceState { device, state, .. } => {
            set_up(shared, device, state == DeviceState::Running)
        }
        Notification::Activation {
            device, active, ok, ..
        } => activation_done(shared, device, active, ok),
        Notification::Reconfigured {
            active, refused, ..
        } => reconfigured(shared, active, refused.as_ref()),
        // The server is to restart: the program is to close its controller.
        Notification::StopRequest { .. } => {
            let cbf = shared.callbacks.get(PNIO_CBE_CP_STOP_REQ);
            let mut prm = PNIO_CBE_PRM::new(PNIO_CBE_CP_STOP_REQ, shared.handle);
            CallbackTable::invoke(cbf, &mut prm);
        }
        Notification::ControllerSignal => {
            let start = lock(&shared.led).signal(Instant::now());
            if start {
                led_flash(shared, PNIO_CBE_START_LED_FLASH);
            }
        }
        // The handle announces itself to a new server by itself; the jobs of its
        // predecessors will never be confirmed.
        Notification::ServerStarted { generation } => {
            fail_jobs(shared, |g, _| g != Some(generation));
            // A new server brings its devices up anew: each is reported when it comes.
            shared.devices_up.set_all(false);
        }
        // Module differences have no IO-Base event (the device's own alarms report them);
        // the station's events are of a server in the device role, which this IO
        // controller interface does not serve.
        Notification::ModuleDiff { .. }
        | Notification::StationAr { .. }
        | Notification::StationArEnded { .. }
        | Notification::StationPlcRunning { .. }
        | Notification::StationBlink
        | Notification::StationNeighbours { .. }
        | Notification::StationIdentity { .. }
        | Notification::StationPlug { .. }
        | Notification::StationRecord { .. }
        | Notification::StationAlarmDone { .. }
        | Notification::StationPlugParameterized { .. }
        | Notification::StationArCheck { .. }
        | Notification::StationDcpSetCheck { .. } => {}
        // The controller's own interface: for the handle of `PNIO_interface_open`.
        Notification::InterfaceAlarm(_)
        | Notification::InterfaceRecord { .. }
        | Notification::ControllerAddress { .. } => {}
        // Of the program that asked for a restart (SERV_CP_download, SERV_CP_reset).
        Notification::Restart { .. } => {}
        Notification::PeConfirmation {
            reference,
            answer,
            status,
            ..
        } => super::pe::pe_done(shared, reference, answer.as_ref(), status),
    }
}

/// Confirms the jobs and activations whose confirmation is overdue as failed: the server
/// that took them is gone or lost them.
fn expire(shared: &Shared) -> bool {
    let now = Instant::now();
    fail_jobs(shared, |_, deadline| deadline <= now)
}

/// Confirms as failed ("no connection") every record job and activation that `gone` picks
/// by the server generation it was sent to and its deadline.
fn fail_jobs(shared: &Shared, gone: impl Fn(Option<u64>, Instant) -> bool) -> bool {
    let (records, activations) = {
        let mut jobs = lock(&shared.jobs);
        let lost: Vec<u64> = jobs
            .records
            .iter()
            .filter(|(_, j)| gone(j.generation, j.deadline))
            .map(|(&r, _)| r)
            .collect();
        let mut records: Vec<RecordJob> =
            lost.iter().filter_map(|r| jobs.records.remove(r)).collect();
        // In the order they were asked for.
        records.sort_by_key(|j| j.deadline);
        let (lost, waiting): (Vec<ActivationJob>, Vec<ActivationJob>) = jobs
            .activations
            .drain(..)
            .partition(|j| gone(j.generation, j.deadline));
        jobs.activations.extend(waiting);
        (records, lost)
    };
    let reconfig = {
        let mut jobs = lock(&shared.jobs);
        match &jobs.reconfig {
            Some(j) if gone(j.generation, j.deadline) => jobs.reconfig.take(),
            _ => None,
        }
    };
    if let Some(job) = &reconfig {
        deliver_reconfig(shared, job, job.tailor, PNIO_ERR_NO_FW_COMMUNICATION, None);
    }
    let pe: Vec<super::pe::PeJob> = {
        let mut jobs = lock(&shared.jobs);
        let lost: Vec<u64> = jobs
            .pe
            .iter()
            .filter(|(_, j)| gone(j.generation, j.deadline))
            .map(|(&r, _)| r)
            .collect();
        lost.iter().filter_map(|r| jobs.pe.remove(r)).collect()
    };
    for job in &pe {
        super::pe::deliver(shared, job, None, no_connection());
    }
    let any =
        !records.is_empty() || !activations.is_empty() || reconfig.is_some() || !pe.is_empty();
    for job in records {
        deliver_record(shared, &job, build::NO_CONNECTION, &[]);
    }
    for job in activations {
        deliver_activation(shared, &job, PNIO_ERR_NO_FW_COMMUNICATION);
    }
    any
}

/// IO-Base's "no connection" status of a job the server can no longer confirm.
fn no_connection() -> procimg_client::RecordStatus {
    procimg_client::RecordStatus {
        error_code: 0xc0,
        error_decode: 0x80,
        error_code1: 0xa3,
        ..procimg_client::RecordStatus::default()
    }
}

/// While jobs wait, looks whether the server they were sent to still runs, and confirms them
/// as failed when it is gone (a killed server says nothing; its successor, if one comes, may
/// take long).
fn orphaned(shared: &Shared) -> bool {
    {
        let jobs = lock(&shared.jobs);
        if jobs.records.is_empty() && jobs.activations.is_empty() && jobs.pe.is_empty() {
            return false;
        }
    }
    // Under the services lock, as jobs are stamped: the generation looked at is the one the
    // liveness answer is about.
    let Some((generation, Some(false))) =
        shared.with_services(|s| (s.generation(), s.server_alive()))
    else {
        return false;
    };
    fail_jobs(shared, |g, _| g == generation)
}

fn record_done(shared: &Shared, c: &RecordConfirmation) {
    let Some(job) = lock(&shared.jobs).records.remove(&c.reference) else {
        // Not ours any more: timed out, or the request's answer was lost.
        return;
    };
    let failed = !c.status.is_ok();
    deliver_record(shared, &job, build::err_stat(&c.status, failed), &c.data);
}

fn deliver_record(shared: &Shared, job: &RecordJob, err: PNIO_ERR_STAT, data: &[u8]) {
    let t = if job.write {
        PNIO_CBE_REC_WRITE_CONF
    } else {
        PNIO_CBE_REC_READ_CONF
    };
    let cbf = shared.callbacks.get(t);
    if cbf.is_none() {
        return;
    }
    // The program gets a copy of the address it sent the job to, alive during the callback.
    let mut addr = job.addr;
    let mut prm = PNIO_CBE_PRM::new(t, shared.handle);
    if job.write {
        prm.u.RecWriteConf = PNIO_CBE_PRM_REC_WRITE_CONF {
            pAddr: &mut addr,
            RecordIndex: job.index,
            ReqRef: job.req_ref,
            Err: err,
        };
    } else {
        // The server never sends more than was asked for; the program is told no more either.
        let data = &data[..data.len().min(job.max_len as usize)];
        prm.u.RecReadConf = PNIO_CBE_PRM_REC_READ_CONF {
            pAddr: &mut addr,
            RecordIndex: job.index,
            ReqRef: job.req_ref,
            Err: err,
            Length: data.len() as u32,
            pBuffer: if data.is_empty() {
                NO_DATA.as_ptr()
            } else {
                data.as_ptr()
            },
        };
    }
    CallbackTable::invoke(cbf, &mut prm);
}

/// Delivers an alarm (one at a time: this thread is the only one that does) and
/// acknowledges it when the callback has returned.
fn alarm(shared: &Shared, a: &AlarmReport) {
    let cbf = shared.callbacks.get(PNIO_CBE_ALARM_IND);
    if cbf.is_some() {
        let (addr, data) = build::alarm(&shared.layout, a);
        // IndRef is "internal, reserved": the server's alarm id, for logs.
        deliver_alarm(shared, addr, a.id as PNIO_REF, &data);
    }
    if shared.acknowledges {
        // An alarm that no longer waits for us (acknowledged by the server's timeout, or
        // from before the subscription) is refused: nothing to do then.
        let _ = shared.with_services(|s| s.acknowledge(a));
    }
}

/// IO-Base's station failure / return alarm for a device leaving / entering data exchange.
/// Device `device` is (`true`) or is not in data exchange, as the server said.
fn set_up(shared: &Shared, device: u32, up: bool) {
    shared.devices_up.set(device as usize, up);
}

fn station_alarm(shared: &Shared, device: u32, failure: bool) {
    let cbf = shared.callbacks.get(PNIO_CBE_ALARM_IND);
    if cbf.is_some() {
        let (addr, data) = build::station_alarm(&shared.layout, device, failure);
        deliver_alarm(shared, addr, 0, &data);
    }
}

fn deliver_alarm(shared: &Shared, addr: PNIO_ADDR, ind_ref: PNIO_REF, data: &PNIO_CTRL_ALARM_DATA) {
    // Read again: the table is cleared when the controller closes.
    let cbf = shared.callbacks.get(PNIO_CBE_ALARM_IND);
    let mut addr = addr;
    let mut prm = PNIO_CBE_PRM::new(PNIO_CBE_ALARM_IND, shared.handle);
    prm.u.AlarmInd = PNIO_CBE_PRM_ALARM_IND {
        pAddr: &mut addr,
        IndRef: ind_ref,
        pAlarmData: data,
    };
    CallbackTable::invoke(cbf, &mut prm);
}

fn activation_done(shared: &Shared, device: u32, active: bool, ok: bool) {
    let job = {
        let mut jobs = lock(&shared.jobs);
        // The server confirms a device's (de)activations in the order it took them.
        let at = jobs
            .activations
            .iter()
            .position(|j| j.device == device && j.active == active)
            .or_else(|| jobs.activations.iter().position(|j| j.device == device));
        at.and_then(|i| jobs.activations.remove(i))
    };
    if let Some(job) = job {
        let result = if ok {
            PNIO_OK
        } else {
            PNIO_ERR_DEV_ACT_NOT_ALLOWED
        };
        deliver_activation(shared, &job, result);
    }
}

/// Stops the LED's flashing when its time is over.
fn led_over(shared: &Shared) {
    let over = lock(&shared.led).over(Instant::now());
    if over {
        led_flash(shared, PNIO_CBE_STOP_LED_FLASH);
    }
}

/// `PNIO_CBE_START_LED_FLASH` (at DCP Signal's 2 Hz) or `PNIO_CBE_STOP_LED_FLASH`.
fn led_flash(shared: &Shared, event: PNIO_CBE_TYPE) {
    let mut prm = PNIO_CBE_PRM::new(event, shared.handle);
    prm.u.LedFlash = PNIO_CBE_PRM_LED_FLASH {
        Frequency: if event == PNIO_CBE_START_LED_FLASH {
            FLASH_HZ
        } else {
            0
        },
    };
    CallbackTable::invoke(shared.callbacks.get(event), &mut prm);
}

/// The end of the reconfiguration under way: its callback, naming by the program's own
/// address the device or port a refusal names.
fn reconfigured(shared: &Shared, active: bool, refused: Option<&TailoringRefusal>) {
    let Some(job) = lock(&shared.jobs).reconfig.take() else {
        return;
    };
    let (status, addr) = match refused {
        None => (PNIO_OK, None),
        Some(TailoringRefusal::Station { device, .. }) => (
            PNIO_ERR_INVALID_STATION,
            job.devices
                .iter()
                .find(|(d, _)| d == device)
                .map(|(_, a)| *a),
        ),
        Some(TailoringRefusal::Port { port, .. }) => (
            PNIO_ERR_INVALID_PORT,
            job.ports.iter().find(|(p, _)| p == port).map(|(_, a)| *a),
        ),
    };
    deliver_reconfig(shared, &job, active, status, addr);
}

fn deliver_reconfig(
    shared: &Shared,
    job: &ReconfigJob,
    active: bool,
    status: u32,
    addr: Option<PNIO_ADDR>,
) {
    let cbf = shared.callbacks.get(PNIO_CBE_IOSYSTEM_RECONFIG);
    // All zero when nothing made it fail (the manual's "zero if none").
    let mut addr = addr.unwrap_or(PNIO_ADDR {
        AddrType: 0,
        IODataType: 0,
        u: PNIO_ADDR_u { Reserved: [0; 5] },
    });
    let mut prm = PNIO_CBE_PRM::new(PNIO_CBE_IOSYSTEM_RECONFIG, shared.handle);
    prm.u.IoSystemReconf = PNIO_CBE_PRM_IOSYS_CONF {
        pAddr: &mut addr,
        Mode: if active && job.tailor {
            PNIO_DA_TRUE
        } else {
            PNIO_DA_FALSE
        },
        Status: status,
    };
    CallbackTable::invoke(cbf, &mut prm);
}

fn deliver_activation(shared: &Shared, job: &ActivationJob, result: u32) {
    let cbf = shared.callbacks.get(PNIO_CBE_DEV_ACT_CONF);
    if cbf.is_none() {
        return;
    }
    let mut addr = job.addr;
    let mut prm = PNIO_CBE_PRM::new(PNIO_CBE_DEV_ACT_CONF, shared.handle);
    prm.u.DevActConf = PNIO_CBE_PRM_DEV_ACT_CONF {
        pAddr: &mut addr,
        Mode: if job.active {
            PNIO_DA_TRUE
        } else {
            PNIO_DA_FALSE
        },
        Result: result,
    };
    CallbackTable::invoke(cbf, &mut prm);
}

/// The answer of a diagnosis request, owned until its callback has returned.
enum Answer {
    None,
    Submodules(Vec<crate::iobase::types::PNIO_CTRL_DIAG_CONFIG_SUBMODULE>),
    Slices(Vec<crate::iobase::types::PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE>),
    Device(Box<crate::iobase::types::PNIO_CTRL_DIAG_DEVICE>),
    Diagnostic(Box<crate::iobase::types::PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC_DATA>),
    NameAddr(Box<crate::iobase::types::PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO_DATA>),
    Counters(Box<crate::iobase::types::PNIO_CTRL_COMM_COUNTER_DATA>),
}

impl Answer {
    /// Pointer and length in bytes for `PNIO_CBE_PRM_CTRL_DIAG_CONF`; an empty answer points
    /// at `none`.
    fn buffer(&mut self, none: &mut [u8; 4]) -> (*mut u8, usize) {
        fn bytes<T>(v: &mut [T]) -> (*mut u8, usize) {
            (v.as_mut_ptr().cast(), std::mem::size_of_val(v))
        }
        let (p, n) = match self {
            Answer::None => (none.as_mut_ptr(), 0),
            Answer::Submodules(v) => bytes(v),
            Answer::Slices(v) => bytes(v),
            Answer::Device(d) => bytes(std::slice::from_mut(&mut **d)),
            Answer::Diagnostic(d) => bytes(std::slice::from_mut(&mut **d)),
            Answer::NameAddr(d) => bytes(std::slice::from_mut(&mut **d)),
            Answer::Counters(d) => bytes(std::slice::from_mut(&mut **d)),
        };
        if n == 0 {
            (none.as_mut_ptr(), 0)
        } else {
            (p, n)
        }
    }
}

/// Answers one waiting diagnosis request; whether there was one.
fn diagnose(shared: &Shared) -> bool {
    let Some(job) = lock(&shared.jobs).diags.pop_front() else {
        return false;
    };
    if shared.callbacks.get(PNIO_CBE_CTRL_DIAG_CONF).is_none() {
        // Closed meanwhile: nobody to answer.
        return true;
    }
    let (mut answer, code) = answer(shared, &job);
    let mut none = [0u8; 4];
    let (buffer, len) = answer.buffer(&mut none);
    let cbf = shared.callbacks.get(PNIO_CBE_CTRL_DIAG_CONF);
    let mut prm = PNIO_CBE_PRM::new(PNIO_CBE_CTRL_DIAG_CONF, shared.handle);
    prm.u.CtrlDiagConf = PNIO_CBE_PRM_CTRL_DIAG_CONF {
        pDiagData: job.request.0,
        DiagDataBufferLen: len as u32,
        pDiagDataBuffer: buffer,
        ErrorCode: code,
    };
    CallbackTable::invoke(cbf, &mut prm);
    true
}

fn answer(shared: &Shared, job: &DiagJob) -> (Answer, u32) {
    match job.service {
        PNIO_CTRL_DIAG_CONFIG_SUBMODULE_LIST => (
            Answer::Submodules(build::submodule_list(&shared.layout)),
            PNIO_OK,
        ),
        // procimg has no IO router: the answer is its length, 0.
        PNIO_CTRL_DIAG_CONFIG_IOROUTER_PRESENT => (Answer::None, PNIO_OK),
        PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE_LIST => (
            Answer::Slices(build::output_slices(&shared.layout)),
            PNIO_OK,
        ),
        PNIO_CTRL_DIAG_DEVICE_STATE | PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC => {
            match device_diagnosis(shared, job.device) {
                Ok(d) if job.service == PNIO_CTRL_DIAG_DEVICE_STATE => {
                    (Answer::Device(Box::new(build::device_state(&d))), PNIO_OK)
                }
                Ok(d) => (
                    Answer::Diagnostic(Box::new(build::device_diagnostic(&d))),
                    PNIO_OK,
                ),
                Err(code) => (Answer::None, code),
            }
        }
        PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO => match controller(shared) {
            Ok(c) => (
                Answer::NameAddr(Box::new(build::name_addr_info(&c))),
                PNIO_OK,
            ),
            Err(code) => (Answer::None, code),
        },
        // RESET answers the counters as they were, then starts them again from 0.
        PNIO_CTRL_DIAG_GET_COMM_COUNTER_DATA | PNIO_CTRL_DIAG_RESET_COMM_COUNTERS => {
            let counters = controller(shared).map(|c| build::comm_counters(&c));
            let reset = || {
                shared
                    .with_services(|s| s.reset_comm_counters())
                    .ok_or(PNIO_ERR_NO_FW_COMMUNICATION)?
                    .map_err(|e| super::control_code(&e))
            };
            match counters {
                Ok(c) if job.service == PNIO_CTRL_DIAG_GET_COMM_COUNTER_DATA => {
                    (Answer::Counters(Box::new(c)), PNIO_OK)
                }
                Ok(c) => match reset() {
                    Ok(()) => (Answer::Counters(Box::new(c)), PNIO_OK),
                    Err(code) => (Answer::None, code),
                },
                Err(code) => (Answer::None, code),
            }
        }
        // Refused at the call; kept for safety.
        _ => (Answer::None, PNIO_ERR_PRM_INVALIDARG),
    }
}

/// The controller's own station, from the server's status.
fn controller(shared: &Shared) -> Result<procimg_client::ControllerReport, u32> {
    let status = shared
        .with_services(|s| s.control().status())
        .ok_or(PNIO_ERR_NO_FW_COMMUNICATION)?
        .map_err(|e| super::control_code(&e))?;
    status.controller.ok_or(PNIO_ERR_NO_FW_COMMUNICATION)
}

/// The server's diagnosis of `device`.
fn device_diagnosis(shared: &Shared, device: Option<u32>) -> Result<DeviceDiagnosis, u32> {
    let device = device.ok_or(PNIO_ERR_PRM_ADD)?;
    let report = shared
        .with_services(|s| s.diagnosis())
        .ok_or(PNIO_ERR_NO_FW_COMMUNICATION)?
        .map_err(|e| super::control_code(&e))?;
    report
        .devices
        .into_iter()
        .find(|d| d.device == device)
        .ok_or(PNIO_ERR_PRM_ADD)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::iobase::devices_up::DevicesUp;
    use crate::iobase::services::address::tests::demo_layout;
    use crate::iobase::services::{Jobs, Wake};
    use crate::iobase::types::PNIO_IO_IN;
    use std::sync::Mutex;
    use std::sync::atomic::AtomicBool;
    use std::time::Duration;

    /// (ReqRef, ErrCode) of the read confirmations, and the Results of the activation
    /// confirmations, of this test's handle.
    static READS: Mutex<Vec<(u32, u8)>> = Mutex::new(Vec::new());
    static ACTIVATIONS: Mutex<Vec<u32>> = Mutex::new(Vec::new());

    unsafe extern "C" fn on_read(prm: *mut PNIO_CBE_PRM) {
        // SAFETY: the worker's parameters of a REC_READ_CONF, valid for the call.
        let c = unsafe { (*prm).u.RecReadConf };
        READS.lock().unwrap().push((c.ReqRef, c.Err.ErrCode));
    }
    unsafe extern "C" fn on_activation(prm: *mut PNIO_CBE_PRM) {
        // SAFETY: the worker's parameters of a DEV_ACT_CONF, valid for the call.
        let c = unsafe { (*prm).u.DevActConf };
        ACTIVATIONS.lock().unwrap().push(c.Result);
    }

    fn shared() -> Shared {
        let callbacks = Arc::new(CallbackTable::new());
        assert!(callbacks.set_once(PNIO_CBE_REC_READ_CONF, Some(on_read)));
        assert!(callbacks.set_once(PNIO_CBE_DEV_ACT_CONF, Some(on_activation)));
        Shared {
            instance: "worker-test".into(),
            handle: 77,
            layout: demo_layout(),
            callbacks,
            led: Mutex::new(procimg_client::iobase::LedFlash::default()),
            devices_up: Arc::new(DevicesUp::new(3)),
            acknowledges: false,
            pe_cbf: Mutex::new(None),
            services: Mutex::new(None),
            jobs: Mutex::new(Jobs::default()),
            stop: AtomicBool::new(false),
            wake: Wake::new().unwrap(),
        }
    }

    #[test]
    fn a_devices_data_exchange_follows_the_servers_notifications() {
        let s = shared();
        let up = |d| s.devices_up.get(d);
        handle(
            &s,
            Notification::DeviceReturn {
                device: 1,
                name: "counter".into(),
            },
        );
        assert!(up(1) && !up(0));
        handle(
            &s,
            Notification::DeviceState {
                device: 0,
                name: "echo".into(),
                state: DeviceState::Running,
            },
        );
        assert!(up(0));
        handle(
            &s,
            Notification::DeviceFailure {
                device: 1,
                name: "counter".into(),
                reason: "no input frames within the watchdog time".into(),
            },
        );
        assert!(!up(1) && up(0));
        handle(
            &s,
            Notification::DeviceState {
                device: 0,
                name: "echo".into(),
                state: DeviceState::Unknown,
            },
        );
        assert!(
            !up(0),
            "a state this library does not know is not data exchange"
        );
        handle(
            &s,
            Notification::DeviceReturn {
                device: 0,
                name: "echo".into(),
            },
        );
        handle(&s, Notification::ServerStarted { generation: 9 });
        assert!(!up(0), "a new server brings its devices up anew");
    }

    fn read_job(req_ref: u32, generation: Option<u64>) -> RecordJob {
        RecordJob {
            req_ref,
            addr: PNIO_ADDR::logical(PNIO_IO_IN, 0),
            index: 0xAFF0,
            max_len: 16,
            write: false,
            deadline: Instant::now() + Duration::from_secs(60),
            generation,
        }
    }

    #[test]
    fn a_new_server_fails_the_jobs_of_its_predecessors_at_once() {
        let s = shared();
        {
            let mut jobs = s.jobs.lock().unwrap();
            jobs.records.insert(1, read_job(11, Some(0xA)));
            jobs.records.insert(2, read_job(12, None));
            jobs.records.insert(3, read_job(13, Some(0xB)));
            let addr = PNIO_ADDR::logical(PNIO_IO_IN, 0);
            for (id, generation) in [(4, Some(0xA)), (5, Some(0xB))] {
                jobs.activations.push_back(ActivationJob {
                    id,
                    device: 0,
                    active: true,
                    addr,
                    deadline: Instant::now() + Duration::from_secs(60),
                    generation,
                });
            }
        }
        handle(&s, Notification::ServerStarted { generation: 0xB });
        let mut reads = READS.lock().unwrap().clone();
        reads.sort();
        // The jobs of server A and of a server that did not say, with "no connection".
        assert_eq!(reads, [(11, 0xC0), (12, 0xC0)]);
        assert_eq!(*ACTIVATIONS.lock().unwrap(), [PNIO_ERR_NO_FW_COMMUNICATION]);
        // Server B's own jobs wait for their answers.
        let jobs = s.jobs.lock().unwrap();
        assert_eq!(jobs.records.keys().copied().collect::<Vec<_>>(), [3]);
        assert_eq!(jobs.activations.len(), 1);
        assert_eq!(jobs.activations[0].id, 5);
    }
}
