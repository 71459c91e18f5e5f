// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO device as a [`Role`]: the protocol crate's device engine, with its cyclic exchange
//! handed over to the cycle thread, and the daemon's bookkeeping around it (the station
//! report the control side reads, the log).

use super::alarms::{AlarmOrder, ClientAlarms};
use super::diagnosis;
use super::identity::{IdentityChange, IdentityWatch};
use super::state_file::{self, KeptState};
use super::station::{ImageApplication, Station, StationEvent};
use crate::io::pnio::channel::Channel;
use crate::roles::address::InterfaceAddress;
use crate::roles::port_watch::PortWatch;
use crate::roles::{CycleReport, DroppedDatagrams, Effect, Role};
use procimg_control::{PlugRefusal, Refusal, StationDiagnosisChange};
use procimg_profinet::device::{ArState, Device, DeviceAction, PlugError, SubslotAddr};
use procimg_profinet::wire::record::RecordErrorCode;
use procimg_profinet::wire::rpc::RPC_PORT;
use procimg_profinet::wire::rt::data_status::{PROVIDER_RUN, STATE_PRIMARY, STATION_OK};
use procimg_profinet::wire::rta_pdu::AbortCode;
use std::net::SocketAddrV4;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::sync::mpsc::SyncSender;

/// What the client services ask of the device.
#[derive(Debug)]
pub enum DeviceCommand {
    /// Change the station's diagnosis; the outcome goes back on `reply`.
    Diagnosis {
        /// The change.
        change: StationDiagnosisChange,
        /// Only the store changes: the client sends the alarm.
        silent: bool,
        /// Where the outcome goes: `Err` says why the change was refused.
        reply: SyncSender<Result<(), String>>,
    },
    /// Send a process alarm of submodule (`api`, `slot`, `subslot`); the outcome goes back
    /// on `reply`.
    ProcessAlarm {
        /// Where: API, slot, subslot.
        at: (u32, u16, u16),
        /// Manufacturer-specific UserStructureIdentifier.
        usi: u16,
        /// The alarm's data.
        data: Vec<u8>,
        /// Where the outcome goes.
        reply: SyncSender<Result<(), String>>,
    },
    /// Plug (`Some` ident numbers: module, submodule) or pull (`None`) the submodule at a
    /// position; the outcome goes back on `reply`.
    Plug {
        /// Where.
        at: SubslotAddr,
        /// What is plugged, or `None` to pull.
        idents: Option<(u32, u32)>,
        /// Where the outcome goes: `Err` says why it was refused.
        reply: SyncSender<Result<(), Refusal>>,
    },
    /// End the AR of this ARUUID (as the notifications write it) on the application's
    /// request; the station stays on the wire.
    AbortAr {
        /// The ARUUID.
        ar_uuid: String,
        /// Where the outcome goes.
        reply: SyncSender<Result<(), Refusal>>,
    },
    /// Announce the return of the submodule at a position (a Return of Submodule alarm).
    ReturnSubmodule {
        /// Where.
        at: SubslotAddr,
        /// Where the outcome goes.
        reply: SyncSender<Result<(), Refusal>>,
    },
    /// The application reports a station problem, or none; done goes back on `reply`.
    Problem {
        /// A problem or none.
        problem: bool,
        /// Where the outcome goes.
        reply: SyncSender<Result<(), String>>,
    },
    /// A client's alarm; whether it went out goes back on `reply`, its acknowledgement
    /// later as [`StationEvent::AlarmDone`].
    Alarm {
        /// The alarm.
        order: AlarmOrder,
        /// Where the outcome goes.
        reply: SyncSender<Result<(), Refusal>>,
    },
    /// Give the user records of a submodule to a client (`true`, with the station's own
    /// records `Taken` names) or answer them again.
    Records(SubslotAddr, bool, super::application::Taken),
    /// A client's answer to record job `job`: the record read (anything for a write) or the
    /// PNIORW error; the outcome goes back on `reply`.
    AnswerRecord {
        /// The job.
        job: u64,
        /// The answer.
        answer: Result<Vec<u8>, (RecordErrorCode, u8)>,
        /// Where the outcome goes: `Err` when the job waits no more.
        reply: SyncSender<Result<(), String>>,
    },
    /// Have new ARs checked by a client, or not.
    CheckConnects(bool),
    /// A client's answer to AR check `job`: accept, or refuse with ErrorCode1/2; the
    /// outcome goes back on `reply`.
    AnswerConnect {
        /// The check.
        job: u64,
        /// The answer.
        answer: Result<(), (u8, u8)>,
        /// Where the outcome goes: `Err` when the check waits no more.
        reply: SyncSender<Result<(), String>>,
    },
    /// Have DCP's changes of the station checked by a client, or not.
    VerifyDcpSets(bool),
    /// A client's verdict on DCP Set check `job`; the outcome goes back on `reply`.
    AnswerDcpSet {
        /// The check.
        job: u64,
        /// Allow (`true`) or veto.
        allow: bool,
        /// Where the outcome goes: `Err` when the check waits no more.
        reply: SyncSender<Result<(), String>>,
    },
    /// Hold the ApplicationReady after each PrmEnd, or not.
    HoldApplicationReady(bool),
    /// Let a held ApplicationReady go out.
    ReleaseApplicationReady,
    /// The submodules a client is not ready for ("application ready pending").
    NotReady(Vec<SubslotAddr>),
}

