// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller services behind the IO-Base API: record jobs, alarms, device activation and
//! diagnosis, delivered to the program's callbacks on a thread of their own.
//!
//! One [`ServiceWorker`] per open controller holds a [`Services`] handle of the Rust client
//! and one thread. The API calls (`PNIO_rec_read_req`, `PNIO_rec_write_req`,
//! `PNIO_device_activate`, `PNIO_ctrl_diag_req`) check what is theirs to check, note the job
//! and hand it to the server from the calling thread; the worker thread waits for the
//! server's notifications and calls the callbacks, one at a time:
//!
//! * `PNIO_CBE_REC_READ_CONF` / `PNIO_CBE_REC_WRITE_CONF` for every record job, with the
//!   caller's `ReqRef`, a copy of the address the job was sent to, and the PNIOStatus. A job
//!   the server can no longer confirm is confirmed as failed with IO-Base's "no connection"
//!   status (0xC0, 0x80, 0xA3, 0): at once when the worker learns that the server it was sent
//!   to is gone or that a new server started, else after [`JOB_TIMEOUT`].
//! * `PNIO_CBE_ALARM_IND` for the devices' alarms, strictly one at a time, each acknowledged
//!   to the device when the callback has returned (without an alarm callback the server
//!   acknowledges them itself); and for every station failure and return, as the synthetic
//!   alarms `PNIO_ALARM_DEV_FAILURE` / `PNIO_ALARM_DEV_RETURN`.
//! * `PNIO_CBE_DEV_ACT_CONF` when the server has carried out a (de)activation.
//! * `PNIO_CBE_CTRL_DIAG_CONF` for `PNIO_ctrl_diag_req`, with the caller's request pointer.
//! * `PNIO_CBE_IOSYSTEM_RECONFIG` when the server has reconfigured the IO system
//!   (`PNIO_iosystem_reconfig`), or refused to.
//! * `PNIO_CBE_START_LED_FLASH` when a DCP Signal comes to the controller's own station,
//!   and `PNIO_CBE_STOP_LED_FLASH` three seconds later (another Signal meanwhile extends
//!   the flashing).
//!
//! Choices where the manual leaves room:
//! * Parallel record jobs are capped at 16 per controller (PN Driver's limit, and the
//!   server's per subscriber); one more is refused with `PNIO_ERR_NO_RESOURCE`, the code for
//!   "out of resources" (the manual's list for the record functions has none closer).
//! * Station numbers (`DeviceNum`, `StatNo`) are the device's layout index + 1 (see
//!   [`build`]).
//! * `PNIO_ctrl_diag_req` answers CONFIG_SUBMODULE_LIST, DEVICE_STATE,
//!   CONFIG_IOROUTER_PRESENT (none), CONFIG_OUTPUT_SLICE_LIST (all bits of every output
//!   submodule) and DEVICE_DIAGNOSTIC (the mode and, of the device's last failure, the CM
//!   error cause, the abort reason of an ERR-RTA and the failure's PNIO status).
//!   Other services are refused at the call with `PNIO_ERR_PRM_INVALIDARG`, an address of no
//!   device with `PNIO_ERR_PRM_ADD`, and the call without a registered
//!   `PNIO_CBE_CTRL_DIAG_CONF` callback with `PNIO_ERR_SEQUENCE` (register first).
//! * A (de)activation the server reports as not carried out is confirmed with Result
//!   `PNIO_ERR_DEV_ACT_NOT_ALLOWED`.

mod address;
pub(crate) mod build;
mod pe;
mod worker;

