// SPDX-License-Identifier: MIT OR Apache-2.0
//! The worker of one open controller interface (`PNIO_interface_open`): its subscription to
//! the server's services and the thread that calls its callbacks, one at a time, with no
//! lock held:
//!
//! * `PNIO_CBE_IFC_REC_READ_CONF` (`RecReadConf`) for each record read, with the caller's
//!   `ReqRef` and address. `Err` carries the PNIO status, and `AddValue1` the call's PNIO
//!   result as PN Driver puts it there (`PNIO_OK`; `PNIO_ERR_PRM_REC_INDEX` for an index
//!   the interface does not have, `PNIO_ERR_PRM_ADD` for a subslot, `PNIO_ERR_INTERNAL`
//!   otherwise). A read the server can no longer confirm fails with IO-Base's "no
//!   connection" status (0xC0, 0x80, 0xA3, 0) after [`JOB_TIMEOUT`], or at once when a new
//!   server started.
//! * `PNIO_CBE_IFC_ALARM_IND` (`AlarmInd`) for the interface's alarms, at the diagnostic
//!   address of the submodule that raised it; the next one comes when the callback has
//!   returned.
//! * `PNIO_CBE_IFC_SET_ADDR_CONF` (`SetAddrConf`) when a `PNIO_interface_set_ip_and_nos`
//!   ended, and when an engineering tool set the name or address by DCP (then `Mode` says
//!   what changed), with the station as it is now.
//! * `PNIO_CBE_REMA_READ_CONF` (`RemaReadConf`) after a change to be kept across a restart:
//!   the station's remanent name and IP suite as a small XML document
//!   ([`super::rema`]).

use super::callbacks::CallbackTable;
use super::errors::*;
use super::interface_types::{
    PNIO_CBE_PRM_REMA_READ_IND, PNIO_CBE_PRM_SET_ADDR_CONF, PNIO_SET_IP_MODE,
    PNIO_SET_IP_NOS_MODE_TYPE, PNIO_SET_NOS_MODE,
};
use super::services::build;
use super::sync::lock;
use super::types::*;
use super::wake::Wake;
use crate::ffi::set_last_error;
use procimg_client::{
    AddressProblem, AlarmReport, AttachError, ControlError, ControllerAddress, ControllerReport,
    Notification, RecordStatus, Refusal, ServiceOptions, Services,
};
use std::collections::{BTreeMap, HashMap};
use std::net::Ipv4Addr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// The open interfaces, by handle.
pub(crate) static INTERFACES: Mutex<BTreeMap<u32, Arc<InterfaceWorker>>> =
    Mutex::new(BTreeMap::new());

/// The handles of the interfaces open now.
pub(crate) fn open_handles() -> Vec<u32> {
    lock(&INTERFACES).keys().copied().collect()
}

/// How long a record read or an address change waits for its confirmation.
const JOB_TIMEOUT: Duration = Duration::from_secs(60);

/// Record reads one interface may have open (PN Driver's request blocks).
const MAX_READS: usize = procimg_control::services::MAX_RECORD_JOBS;

/// The longest wait of the thread between looks at its jobs and its stop flag.
const POLL: Duration = Duration::from_millis(100);

/// The diagnostic addresses of the interface and its port.
#[derive(Clone, Copy, Debug)]
pub(crate) struct OwnAddresses {
    /// The interface submodule's.
    pub interface: u32,
    /// The port's.
    pub port: u32,
}

/// A record read on its way.
struct ReadJob {
    req_ref: PNIO_REF,
    addr: PNIO_ADDR,
    index: u32,
    deadline: Instant,
}

/// A change of the name or address on its way.
struct AddressJob {
    mode: PNIO_SET_IP_NOS_MODE_TYPE,
    deadline: Instant,
}

#[derive(Default)]
struct Jobs {
    next_reference: u64,
    reads: HashMap<u64, ReadJob>,
    address: Option<AddressJob>,
}

/// The station as the worker last knew it: for the `Mode` of a DCP change.
#[derive(Clone)]
struct Station {
    name: String,
    ip: [Ipv4Addr; 3],
}