/// The device on the acyclic thread.
pub struct DeviceRole {
    device: Device<ImageApplication>,
    station: Arc<Station>,
    /// Where the cycle thread learns of the station problem indicator.
    channel: Arc<Channel>,
    /// The engine's actions before they become effects (kept for its capacity).
    actions: Vec<DeviceAction>,
    /// Where the AR stood after the last call, to tell its changes.
    last_state: ArState,
    /// The ARUUID of the AR up, for its end (when the engine no longer has it).
    ar_uuid: String,
    /// The station's name and address as last seen, to tell DCP's changes.
    identity: IdentityWatch,
    /// DCP Signal requests seen so far.
    signals: u32,
    /// The neighbour table's change count as last told.
    neighbours_told: u64,
    /// The station's SNMP snapshot, if it has an SNMP subagent.
    snmp: Option<super::snmp::SnmpFeed>,
    /// Aborted ARs seen so far, to tell an abort from a Release.
    aborted: u64,
    /// The state file and what it holds, if the station has one.
    kept: Option<Kept>,
    /// The station's address on a real interface, which follows DCP's changes.
    address: Option<InterfaceAddress>,
    /// The real interface whose link and counters the physical records report.
    port: Option<PortWatch>,
    /// The DataStatus bits of the PLC's last output frame that the application is told of
    /// (RUN, StationProblemIndicator, primary), while its data flows.
    plc_status: Option<u8>,
    /// The cycle took the PLC's first valid frame of the current exchange.
    data_flows: bool,
    /// The clients' alarms waiting for the PLC's acknowledgement.
    alarms: ClientAlarms,
    /// A client reports a problem of the station.
    problem: bool,
    /// The station waits for its program to define it: it takes no AR whatever the mode.
    waiting: bool,
}

/// The state file as the role keeps it up to date.
pub struct Kept {
    /// Where it is.
    pub path: PathBuf,
    /// What it holds.
    pub state: KeptState,
    /// The engine's kept-identity changes and I&M writes already in it.
    seen: (u64, u64),
}

impl Kept {
    /// `state`, as loaded from `path`.
    pub fn new(path: PathBuf, state: KeptState) -> Kept {
        Kept {
            path,
            state,
            seen: (0, 0),
        }
    }
}

