// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller's client services on the control side: record jobs, device activation,
//! alarm delivery with acknowledgement, device events and diagnosis. Requests come from
//! clients over the control service and go to the acyclic thread as [`ControllerCommand`]s;
//! what the controller reports comes back as [`DeviceEvent`]s and goes out as
//! [`Notification`]s.
//!
//! Alarm acknowledgement follows IO-Base: the device's alarm is acknowledged when the
//! clients that take part have handled it (IO-Base: when the alarm callback returns), at
//! once when none takes part, and after [`ALARM_ACK_TIMEOUT_MS`] at the latest, so that one
//! hung client cannot hold back a device's alarms for good.

use super::ControllerCommand;
use super::states::{DeviceStates, reported};
use crate::acyclic::DatagramCounters;
use crate::image::Tables;
use crate::io::pnio::channel::Channel;
use crate::roles::subscribers::{Subscriber, Subscribers};
use crate::roles::{Answers, RoleServices};
use crate::shm::Notices;
use procimg_control::services::{
    ALARM_ACK_TIMEOUT_MS, AddressProblem, AddressRefusal, AlarmReport, DeviceDiagnosis,
    DiagnosisReport, FailureCause, MAX_RECORD_JOBS, MAX_RECORD_LEN, Notification,
    RecordConfirmation, RecordStatus, RecordTarget, SubmoduleDiff, TailoringRefusal,
};
use procimg_control::{
    self as control, ControllerRequest, DeviceReport, NetworkReport, PortRef, Refusal, Response,
    SubscriberReport, Tailoring,
};
use procimg_profinet::controller::{
    self, AddressError, AlarmTicket, DeviceEvent, DeviceState, PortEnd, Reconfiguration,
    RecordFailure, RecordRequest, RecordResult, StationAddress, TailorError,
};
use procimg_profinet::wire::PnioStatus;
use procimg_profinet::wire::alarm::{AlarmNotification, Priority};
use std::collections::{HashMap, HashSet, VecDeque};
use std::sync::Arc;
use std::sync::mpsc::{Receiver, Sender};
use std::time::{Duration, Instant};

/// What the control side holds of the running controller.
pub struct ControllerLink {
    /// Commands for the controller.
    pub commands: Sender<ControllerCommand>,
    /// What the controller reports.
    pub events: Receiver<DeviceEvent>,
    /// The device states the acyclic thread publishes.
    pub states: Arc<DeviceStates>,
    /// The interface counters of the cycle thread.
    pub channel: Arc<Channel>,
    /// The datagrams the controller dropped.
    pub datagrams: Arc<DatagramCounters>,
}

/// An alarm whose AlarmAck waits for subscribers.
struct PendingAlarm {
    id: u64,
    ticket: AlarmTicket,
    waiting: Vec<u64>,
    deadline: Instant,
}

/// A record job on its way.
struct Job {
    reply_to: u64,
    reference: u64,
}

/// What the diagnosis reports of a device beyond its state.
#[derive(Default)]
struct DeviceRecord {
    /// Offline until the controller reports otherwise.
    state: control::DeviceState,
    inactive: bool,
    last_error: String,
    cause: FailureCause,
    /// The PNIO status of the last failure, if it had one.
    pnio_status: Option<[u8; 4]>,
    failures: u64,
    module_diff: Vec<SubmoduleDiff>,
}

/// A record request as a client gave it.
struct RecordJob {
    /// Who gets the confirmation.
    pub reply_to: u64,
    /// Echoed in the confirmation.
    pub reference: u64,
    /// The record.
    pub target: RecordTarget,
    /// Read: the most bytes wanted.
    pub max_len: u32,
    /// Write: the data.
    pub write: Option<Vec<u8>>,
}