/// What the API calls and the thread share.
struct Shared {
    handle: u32,
    instance: String,
    addresses: OwnAddresses,
    callbacks: Arc<CallbackTable>,
    services: Mutex<Option<Services>>,
    jobs: Mutex<Jobs>,
    station: Mutex<Station>,
    stop: AtomicBool,
    wake: Wake,
}

impl Shared {
    fn fail(&self, what: &str, code: u32, detail: impl std::fmt::Display) -> u32 {
        set_last_error(format!(
            "{what} on interface handle {} (procimg instance \"{}\"): {detail} ({})",
            self.handle,
            self.instance,
            name(code)
        ));
        code
    }

    fn with_services<R>(&self, f: impl FnOnce(&mut Services) -> R) -> Option<R> {
        lock(&self.services).as_mut().map(f)
    }
}

/// One open interface.
pub(crate) struct InterfaceWorker {
    shared: Arc<Shared>,
    thread: Mutex<Option<JoinHandle<()>>>,
}

impl InterfaceWorker {
    /// Subscribes to the services of `instance`, learns the interface's addresses and
    /// starts the thread; a PNIO error code (the thread's last error says why) if the
    /// instance runs no controller.
    pub(crate) fn start(
        handle: u32,
        cp_index: u32,
        instance: String,
        callbacks: Arc<CallbackTable>,
    ) -> Result<InterfaceWorker, u32> {
        const F: &str = "PNIO_interface_open";
        let name = format!("PNIO interface {handle} (CP {cp_index})");
        let services = Services::open(&instance, ServiceOptions::new(&name)).map_err(|e| {
            let code = match e {
                AttachError::Refused {
                    refusal: Refusal::TooManyClients { .. },
                    ..
                } => PNIO_ERR_NO_RESOURCE,
                _ => PNIO_ERR_CREATE_INSTANCE,
            };
            fail(
                F,
                code,
                format_args!("no PROFINET interface of CP {cp_index} to open: {e}"),
            )
        })?;
        let report = services
            .control()
            .status()
            .map_err(|e| {
                fail(
                    F,
                    PNIO_ERR_CREATE_INSTANCE,
                    format_args!("procimg instance \"{instance}\" does not answer: {e}"),
                )
            })?
            .controller
            .ok_or_else(|| {
                fail(
                    F,
                    PNIO_ERR_CREATE_INSTANCE,
                    format_args!(
                        "procimg instance \"{instance}\" runs no IO controller (role = \
                         \"device\"?): the interface functions are the controller's"
                    ),
                )
            })?;
        let wake = Wake::new().map_err(|e| {
            fail(
                F,
                PNIO_ERR_NO_RESOURCE,
                format_args!("no eventfd for the interface's thread ({e})"),
            )
        })?;
        let shared = Arc::new(Shared {
            handle,
            addresses: OwnAddresses {
                interface: report.interface_address,
                port: report.port_address,
            },
            station: Mutex::new(station_of(&report)),
            instance,
            callbacks,
            services: Mutex::new(Some(services)),
            jobs: Mutex::new(Jobs::default()),
            stop: AtomicBool::new(false),
            wake,
        });
        let for_thread = shared.clone();
        let thread = std::thread::Builder::new()
            .name(format!("pnio-ifc-{handle}"))
            .spawn(move || run(&for_thread))
            .map_err(|e| {
                fail(
                    F,
                    PNIO_ERR_NO_RESOURCE,
                    format_args!("cannot start the interface's thread: {e}"),
                )
            })?;
        Ok(InterfaceWorker {
            shared,
            thread: Mutex::new(Some(thread)),
        })
    }

    pub(crate) fn handle(&self) -> u32 {
        self.shared.handle
    }

    pub(crate) fn instance(&self) -> &str {
        &self.shared.instance
    }

    pub(crate) fn addresses(&self) -> OwnAddresses {
        self.shared.addresses
    }

    pub(crate) fn callbacks(&self) -> &CallbackTable {
        &self.shared.callbacks
    }

    /// Stops the thread: no callback runs after this returns (from another thread than
    /// the worker's).
    pub(crate) fn stop(&self) {
        self.shared.callbacks.clear();
        self.shared.stop.store(true, Ordering::Release);
        self.shared.wake.raise();
        if let Some(t) = lock(&self.thread).take() {
            let _ = t.join();
        }
    }