use super::callbacks::CallbackTable;
use super::devices_up::DevicesUp;
use super::errors::fail;
use super::errors::{
    PNIO_ERR_INTERNAL, PNIO_ERR_MAX_REACHED, PNIO_ERR_MODE_VALUE, PNIO_ERR_NO_FW_COMMUNICATION,
    PNIO_ERR_NO_RESOURCE, PNIO_ERR_NOT_REENTERABLE, PNIO_ERR_OS_RES, PNIO_ERR_PRM_ADD,
    PNIO_ERR_PRM_DEV_STATE, PNIO_ERR_PRM_INVALIDARG, PNIO_ERR_PRM_REC_INDEX, PNIO_ERR_SEQUENCE,
    PNIO_ERR_START_THREAD_FAILED, PNIO_ERR_VALUE_LEN, PNIO_OK, name,
};
use super::sync::lock;
use super::types::{
    PNIO_ADDR, PNIO_CBE_ALARM_IND, PNIO_CBE_CTRL_DIAG_CONF, PNIO_CBE_IOSYSTEM_RECONFIG,
    PNIO_CTRL_DIAG, PNIO_CTRL_DIAG_CONFIG_IOROUTER_PRESENT, PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO,
    PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE_LIST, PNIO_CTRL_DIAG_CONFIG_SUBMODULE_LIST,
    PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC, PNIO_CTRL_DIAG_DEVICE_STATE, PNIO_CTRL_DIAG_ENUM,
    PNIO_CTRL_DIAG_GET_COMM_COUNTER_DATA, PNIO_CTRL_DIAG_RESET_COMM_COUNTERS, PNIO_DA_FALSE,
    PNIO_DA_TRUE, PNIO_DEV_ACT_TYPE, PNIO_MAX_REC_LEN, PNIO_REF,
};
use super::wake::Wake;
use crate::ffi::set_last_error;
use procimg_client::iobase::LedFlash;
use procimg_client::{
    AttachError, ControlError, Layout, PortRef, RecordTarget, Refusal, ServiceOptions, Services,
    Tailoring,
};
use std::collections::{HashMap, VecDeque};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Record jobs one controller may have open at a time.
pub(crate) const MAX_RECORD_JOBS: usize = procimg_control::services::MAX_RECORD_JOBS;

/// Diagnosis requests one controller may have waiting for the worker.
const MAX_DIAG_JOBS: usize = 64;

/// How long a record job or an activation waits for its confirmation before it is confirmed
/// as failed: longer than the server's own retries of a job queued behind others. Jobs of a
/// server that is gone or was followed by a new one fail before (see [`worker`]).
const JOB_TIMEOUT: Duration = Duration::from_secs(60);

/// What the worker of one controller needs to know.
pub(crate) struct ServiceContext {
    /// Server instance name.
    pub instance: String,
    /// The PNIO handle, put into `PNIO_CBE_PRM.Handle`.
    pub handle: u32,
    /// The CpIndex the controller was opened with.
    pub cp_index: u32,
    /// The server's layout, for logical addresses.
    pub layout: Layout,
    /// The program's callbacks, read at delivery time.
    pub callbacks: Arc<CallbackTable>,
    /// Per device of the layout: in data exchange. The worker keeps it as the server's
    /// notifications say, before it calls the program back, so that the data functions and
    /// the callbacks agree.
    pub devices_up: Arc<DevicesUp>,
}

/// An open record job.
#[derive(Clone, Copy)]
struct RecordJob {
    req_ref: PNIO_REF,
    addr: PNIO_ADDR,
    index: u32,
    /// For reads, the most bytes the program asked for.
    max_len: u32,
    write: bool,
    deadline: Instant,
    /// The generation of the server the job was sent to (`None`: it did not say).
    generation: Option<u64>,
}

/// A (de)activation waiting for its confirmation.
#[derive(Clone, Copy)]
struct ActivationJob {
    id: u64,
    device: u32,
    active: bool,
    addr: PNIO_ADDR,
    deadline: Instant,
    /// The generation of the server the activation was sent to (`None`: it did not say).
    generation: Option<u64>,
}

/// A `PNIO_iosystem_reconfig` waiting for its confirmation, with the addresses the program
/// named each device and port by (the confirmation names the one that made it fail).
struct ReconfigJob {
    tailor: bool,
    devices: Vec<(u32, PNIO_ADDR)>,
    ports: Vec<(PortRef, PNIO_ADDR)>,
    deadline: Instant,
    /// The generation of the server it was sent to (`None`: it did not say).
    generation: Option<u64>,
}