/// The controller's client services.
pub struct ControllerServices {
    link: Option<ControllerLink>,
    names: Vec<String>,
    devices: Vec<DeviceRecord>,
    subscribers: Subscribers,
    alarms: Vec<PendingAlarm>,
    next_alarm: u64,
    jobs: HashMap<u64, Job>,
    next_job: u64,
    activations: Vec<VecDeque<u64>>,
    /// Who asked for each reconfiguration under way, in order.
    reconfigurations: VecDeque<u64>,
    /// The controller's own station on its interface, when it runs one.
    interface: Option<super::interface::ControllerInterface>,
    /// Reads of the interface's records on their way, by job id.
    interface_jobs: HashMap<u64, InterfaceJob>,
    /// Who asked for each change of the station's name or address, by job id.
    address_jobs: HashMap<u64, u64>,
    /// PROFIenergy commands on their way.
    pe: super::pe_jobs::PeJobs,
}

/// A read of a record of the controller's own interface on its way.
struct InterfaceJob {
    reply_to: u64,
    reference: u64,
    max_len: u32,
}

impl ControllerServices {
    /// The services for the devices `names`, connected to the running controller by `link`
    /// (without one, every request to the controller is refused as busy and every device
    /// reported offline).
    pub fn new(names: Vec<String>, link: Option<ControllerLink>) -> ControllerServices {
        let devices = (0..names.len())
            .map(|d| {
                // An optional device starts deactivated, waiting for the IO system's
                // tailoring.
                let state = link
                    .as_ref()
                    .map_or(control::DeviceState::Offline, |l| l.states.reported(d));
                DeviceRecord {
                    state,
                    inactive: state == control::DeviceState::Deactivated,
                    ..DeviceRecord::default()
                }
            })
            .collect();
        ControllerServices {
            link,
            activations: names.iter().map(|_| VecDeque::new()).collect(),
            reconfigurations: VecDeque::new(),
            names,
            devices,
            subscribers: Subscribers::default(),
            alarms: Vec::new(),
            next_alarm: 1,
            jobs: HashMap::new(),
            next_job: 1,
            interface: None,
            interface_jobs: HashMap::new(),
            address_jobs: HashMap::new(),
            pe: Default::default(),
        }
    }

    /// Reports `interface`, the controller's own station, from now on.
    pub fn with_interface(mut self, interface: super::interface::ControllerInterface) -> Self {
        self.interface = Some(interface);
        self
    }

    /// The services for the devices of `tables` with no controller behind them: for a
    /// control side that serves the image alone (benches, tests).
    pub fn unlinked(tables: &Tables) -> ControllerServices {
        let names = (0..tables.devices.len())
            .map(|d| tables.device_name(d).to_string())
            .collect();
        ControllerServices::new(names, None)
    }

    fn device(&self, device: u32) -> Result<usize, Refusal> {
        let d = device as usize;
        if d < self.names.len() {
            Ok(d)
        } else {
            Err(Refusal::NoSuchDevice { device })
        }
    }

    fn command(&self, c: ControllerCommand) -> Result<(), Refusal> {
        match &self.link {
            Some(l) => l.commands.send(c).map_err(|_| Refusal::ServerBusy),
            None => Err(Refusal::ServerBusy),
        }
    }

    /// Announces a subscriber (again: its settings are replaced); alarms stop waiting for
    /// one that no longer acknowledges.
    fn subscribe(&mut self, id: u64, subscriber: Subscriber) {
        let acknowledges = subscriber.acknowledges;
        self.subscribers.subscribe(id, subscriber);
        if !acknowledges {
            self.release_waits(id);
        }
    }

    /// Withdraws a subscriber.
    fn unsubscribe(&mut self, subscriber: u64) -> Result<(), Refusal> {
        self.subscribers.unsubscribe(subscriber)?;
        self.release_waits(subscriber);
        Ok(())
    }

    /// Forgets subscribers whose process is gone (`alive`: the live iceoryx2 node ids).
    fn reap(&mut self, alive: &HashSet<String>) -> Vec<String> {
        self.subscribers
            .reap(alive)
            .into_iter()
            .map(|(id, s)| {
                self.release_waits(id);
                s.to_string()
            })
            .collect()
    }