impl DeviceRole {
    /// `device` (its cyclic exchange already handed over), publishing to `station` and, for
    /// the cycle thread, to `channel`.
    pub fn new(
        device: Device<ImageApplication>,
        station: Arc<Station>,
        channel: Arc<Channel>,
    ) -> DeviceRole {
        DeviceRole {
            identity: IdentityWatch::new(&device),
            device,
            station,
            channel,
            actions: Vec::new(),
            last_state: ArState::Idle,
            ar_uuid: String::new(),
            signals: 0,
            neighbours_told: 0,
            snmp: None,
            aborted: 0,
            kept: None,
            address: None,
            port: None,
            plc_status: None,
            data_flows: false,
            alarms: ClientAlarms::default(),
            problem: false,
            waiting: false,
        }
    }

    /// A station that waits for its program: it answers DCP but takes no AR, whatever the
    /// mode.
    pub fn waiting_for_program(mut self, waiting: bool) -> DeviceRole {
        self.waiting = waiting;
        self
    }

    /// Keeps what must survive a restart in `kept` from now on.
    pub fn with_state_file(mut self, kept: Kept) -> DeviceRole {
        self.kept = Some(kept);
        self
    }

    /// Gives the interface the station's address whenever DCP changes it, from now on.
    pub fn with_address(mut self, address: InterfaceAddress) -> DeviceRole {
        self.address = Some(address);
        self
    }

    /// Reports `interface`'s link and counters in the physical device's records, from now
    /// on: looked at every second, and before every call of a peer (a record read then
    /// gets the counters as they are).
    pub fn with_port(mut self, interface: &str) -> DeviceRole {
        self.port = Some(PortWatch::new(interface));
        self
    }

    /// Keeps `feed`, the station's SNMP snapshot, up to date from now on.
    pub fn with_snmp(mut self, feed: super::snmp::SnmpFeed) -> DeviceRole {
        self.snmp = Some(feed);
        self
    }

    /// Tells the engine the interface's link and counters, if it has a real one.
    fn look_at_port(&mut self, now_ns: u64) {
        let Some(port) = self.port.as_mut() else {
            return;
        };
        let (link, counters) = port.look(now_ns);
        if let Some(link) = link {
            self.device.set_port_link(link);
        }
        self.device.set_port_counters(counters);
    }

    /// Writes the state file when DCP set something to keep or the PLC wrote I&M data.
    fn keep(&mut self) {
        let Some(k) = self.kept.as_mut() else {
            return;
        };
        let now = (
            self.device.station().kept_identity().changes,
            self.device.station().im_write_count(),
        );
        if now == k.seen {
            return;
        }
        k.seen = now;
        state_file::keep_identity(&mut k.state, self.device.station().kept_identity());
        if self.device.station().im_write_count() > 0 {
            k.state.im = Some(state_file::kept_im(self.device.station().im_records()));
        }
        match state_file::save(&k.path, &k.state) {
            Ok(()) => tracing::debug!("state file {} written", k.path.display()),
            Err(e) => tracing::error!("{e}"),
        }
    }

