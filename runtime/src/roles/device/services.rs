// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device role's part of the client services: the station in the status report, its
//! diagnosis and process alarms, its events as notifications to the subscribers, the
//! subscribers' say in the AR (records they take, the ApplicationReady they hold: see
//! [`super::application`]), and a clear refusal of the IO controller's services (record jobs towards devices, activation, alarm
//! acknowledgement, the controller's diagnosis).

use super::alarms::AlarmOrder;
use super::application::{ApplicationSay, Order, Taken};
use super::notifications::notification;
use super::program::StationProgram;
use super::role::DeviceCommand;
use super::station::{Station, StationEvent};
use crate::acyclic::DatagramCounters;
use crate::io::pnio::channel::Channel;
use crate::roles::subscribers::{Subscriber, Subscribers};
use crate::roles::{Answers, RoleServices};
use crate::shm::Notices;
use procimg_control::services::Notification;
use procimg_control::{
    ArState, DefinedIdentity, DeviceReport, DeviceRequest, NetworkReport, Refusal, Response,
    StationProgramReport, StationReport, StationTreeEntry, SubscriberReport,
};
use procimg_profinet::device::SubslotAddr;
use procimg_profinet::wire::record::RecordErrorCode;
use std::collections::HashSet;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, SyncSender};
use std::time::{Duration, Instant};

/// How long a client's request waits for the acyclic thread to carry it out: it only
/// changes the engine's state and queues frames.
const COMMAND_WAIT: Duration = Duration::from_millis(500);

/// The refusal of a tree for a station whose configuration gives its tree.
const CONFIGURED_TREE: &str = "this station's tree is its configuration's \
     ([[station.submodule]]); a program defines the tree of a station configured with `gsdml` \
     and no submodules";

/// The device role's client services.
pub struct DeviceServices {
    station: Arc<Station>,
    commands: Sender<DeviceCommand>,
    events: Receiver<StationEvent>,
    channel: Arc<Channel>,
    datagrams: Arc<DatagramCounters>,
    subscribers: Subscribers,
    say: ApplicationSay,
    /// The station's program, for a station its program defines.
    program: Option<Arc<StationProgram>>,
}

impl DeviceServices {
    /// The services of `station` (the clients' `say` over its submodules), giving the role
    /// `commands` and taking its `events`; `channel` and `datagrams` hold the network
    /// counters.
    pub fn new(
        station: Arc<Station>,
        say: ApplicationSay,
        commands: Sender<DeviceCommand>,
        events: Receiver<StationEvent>,
        channel: Arc<Channel>,
        datagrams: Arc<DatagramCounters>,
    ) -> DeviceServices {
        DeviceServices {
            station,
            commands,
            events,
            channel,
            datagrams,
            subscribers: Subscribers::default(),
            say,
            program: None,
        }
    }

    /// For a station its program defines: `program` takes the definitions.
    pub fn with_program(mut self, program: Option<Arc<StationProgram>>) -> DeviceServices {
        self.program = program;
        self
    }

    /// Subscriber `subscriber`'s program defines the station as `tree`.
    fn define(
        &mut self,
        subscriber: u64,
        tree: &[StationTreeEntry],
        identity: &DefinedIdentity,
    ) -> Response {
        let refused = |message: String| Response::Refused(Refusal::BadRequest { message });
        let Some(program) = &self.program else {
            return refused(CONFIGURED_TREE.into());
        };
        let Some(who) = self.subscribers.get(subscriber).cloned() else {
            return Response::Refused(Refusal::UnknownSubscriber);
        };
        let standing = self.say.standing(subscriber);
        match program.define(
            subscriber,
            &who,
            tree,
            identity,
            self.station.has_ar(),
            standing,
        ) {
            Ok(()) => {
                tracing::info!(
                    "{who} defines the station: {} submodules after the device access point",
                    tree.len()
                );
                Response::Done
            }
            Err(e) => refused(e.to_string()),
        }
    }