    /// Starts a record job.
    fn record(&mut self, job: RecordJob) -> Result<(), Refusal> {
        let t = job.target;
        let device = self.device(t.device)?;
        let len = job
            .write
            .as_ref()
            .map_or(job.max_len, |d| u32::try_from(d.len()).unwrap_or(u32::MAX));
        if len > MAX_RECORD_LEN {
            return Err(Refusal::RecordTooLong {
                len,
                max: MAX_RECORD_LEN,
            });
        }
        let open = self
            .jobs
            .values()
            .filter(|j| j.reply_to == job.reply_to)
            .count();
        if open >= MAX_RECORD_JOBS {
            return Err(Refusal::TooManyJobs {
                max: MAX_RECORD_JOBS as u32,
            });
        }
        let id = self.next_job;
        self.command(ControllerCommand::Record(RecordRequest {
            reference: id,
            device,
            api: t.api,
            slot: t.slot,
            subslot: t.subslot,
            index: t.index,
            max_len: job.max_len,
            write: job.write,
        }))?;
        self.next_job += 1;
        self.jobs.insert(
            id,
            Job {
                reply_to: job.reply_to,
                reference: job.reference,
            },
        );
        Ok(())
    }

    /// Activates or deactivates a device; `online` says whether the controller is (or is
    /// becoming) CLEAR or OPERATE.
    fn activate(
        &mut self,
        reply_to: u64,
        device: u32,
        active: bool,
        online: bool,
    ) -> Result<(), Refusal> {
        let d = self.device(device)?;
        if !online {
            return Err(Refusal::Offline);
        }
        self.command(ControllerCommand::Activate { device: d, active })?;
        if let Some(q) = self.activations.get_mut(d) {
            q.push_back(reply_to);
        }
        Ok(())
    }

    /// Reconfigures the IO system: deactivates all, or tailors it.
    fn reconfigure(&mut self, reply_to: u64, tailoring: Option<Tailoring>) -> Result<(), Refusal> {
        let how = match tailoring {
            None => Reconfiguration::Deactivate,
            Some(t) => Reconfiguration::Tailor {
                optional_present: t.devices.iter().map(|&d| d as usize).collect(),
                links: t
                    .links
                    .iter()
                    .map(|[a, b]| (port_end(a), port_end(b)))
                    .collect(),
            },
        };
        self.command(ControllerCommand::Reconfigure(how))?;
        self.reconfigurations.push_back(reply_to);
        Ok(())
    }

    /// Starts a read of a record of the controller's own interface.
    fn interface_record(
        &mut self,
        reply_to: u64,
        reference: u64,
        subslot: u16,
        index: u16,
        max_len: u32,
    ) -> Result<(), Refusal> {
        if max_len > MAX_RECORD_LEN {
            return Err(Refusal::RecordTooLong {
                len: max_len,
                max: MAX_RECORD_LEN,
            });
        }
        let open = self
            .interface_jobs
            .values()
            .filter(|j| j.reply_to == reply_to)
            .count();
        if open >= MAX_RECORD_JOBS {
            return Err(Refusal::TooManyJobs {
                max: MAX_RECORD_JOBS as u32,
            });
        }
        let id = self.next_job;
        self.command(ControllerCommand::InterfaceRecord {
            reference: id,
            subslot,
            index,
        })?;
        self.next_job += 1;
        self.interface_jobs.insert(
            id,
            InterfaceJob {
                reply_to,
                reference,
                max_len,
            },
        );
        Ok(())
    }

    /// Starts a PROFIenergy command.
    fn pe_command(
        &mut self,
        reply_to: u64,
        reference: u64,
        target: RecordTarget,
        command: procimg_control::pe::PeCommand,
    ) -> Result<(), Refusal> {
        let device = self.device(target.device)?;
        if self.link.is_none() {
            return Err(Refusal::ServerBusy);
        }
        if self.pe.open_of(reply_to) >= MAX_RECORD_JOBS {
            return Err(Refusal::TooManyJobs {
                max: MAX_RECORD_JOBS as u32,
            });
        }
        let id = self.next_job;
        self.next_job += 1;
        let write = self.pe.start(
            id,
            reply_to,
            reference,
            target,
            device,
            command,
            Instant::now(),
        );
        self.command(ControllerCommand::Record(write))
            .inspect_err(|_| self.pe.forget(id))
    }

