// SPDX-License-Identifier: MIT OR Apache-2.0
//! The life of one device's AR, sans-IO: identify by name → set IP when needed → Connect →
//! write the parameter records → PrmEnd → wait for the device's ApplicationReady → data
//! exchange; on any failure, back off and start again.

use super::cyclic::CyclicAr;
use super::plan::{ControllerIdentity, DevicePlan};
use super::rpc_call::{Answer, Reply, RpcCall};
use super::uuids::UuidSource;
use super::{
    AlarmTicket, ControllerAction, DeviceEvent, DeviceState, FailureCause, RecordData,
    RecordFailure, RecordRequest, RecordResult,
};
use crate::dcp_client::{self, Identify, Set, SetOutcome};
use crate::rta::{RtaChannel, RtaEvent};
use crate::wire::alarm::{AlarmAck, AlarmBlock, AlarmNotification, Priority};
use crate::wire::connect::{ConnectResponse, IdentInfo, ModuleDiffBlock, ModuleState};
use crate::wire::control::ControlBlock;
use crate::wire::ethernet::{self, ETHERTYPE_PROFINET, VlanTag};
use crate::wire::record::{self, IodHeader};
use crate::wire::rpc::{self, opnum};
use crate::wire::rta_pdu;
use crate::wire::rta_pdu::{ErrRta, RtaPdu};
use crate::wire::{EmitError, MacAddress, PnioStatus, Uuid};
use std::collections::VecDeque;
use std::net::{Ipv4Addr, SocketAddrV4};

mod alarms;
mod learn;
mod records;
mod step;
#[cfg(test)]
mod tests;
pub use learn::TreePlanner;
use records::{record_result, write_failure};
use step::{Ar, Phase, Plug, Step, priority_slot};

/// How long Identify responses are awaited: the name's device answers within its
/// ResponseDelayFactor (1: at once); the rest of the window catches a second device of the
/// same name.
const IDENTIFY_WINDOW_NS: u64 = 200_000_000;
/// How long a DCP Set may take.
const SET_TIMEOUT_NS: u64 = 1_000_000_000;
/// How long the device may take from PrmEnd to ApplicationReady.
const APP_READY_TIMEOUT_NS: u64 = 20_000_000_000;
/// First and largest back-off after a failure: doubled per failure in a row, so that a
/// device that comes back is found again within a second (an Identify window and the
/// largest back-off), while one that stays away costs an Identify a second.
const BACKOFF_MIN_NS: u64 = 100_000_000;
const BACKOFF_MAX_NS: u64 = 800_000_000;
/// DCP ResponseDelayFactor of an Identify by name: one device answers, so no spreading.
const IDENTIFY_DELAY_FACTOR: u16 = 1;

/// One device.
pub struct DeviceAr {
    pub(super) plan: DevicePlan,
    state: DeviceState,
    step: Step,
    /// The device should be connected (mode not OFFLINE and not deactivated).
    wanted: bool,
    /// Deactivated by a client.
    pub(super) deactivated: bool,
    /// The device's MAC and IP address as found, for the next Connect.
    mac: Option<MacAddress>,
    ip: Option<Ipv4Addr>,
    epoch: u32,
    session_key: u16,
    failures: u32,
    xid: u32,
    records: VecDeque<RecordRequest>,
    /// Plugged submodules whose sub-cycle waits for the AR to be free (before client
    /// records).
    plugs: VecDeque<Plug>,
    /// ARUUIDs and activity UUIDs.
    uuids: UuidSource,
    /// Read the device's RealIdentificationData before each Connect (`learn.rs`).
    learn_tree: bool,
    /// What plans the device from its RealIdentificationData, if anything does (`learn.rs`;
    /// boxed: most devices have none).
    planning: Option<Box<learn::Planning>>,
    /// The Release of the last AR while its answer is awaited, and where it went.
    releasing: Option<(RpcCall, SocketAddrV4)>,
}