    /// Whether the GSDML file allows `tree`.
    fn check_tree(&self, tree: &[StationTreeEntry]) -> Response {
        let refused = |message: String| Response::Refused(Refusal::BadRequest { message });
        match &self.program {
            None => refused(CONFIGURED_TREE.into()),
            Some(p) => match p.plan(tree, &DefinedIdentity::default()) {
                Ok(_) => Response::Done,
                Err(e) => refused(e.to_string()),
            },
        }
    }

    /// In the station its program defined: the program is known from the start, and what it
    /// said before holds (sent to the engine before the station takes its first frame).
    pub fn resume_program(&mut self) {
        let Some((definer, standing)) = self.program.as_ref().and_then(|p| p.carried()) else {
            return;
        };
        self.subscribers.subscribe(definer.subscriber, definer.who);
        for order in self.say.resume(definer.subscriber, &standing) {
            self.order(order);
        }
    }

    /// Subscriber `subscriber`'s program ends.
    fn release(&mut self, subscriber: u64) -> Response {
        match &self.program {
            Some(p) if p.release(subscriber) => {
                tracing::info!("the station's program ended: the station waits for another");
                Response::Done
            }
            _ => Response::Refused(Refusal::BadRequest {
                message: "this subscriber did not define the station; only its program \
                          releases it"
                    .into(),
            }),
        }
    }

    /// Publishes `event` to the subscribers; a record job to the one that took its records.
    fn publish(&mut self, event: StationEvent, notices: &mut Notices) {
        if matches!(
            event,
            StationEvent::Ar(procimg_control::ArReport {
                state: ArState::Parameterized,
                ..
            }) | StationEvent::PlugParameterized(_)
        ) {
            self.say.parameters_ended();
        }
        match notification(event) {
            Notification::StationRecord { job, .. } => {
                let at = SubslotAddr::new(job.api, job.slot, job.subslot);
                match self.say.job(job.job, at, Instant::now()) {
                    Ok(reply_to) => notices.publish(&Notification::StationRecord { reply_to, job }),
                    Err(order) => self.order(order),
                }
            }
            Notification::StationDcpSetCheck { check, .. } => {
                match self.say.dcp_check(check.job, Instant::now()) {
                    Ok(reply_to) => {
                        notices.publish(&Notification::StationDcpSetCheck { reply_to, check })
                    }
                    Err(order) => self.order(order),
                }
            }
            Notification::StationArCheck { check, .. } => {
                match self.say.ar_check(check.job, Instant::now()) {
                    Ok(reply_to) => {
                        notices.publish(&Notification::StationArCheck { reply_to, check })
                    }
                    Err(order) => self.order(order),
                }
            }
            n => notices.publish(&n),
        }
    }

    /// Passes an order of the clients' say to the engine.
    fn order(&self, order: Order) {
        let command = match order {
            Order::Records(at, to_client, taken) => DeviceCommand::Records(at, to_client, taken),
            Order::Hold(hold) => DeviceCommand::HoldApplicationReady(hold),
            Order::Release => DeviceCommand::ReleaseApplicationReady,
            Order::Check(on) => DeviceCommand::CheckConnects(on),
            Order::Accept(job) => {
                // Nobody waits for the outcome: the check is the station's to end.
                let (reply, _) = std::sync::mpsc::sync_channel(1);
                DeviceCommand::AnswerConnect {
                    job,
                    answer: Ok(()),
                    reply,
                }
            }
            Order::VerifyDcp(on) => DeviceCommand::VerifyDcpSets(on),
            Order::AllowDcp(job) => {
                // Nobody waits for the outcome: the check is the station's to end.
                let (reply, _) = std::sync::mpsc::sync_channel(1);
                DeviceCommand::AnswerDcpSet {
                    job,
                    allow: true,
                    reply,
                }
            }
            Order::Busy(job) => {
                // Nobody waits for the outcome: the job is the station's to end.
                let (reply, _) = std::sync::mpsc::sync_channel(1);
                DeviceCommand::AnswerRecord {
                    job,
                    answer: Err((RecordErrorCode::ResourceBusy, 0)),
                    reply,
                }
            }
        };
        // The acyclic thread has ended only when procimgd stops: nothing to do then.
        let _ = self.commands.send(command);
    }