    /// Carries out what the PROFIenergy commands asked for: their record jobs, and the
    /// confirmations of those that ended.
    fn apply_pe(&mut self, steps: super::pe_jobs::PeSteps, notices: &mut Notices) {
        for r in steps.records {
            let _ = self.command(ControllerCommand::Record(r));
        }
        for d in steps.done {
            let (answer, status, message) = match d.result {
                Ok(a) => (Some(a), RecordStatus::OK, String::new()),
                Err((status, message)) => (None, status, message),
            };
            notices.publish(&Notification::PeConfirmation {
                reply_to: d.reply_to,
                reference: d.reference,
                target: d.target,
                command: d.command,
                answer,
                status,
                message,
            });
        }
    }

    /// Starts a change of the station's name or address.
    fn set_address(&mut self, reply_to: u64, change: StationAddress) -> Result<(), Refusal> {
        let id = self.next_job;
        self.command(ControllerCommand::StationAddress {
            reference: id,
            change,
        })?;
        self.next_job += 1;
        self.address_jobs.insert(id, reply_to);
        Ok(())
    }

    /// A subscriber acknowledges an alarm.
    fn acknowledge(&mut self, subscriber: u64, alarm: u64) -> Result<(), Refusal> {
        if self.subscribers.get(subscriber).is_none() {
            return Err(Refusal::UnknownSubscriber);
        }
        let Some(i) = self
            .alarms
            .iter()
            .position(|a| a.id == alarm && a.waiting.contains(&subscriber))
        else {
            return Err(Refusal::UnknownAlarm { alarm });
        };
        self.alarms[i].waiting.retain(|&s| s != subscriber);
        if self.alarms[i].waiting.is_empty() {
            let a = self.alarms.swap_remove(i);
            let _ = self.command(ControllerCommand::AcknowledgeAlarm(a.ticket));
        }
        Ok(())
    }

    /// Stops waiting for `subscriber`'s acknowledgements.
    fn release_waits(&mut self, subscriber: u64) {
        for a in &mut self.alarms {
            a.waiting.retain(|&s| s != subscriber);
        }
        self.acknowledge_settled();
    }

    /// Acknowledges the alarms nobody waits for any more.
    fn acknowledge_settled(&mut self) {
        let mut i = 0;
        while i < self.alarms.len() {
            if self.alarms[i].waiting.is_empty() {
                let a = self.alarms.swap_remove(i);
                let _ = self.command(ControllerCommand::AcknowledgeAlarm(a.ticket));
            } else {
                i += 1;
            }
        }
    }

    /// Handles what the controller reported and the acknowledgement timeouts; `wait` is the
    /// longest time to wait for a first report.
    fn poll_events(&mut self, wait: Duration, notices: &mut Notices) {
        let mut events = Vec::new();
        match &self.link {
            Some(l) => {
                if let Ok(e) = l.events.recv_timeout(wait) {
                    events.push(e);
                    events.extend(l.events.try_iter());
                }
            }
            None => std::thread::sleep(wait),
        }
        for e in events {
            self.on_event(e, notices);
        }
        let mut steps = super::pe_jobs::PeSteps::default();
        let next_job = &mut self.next_job;
        self.pe.poll(
            Instant::now(),
            || {
                *next_job += 1;
                *next_job - 1
            },
            &mut steps,
        );
        self.apply_pe(steps, notices);
        let now = Instant::now();
        let mut late = Vec::new();
        for a in &mut self.alarms {
            if now >= a.deadline {
                late.append(&mut a.waiting);
            }
        }
        if !late.is_empty() {
            let names: Vec<String> = late
                .iter()
                .filter_map(|&s| self.subscribers.get(s))
                .map(ToString::to_string)
                .collect();
            tracing::warn!(
                "alarm not acknowledged within {ALARM_ACK_TIMEOUT_MS} ms by {}; \
                 acknowledged to the device without them",
                names.join(", ")
            );
            self.acknowledge_settled();
        }
    }