    /// Turns the engine's actions into effects, and what changed into events.
    fn hand_over(&mut self, out: &mut Vec<Effect<StationEvent>>) {
        for a in self.actions.drain(..) {
            out.push(match a {
                DeviceAction::Frame(f) => Effect::Frame(f),
                // Client calls (the ApplicationReady) go from port 34964 too: the PLC answers
                // to the port a call came from.
                DeviceAction::Datagram { to, payload, .. } => Effect::Datagram { to, payload },
                DeviceAction::StartCyclic(ar) => Effect::Start(ar),
                DeviceAction::StopCyclic { .. } => Effect::Stop { device: 0 },
                DeviceAction::Record(r) => Effect::Event(StationEvent::Record(r)),
                DeviceAction::ArCheck(c) => Effect::Event(StationEvent::ArCheck(c)),
                DeviceAction::DcpSetCheck(c) => Effect::Event(StationEvent::DcpSetCheck(c)),
            });
        }
        // A pending fault, or what a client reported.
        let problem = self.device.station_problem() || self.problem;
        self.channel
            .station_problem
            .store(problem, Ordering::Relaxed);
        self.keep();
        self.station.refresh(&self.device, problem);
        // Told before the AR's end that a new name or address brings about.
        if let Some(change) = self.identity.check(&self.device) {
            // Before the DCP answer (among `out`) goes: the PLC connects to the new address
            // as soon as it has the answer.
            if let Some(a) = self.address.as_mut() {
                let id = &change.identity;
                // Logged: the station goes on with the address DCP gave it.
                if let Err(e) = a.follow(id.ip, id.netmask, id.gateway) {
                    tracing::error!("{e}");
                }
            }
            let IdentityChange {
                identity,
                permanent,
                factory_reset,
            } = change;
            self.tell(
                StationEvent::Identity {
                    identity,
                    permanent,
                    factory_reset,
                },
                out,
            );
        }
        let state = self.device.ar().state();
        if state == ArState::Idle {
            self.data_flows = false;
        }
        for at in self.device.take_plug_parameterized() {
            self.tell(StationEvent::PlugParameterized(at), out);
        }
        // Before the AR's end is told: its acknowledgements came while it was up.
        for event in self.alarms.ended(&self.device, state == ArState::Idle) {
            self.tell(event, out);
        }
        if state != self.last_state {
            let event = if let Some(reported) = super::station::reported(state) {
                self.ar_uuid = self
                    .device
                    .ar()
                    .ar_uuid()
                    .map(|u| u.to_string())
                    .unwrap_or_default();
                StationEvent::Ar(procimg_control::ArReport {
                    state: reported,
                    ar_uuid: self.ar_uuid.clone(),
                    controller_mac: self
                        .device
                        .ar()
                        .controller_mac()
                        .map(|m| m.to_string())
                        .unwrap_or_default(),
                    controller_name: self
                        .device
                        .ar()
                        .controller_name()
                        .unwrap_or_default()
                        .to_owned(),
                    plc_running: None,
                })
            } else {
                let aborted = self.device.ar().aborted_ars() != self.aborted;
                self.aborted = self.device.ar().aborted_ars();
                let code = self.device.ar().last_abort().filter(|_| aborted);
                StationEvent::ArEnded {
                    ar_uuid: std::mem::take(&mut self.ar_uuid),
                    abort: code,
                    // Ended by this device taking part no more (procimgd stopping, OFFLINE).
                    planned: code == Some(AbortCode::AbortRequest),
                }
            };
            self.tell(event, out);
            self.last_state = state;
        }
        // The PLC's RUN/STOP, station problem and primary/backup, from its output frames'
        // DataStatus, once its data flows.
        let told = PROVIDER_RUN | STATION_OK | STATE_PRIMARY;
        let status = (self.device.ar().state() == ArState::Data && self.data_flows)
            .then(|| self.channel.peer_data_status.load(Ordering::Relaxed) & told);
        if status != self.plc_status {
            self.plc_status = status;
            if let Some(s) = status {
                let event = StationEvent::PlcRunning {
                    running: s & PROVIDER_RUN != 0,
                    station_problem: s & STATION_OK == 0,
                    backup: s & STATE_PRIMARY == 0,
                };
                self.tell(event, out);
            }
        }
        if self.device.station().signal_count() != self.signals {
            self.signals = self.device.station().signal_count();
            self.tell(StationEvent::Blink, out);
        }
        if let Some(feed) = self.snmp.as_mut() {
            feed.follow(&self.device, crate::sys::clock::now_ns());
        }
        let neighbours = self.device.station().neighbours();
        if neighbours.changes != self.neighbours_told {
            self.neighbours_told = neighbours.changes;
            let now_ns = crate::sys::clock::now_ns();
            let event = StationEvent::Neighbours {
                neighbours: neighbours
                    .entries()
                    .iter()
                    .map(|n| super::station::neighbour(n, now_ns))
                    .collect(),
                alias_name: self.device.station().alias_name().map(str::to_owned),
            };
            self.tell(event, out);
        }
    }