    /// A subscriber's say: `subscriber` must be announced.
    fn known(&self, subscriber: u64) -> Result<(), Refusal> {
        self.subscribers
            .get(subscriber)
            .map(|_| ())
            .ok_or(Refusal::UnknownSubscriber)
    }

    /// A subscriber's change of its say (`change` gets the say, the subscriber and a way to
    /// name another subscriber), passed on to the engine.
    fn change_say(
        &mut self,
        subscriber: u64,
        change: impl FnOnce(
            &mut ApplicationSay,
            &dyn Fn(u64) -> String,
        ) -> Result<Option<Order>, Refusal>,
    ) -> Result<(), Refusal> {
        self.known(subscriber)?;
        let subscribers = &self.subscribers;
        let name = |id: u64| {
            subscribers
                .get(id)
                .map_or_else(|| format!("{id:x}"), |s| s.name.clone())
        };
        if let Some(order) = change(&mut self.say, &name)? {
            self.order(order);
        }
        Ok(())
    }

    /// Passes a subscriber's answer to the engine; `stale` is the refusal when the engine's
    /// timeout came first (its error then starts with `engine_says`).
    fn answer(
        &self,
        command: impl FnOnce(SyncSender<Result<(), String>>) -> DeviceCommand,
        engine_says: &str,
        stale: Refusal,
    ) -> Response {
        match self.carry_out(command) {
            Response::Refused(Refusal::BadRequest { message })
                if message.starts_with(engine_says) =>
            {
                Response::Refused(stale)
            }
            r => r,
        }
    }

    fn answer_dcp_set(&mut self, subscriber: u64, job: u64, allow: bool) -> Response {
        if let Err(r) = self.say.answer_dcp(subscriber, job) {
            return Response::Refused(r);
        }
        self.answer(
            |reply| DeviceCommand::AnswerDcpSet { job, allow, reply },
            "DCP Set check",
            Refusal::StaleDcpCheck { job },
        )
    }

    fn answer_ar_check(&mut self, subscriber: u64, job: u64, refuse: Option<(u8, u8)>) -> Response {
        if let Err(r) = self.say.answer_check(subscriber, job) {
            return Response::Refused(r);
        }
        let answer = refuse.map_or(Ok(()), Err);
        self.answer(
            |reply| DeviceCommand::AnswerConnect { job, answer, reply },
            "AR check",
            Refusal::StaleArCheck { job },
        )
    }

    fn answer_record(
        &mut self,
        subscriber: u64,
        job: u64,
        data: Vec<u8>,
        error: Option<(u8, u8)>,
    ) -> Response {
        if let Err(r) = self.say.answer(subscriber, job) {
            return Response::Refused(r);
        }
        let answer = match error {
            None => Ok(data),
            Some((c1, c2)) => Err((RecordErrorCode::from(c1), c2)),
        };
        self.answer(
            |reply| DeviceCommand::AnswerRecord { job, answer, reply },
            "record job",
            Refusal::StaleRecordJob { job },
        )
    }
}

/// What the acyclic thread answers a refused command with.
trait IntoRefusal {
    fn into_refusal(self) -> Refusal;
}

/// A message: the request was wrong in a way the message explains.
impl IntoRefusal for String {
    fn into_refusal(self) -> Refusal {
        Refusal::BadRequest { message: self }
    }
}

/// A refusal of its own kind (a plug's), for programs to act on.
impl IntoRefusal for Refusal {
    fn into_refusal(self) -> Refusal {
        self
    }
}

impl DeviceServices {
    /// Has the acyclic thread carry out the command `make` builds and waits for the outcome.
    fn carry_out<E: IntoRefusal>(
        &self,
        make: impl FnOnce(std::sync::mpsc::SyncSender<Result<(), E>>) -> DeviceCommand,
    ) -> Response {
        let (reply, outcome) = std::sync::mpsc::sync_channel(1);
        let refused = |message: String| Response::Refused(Refusal::BadRequest { message });
        if self.commands.send(make(reply)).is_err() {
            return refused("the device's PROFINET thread has ended".into());
        }
        match outcome.recv_timeout(COMMAND_WAIT) {
            Ok(Ok(())) => Response::Done,
            Ok(Err(why)) => Response::Refused(why.into_refusal()),
            Err(_) => refused(format!(
                "the device's PROFINET thread did not take the request within {COMMAND_WAIT:?}; \
                 try again"
            )),
        }
    }
}