    fn on_event(&mut self, e: DeviceEvent, notices: &mut Notices) {
        let name = |d: usize| self.names.get(d).cloned().unwrap_or_default();
        match e {
            DeviceEvent::State { device, state } => {
                if let Some(r) = self.devices.get_mut(device) {
                    r.state = reported(state);
                    if state == DeviceState::Running {
                        r.last_error.clear();
                        r.cause = FailureCause::None;
                        r.pnio_status = None;
                    }
                }
                notices.publish(&Notification::DeviceState {
                    device: device as u32,
                    name: name(device),
                    state: reported(state),
                });
            }
            DeviceEvent::Failure {
                device,
                cause,
                reason,
                status,
                ..
            } => {
                if let Some(r) = self.devices.get_mut(device) {
                    r.failures += 1;
                    r.last_error = reason.clone();
                    r.cause = reported_cause(cause);
                    r.pnio_status = status.map(|s| s.to_bytes());
                }
                notices.publish(&Notification::DeviceFailure {
                    device: device as u32,
                    name: name(device),
                    reason,
                });
            }
            DeviceEvent::Return { device } => notices.publish(&Notification::DeviceReturn {
                device: device as u32,
                name: name(device),
            }),
            DeviceEvent::Problem {
                device,
                cause,
                reason,
                status,
            } => {
                if let Some(r) = self.devices.get_mut(device) {
                    r.last_error = reason;
                    r.cause = reported_cause(cause);
                    r.pnio_status = status.map(|s| s.to_bytes());
                }
            }
            DeviceEvent::ModuleDiff { device, diff } => {
                let submodules: Vec<SubmoduleDiff> = diff
                    .submodules()
                    .map(|(api, slot, subslot, st)| SubmoduleDiff {
                        api,
                        slot,
                        subslot,
                        state: st.0,
                        text: st.to_string(),
                    })
                    .collect();
                if let Some(r) = self.devices.get_mut(device) {
                    r.module_diff = submodules.clone();
                }
                notices.publish(&Notification::ModuleDiff {
                    device: device as u32,
                    name: name(device),
                    submodules,
                });
            }
            DeviceEvent::Alarm {
                device,
                notification,
                ticket,
            } => self.on_alarm(device, &notification, ticket, notices),
            DeviceEvent::Record(r) if self.pe.owns(r.request.reference) => {
                let mut steps = super::pe_jobs::PeSteps::default();
                self.pe.on_record(r, Instant::now(), &mut steps);
                self.apply_pe(steps, notices);
            }
            DeviceEvent::Record(r) => self.on_record(r, notices),
            DeviceEvent::Signal => notices.publish(&Notification::ControllerSignal),
            DeviceEvent::InterfaceAlarm(n) => {
                let id = self.next_alarm;
                self.next_alarm += 1;
                let station = self
                    .interface
                    .as_ref()
                    .map(|i| i.report().station_name)
                    .unwrap_or_default();
                let report = alarm_report(id, 0, station, &n);
                notices.publish(&Notification::InterfaceAlarm(report));
            }
            DeviceEvent::InterfaceRecord {
                reference,
                subslot,
                index,
                result,
            } => {
                let Some(job) = self.interface_jobs.remove(&reference) else {
                    return;
                };
                let (status, data, message) = match result {
                    Ok(mut data) => {
                        let more = data.len() > job.max_len as usize;
                        data.truncate(job.max_len as usize);
                        let status = RecordStatus {
                            add_value1: u16::from(more),
                            ..RecordStatus::OK
                        };
                        (status, data, String::new())
                    }
                    Err(code) => (
                        RecordStatus {
                            error_code: 0xde,
                            error_decode: 0x80,
                            error_code1: code.into(),
                            ..RecordStatus::default()
                        },
                        Vec::new(),
                        format!(
                            "record {index:#06x} of the controller's interface subslot \
                             {subslot:#06x}: {code}"
                        ),
                    ),
                };
                notices.publish(&Notification::InterfaceRecord {
                    reply_to: job.reply_to,
                    reference: job.reference,
                    subslot,
                    index,
                    status,
                    data,
                    message,
                });
            }
            DeviceEvent::StationAddress {
                change,
                reference,
                result,
            } => {
                let reply_to = match reference {
                    Some(r) => match self.address_jobs.remove(&r) {
                        Some(reply_to) => Some(reply_to),
                        None => return,
                    },
                    None => None,
                };
                if result.is_ok()
                    && let Some(i) = self.interface.as_mut()
                {
                    i.take_address(&change);
                }
                let Some(now) = self.interface.as_ref().map(|i| i.report()) else {
                    return;
                };
                notices.publish(&Notification::ControllerAddress {
                    reply_to,
                    name: now.station_name,
                    ip: now.ip,
                    netmask: now.netmask,
                    gateway: now.gateway,
                    permanent: change.permanent,
                    refused: result.err().map(|e| AddressRefusal {
                        problem: match e {
                            AddressError::NotAllowed { .. } => AddressProblem::NotAllowed,
                            AddressError::Name(_) | AddressError::NoName => AddressProblem::Name,
                            AddressError::Ip { .. } => AddressProblem::Ip,
                            AddressError::NotCarriedOut(_) => AddressProblem::Interface,
                        },
                        message: e.to_string(),
                    }),
                });
            }
            DeviceEvent::Reconfigured { result } => {
                let Some(reply_to) = self.reconfigurations.pop_front() else {
                    return;
                };
                let (active, refused) = match result {
                    Ok(active) => (active, None),
                    Err(e) => (true, Some(tailoring_refusal(&e))),
                };
                notices.publish(&Notification::Reconfigured {
                    reply_to,
                    active,
                    refused,
                });
            }
            DeviceEvent::Activation { device, active } => {
                if let Some(r) = self.devices.get_mut(device) {
                    r.inactive = !active;
                }
                if let Some(reply_to) = self.activations.get_mut(device).and_then(|q| q.pop_front())
                {
                    notices.publish(&Notification::Activation {
                        reply_to,
                        device: device as u32,
                        active,
                        ok: true,
                    });
                }
            }
        }
    }