/// The program's `PNIO_CTRL_DIAG`, handed back in the confirmation.
struct DiagRequest(*mut PNIO_CTRL_DIAG);

// SAFETY: the pointer is never dereferenced by the library after the call that took it; it
// only travels to the worker thread to be handed back to the program in its confirmation.
unsafe impl Send for DiagRequest {}

/// A diagnosis request waiting for the worker.
struct DiagJob {
    request: DiagRequest,
    service: PNIO_CTRL_DIAG_ENUM,
    /// For the device services, the device.
    device: Option<u32>,
}

/// The jobs of one controller.
#[derive(Default)]
struct Jobs {
    next_reference: u64,
    records: HashMap<u64, RecordJob>,
    activations: VecDeque<ActivationJob>,
    diags: VecDeque<DiagJob>,
    reconfig: Option<ReconfigJob>,
    /// PROFIenergy commands waiting for their confirmation, by reference.
    pe: HashMap<u64, pe::PeJob>,
}

impl Jobs {
    fn reference(&mut self) -> u64 {
        self.next_reference += 1;
        self.next_reference
    }
}

/// What the API calls and the worker share.
struct Shared {
    instance: String,
    handle: u32,
    layout: Layout,
    callbacks: Arc<CallbackTable>,
    /// The controller station's LED, flashing after a DCP Signal.
    led: Mutex<LedFlash>,
    devices_up: Arc<DevicesUp>,
    /// Whether the server waits for our acknowledgement of alarms.
    acknowledges: bool,
    /// The PE confirmation callback (`PNIO_register_pe_cbf`).
    pe_cbf: Mutex<crate::iobase::pe_types::PNIO_PE_CBF>,
    /// `None` once the worker has ended (and unsubscribed).
    services: Mutex<Option<Services>>,
    jobs: Mutex<Jobs>,
    stop: AtomicBool,
    wake: Wake,
}

/// The function whose failures `ServiceWorker::start` reports.
const OPEN: &str = "PNIO_controller_open";

impl Shared {
    /// Records the failure text for the calling thread, naming the code, and returns `code`.
    fn fail(&self, what: &str, code: u32, detail: impl std::fmt::Display) -> u32 {
        set_last_error(format!(
            "{what} on PNIO handle {} (procimg instance \"{}\"): {detail} ({})",
            self.handle,
            self.instance,
            name(code)
        ));
        code
    }

    fn fail_control(&self, what: &str, e: &ControlError) -> u32 {
        self.fail(what, control_code(e), e)
    }

    /// Runs `f` on the services handle; `None` once the worker has stopped.
    fn with_services<R>(&self, f: impl FnOnce(&mut Services) -> R) -> Option<R> {
        lock(&self.services).as_mut().map(f)
    }
}

/// The IO-Base code for a control request that failed.
fn control_code(e: &ControlError) -> u32 {
    match e {
        ControlError::NoServer { .. }
        | ControlError::NoAnswer { .. }
        | ControlError::Transport { .. }
        | ControlError::Refused(Refusal::UnknownSubscriber) => PNIO_ERR_NO_FW_COMMUNICATION,
        ControlError::Refused(Refusal::TooManyJobs { .. } | Refusal::ServerBusy) => {
            PNIO_ERR_NO_RESOURCE
        }
        ControlError::Refused(Refusal::RecordTooLong { .. }) => PNIO_ERR_VALUE_LEN,
        ControlError::Refused(Refusal::NoSuchDevice { .. }) => PNIO_ERR_PRM_ADD,
        ControlError::Refused(Refusal::Offline) => PNIO_ERR_MODE_VALUE,
        _ => PNIO_ERR_INTERNAL,
    }
}

/// The services worker of one controller.
pub(crate) struct ServiceWorker {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
}