    /// Sends a record read.
    pub(crate) fn read_record(
        &self,
        addr: PNIO_ADDR,
        subslot: u16,
        index: u16,
        req_ref: PNIO_REF,
        length: u32,
    ) -> u32 {
        const F: &str = "PNIO_interface_rec_read_req";
        let s = &self.shared;
        let mut jobs = lock(&s.jobs);
        if jobs.reads.len() >= MAX_READS {
            return s.fail(
                F,
                PNIO_ERR_NO_RESOURCE,
                format_args!("{MAX_READS} record reads are open: wait for a confirmation"),
            );
        }
        jobs.next_reference += 1;
        let reference = jobs.next_reference;
        let sent =
            s.with_services(|sv| sv.interface_record_read(subslot, index, length, reference));
        match sent {
            Some(Ok(())) => {
                jobs.reads.insert(
                    reference,
                    ReadJob {
                        req_ref,
                        addr,
                        index: u32::from(index),
                        deadline: Instant::now() + JOB_TIMEOUT,
                    },
                );
                drop(jobs);
                s.wake.raise();
                PNIO_OK
            }
            Some(Err(e)) => s.fail(F, control_code(&e), e),
            None => s.fail(F, PNIO_ERR_WRONG_HND, "the interface is closing"),
        }
    }

    /// Sends a change of the name or address.
    pub(crate) fn set_address(
        &self,
        mode: PNIO_SET_IP_NOS_MODE_TYPE,
        change: ControllerAddress,
    ) -> u32 {
        const F: &str = "PNIO_interface_set_ip_and_nos";
        let s = &self.shared;
        let mut jobs = lock(&s.jobs);
        if jobs.address.is_some() {
            return s.fail(
                F,
                PNIO_ERR_NOT_REENTERABLE,
                "the previous change is not confirmed yet: wait for PNIO_CBE_IFC_SET_ADDR_CONF",
            );
        }
        match s.with_services(|sv| sv.set_controller_address(&change)) {
            Some(Ok(())) => {
                jobs.address = Some(AddressJob {
                    mode,
                    deadline: Instant::now() + JOB_TIMEOUT,
                });
                PNIO_OK
            }
            Some(Err(e)) => s.fail(F, control_code(&e), e),
            None => s.fail(F, PNIO_ERR_WRONG_HND, "the interface is closing"),
        }
    }
}

impl Drop for InterfaceWorker {
    fn drop(&mut self) {
        self.stop();
    }
}

/// The IO-Base code of a control request that failed.
fn control_code(e: &ControlError) -> u32 {
    match e {
        ControlError::Refused(Refusal::TooManyJobs { .. } | Refusal::ServerBusy) => {
            PNIO_ERR_NO_RESOURCE
        }
        ControlError::Refused(Refusal::RecordTooLong { .. }) => PNIO_ERR_VALUE_LEN,
        _ => PNIO_ERR_NO_FW_COMMUNICATION,
    }
}

fn station_of(r: &ControllerReport) -> Station {
    let ip = |s: &str| s.parse().unwrap_or(Ipv4Addr::UNSPECIFIED);
    Station {
        name: r.station_name.clone(),
        ip: [ip(&r.ip), ip(&r.netmask), ip(&r.gateway)],
    }
}

/// The thread's loop, until stop; then unsubscribes.
fn run(shared: &Shared) {
    let notify_fd = shared.with_services(|s| s.notify_fd()).unwrap_or(-1);
    while !shared.stop.load(Ordering::Acquire) {
        expire(shared);
        let batch: Vec<Notification> = shared
            .with_services(|s| std::iter::from_fn(|| s.try_next()).take(64).collect())
            .unwrap_or_default();
        let idle = batch.is_empty();
        for n in batch {
            if shared.stop.load(Ordering::Acquire) {
                break;
            }
            handle(shared, n);
        }
        if idle {
            procimg_shm_layout::os::wait_any_readable(
                [notify_fd, shared.wake.fd()],
                POLL.as_nanos() as u64,
            );
            shared.wake.clear();
        }
    }
    drop(lock(&shared.services).take());
}