impl Answers<DeviceRequest> for DeviceServices {
    fn handle(
        &mut self,
        request: DeviceRequest,
        _online: bool,
        _notices: &mut Notices,
    ) -> Response {
        match request {
            DeviceRequest::StationOwnRecords {
                subscriber,
                api,
                slot,
                subslot,
                own,
                im,
                pe,
            } => done(self.change_say(subscriber, |say, name| {
                say.own(
                    subscriber,
                    SubslotAddr::new(api, slot, subslot),
                    own,
                    Taken { im, pe },
                    name,
                )
            })),
            DeviceRequest::StationVerifyDcp { subscriber, verify } => {
                done(self.change_say(subscriber, |say, name| {
                    say.verify_dcp(subscriber, verify, name)
                }))
            }
            DeviceRequest::StationDcpSetAnswer {
                subscriber,
                job,
                allow,
            } => self.answer_dcp_set(subscriber, job, allow),
            DeviceRequest::StationCheckArs { subscriber, check } => {
                done(self.change_say(subscriber, |say, name| say.check(subscriber, check, name)))
            }
            DeviceRequest::StationArCheckAnswer {
                subscriber,
                job,
                refuse,
            } => self.answer_ar_check(subscriber, job, refuse),
            DeviceRequest::StationDefine {
                subscriber,
                tree,
                identity,
            } => self.define(subscriber, &tree, &identity),
            DeviceRequest::StationCheckTree { tree } => self.check_tree(&tree),
            DeviceRequest::StationRelease { subscriber } => self.release(subscriber),
            DeviceRequest::StationAbortAr { ar_uuid } => {
                self.carry_out(|reply| DeviceCommand::AbortAr { ar_uuid, reply })
            }
            DeviceRequest::StationRecordAnswer {
                subscriber,
                job,
                data,
                error,
            } => self.answer_record(subscriber, job, data, error),
            DeviceRequest::StationHoldApplicationReady { subscriber, hold } => {
                done(self.known(subscriber).map(|()| {
                    for o in self.say.hold(subscriber, hold) {
                        self.order(o);
                    }
                }))
            }
            DeviceRequest::StationApplicationReady {
                subscriber,
                not_ready,
            } => {
                done(self.known(subscriber).map(|()| {
                    if !not_ready.is_empty() {
                        let at = not_ready
                            .into_iter()
                            .map(|(api, slot, subslot)| SubslotAddr::new(api, slot, subslot))
                            .collect();
                        // Before the release: the acyclic thread takes commands in order.
                        let _ = self.commands.send(DeviceCommand::NotReady(at));
                    }
                    if let Some(o) = self.say.ready(subscriber) {
                        self.order(o);
                    }
                }))
            }
            DeviceRequest::StationDiagnosis { change, silent } => {
                self.carry_out(|reply| DeviceCommand::Diagnosis {
                    change,
                    silent,
                    reply,
                })
            }
            DeviceRequest::StationProblem { problem } => {
                self.carry_out(|reply| DeviceCommand::Problem { problem, reply })
            }
            DeviceRequest::StationAlarm {
                subscriber,
                tag,
                api,
                slot,
                subslot,
                alarm,
                usi,
                data,
            } => match self.known(subscriber) {
                Ok(()) => self.carry_out(|reply| DeviceCommand::Alarm {
                    order: AlarmOrder {
                        subscriber,
                        tag,
                        at: SubslotAddr::new(api, slot, subslot),
                        alarm,
                        usi,
                        data,
                    },
                    reply,
                }),
                Err(r) => Response::Refused(r),
            },
            DeviceRequest::StationProcessAlarm {
                api,
                slot,
                subslot,
                usi,
                data,
            } => self.carry_out(|reply| DeviceCommand::ProcessAlarm {
                at: (api, slot, subslot),
                usi,
                data,
                reply,
            }),
            DeviceRequest::StationPlug {
                api,
                slot,
                subslot,
                module_ident,
                submodule_ident,
            } => self.carry_out(|reply| DeviceCommand::Plug {
                at: SubslotAddr::new(api, slot, subslot),
                idents: Some((module_ident, submodule_ident)),
                reply,
            }),
            DeviceRequest::StationPull { api, slot, subslot } => {
                self.carry_out(|reply| DeviceCommand::Plug {
                    at: SubslotAddr::new(api, slot, subslot),
                    idents: None,
                    reply,
                })
            }
            DeviceRequest::StationReturnSubmodule { api, slot, subslot } => {
                self.carry_out(|reply| DeviceCommand::ReturnSubmodule {
                    at: SubslotAddr::new(api, slot, subslot),
                    reply,
                })
            }
        }
    }
}