impl DeviceAr {
    /// A device waiting to be wanted; its AR and activity UUIDs come from `uuids`.
    pub fn new(plan: DevicePlan, uuids: UuidSource) -> DeviceAr {
        // Only the low bits of the index matter: the Xid just has to differ between devices.
        let xid = 0x0100_0000 | ((plan.device as u32) << 12);
        // An optional device waits for the IO system's tailoring to name it.
        let deactivated = plan.optional;
        DeviceAr {
            plan,
            state: if deactivated {
                DeviceState::Deactivated
            } else {
                DeviceState::Offline
            },
            step: Step::Idle,
            wanted: false,
            deactivated,
            mac: None,
            ip: None,
            epoch: 0,
            session_key: 0,
            failures: 0,
            xid,
            records: VecDeque::new(),
            plugs: VecDeque::new(),
            uuids,
            learn_tree: false,
            planning: None,
            releasing: None,
        }
    }

    /// The device's state.
    pub fn state(&self) -> DeviceState {
        self.state
    }

    fn set_state(&mut self, s: DeviceState, out: &mut Vec<ControllerAction>) {
        if self.state != s {
            self.state = s;
            out.push(ControllerAction::Event(DeviceEvent::State {
                device: self.plan.device,
                state: s,
            }));
        }
    }

    /// Whether it should be connected: starts or stops the AR.
    pub fn set_wanted(
        &mut self,
        wanted: bool,
        id: &ControllerIdentity,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        let wanted = wanted && !self.deactivated;
        if wanted == self.wanted {
            return;
        }
        self.wanted = wanted;
        if wanted {
            self.failures = 0;
            self.start(id, now, out);
        } else {
            self.release(id, now, out);
        }
    }

    fn start(&mut self, id: &ControllerIdentity, now: u64, out: &mut Vec<ControllerAction>) {
        self.xid = self.xid.wrapping_add(1);
        let req = Identify::new(self.xid);
        match req.request(id.mac, Some(&self.plan.name), IDENTIFY_DELAY_FACTOR) {
            Ok(frame) => out.push(ControllerAction::Frame(frame)),
            Err(_) => {
                return self.fail(
                    FailureCause::Internal,
                    "the DCP Identify request could not be built",
                    now,
                    out,
                );
            }
        }
        self.step = Step::Identify {
            since: now,
            id: req,
        };
        self.set_state(DeviceState::Searching, out);
    }

    /// Ends the AR: Release to the device if it has one, stop the cyclic exchange.
    fn release(&mut self, id: &ControllerIdentity, now: u64, out: &mut Vec<ControllerAction>) {
        let _ = id;
        out.push(ControllerAction::Stop {
            device: self.plan.device,
        });
        // The Release is awaited (and repeated) as other calls are, but nothing waits for it:
        // its answer only ends the call, so that the socket is not closed under it when
        // procimgd stops ([`releasing`](Self::releasing)). A record job on the wire ends with
        // the AR, without a result (only the queued ones are failed below).
        if let Step::Ar { mut ar, .. } = core::mem::replace(&mut self.step, Step::Idle) {
            let block = ControlBlock::release(ar.uuid, ar.session_key).to_bytes();
            let object = self.plan.object_uuid();
            if let Some(call) = ar.next_call(object, opnum::RELEASE, &block, 0, now) {
                call.send(ar.rpc_server(), out);
                self.releasing = Some((call, ar.rpc_server()));
            }
        }
        self.fail_records("the device was released", out);
        if self.state == DeviceState::Running {
            // IO-Base reports every end of data exchange as a station failure, a wanted
            // one (deactivation, OFFLINE) included.
            let (cause, reason) = if self.deactivated {
                (FailureCause::Deactivated, "deactivated by a client")
            } else {
                (
                    FailureCause::Released,
                    "released: the controller went OFFLINE",
                )
            };
            out.push(ControllerAction::Event(DeviceEvent::Failure {
                device: self.plan.device,
                cause,
                reason: reason.into(),
                planned: true,
                status: None,
            }));
        }
        let s = if self.deactivated {
            DeviceState::Deactivated
        } else {
            DeviceState::Offline
        };
        self.set_state(s, out);
    }