fn handle(shared: &Shared, n: Notification) {
    match n {
        Notification::InterfaceRecord {
            reference,
            status,
            data,
            ..
        } => {
            let job = lock(&shared.jobs).reads.remove(&reference);
            if let Some(job) = job {
                read_done(shared, &job, status, &data);
            }
        }
        Notification::InterfaceAlarm(a) => alarm(shared, &a),
        Notification::ControllerAddress {
            reply_to,
            name,
            ip,
            netmask,
            gateway,
            permanent,
            refused,
        } => {
            let ours = shared
                .with_services(|s| s.id())
                .is_some_and(|id| reply_to == Some(id));
            if reply_to.is_some() && !ours {
                return;
            }
            let now = Station {
                name,
                ip: [ip, netmask, gateway].map(|s| s.parse().unwrap_or(Ipv4Addr::UNSPECIFIED)),
            };
            let before = std::mem::replace(&mut *lock(&shared.station), now.clone());
            let (mode, err) = if ours {
                let mode = lock(&shared.jobs).address.take().map_or(0, |j| j.mode);
                let err = refused.map_or(PNIO_OK, |r| match r.problem {
                    AddressProblem::NotAllowed => PNIO_ERR_SET_IP_NOS_NOT_ALLOWED,
                    AddressProblem::Name => PNIO_ERR_PRM_NOS,
                    AddressProblem::Ip => PNIO_ERR_PRM_IP,
                    AddressProblem::Interface => PNIO_ERR_INTERNAL,
                });
                (mode, err)
            } else {
                let mut mode = 0;
                if before.name != now.name {
                    mode |= PNIO_SET_NOS_MODE;
                }
                if before.ip != now.ip {
                    mode |= PNIO_SET_IP_MODE;
                }
                (mode, PNIO_OK)
            };
            set_addr_conf(shared, mode, &now, err);
            if err == PNIO_OK && permanent {
                rema(shared, &now);
            }
        }
        // A new server forgets the jobs of its predecessor.
        Notification::ServerStarted { .. } => {
            let reads: Vec<ReadJob> = lock(&shared.jobs).reads.drain().map(|(_, j)| j).collect();
            for job in reads {
                read_done(shared, &job, NO_CONNECTION, &[]);
            }
            fail_address(shared);
        }
        _ => {}
    }
}

/// IO-Base's "no connection" status of a job the server can no longer confirm.
const NO_CONNECTION: RecordStatus = RecordStatus {
    error_code: 0xc0,
    error_decode: 0x80,
    error_code1: 0xa3,
    error_code2: 0,
    add_value1: 0,
    add_value2: 0,
};

/// Confirms the overdue jobs as failed.
fn expire(shared: &Shared) {
    let now = Instant::now();
    let late: Vec<ReadJob> = {
        let mut jobs = lock(&shared.jobs);
        let keys: Vec<u64> = jobs
            .reads
            .iter()
            .filter(|(_, j)| j.deadline <= now)
            .map(|(k, _)| *k)
            .collect();
        keys.iter().filter_map(|k| jobs.reads.remove(k)).collect()
    };
    for job in late {
        read_done(shared, &job, NO_CONNECTION, &[]);
    }
    let address_late = lock(&shared.jobs)
        .address
        .as_ref()
        .is_some_and(|j| j.deadline <= now);
    if address_late {
        fail_address(shared);
    }
}

/// Confirms a pending change of the name or address as failed.
fn fail_address(shared: &Shared) {
    let job = lock(&shared.jobs).address.take();
    if let Some(job) = job {
        let station = lock(&shared.station).clone();
        set_addr_conf(shared, job.mode, &station, PNIO_ERR_NO_FW_COMMUNICATION);
    }
}