    fn on_alarm(
        &mut self,
        device: usize,
        n: &AlarmNotification,
        ticket: AlarmTicket,
        notices: &mut Notices,
    ) {
        let id = self.next_alarm;
        self.next_alarm += 1;
        let name = self.names.get(device).cloned().unwrap_or_default();
        let report = alarm_report(id, device as u32, name, n);
        let waiting = self.subscribers.acknowledging();
        notices.publish(&Notification::Alarm(report));
        if waiting.is_empty() {
            let _ = self.command(ControllerCommand::AcknowledgeAlarm(ticket));
        } else {
            self.alarms.push(PendingAlarm {
                id,
                ticket,
                waiting,
                deadline: Instant::now() + Duration::from_millis(ALARM_ACK_TIMEOUT_MS),
            });
        }
    }

    fn on_record(&mut self, r: RecordResult, notices: &mut Notices) {
        let Some(job) = self.jobs.remove(&r.request.reference) else {
            return;
        };
        let q = &r.request;
        let (status, data, message) = match r.result {
            Ok(d) => (
                RecordStatus {
                    add_value1: d.add_value1,
                    add_value2: d.add_value2,
                    ..RecordStatus::OK
                },
                d.data,
                String::new(),
            ),
            Err(f) => (record_status(&f), Vec::new(), f.reason),
        };
        notices.publish(&Notification::Record {
            reply_to: job.reply_to,
            confirmation: RecordConfirmation {
                reference: job.reference,
                target: RecordTarget {
                    device: q.device as u32,
                    api: q.api,
                    slot: q.slot,
                    subslot: q.subslot,
                    index: q.index,
                },
                write: q.write.is_some(),
                status,
                data,
                message,
            },
        });
    }

    /// The devices' state.
    fn diagnosis(&self) -> DiagnosisReport {
        DiagnosisReport {
            devices: self
                .devices
                .iter()
                .enumerate()
                .map(|(d, r)| DeviceDiagnosis {
                    device: d as u32,
                    name: self.names[d].clone(),
                    state: r.state,
                    active: !r.inactive,
                    last_error: r.last_error.clone(),
                    cause: r.cause,
                    failures: r.failures,
                    module_diff: r.module_diff.clone(),
                    pnio_status: r.pnio_status,
                })
                .collect(),
        }
    }