impl ServiceWorker {
    /// Subscribes to the services of `ctx.instance` and starts the worker thread. Alarms wait
    /// for this controller's acknowledgement when an alarm callback is registered now (it can
    /// only be registered by `PNIO_controller_open`). Fails with a PNIO error code, the
    /// thread's last error text saying why.
    pub(crate) fn start(ctx: ServiceContext) -> Result<ServiceWorker, u32> {
        let acknowledges = ctx.callbacks.get(PNIO_CBE_ALARM_IND).is_some();
        let name = format!("PNIO controller {} (CP {})", ctx.handle, ctx.cp_index);
        let opened = Services::open(
            &ctx.instance,
            ServiceOptions::new(&name).acknowledge_alarms(acknowledges),
        );
        let services = opened.map_err(|e| {
            let code = match e {
                AttachError::Refused {
                    refusal: Refusal::TooManyClients { .. },
                    ..
                } => PNIO_ERR_MAX_REACHED,
                _ => PNIO_ERR_NO_FW_COMMUNICATION,
            };
            fail(
                OPEN,
                code,
                format_args!(
                    "PNIO controller {} cannot subscribe to the record, alarm and diagnosis \
                     services: {e}",
                    ctx.handle
                ),
            )
        })?;
        let wake = Wake::new().map_err(|e| {
            fail(
                OPEN,
                PNIO_ERR_OS_RES,
                format_args!(
                    "PNIO controller {}: no eventfd for the services thread ({e}); raise the \
                     process's descriptor limit",
                    ctx.handle
                ),
            )
        })?;
        let shared = Arc::new(Shared {
            instance: ctx.instance,
            handle: ctx.handle,
            layout: ctx.layout,
            callbacks: ctx.callbacks,
            led: Mutex::new(LedFlash::default()),
            devices_up: ctx.devices_up,
            acknowledges,
            pe_cbf: Mutex::new(None),
            services: Mutex::new(Some(services)),
            jobs: Mutex::new(Jobs::default()),
            stop: AtomicBool::new(false),
            wake,
        });
        let for_thread = shared.clone();
        let thread = std::thread::Builder::new()
            .name(format!("pnio-svc-{}", shared.handle))
            .spawn(move || worker::run(for_thread))
            .map_err(|e| {
                fail(
                    OPEN,
                    PNIO_ERR_START_THREAD_FAILED,
                    format_args!(
                        "PNIO controller {}: cannot start the services thread: {e}",
                        shared.handle
                    ),
                )
            })?;
        Ok(ServiceWorker {
            shared,
            thread: Some(thread),
        })
    }

    /// Resolves a record job's address.
    fn record_target(&self, what: &str, addr: &PNIO_ADDR, index: u32) -> Result<RecordTarget, u32> {
        let s = &self.shared;
        let Some(r) = address::resolve(&s.layout, addr) else {
            return Err(s.fail(
                what,
                PNIO_ERR_PRM_ADD,
                format_args!(
                    "no submodule has {}; `PNIO_ctrl_diag_req` with \
                     PNIO_CTRL_DIAG_CONFIG_SUBMODULE_LIST lists the addresses",
                    address::describe(addr)
                ),
            ));
        };
        let Ok(index) = u16::try_from(index) else {
            return Err(s.fail(
                what,
                PNIO_ERR_PRM_REC_INDEX,
                format_args!("record index {index:#x} is above 0xFFFF"),
            ));
        };
        Ok(r.record(index))
    }