/// `PNIO_CBE_IFC_REC_READ_CONF` for `job`.
fn read_done(shared: &Shared, job: &ReadJob, status: RecordStatus, data: &[u8]) {
    let cbf = shared.callbacks.get(PNIO_CBE_IFC_REC_READ_CONF);
    if cbf.is_none() {
        return;
    }
    let result = match (status.error_code, status.error_code1) {
        (0, _) => PNIO_OK,
        (0xde, 0xb0) => PNIO_ERR_PRM_REC_INDEX,
        (0xde, 0xb2) => PNIO_ERR_PRM_ADD,
        (0xc0, _) => PNIO_ERR_NO_FW_COMMUNICATION,
        _ => PNIO_ERR_INTERNAL,
    };
    let mut addr = job.addr;
    let mut prm = PNIO_CBE_PRM::new(PNIO_CBE_IFC_REC_READ_CONF, shared.handle);
    prm.u.RecReadConf = PNIO_CBE_PRM_REC_READ_CONF {
        pAddr: &mut addr,
        RecordIndex: job.index,
        ReqRef: job.req_ref,
        Err: PNIO_ERR_STAT {
            ErrCode: status.error_code,
            ErrDecode: status.error_decode,
            ErrCode1: status.error_code1,
            ErrCode2: status.error_code2,
            // PN Driver's place for the call's result, which its samples test.
            AddValue1: result as u16,
            AddValue2: status.add_value2,
        },
        Length: data.len() as u32,
        pBuffer: if data.is_empty() {
            EMPTY.as_ptr()
        } else {
            data.as_ptr()
        },
    };
    CallbackTable::invoke(cbf, &mut prm);
}

/// Where an empty record points: a valid, non-NULL address.
static EMPTY: [u8; 4] = [0; 4];

/// `PNIO_CBE_IFC_ALARM_IND` for alarm `a`.
fn alarm(shared: &Shared, a: &AlarmReport) {
    let cbf = shared.callbacks.get(PNIO_CBE_IFC_ALARM_IND);
    if cbf.is_none() {
        return;
    }
    let data = build::interface_alarm(a);
    let OwnAddresses { interface, port } = shared.addresses;
    let at = if a.subslot & 0x00ff == 0 {
        interface
    } else {
        port
    };
    let mut addr = PNIO_ADDR::logical(PNIO_IO_IN, at);
    let mut prm = PNIO_CBE_PRM::new(PNIO_CBE_IFC_ALARM_IND, shared.handle);
    prm.u.AlarmInd = PNIO_CBE_PRM_ALARM_IND {
        pAddr: &mut addr,
        IndRef: a.id as PNIO_REF,
        pAlarmData: &*data,
    };
    CallbackTable::invoke(cbf, &mut prm);
}

/// `PNIO_CBE_IFC_SET_ADDR_CONF` with the station as it is now.
fn set_addr_conf(shared: &Shared, mode: PNIO_SET_IP_NOS_MODE_TYPE, now: &Station, err: u32) {
    let cbf = shared.callbacks.get(PNIO_CBE_IFC_SET_ADDR_CONF);
    if cbf.is_none() {
        return;
    }
    let mut name = now.name.clone().into_bytes();
    let [ip, mask, gateway] = now.ip.map(|a| a.octets());
    let mut prm = PNIO_CBE_PRM::new(PNIO_CBE_IFC_SET_ADDR_CONF, shared.handle);
    prm.u.SetAddrConf = PNIO_CBE_PRM_SET_ADDR_CONF {
        Mode: mode,
        pStationName: name.as_mut_ptr().cast(),
        StationNameLen: name.len() as u16,
        LocalIPAddress: ip,
        LocalSubnetMask: mask,
        DefaultRouterAddr: gateway,
        Options: 0,
        Err: err,
    };
    CallbackTable::invoke(cbf, &mut prm);
}

/// `PNIO_CBE_REMA_READ_CONF` with the station's remanent data.
fn rema(shared: &Shared, now: &Station) {
    let cbf = shared.callbacks.get(PNIO_CBE_REMA_READ_CONF);
    if cbf.is_none() {
        return;
    }
    let mut text = super::rema::RemanentData {
        name: now.name.clone(),
        ip_suite: now.ip,
    }
    .to_xml()
    .into_bytes();
    let mut prm = PNIO_CBE_PRM::new(PNIO_CBE_REMA_READ_CONF, shared.handle);
    prm.u.RemaReadConf = PNIO_CBE_PRM_REMA_READ_IND {
        RemaXMLBuffer: text.as_mut_ptr(),
        RemaXMLBufferLength: text.len() as u32,
        Err: PNIO_OK,
    };
    CallbackTable::invoke(cbf, &mut prm);
}