    /// Tells the station report (and the log), then the client services, of `event`.
    fn tell(&self, event: StationEvent, out: &mut Vec<Effect<StationEvent>>) {
        self.station.note(&event);
        out.push(Effect::Event(event));
    }
}

impl Role for DeviceRole {
    type Command = DeviceCommand;
    type Event = StationEvent;

    fn set_online(&mut self, online: bool, now_ns: u64, out: &mut Vec<Effect<StationEvent>>) {
        self.device
            .set_accepting(online && !self.waiting, now_ns, &mut self.actions);
        self.hand_over(out);
    }

    fn command(&mut self, c: DeviceCommand, now_ns: u64, out: &mut Vec<Effect<StationEvent>>) {
        match c {
            DeviceCommand::Diagnosis {
                change,
                silent,
                reply,
            } => {
                let r = if silent {
                    diagnosis::keep(&mut self.device, &change)
                } else {
                    diagnosis::apply(&mut self.device, &change, now_ns, &mut self.actions)
                };
                // The asker may have given up waiting: nothing to tell then.
                let _ = reply.try_send(r);
            }
            DeviceCommand::ProcessAlarm {
                at: (api, slot, subslot),
                usi,
                data,
                reply,
            } => {
                let sent = self.device.raise_process_alarm(
                    api,
                    slot,
                    subslot,
                    usi,
                    &data,
                    now_ns,
                    &mut self.actions,
                );
                let r = if sent {
                    Ok(())
                } else {
                    Err(format!(
                        "no process alarm went out for API {api} slot {slot} subslot \
                         {subslot:#06x}: it needs an AR in data exchange with that submodule \
                         (the PLC's AR is {}), a USI of 0x0000 to 0x7FFF, and data the AR's \
                         alarm length allows",
                        super::station::state_name(self.device.ar().state())
                    ))
                };
                let _ = reply.try_send(r);
            }
            DeviceCommand::Plug { at, idents, reply } => {
                let r = match idents {
                    Some((m, sub)) => {
                        self.device
                            .plug_submodule(at, m, sub, now_ns, &mut self.actions)
                    }
                    None => self.device.pull_submodule(at, now_ns, &mut self.actions),
                };
                let r = r.map_err(plug_refusal).map(|alarm| {
                    self.tell(StationEvent::Plug { at, idents, alarm }, out);
                });
                let _ = reply.try_send(r);
            }
            DeviceCommand::AbortAr { ar_uuid, reply } => {
                let current = self.device.ar().ar_uuid();
                let aborted = match current {
                    Some(uuid) if uuid.to_string() == ar_uuid => {
                        self.device
                            .abort_ar_on_request(uuid, now_ns, &mut self.actions)
                    }
                    _ => false,
                };
                let r = if aborted {
                    Ok(())
                } else {
                    Err(Refusal::ArGone { ar_uuid })
                };
                let _ = reply.try_send(r);
            }
            DeviceCommand::ReturnSubmodule { at, reply } => {
                let r = self
                    .device
                    .return_submodule(at, now_ns, &mut self.actions)
                    .map_err(plug_refusal)
                    .and_then(|alarm| match alarm {
                        Some(_) => Ok(()),
                        None => Err(Refusal::StationPlug {
                            refused: PlugRefusal::NotInDataExchange,
                            message: format!(
                                "no Return of Submodule alarm went out for {at}: it needs the \
                                 PLC's AR in data exchange with that submodule (the AR is {})",
                                super::station::state_name(self.device.ar().state())
                            ),
                        }),
                    });
                let _ = reply.try_send(r);
            }
            DeviceCommand::Problem { problem, reply } => {
                self.problem = problem;
                let _ = reply.try_send(Ok(()));
            }
            DeviceCommand::Alarm { order, reply } => {
                let r = self
                    .alarms
                    .send(&mut self.device, order, now_ns, &mut self.actions);
                let _ = reply.try_send(r);
            }
            DeviceCommand::Records(at, to_client, taken) => {
                self.device.delegate_records(at, to_client);
                self.device.delegate_im_records(at, to_client && taken.im);
                self.device.delegate_pe_records(at, to_client && taken.pe);
            }
            DeviceCommand::AnswerRecord { job, answer, reply } => {
                let r = self
                    .device
                    .answer_record(job, answer, &mut self.actions)
                    .map_err(|e| e.to_string());
                let _ = reply.try_send(r);
            }
            DeviceCommand::CheckConnects(on) => self.device.check_connects(on),
            DeviceCommand::AnswerConnect { job, answer, reply } => {
                let r = self
                    .device
                    .answer_connect(job, answer, now_ns, &mut self.actions)
                    .map_err(|e| e.to_string());
                let _ = reply.try_send(r);
            }
            DeviceCommand::VerifyDcpSets(on) => self.device.verify_dcp_sets(on),
            DeviceCommand::AnswerDcpSet { job, allow, reply } => {
                let r = self
                    .device
                    .answer_dcp_set(job, allow, now_ns, &mut self.actions)
                    .map_err(|e| e.to_string());
                let _ = reply.try_send(r);
            }
            DeviceCommand::HoldApplicationReady(hold) => self.device.hold_application_ready(hold),
            DeviceCommand::NotReady(at) => self.device.application_ready_pending(at),
            DeviceCommand::ReleaseApplicationReady => {
                if self.device.release_application_ready(now_ns) {
                    tracing::debug!("the clients applied the parameters: ApplicationReady goes");
                }
            }
        }
        self.hand_over(out);
    }