    /// Notes a record job and hands it to the server.
    fn record_job(
        &self,
        what: &str,
        addr: &PNIO_ADDR,
        target: RecordTarget,
        req_ref: PNIO_REF,
        write: Option<&[u8]>,
        max_len: u32,
    ) -> u32 {
        let s = &self.shared;
        let reference = {
            let mut jobs = lock(&s.jobs);
            if jobs.records.len() >= MAX_RECORD_JOBS {
                return s.fail(
                    what,
                    PNIO_ERR_NO_RESOURCE,
                    format_args!(
                        "{MAX_RECORD_JOBS} record jobs are open already; wait for a \
                         confirmation before the next request"
                    ),
                );
            }
            let reference = jobs.reference();
            // Noted before the server has it: its confirmation may come before `record_*`
            // returns.
            jobs.records.insert(
                reference,
                RecordJob {
                    req_ref,
                    addr: *addr,
                    index: u32::from(target.index),
                    max_len,
                    write: write.is_some(),
                    deadline: Instant::now() + JOB_TIMEOUT,
                    generation: None,
                },
            );
            reference
        };
        self.hand_over(
            what,
            |jobs, generation| {
                if let Some(j) = jobs.records.get_mut(&reference) {
                    j.generation = generation;
                }
            },
            |sv| match write {
                Some(data) => sv.record_write(target, data, reference),
                None => sv.record_read(target, max_len, reference),
            },
            |jobs| {
                jobs.records.remove(&reference);
            },
        )
    }

    /// Hands a noted job to the server: `stamp` gives it the generation of the server it
    /// goes to (under the services lock: the worker learns of a new server under it too),
    /// `send` sends it. When it cannot be sent, `forget` drops the note and the failure is
    /// returned.
    fn hand_over(
        &self,
        what: &str,
        stamp: impl FnOnce(&mut Jobs, Option<u64>),
        send: impl FnOnce(&mut Services) -> Result<(), ControlError>,
        forget: impl FnOnce(&mut Jobs),
    ) -> u32 {
        let s = &self.shared;
        let sent = s.with_services(|sv| {
            stamp(&mut lock(&s.jobs), sv.generation());
            send(sv)
        });
        let failed = match sent {
            Some(Ok(())) => return PNIO_OK,
            Some(Err(e)) => s.fail_control(what, &e),
            None => s.fail(
                what,
                PNIO_ERR_NO_FW_COMMUNICATION,
                "the controller is being closed",
            ),
        };
        forget(&mut lock(&s.jobs));
        failed
    }

    /// `PNIO_rec_read_req`: starts a read of at most `length` bytes of record `record_index`
    /// of the submodule at `addr`; confirmed by `PNIO_CBE_REC_READ_CONF` with `req_ref`.
    pub(crate) fn rec_read_req(
        &self,
        addr: &PNIO_ADDR,
        record_index: u32,
        req_ref: PNIO_REF,
        length: u32,
    ) -> u32 {
        const WHAT: &str = "PNIO_rec_read_req";
        let target = match self.record_target(WHAT, addr, record_index) {
            Ok(t) => t,
            Err(code) => return code,
        };
        if length == 0 || length > PNIO_MAX_REC_LEN {
            return self.shared.fail(
                WHAT,
                PNIO_ERR_VALUE_LEN,
                format_args!("Length {length}: a record read takes 1 to {PNIO_MAX_REC_LEN} bytes"),
            );
        }
        self.record_job(WHAT, addr, target, req_ref, None, length)
    }

    /// `PNIO_rec_write_req`: starts a write of `data` to record `record_index` of the
    /// submodule at `addr`; confirmed by `PNIO_CBE_REC_WRITE_CONF` with `req_ref`.
    pub(crate) fn rec_write_req(
        &self,
        addr: &PNIO_ADDR,
        record_index: u32,
        req_ref: PNIO_REF,
        data: &[u8],
    ) -> u32 {
        const WHAT: &str = "PNIO_rec_write_req";
        let target = match self.record_target(WHAT, addr, record_index) {
            Ok(t) => t,
            Err(code) => return code,
        };
        if data.is_empty() || data.len() > PNIO_MAX_REC_LEN as usize {
            return self.shared.fail(
                WHAT,
                PNIO_ERR_VALUE_LEN,
                format_args!(
                    "Length {}: a record write takes 1 to {PNIO_MAX_REC_LEN} bytes",
                    data.len()
                ),
            );
        }
        self.record_job(WHAT, addr, target, req_ref, Some(data), 0)
    }