    fn fail(&mut self, cause: FailureCause, why: &str, now: u64, out: &mut Vec<ControllerAction>) {
        self.fail_with(cause, why, None, now, out);
    }

    /// [`fail`](Self::fail) with the PNIO status that says why (a negative response's, the
    /// ERR-RTA's of an abort); without one, the status of the abort sent to the device, if
    /// one was.
    fn fail_with(
        &mut self,
        cause: FailureCause,
        why: &str,
        status: Option<PnioStatus>,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        // The AR ends here; a record job on the wire is failed with the queued ones. An AR
        // whose Connect is unanswered is not known to the device yet: nothing to tell it.
        let accepted = match core::mem::replace(&mut self.step, Step::Idle) {
            Step::Ar {
                phase: Phase::Connect(_),
                ..
            } => None,
            Step::Ar {
                ar,
                phase: Phase::Record { request, .. },
            } => {
                self.records.push_front(request);
                Some(ar)
            }
            Step::Ar { ar, .. } => Some(ar),
            _ => None,
        };
        self.give_up(accepted, cause, why, status, now, out);
    }

    /// [`fail_with`](Self::fail_with) for an AR the device accepted that the caller took out
    /// of its step (to answer its call, or to make the next one): the step no longer holds
    /// it, so it is handed over, or the device would never learn that it is given up.
    fn fail_accepted(
        &mut self,
        ar: Box<Ar>,
        cause: FailureCause,
        why: &str,
        status: Option<PnioStatus>,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        self.give_up(Some(ar), cause, why, status, now, out);
    }

    /// Ends the attempt: the cyclic exchange stops, `accepted` (the AR the device accepted,
    /// if any) is aborted towards the device, the queued record jobs fail, and the next
    /// attempt waits for the back-off.
    fn give_up(
        &mut self,
        accepted: Option<Box<Ar>>,
        cause: FailureCause,
        why: &str,
        status: Option<PnioStatus>,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        out.push(ControllerAction::Stop {
            device: self.plan.device,
        });
        let code = cause.abort_code();
        let aborted = accepted.is_some_and(|mut ar| ar.abort(code, out));
        let status = status.or(aborted.then(|| ErrRta::abort(code).status));
        self.fail_records(why, out);
        let was_running = self.state == DeviceState::Running;
        if was_running {
            out.push(ControllerAction::Event(DeviceEvent::Failure {
                device: self.plan.device,
                cause,
                reason: why.to_string(),
                planned: false,
                status,
            }));
        } else {
            out.push(ControllerAction::Event(DeviceEvent::Problem {
                device: self.plan.device,
                cause,
                reason: why.to_string(),
                status,
            }));
        }
        let backoff = (BACKOFF_MIN_NS << self.failures.min(8)).min(BACKOFF_MAX_NS);
        self.failures = self.failures.saturating_add(1);
        self.step = Step::Backoff {
            until: now + backoff,
        };
        self.set_state(DeviceState::Failed, out);
    }

    /// Whether the Release of its last AR still waits for the device's answer.
    pub fn releasing(&self) -> bool {
        self.releasing.is_some()
    }