    /// The announced subscribers, with the alarms waiting for each.
    fn subscribers(&self) -> Vec<SubscriberReport> {
        self.subscribers.report(|id| {
            self.alarms
                .iter()
                .filter(|a| a.waiting.contains(&id))
                .count() as u32
        })
    }
}

impl Answers<ControllerRequest> for ControllerServices {
    fn handle(
        &mut self,
        request: ControllerRequest,
        online: bool,
        _notices: &mut Notices,
    ) -> Response {
        let result = match request {
            ControllerRequest::RecordRead {
                reply_to,
                reference,
                target,
                max_len,
            } => {
                return accepted(self.record(RecordJob {
                    reply_to,
                    reference,
                    target,
                    max_len,
                    write: None,
                }));
            }
            ControllerRequest::RecordWrite {
                reply_to,
                reference,
                target,
                data,
            } => {
                return accepted(self.record(RecordJob {
                    reply_to,
                    reference,
                    target,
                    max_len: 0,
                    write: Some(data),
                }));
            }
            ControllerRequest::ActivateDevice {
                reply_to,
                device,
                active,
            } => self.activate(reply_to, device, active, online),
            ControllerRequest::ReconfigureIoSystem {
                reply_to,
                tailoring,
            } => self.reconfigure(reply_to, tailoring),
            ControllerRequest::AcknowledgeAlarm { subscriber, alarm } => {
                self.acknowledge(subscriber, alarm)
            }
            ControllerRequest::Diagnosis => return Response::Diagnosis(Box::new(self.diagnosis())),
            ControllerRequest::InterfaceRecordRead {
                reply_to,
                reference,
                subslot,
                index,
                max_len,
            } => {
                return accepted(
                    self.interface_record(reply_to, reference, subslot, index, max_len),
                );
            }
            ControllerRequest::PeCommand {
                reply_to,
                reference,
                target,
                command,
            } => return accepted(self.pe_command(reply_to, reference, target, command)),
            ControllerRequest::SetControllerAddress {
                reply_to,
                name,
                ip_suite,
                permanent,
            } => {
                return accepted(self.set_address(
                    reply_to,
                    StationAddress {
                        name,
                        ip_suite,
                        permanent,
                    },
                ));
            }
            ControllerRequest::ResetCommCounters => {
                if let Some(i) = self.interface.as_mut() {
                    i.reset();
                }
                Ok(())
            }
        };
        match result {
            Ok(()) => Response::Done,
            Err(r) => Response::Refused(r),
        }
    }
}

impl RoleServices for ControllerServices {
    fn name(&self) -> &'static str {
        "controller"
    }

    fn controller_services(&mut self) -> Option<&mut dyn Answers<ControllerRequest>> {
        Some(self)
    }

    fn subscribe(&mut self, id: u64, subscriber: Subscriber) {
        ControllerServices::subscribe(self, id, subscriber);
    }

    fn unsubscribe(&mut self, id: u64) -> Result<(), Refusal> {
        ControllerServices::unsubscribe(self, id)
    }

    fn poll(&mut self, wait: Duration, notices: &mut Notices) {
        self.poll_events(wait, notices);
    }

    fn reap(&mut self, alive: &HashSet<String>) -> Vec<String> {
        ControllerServices::reap(self, alive)
    }

    fn devices(&self) -> Vec<DeviceReport> {
        (0..self.names.len())
            .map(|d| DeviceReport {
                name: self.names[d].clone(),
                state: self
                    .link
                    .as_ref()
                    .map_or(control::DeviceState::Offline, |l| l.states.reported(d)),
            })
            .collect()
    }

    fn controller(&self) -> Option<procimg_control::ControllerReport> {
        self.interface
            .as_ref()
            .map(super::interface::ControllerInterface::report)
    }

    fn network(&self) -> NetworkReport {
        self.link.as_ref().map_or_else(NetworkReport::default, |l| {
            crate::roles::network_report(&l.channel, &l.datagrams)
        })
    }

    fn subscribers(&self) -> Vec<SubscriberReport> {
        ControllerServices::subscribers(self)
    }

    fn released(&self) -> bool {
        self.link.as_ref().is_none_or(|l| l.states.all_released())
    }
}