    fn on_frame(&mut self, frame: &[u8], now_ns: u64, out: &mut Vec<Effect<StationEvent>>) {
        self.device.on_frame(frame, now_ns, &mut self.actions);
        self.hand_over(out);
    }

    fn on_datagram(
        &mut self,
        from: SocketAddrV4,
        payload: &[u8],
        now_ns: u64,
        out: &mut Vec<Effect<StationEvent>>,
    ) {
        self.look_at_port(now_ns);
        self.device
            .on_datagram(from, RPC_PORT, payload, now_ns, &mut self.actions);
        self.hand_over(out);
    }

    fn on_cycle(&mut self, report: CycleReport, now_ns: u64, out: &mut Vec<Effect<StationEvent>>) {
        match report {
            CycleReport::DataStarted { epoch, .. } => {
                if self.device.cyclic_started(epoch, now_ns) {
                    self.data_flows = true;
                    tracing::debug!("the PLC's output data arrives");
                }
            }
            CycleReport::WatchdogExpired { epoch, .. } => {
                self.device.cyclic_expired(epoch, now_ns, &mut self.actions)
            }
        }
        self.hand_over(out);
    }

    fn poll(&mut self, now_ns: u64, out: &mut Vec<Effect<StationEvent>>) {
        if self.port.as_ref().is_some_and(|p| p.due(now_ns)) {
            self.look_at_port(now_ns);
        }
        self.device.poll(now_ns, &mut self.actions);
        self.hand_over(out);
    }

    fn deadline(&self) -> Option<u64> {
        let port = self.port.as_ref().map(PortWatch::next_ns);
        self.device.next_deadline_ns().into_iter().chain(port).min()
    }

    fn dropped_datagrams(&self) -> DroppedDatagrams {
        DroppedDatagrams::default()
    }
}

/// The refusal a client gets for a plug, pull or return the engine refused.
fn plug_refusal(e: PlugError) -> Refusal {
    let refused = match e {
        PlugError::NotConfigured(_) => PlugRefusal::NotConfigured,
        PlugError::AlreadyPlugged(_) => PlugRefusal::AlreadyPlugged,
        PlugError::NotPlugged(_) => PlugRefusal::NotPlugged,
        PlugError::ArStartingUp => PlugRefusal::ArStartingUp,
    };
    Refusal::StationPlug {
        refused,
        message: e.to_string(),
    }
}