impl RoleServices for DeviceServices {
    fn name(&self) -> &'static str {
        "device"
    }

    fn device_services(&mut self) -> Option<&mut dyn Answers<DeviceRequest>> {
        Some(self)
    }

    /// Notifications go to every client of the notification service; announcing makes the
    /// subscriber known (status report, reaping). Its wish to acknowledge alarms is ignored:
    /// the station's alarms are the PLC's to acknowledge, none waits for a client, and the
    /// status says so.
    fn subscribe(&mut self, id: u64, subscriber: Subscriber) {
        self.subscribers.subscribe(
            id,
            Subscriber {
                acknowledges: false,
                ..subscriber
            },
        );
    }

    fn unsubscribe(&mut self, id: u64) -> Result<(), Refusal> {
        self.subscribers.unsubscribe(id)?;
        for o in self.say.forget(id) {
            self.order(o);
        }
        Ok(())
    }

    fn poll(&mut self, wait: Duration, notices: &mut Notices) {
        // The station has logged its events as it noted them; here they become notifications.
        match self.events.recv_timeout(wait) {
            Ok(event) => self.publish(event, notices),
            Err(RecvTimeoutError::Timeout) => {}
            // The acyclic thread has ended (procimgd is stopping): wait all the same.
            Err(RecvTimeoutError::Disconnected) => std::thread::sleep(wait),
        }
        while let Ok(event) = self.events.try_recv() {
            self.publish(event, notices);
        }
    }

    fn finish(&mut self, notices: &mut Notices) {
        // The role's threads have ended: what is left is the AR's end.
        while let Ok(event) = self.events.try_recv() {
            self.publish(event, notices);
        }
    }

    fn reap(&mut self, alive: &HashSet<String>) -> Vec<String> {
        let gone = self.subscribers.reap(alive);
        for (id, _) in &gone {
            for o in self.say.forget(*id) {
                self.order(o);
            }
        }
        if let Some(d) = self.program.as_ref().and_then(|p| p.reap(alive)) {
            tracing::info!(
                "the station's program {} is gone: the station waits for another",
                d.who
            );
        }
        gone.into_iter().map(|(_, s)| s.to_string()).collect()
    }

    fn devices(&self) -> Vec<DeviceReport> {
        Vec::new()
    }

    fn network(&self) -> NetworkReport {
        crate::roles::network_report(&self.channel, &self.datagrams)
    }

    fn subscribers(&self) -> Vec<SubscriberReport> {
        // No alarm waits for a subscriber in the device role.
        self.subscribers.report(|_| 0)
    }

    fn station(&self) -> Option<StationReport> {
        let mut report = self.station.report();
        report.program = self.program.as_ref().and_then(|p| {
            let file = p.waiting().station.program.as_ref()?;
            Some(StationProgramReport {
                gsdml: file.gsdml.display().to_string(),
                defined_by: p.definer().map(|d| d.who.to_string()),
            })
        });
        Some(report)
    }

    fn released(&self) -> bool {
        !self.station.has_ar()
    }
}

/// A request's outcome as its response.
fn done(r: Result<(), Refusal>) -> Response {
    match r {
        Ok(()) => Response::Done,
        Err(r) => Response::Refused(r),
    }
}