    /// The next timer.
    pub fn deadline(&self) -> Option<u64> {
        let release = self.releasing.as_ref().map(|(c, _)| c.deadline_ns());
        let step = self.step_deadline();
        match (step, release) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    fn step_deadline(&self) -> Option<u64> {
        // Alarm channels retransmit on a 100 ms grid; the owner polls at least that often.
        match &self.step {
            Step::Identify { since, .. } => Some(since + IDENTIFY_WINDOW_NS),
            Step::SetIp { since, .. } => Some(since + SET_TIMEOUT_NS),
            Step::Ar {
                phase: Phase::WaitAppReady { since },
                ..
            } => Some(since + APP_READY_TIMEOUT_NS),
            Step::Ar { phase, .. } => phase.call().map(RpcCall::deadline_ns),
            Step::Learn { call } => Some(call.deadline_ns()),
            Step::Backoff { until } => Some(*until),
            Step::Idle => None,
        }
    }

    /// Timers and queued work.
    pub fn poll(&mut self, id: &ControllerIdentity, now: u64, out: &mut Vec<ControllerAction>) {
        if let Some((call, to)) = self.releasing.as_mut() {
            if call.retry_due(now) {
                call.resent(now);
                call.send(*to, out);
            } else if call.expired(now) {
                self.releasing = None;
            }
        }
        let mut rta = Vec::new();
        if let Some(ar) = self.step.ar_mut() {
            ar.alarm_high.poll(now, &mut rta);
            ar.alarm_low.poll(now, &mut rta);
        }
        self.on_rta_events(rta, id, now, out);
        match &mut self.step {
            Step::Identify {
                since, id: ident, ..
            } if now >= *since + IDENTIFY_WINDOW_NS => {
                let found = ident.devices().first().cloned();
                match found {
                    Some(d) => self.identified(d, id, now, out),
                    None => {
                        let why = format!(
                            "no device named {:?} answered DCP Identify; check the name, \
                             the cabling and that the device is powered",
                            self.plan.name
                        );
                        self.fail(FailureCause::NotFound, &why, now, out)
                    }
                }
            }
            Step::SetIp { since, .. } if now >= *since + SET_TIMEOUT_NS => self.fail(
                FailureCause::IpSetFailed,
                "the device did not answer DCP Set IP",
                now,
                out,
            ),
            Step::Ar {
                phase: Phase::WaitAppReady { since },
                ..
            } if now >= *since + APP_READY_TIMEOUT_NS => {
                self.fail(
                    FailureCause::NoApplicationReady,
                    "the device sent no ApplicationReady after PrmEnd",
                    now,
                    out,
                );
            }
            Step::Ar {
                phase: Phase::Running,
                ..
            } => self.next_record(now, out),
            Step::Ar { ar, phase } => {
                let Some(c) = phase.call_mut() else { return };
                if c.retry_due(now) {
                    c.resent(now);
                    c.send(ar.rpc_server(), out);
                } else if c.expired(now) {
                    let op = opnum::name(c.opnum).unwrap_or("RPC");
                    let why = format!("the device did not answer the {op} request");
                    self.fail(FailureCause::RpcTimeout, &why, now, out);
                }
            }
            Step::Learn { call } => {
                if call.retry_due(now) {
                    call.resent(now);
                    if let Some(ip) = self.ip {
                        call.send(SocketAddrV4::new(ip, rpc::RPC_PORT), out);
                    }
                } else if call.expired(now) {
                    // Unanswered: connect with the plan as it is.
                    self.connect(id, now, out);
                }
            }
            Step::Backoff { until } if now >= *until => {
                if self.wanted {
                    self.start(id, now, out);
                } else {
                    self.step = Step::Idle;
                }
            }
            _ => {}
        }
    }

    fn identified(
        &mut self,
        d: dcp_client::DeviceInfo,
        id: &ControllerIdentity,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        self.mac = Some(d.mac);
        let current = d.ip.map(|(ip, _, _)| Ipv4Addr::from(ip));
        match (self.plan.ip, current) {
            (Some(want), have) if have != Some(want) => {
                self.xid = self.xid.wrapping_add(1);
                let mask = [255, 255, 255, 0];
                // Without a router the gateway is the device's own address, as an S7 sets it.
                let set = Set::ip(self.xid, d.mac, want.octets(), mask, want.octets(), false);
                match set.request(id.mac) {
                    Ok(frame) => out.push(ControllerAction::Frame(frame)),
                    Err(_) => {
                        return self.fail(
                            FailureCause::Internal,
                            "the DCP Set request could not be built",
                            now,
                            out,
                        );
                    }
                }
                self.step = Step::SetIp { since: now, set };
                self.set_state(DeviceState::SettingIp, out);
            }
            (want, have) => {
                let Some(ip) = want.or(have).filter(|ip| !ip.is_unspecified()) else {
                    return self.fail(
                        FailureCause::IpSetFailed,
                        "the device has no IP address and none is configured; set `ip` for it",
                        now,
                        out,
                    );
                };
                self.ip = Some(ip);
                self.connect_or_learn(id, now, out);
            }
        }
    }

    fn connect(&mut self, id: &ControllerIdentity, now: u64, out: &mut Vec<ControllerAction>) {
        let (Some(ip), Some(mac)) = (self.ip, self.mac) else {
            return self.fail(
                FailureCause::IpSetFailed,
                "no address to connect to",
                now,
                out,
            );
        };
        self.session_key = self.session_key.wrapping_add(1);
        self.epoch = self.epoch.wrapping_add(1);
        let uuid = self.uuids.next_uuid();
        let activity = self.uuids.next_uuid();
        let req = self.plan.connect_request(id, uuid, self.session_key);
        let Ok(blocks) = req.to_vec() else {
            return self.fail(
                FailureCause::Internal,
                "the Connect request could not be built",
                now,
                out,
            );
        };
        let Ok(call) = RpcCall::new(
            self.plan.object_uuid(),
            activity,
            0,
            opnum::CONNECT,
            &blocks,
            0,
            now,
        ) else {
            return self.fail(
                FailureCause::Internal,
                "the Connect request does not fit one RPC PDU",
                now,
                out,
            );
        };
        let (hi, lo) = (req.alarm_cr.rta_timeout_factor, req.alarm_cr.rta_retries);
        let local = req.alarm_cr.local_alarm_reference;
        let ar = Box::new(Ar {
            uuid,
            session_key: self.session_key,
            activity,
            seq: 0,
            ip,
            peer_mac: mac,
            // The remote endpoint is known from the response; set again there.
            alarm_high: RtaChannel::new(Priority::High, local, 0, hi, lo),
            alarm_low: RtaChannel::new(Priority::Low, local, 0, hi, lo),
            record_seq: 0,
            unacked: [None, None],
            absent: Vec::new(),
            own_mac: id.mac,
        });
        call.send(ar.rpc_server(), out);
        self.step = Step::Ar {
            ar,
            phase: Phase::Connect(call),
        };
        self.set_state(DeviceState::Connecting, out);
    }

    /// A DCP or alarm frame from the interface.
    pub fn on_frame(
        &mut self,
        frame: &[u8],
        id: &ControllerIdentity,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        match &mut self.step {
            Step::Identify { id: ident, .. } => {
                // A name is unique on the network: the first answer is the device.
                if ident.on_frame(frame)
                    && let Some(d) = ident.devices().first().cloned()
                {
                    self.identified(d, id, now, out);
                }
                return;
            }
            Step::SetIp { set, .. } => {
                match set.on_frame(frame) {
                    Some(SetOutcome::Done) => {
                        self.ip = self.plan.ip;
                        self.connect_or_learn(id, now, out);
                    }
                    Some(other) => {
                        let why = format!("DCP Set IP refused: {other}");
                        self.fail(FailureCause::IpSetFailed, &why, now, out);
                    }
                    None => {}
                }
                return;
            }
            _ => {}
        }
        // Alarms of our AR.
        let Some(ar) = self.step.ar_mut() else { return };
        let Ok(eth) = ethernet::Frame::new_checked(frame) else {
            return;
        };
        if eth.src() != ar.peer_mac {
            return;
        }
        let Ok(packet) = rta_pdu::Packet::new_checked(eth.payload()) else {
            return;
        };
        let Ok(pdu) = RtaPdu::parse(&packet) else {
            return;
        };
        let mut events = Vec::new();
        ar.channel(pdu.priority).receive(&pdu, now, &mut events);
        self.on_rta_events(events, id, now, out);
    }

    /// An RPC answer from the device's address.
    pub fn on_datagram(
        &mut self,
        datagram: &[u8],
        id: &ControllerIdentity,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) -> bool {
        if let Some((call, to)) = self.releasing.as_mut() {
            let mut facks = Vec::new();
            let reply = call.take(datagram, &mut facks);
            let to = *to;
            out.extend(
                facks
                    .into_iter()
                    .map(|payload| ControllerAction::Datagram { to, payload }),
            );
            match reply {
                Reply::Foreign => {}
                Reply::Partial => return true,
                // Whatever it says: the AR is gone on this side already.
                Reply::Done(_) => {
                    self.releasing = None;
                    return true;
                }
            }
        }
        if let Step::Learn { call } = &mut self.step {
            let mut facks = Vec::new();
            let reply = call.take(datagram, &mut facks);
            if let Some(ip) = self.ip {
                for f in facks {
                    out.push(ControllerAction::Datagram {
                        to: SocketAddrV4::new(ip, rpc::RPC_PORT),
                        payload: f,
                    });
                }
            }
            return match reply {
                Reply::Foreign => false,
                Reply::Partial => true,
                Reply::Done(answer) => {
                    self.learned(answer, id, now, out);
                    true
                }
            };
        }
        let Step::Ar { ar, phase } = &mut self.step else {
            return false;
        };
        let Some(call) = phase.call_mut() else {
            return false;
        };
        let mut facks = Vec::new();
        let reply = call.take(datagram, &mut facks);
        let op = call.opnum;
        for f in facks {
            out.push(ControllerAction::Datagram {
                to: ar.rpc_server(),
                payload: f,
            });
        }
        let answer = match reply {
            Reply::Foreign => return false,
            Reply::Partial => return true,
            Reply::Done(a) => a,
        };
        let (status, blocks) = match answer {
            Answer::Response { status, blocks } => (status, blocks),
            Answer::Refused(code) => {
                let why = format!(
                    "the device's RPC layer refused the {} call (status {code:#010x})",
                    opnum::name(op).unwrap_or("RPC")
                );
                self.fail(FailureCause::RpcError, &why, now, out);
                return true;
            }
        };
        // The AR leaves its step while its answer is judged: a failure from here on hands it
        // to `fail_accepted`, as `fail` would not find it in the step.
        let Step::Ar { ar, phase } = core::mem::replace(&mut self.step, Step::Idle) else {
            return true;
        };
        match phase {
            Phase::Connect(_) => self.connected(ar, status, &blocks, id, now, out),
            Phase::Write(_) => match write_failure(status, &blocks) {
                None => self.prm_end(ar, now, out),
                Some((why, status)) => {
                    self.fail_accepted(ar, FailureCause::Refused, &why, status, now, out)
                }
            },
            Phase::PrmEnd(_) => {
                let prm_end = ControlBlock::prm_end(ar.uuid, ar.session_key);
                let ok = status.is_ok()
                    && ControlBlock::parse(&blocks).is_ok_and(|b| b.answers(&prm_end));
                if ok {
                    self.step = Step::Ar {
                        ar,
                        phase: Phase::WaitAppReady { since: now },
                    };
                    self.set_state(DeviceState::WaitingForApplicationReady, out);
                } else {
                    let why = format!("PrmEnd failed: {}", rpc::describe(status));
                    let status = (!status.is_ok()).then_some(status);
                    self.fail_accepted(ar, FailureCause::Refused, &why, status, now, out);
                }
            }
            Phase::PlugWrite { plug, .. } => match write_failure(status, &blocks) {
                None => self.plug_prm_end(ar, plug, now, out),
                Some((why, status)) => {
                    let why = format!(
                        "the parameters of the submodule plugged at slot {} subslot {:#06x}: \
                         {why}",
                        plug.slot, plug.subslot
                    );
                    self.fail_accepted(ar, FailureCause::Refused, &why, status, now, out)
                }
            },
            Phase::PlugPrmEnd { plug, .. } => {
                let request = ControlBlock::plug_prm_end(ar.uuid, ar.session_key, plug.seq);
                let ok = status.is_ok()
                    && ControlBlock::parse(&blocks).is_ok_and(|b| b.answers(&request));
                self.step = Step::Ar {
                    ar,
                    phase: Phase::Running,
                };
                if ok {
                    self.next_record(now, out);
                } else {
                    let why = format!(
                        "PlugPrmEnd of the submodule plugged at slot {} subslot {:#06x} \
                         failed: {}",
                        plug.slot,
                        plug.subslot,
                        rpc::describe(status)
                    );
                    let status = (!status.is_ok()).then_some(status);
                    self.fail_with(FailureCause::Refused, &why, status, now, out);
                }
            }
            Phase::Record { request, .. } => {
                let result = record_result(&request, status, &blocks);
                out.push(ControllerAction::Event(DeviceEvent::Record(RecordResult {
                    request,
                    result,
                })));
                self.step = Step::Ar {
                    ar,
                    phase: Phase::Running,
                };
                self.next_record(now, out);
            }
            // Without a call there was no answer to take.
            phase @ (Phase::WaitAppReady { .. } | Phase::Running) => {
                self.step = Step::Ar { ar, phase }
            }
        }
        true
    }

    fn connected(
        &mut self,
        mut ar: Box<Ar>,
        status: PnioStatus,
        blocks: &[u8],
        id: &ControllerIdentity,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        if !status.is_ok() {
            let why = format!("Connect refused: {}", rpc::describe(status));
            return self.fail_with(FailureCause::Refused, &why, Some(status), now, out);
        }
        let Ok(res) = ConnectResponse::parse(blocks) else {
            return self.fail(
                FailureCause::RpcError,
                "the Connect response is malformed",
                now,
                out,
            );
        };
        if res.ar.ar_uuid != ar.uuid || res.ar.session_key != ar.session_key {
            return self.fail(
                FailureCause::RpcError,
                "the Connect response names another AR; the device may be connected to \
                 another controller",
                now,
                out,
            );
        }
        ar.peer_mac = res.ar.responder_mac;
        let remote = res.alarm_cr.local_alarm_reference;
        let (f, r) = (1, 3);
        let local = self.plan.alarm_reference();
        ar.alarm_high = RtaChannel::new(Priority::High, local, remote, f, r);
        ar.alarm_low = RtaChannel::new(Priority::Low, local, remote, f, r);
        // What the device lacks, or has something else plugged at, gets no parameters (as
        // an S7 does): the device would refuse them, and its plug alarm brings them later.
        if let Some(diff) = &res.module_diff {
            ar.absent = absent_submodules(diff, &self.plan);
        }
        if let Some(diff) = res.module_diff.clone() {
            out.push(ControllerAction::Event(DeviceEvent::ModuleDiff {
                device: self.plan.device,
                diff,
            }));
        }
        let frame_ids = (
            res.frame_id(1).unwrap_or(self.plan.frame_ids.0),
            res.frame_id(2).unwrap_or(self.plan.frame_ids.1),
        );
        let cyclic = CyclicAr::new(&self.plan, self.epoch, id.mac, ar.peer_mac, frame_ids);
        out.push(ControllerAction::Start(Box::new(cyclic)));
        self.set_state(DeviceState::Parameterizing, out);
        self.write_records(ar, now, out);
    }

    fn plug_prm_end(&mut self, ar: Box<Ar>, plug: Plug, now: u64, out: &mut Vec<ControllerAction>) {
        let block = ControlBlock::plug_prm_end(ar.uuid, ar.session_key, plug.seq).to_bytes();
        self.call(ar, opnum::CONTROL, &block, now, out, |call| {
            Phase::PlugPrmEnd { call, plug }
        });
    }

    fn prm_end(&mut self, ar: Box<Ar>, now: u64, out: &mut Vec<ControllerAction>) {
        let block = ControlBlock::prm_end(ar.uuid, ar.session_key).to_bytes();
        self.call(ar, opnum::CONTROL, &block, now, out, Phase::PrmEnd);
    }

    /// Sends `blocks` as the next call of `ar`'s activity; the AR goes on in the phase that
    /// `phase` makes of the call, or fails when the request does not fit an RPC call.
    fn call(
        &mut self,
        mut ar: Box<Ar>,
        op: u16,
        blocks: &[u8],
        now: u64,
        out: &mut Vec<ControllerAction>,
        phase: impl FnOnce(RpcCall) -> Phase,
    ) {
        match ar.next_call(self.plan.object_uuid(), op, blocks, 0, now) {
            Some(call) => {
                call.send(ar.rpc_server(), out);
                self.step = Step::Ar {
                    ar,
                    phase: phase(call),
                };
            }
            None => self.fail_accepted(
                ar,
                FailureCause::Internal,
                "a request is longer than an RPC call can carry",
                None,
                now,
                out,
            ),
        }
    }

    /// The device's ApplicationReady for our AR: the answer block, or `None` if it is not
    /// for this device.
    pub fn on_application_ready(
        &mut self,
        block: &ControlBlock,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) -> Option<ControlBlock> {
        let Step::Ar { ar, phase } = &mut self.step else {
            return None;
        };
        if block.ar_uuid != ar.uuid {
            return None;
        }
        if block.block_type == crate::wire::BlockType::PlugApplicationReadyReq {
            // The end of a plug sub-cycle: the submodule's IOPS turns GOOD in its data.
            return ControlBlock::done_response_for(block);
        }
        let answer = ControlBlock::application_ready_done(ar.uuid, ar.session_key);
        if matches!(phase, Phase::WaitAppReady { .. }) {
            *phase = Phase::Running;
            self.failures = 0;
            self.set_state(DeviceState::Running, out);
            // Every start of data exchange is a station return, the first one included, as
            // IO-Base reports it.
            out.push(ControllerAction::Event(DeviceEvent::Return {
                device: self.plan.device,
            }));
            self.next_record(now, out);
        }
        Some(answer)
    }

    /// The cycle thread saw no input frames for the watchdog time.
    pub fn on_watchdog(&mut self, epoch: u32, now: u64, out: &mut Vec<ControllerAction>) {
        if epoch == self.epoch && self.step.ar().is_some() {
            let why = format!(
                "no cyclic data from the device for {} ms (DataHoldFactor {}); the AR was \
                 given up and will be set up again",
                self.plan.timing.watchdog_ns() / 1_000_000,
                self.plan.timing.data_hold_factor
            );
            self.fail(FailureCause::NoCyclicData, &why, now, out);
        }
    }

    /// The ApplicationReady is due from this device's AR (for the ApplicationReady
    /// handler: which device has the AR).
    pub fn ar_uuid(&self) -> Option<Uuid> {
        self.step.ar().map(|a| a.uuid)
    }
}

/// The submodules of `plan` that `diff` says are not there or are something else: those of
/// an empty slot (which lists none of its submodules) and those listed as wrong or missing.
fn absent_submodules(diff: &ModuleDiffBlock, plan: &DevicePlan) -> Vec<(u32, u16, u16)> {
    let mut absent = Vec::new();
    for a in &diff.apis {
        for m in &a.modules {
            if m.state == ModuleState::NoModule {
                absent.extend(
                    plan.submodules
                        .iter()
                        .filter(|s| (s.api, s.slot) == (a.api, m.slot))
                        .map(|s| (s.api, s.slot, s.subslot)),
                );
                continue;
            }
            absent.extend(
                m.submodules
                    .iter()
                    .filter(|s| {
                        !matches!(s.state.ident_info(), IdentInfo::Ok | IdentInfo::Substitute)
                    })
                    .map(|s| (a.api, m.slot, s.subslot)),
            );
        }
    }
    absent
}