/// What subscribers are told of alarm `n` of `device` (named `name`), as alarm `id`.
fn alarm_report(id: u64, device: u32, name: String, n: &AlarmNotification) -> AlarmReport {
    let mut block = vec![0u8; n.buffer_len()];
    // The fixed part of the block: header (6), AlarmType, API, slot, subslot, module and
    // submodule ident, AlarmSpecifier; what follows is the user data.
    const FIXED: usize = 6 + 2 + 4 + 2 + 2 + 4 + 4 + 2;
    let payload = match n.emit(&mut block) {
        Ok(()) => block.get(FIXED..).unwrap_or_default().to_vec(),
        Err(_) => Vec::new(),
    };
    AlarmReport {
        id,
        device,
        text: alarm_text(&name, n),
        device_name: name,
        high_priority: n.priority == Priority::High,
        alarm_type: n.alarm_type.into(),
        api: n.api,
        slot: n.slot,
        subslot: n.subslot,
        module_ident: n.module_ident,
        submodule_ident: n.submodule_ident,
        specifier: n.specifier.to_u16(),
        payload,
    }
}

fn accepted(r: Result<(), Refusal>) -> Response {
    match r {
        Ok(()) => Response::Accepted,
        Err(r) => Response::Refused(r),
    }
}

fn record_status(f: &RecordFailure) -> RecordStatus {
    let PnioStatus {
        error_code,
        error_decode,
        error_code1,
        error_code2,
    } = f.status;
    RecordStatus {
        error_code,
        error_decode,
        error_code1,
        error_code2,
        add_value1: f.add_value1,
        add_value2: f.add_value2,
    }
}

fn alarm_text(device: &str, n: &AlarmNotification) -> String {
    let mut t = format!(
        "{} alarm from {device:?}, API {} slot {} subslot {:#06x} (sequence {})",
        n.alarm_type, n.api, n.slot, n.subslot, n.specifier.sequence_number
    );
    if let Some(d) = n.diagnosis() {
        t.push_str(&format!(": {d:?}"));
    }
    t
}

/// The protocol's kind of failure as clients are told it (the control protocol's enum, which
/// also has a value for kinds a newer server may report).
fn reported_cause(cause: controller::FailureCause) -> FailureCause {
    use controller::FailureCause as Protocol;
    match cause {
        Protocol::None => FailureCause::None,
        Protocol::NotFound => FailureCause::NotFound,
        Protocol::IpSetFailed => FailureCause::IpSetFailed,
        Protocol::RpcTimeout => FailureCause::RpcTimeout,
        Protocol::RpcError => FailureCause::RpcError,
        Protocol::Refused => FailureCause::Refused,
        Protocol::NoApplicationReady => FailureCause::NoApplicationReady,
        Protocol::NoCyclicData => FailureCause::NoCyclicData,
        Protocol::DeviceAborted => FailureCause::DeviceAborted,
        Protocol::ControllerAborted => FailureCause::ControllerAborted,
        Protocol::Released => FailureCause::Released,
        Protocol::Deactivated => FailureCause::Deactivated,
        Protocol::Internal => FailureCause::Internal,
    }
}

/// The protocol crate's port end of a request's port.
fn port_end(p: &PortRef) -> PortEnd {
    PortEnd {
        device: p.device as usize,
        slot: p.slot,
        subslot: p.subslot,
    }
}

/// What a client is told of a refused tailoring.
fn tailoring_refusal(e: &TailorError) -> TailoringRefusal {
    let port = |e: &PortEnd| PortRef {
        device: e.device as u32,
        slot: e.slot,
        subslot: e.subslot,
    };
    match e {
        TailorError::NoSuchDevice(d) | TailorError::NotOptional(d) => TailoringRefusal::Station {
            device: *d as u32,
            reason: e.to_string(),
        },
        TailorError::NotProgrammable(p) | TailorError::PortTwice(p) => TailoringRefusal::Port {
            port: port(p),
            reason: e.to_string(),
        },
    }
}