    /// `PNIO_device_activate`: (de)activates the device that has `addr`; confirmed by
    /// `PNIO_CBE_DEV_ACT_CONF`, the state change itself by DEV_RETURN / DEV_FAILURE alarms.
    pub(crate) fn device_activate(&self, addr: &PNIO_ADDR, mode: PNIO_DEV_ACT_TYPE) -> u32 {
        const WHAT: &str = "PNIO_device_activate";
        let s = &self.shared;
        let Some(r) = address::resolve(&s.layout, addr) else {
            return s.fail(
                WHAT,
                PNIO_ERR_PRM_ADD,
                format_args!("no device has {}", address::describe(addr)),
            );
        };
        let active = match mode {
            PNIO_DA_TRUE => true,
            PNIO_DA_FALSE => false,
            other => {
                return s.fail(
                    WHAT,
                    PNIO_ERR_PRM_DEV_STATE,
                    format_args!("DeviceMode {other} is neither PNIO_DA_TRUE nor PNIO_DA_FALSE"),
                );
            }
        };
        let id = {
            let mut jobs = lock(&s.jobs);
            let id = jobs.reference();
            jobs.activations.push_back(ActivationJob {
                id,
                device: r.device,
                active,
                addr: *addr,
                deadline: Instant::now() + JOB_TIMEOUT,
                generation: None,
            });
            id
        };
        self.hand_over(
            WHAT,
            |jobs, generation| {
                if let Some(j) = jobs.activations.iter_mut().find(|j| j.id == id) {
                    j.generation = generation;
                }
            },
            |sv| sv.activate(r.device, active),
            |jobs| jobs.activations.retain(|j| j.id != id),
        )
    }

    /// `PNIO_iosystem_reconfig` after the checks of the call itself: the addresses resolved,
    /// the job noted and handed to the server.
    pub(crate) fn iosystem_reconfig(
        &self,
        tailor: bool,
        devices: &[PNIO_ADDR],
        ports: &[PNIO_ADDR],
    ) -> u32 {
        const WHAT: &str = "PNIO_iosystem_reconfig";
        let s = &self.shared;
        if s.callbacks.get(PNIO_CBE_IOSYSTEM_RECONFIG).is_none() {
            return s.fail(
                WHAT,
                PNIO_ERR_SEQUENCE,
                "register PNIO_CBE_IOSYSTEM_RECONFIG first: it says how the reconfiguration ended",
            );
        }
        let resolve = |addr: &PNIO_ADDR, what: &str| {
            address::resolve(&s.layout, addr).ok_or_else(|| {
                s.fail(
                    WHAT,
                    PNIO_ERR_PRM_ADD,
                    format_args!("no {what} has {}", address::describe(addr)),
                )
            })
        };
        let mut named_devices = Vec::new();
        for addr in devices {
            match resolve(addr, "device") {
                Ok(r) => named_devices.push((r.device, *addr)),
                Err(code) => return code,
            }
        }
        let mut named_ports = Vec::new();
        for addr in ports {
            match resolve(addr, "port submodule") {
                Ok(r) => named_ports.push((
                    PortRef {
                        device: r.device,
                        slot: r.slot,
                        subslot: r.subslot,
                    },
                    *addr,
                )),
                Err(code) => return code,
            }
        }
        let tailoring = tailor.then(|| Tailoring {
            devices: named_devices.iter().map(|(d, _)| *d).collect(),
            links: named_ports
                .chunks_exact(2)
                .map(|pair| [pair[0].0, pair[1].0])
                .collect(),
        });
        {
            let mut jobs = lock(&s.jobs);
            if jobs.reconfig.is_some() {
                return s.fail(
                    WHAT,
                    PNIO_ERR_NOT_REENTERABLE,
                    "the previous reconfiguration has not ended: wait for its \
                     PNIO_CBE_IOSYSTEM_RECONFIG",
                );
            }
            jobs.reconfig = Some(ReconfigJob {
                tailor,
                devices: named_devices,
                ports: named_ports,
                deadline: Instant::now() + JOB_TIMEOUT,
                generation: None,
            });
        }
        self.hand_over(
            WHAT,
            |jobs, generation| {
                if let Some(j) = jobs.reconfig.as_mut() {
                    j.generation = generation;
                }
            },
            |sv| sv.reconfigure_io_system(tailoring),
            |jobs| jobs.reconfig = None,
        )
    }

    /// `PNIO_ctrl_diag_req`: queues the request for the worker, which answers it with
    /// `PNIO_CBE_CTRL_DIAG_CONF`. The request stays the library's until then.
    pub(crate) fn ctrl_diag_req(&self, req: *mut PNIO_CTRL_DIAG) -> u32 {
        const WHAT: &str = "PNIO_ctrl_diag_req";
        let s = &self.shared;
        if s.callbacks.get(PNIO_CBE_CTRL_DIAG_CONF).is_none() {
            return s.fail(
                WHAT,
                PNIO_ERR_SEQUENCE,
                "no PNIO_CBE_CTRL_DIAG_CONF callback is registered to receive the answer; \
                 register it with PNIO_register_cbf (in OFFLINE) first",
            );
        }
        // SAFETY: the caller checked `req` for NULL, and the program hands us a
        // PNIO_CTRL_DIAG it owns for the duration of the request; it is only read, and
        // unaligned reads cost nothing here.
        let copy = unsafe { std::ptr::read_unaligned(req) };
        let device = match copy.DiagService {
            PNIO_CTRL_DIAG_CONFIG_SUBMODULE_LIST
            | PNIO_CTRL_DIAG_CONFIG_IOROUTER_PRESENT
            | PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE_LIST
            | PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO
            | PNIO_CTRL_DIAG_GET_COMM_COUNTER_DATA
            | PNIO_CTRL_DIAG_RESET_COMM_COUNTERS => None,
            PNIO_CTRL_DIAG_DEVICE_STATE | PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC => {
                // SAFETY: the union's PNIO_ADDR member is made of integers: every bit pattern
                // of the request's bytes is a valid value.
                let addr = unsafe { copy.u.Addr };
                match address::resolve(&s.layout, &addr) {
                    Some(r) => Some(r.device),
                    None => {
                        return s.fail(
                            WHAT,
                            PNIO_ERR_PRM_ADD,
                            format_args!("u.Addr: no device has {}", address::describe(&addr)),
                        );
                    }
                }
            }
            other => {
                return s.fail(
                    WHAT,
                    PNIO_ERR_PRM_INVALIDARG,
                    format_args!(
                        "DiagService {other} is not a service of PNIO_ctrl_diag_req: give \
                         1 (CONFIG_SUBMODULE_LIST) to 8 (DEVICE_DIAGNOSTIC)"
                    ),
                );
            }
        };
        {
            let mut jobs = lock(&s.jobs);
            if jobs.diags.len() >= MAX_DIAG_JOBS {
                return s.fail(
                    WHAT,
                    PNIO_ERR_NO_RESOURCE,
                    format_args!(
                        "{MAX_DIAG_JOBS} diagnosis requests wait for their confirmation \
                         already; wait for one first"
                    ),
                );
            }
            jobs.diags.push_back(DiagJob {
                request: DiagRequest(req),
                service: copy.DiagService,
                device,
            });
        }
        s.wake.raise();
        PNIO_OK
    }

    /// Ends the worker: after it returns no callback of this worker runs any more, and the
    /// subscription is gone. Safe when the server is gone. Called from inside one of this
    /// worker's callbacks (which IO-Base does not allow), it cannot wait for that callback:
    /// the thread then ends as soon as the callback returns.
    pub(crate) fn stop(mut self) {
        self.shutdown();
    }

    fn shutdown(&mut self) {
        self.shared.stop.store(true, Ordering::Release);
        self.shared.wake.raise();
        if let Some(t) = self.thread.take()
            && t.thread().id() != std::thread::current().id()
        {
            // A panic of the worker already ended it; nothing more to undo.
            let _ = t.join();
        }
    }
}

impl Drop for ServiceWorker {
    fn drop(&mut self) {
        self.shutdown();
    }
}

#[cfg(test)]
mod tests;
