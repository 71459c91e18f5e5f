// SPDX-License-Identifier: MIT OR Apache-2.0
//! The acyclic side of the server: answers client requests over the control service, keeps
//! the registry and the claims, reaps clients whose process died, and gathers statistics.
//! It runs at normal priority and never makes the cycle wait: it talks to the cycle thread
//! only through [`Shared`].

pub mod force;
mod registry;
pub mod restart;

pub use force::ForceTable;
pub use registry::{ClientEntry, Registry};

use crate::cycle::{Command, Shared};
use crate::image::Tables;
use crate::roles::RoleServices;
use crate::roles::subscribers::Subscriber;
use crate::shm::outputs::{self, IpcThreadsafe};
use crate::shm::{ControlPorts, Ipc, Notices, access, iox2_config};
use crate::stats::{StatsCollector, load};
use iceoryx2::node::{Node, NodeState, NodeView};
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::server::Server;
use iceoryx2::port::update_connections::UpdateConnections;
use iceoryx2::prelude::CallbackProgression;
use procimg_control::services::Notification;
use procimg_control::{
    self as control, ClaimReport, ClientReport, CoreRequest, Refusal, Request, Response,
    StatusReport,
};
use procimg_shm_layout::LayoutHeader;
use procimg_shm_layout::{MAX_CLIENTS, Mode};
use std::collections::{HashMap, HashSet};
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

/// How often the server looks for clients whose process died.
const LIVENESS_PERIOD: Duration = Duration::from_millis(100);

/// What the control side knows about the server it belongs to.
#[derive(Clone, Debug)]
pub struct ServerInfo {
    /// Instance name.
    pub instance: String,
    /// Server generation.
    pub generation: u64,
    /// Cycle time in ns.
    pub cycle_ns: u64,
    /// OPDONE deadline in ns.
    pub opdone_deadline_ns: u64,
}

/// The control side.
pub struct Control {
    info: ServerInfo,
    tables: Tables,
    server: Server<Ipc, [u8], (), [u8], ()>,
    layout: Publisher<Ipc, [u8], LayoutHeader>,
    notices: Notices,
    /// The client services of the role procimgd plays.
    role: Box<dyn RoleServices>,
    shared: Arc<Shared>,
    stats: StatsCollector,
    registry: Registry,
    last_liveness: Instant,
    /// Clients found dead outside the liveness period (a claim held by a dead client), to be
    /// reported by the next `poll`.
    reaped_early: Vec<String>,
    forces: ForceTable,
    /// The doorbell's count when the last round of work began.
    rung_before_round: u32,
    /// Where the configuration came from, for restarts with a new one (none: restarts
    /// are refused, as in benches and tests that run a control side alone).
    source: Option<restart::ConfigSource>,
    /// A restart waiting for the programs to detach.
    restart: Option<restart::PendingRestart>,
    /// The type of station a program set, for the next start.
    type_of_station: Option<String>,
    /// The node of the clients' output ports (which the cycle thread holds).
    outputs_node: Node<IpcThreadsafe>,
    /// Output ports made at registration, by slot, until their client asks to connect.
    pending_outputs: HashMap<u32, (u64, outputs::OutputPort)>,
    // Dropped after the ports above, which live on it.
    _node: Node<Ipc>,
}

impl Control {
    /// The control side over `ports`, serving the requests of the role procimgd plays with
    /// `role`. Subscribers left from a previous server learn that they must announce
    /// themselves again.
    pub fn new(
        info: ServerInfo,
        tables: Tables,
        ports: ControlPorts,
        shared: Arc<Shared>,
        stats: StatsCollector,
        role: Box<dyn RoleServices>,
    ) -> Control {
        let registry = Registry::new(info.generation.rotate_left(17));
        let ControlPorts {
            node,
            server,
            layout,
            notifications,
            notify,
            outputs_node,
        } = ports;
        let mut notices = Notices::new(notifications, notify);
        notices.publish(&Notification::ServerStarted {
            generation: info.generation,
        });
        Control {
            info,
            tables,
            server,
            layout,
            notices,
            role,
            _node: node,
            outputs_node,
            pending_outputs: HashMap::new(),
            shared,
            stats,
            registry,
            last_liveness: Instant::now(),
            reaped_early: Vec::new(),
            forces: ForceTable::default(),
            rung_before_round: 0,
            source: None,
            restart: None,
            type_of_station: None,
        }
    }

    /// Takes restarts (resets, downloads) from now on, checking a new configuration as
    /// `source` says.
    pub fn with_source(mut self, source: restart::ConfigSource) -> Control {
        self.source = Some(source);
        self
    }

    /// The names of the programs attached now.
    fn attached(&self) -> Vec<String> {
        self.registry
            .clients()
            .map(|(_, c)| format!("\"{}\" (pid {})", c.name, c.pid))
            .collect()
    }

    /// Starts a restart with `configuration` for procimgd itself (a SIGHUP): the programs
    /// attached are asked to stop and waited for; refused as a client's would be.
    pub fn restart_with(&mut self, configuration: String) -> Result<(), Refusal> {
        self.begin_restart(0, Some(configuration), control::RestartClients::Ask)
    }

    /// Starts a restart of `reply_to`, with `configuration` or the running one.
    fn begin_restart(
        &mut self,
        reply_to: u64,
        configuration: Option<String>,
        clients: control::RestartClients,
    ) -> Result<(), Refusal> {
        let Some(source) = &self.source else {
            return Err(Refusal::ServerBusy);
        };
        if self.restart.is_some() {
            return Err(Refusal::RestartPending);
        }
        let what = match configuration {
            None => restart::Restart::Same,
            Some(text) => {
                let (config, keep) = source
                    .check(&text, &procimg_nic::interfaces::check)
                    .map_err(|message| Refusal::BadConfiguration { message })?;
                restart::Restart::With(Box::new(config), keep)
            }
        };
        let attached = self.attached();
        let notices = &mut self.notices;
        self.restart = Some(restart::PendingRestart::begin(
            reply_to,
            what,
            clients,
            &attached,
            &mut |n| notices.publish(n),
        )?);
        Ok(())
    }

    /// A restart that is to take effect now, if there is one: the generation ends and the
    /// next starts as it says (a new configuration is kept in the configuration file
    /// first). A restart given up is told to whoever asked.
    pub fn take_restart(&mut self) -> Option<restart::Restart> {
        self.restart.as_ref()?;
        let attached = self.attached();
        let step = self.restart.as_mut()?.step(&attached, Instant::now());
        let reply_to = self
            .restart
            .as_ref()
            .map_or(0, restart::PendingRestart::reply_to);
        let (done, message, next) = match step {
            restart::RestartStep::Waiting => return None,
            restart::RestartStep::GivenUp => (
                false,
                format!(
                    "{} did not close within {} s: the restart is given up",
                    attached.join(", "),
                    control::services::RESTART_WAIT_MS / 1000
                ),
                None,
            ),
            restart::RestartStep::Now(r) => {
                let kept = match (&r, &self.source) {
                    (restart::Restart::With(_, text), Some(source)) => match source.keep(text) {
                        Ok(true) => " (the configuration file holds it now)",
                        Ok(false) => " (kept until procimgd stops: it has no configuration file)",
                        Err(e) => {
                            tracing::warn!("the downloaded configuration is not kept: {e}");
                            " (it could not be written to the configuration file)"
                        }
                    },
                    _ => "",
                };
                let what = match r {
                    restart::Restart::Same => "the server restarts",
                    restart::Restart::With(..) => "the server restarts with the new configuration",
                };
                (true, format!("{what}{kept}"), Some(r))
            }
        };
        self.restart = None;
        if done {
            tracing::info!("{message}");
        } else {
            tracing::warn!("{message}");
        }
        self.notices.publish(&Notification::Restart {
            reply_to,
            done,
            message,
        });
        next
    }

    /// The type of station a program set for the next start, if one did.
    pub fn type_of_station(&self) -> Option<&str> {
        self.type_of_station.as_deref()
    }

    /// Answers every pending request; every `LIVENESS_PERIOD` reaps dead clients. Returns
    /// the names of clients reaped in this call.
    pub fn poll(&mut self) -> Vec<String> {
        // Ports of clients that left, unmapped here rather than in the cycle.
        self.shared.outputs.drop_retired();
        // Input samples faulted in ahead of the cycle's loans, when it asked for more.
        self.shared.input_reserve.extend();
        // Before the work: a ring during it is not slept through by `idle`.
        self.rung_before_round = self.shared.control_rung();
        while let Ok(Some(active)) = self.server.receive() {
            let response = match control::decode::<Request>(active.payload()) {
                Ok(req) => self.handle(req),
                Err(message) => Response::Refused(Refusal::BadRequest { message }),
            };
            let bytes = control::encode(&response);
            match active.loan_slice_uninit(bytes.len()) {
                Ok(out) => {
                    let _ = out.write_from_slice(&bytes).send();
                }
                Err(e) => {
                    // Said to the asker in a few bytes, which fit where the answer did not.
                    tracing::warn!(
                        "a control answer of {} bytes could not be loaned: {e:?}",
                        bytes.len()
                    );
                    let lost = control::encode(&Response::Refused(Refusal::AnswerLost {
                        bytes: bytes.len() as u64,
                        detail: format!("{e:?}"),
                    }));
                    if let Ok(out) = active.loan_slice_uninit(lost.len()) {
                        let _ = out.write_from_slice(&lost).send();
                    }
                }
            }
        }
        // Delivers the layout (history) to subscribers that attached since the last call.
        let _ = self.layout.update_connections();
        self.stats.collect();
        let mut gone = std::mem::take(&mut self.reaped_early);
        if self.last_liveness.elapsed() >= LIVENESS_PERIOD {
            self.last_liveness = Instant::now();
            gone.extend(self.reap_dead_clients());
        }
        gone
    }

    /// Creates the output service of the client just registered as `slot`, `token`, with
    /// the server's subscriber (see `shm::outputs`); the registration is undone if it cannot.
    fn make_outputs(&mut self, slot: u32, token: u64) -> Result<(), Refusal> {
        match outputs::create(
            &self.outputs_node,
            &self.info.instance,
            self.info.generation,
            token,
        ) {
            Ok(port) => {
                // The client opens the service next.
                access::share_now();
                self.pending_outputs.insert(slot, (token, port));
                Ok(())
            }
            Err(e) => {
                self.registry.unregister(&self.shared, slot);
                Err(Refusal::OutputsNotConnected {
                    detail: e.to_string(),
                })
            }
        }
    }

    /// Connects the output port of the client registered as `slot`, `token` to the client's
    /// publisher, and sends it to the cycle thread (see `shm::outputs`).
    fn connect_outputs(&mut self, slot: u32, token: u64) -> Result<(), Refusal> {
        if !self.registry.is_registered(slot, token) {
            return Err(Refusal::UnknownClient);
        }
        let port = match self.pending_outputs.remove(&slot) {
            Some((t, port)) if t == token => port,
            _ => return Err(Refusal::UnknownClient),
        };
        let bounds = outputs::connect(&port, &self.info.instance).map_err(|e| {
            Refusal::OutputsNotConnected {
                detail: e.to_string(),
            }
        })?;
        // The connection's file is this process's: the client's publisher opens it next.
        access::share_now();
        self.shared
            .outputs
            .send(outputs::Arrival {
                slot,
                token,
                port: Box::new(port),
                bounds,
            })
            .map_err(|_| Refusal::ServerBusy)
    }

    /// Whether the cycle is, or is becoming, CLEAR or OPERATE.
    fn online(&self) -> bool {
        self.shared.mode() != Mode::Offline
            || self.shared.target_mode.load(Ordering::Acquire) != Mode::Offline.as_u32()
    }

    /// Handles one request: the core ones here, the rest by the role's services, if the role
    /// procimgd plays has them.
    pub fn handle(&mut self, req: Request) -> Response {
        let online = self.online();
        match req {
            Request::Core(r) => self.handle_core(r),
            Request::Controller(r) => match self.role.controller_services() {
                Some(services) => services.handle(r, online, &mut self.notices),
                None => wrong_role(self.role.name(), r.service()),
            },
            Request::Device(r) => match self.role.device_services() {
                Some(services) => services.handle(r, online, &mut self.notices),
                None => wrong_role(self.role.name(), r.service()),
            },
        }
    }

    /// Handles one of the requests either role answers.
    fn handle_core(&mut self, req: CoreRequest) -> Response {
        let shared = &*self.shared;
        let result = match req {
            CoreRequest::Register {
                name,
                pid,
                role,
                newcycle,
                node_id,
            } => {
                let registered = self
                    .registry
                    .register(shared, name, pid, role, newcycle, node_id)
                    .and_then(|(slot, token)| {
                        self.make_outputs(slot, token).map(|()| (slot, token))
                    });
                return match registered {
                    Ok((slot, token)) => Response::Registered {
                        slot,
                        token,
                        generation: self.info.generation,
                        layout_hash: self.tables.hash,
                        server_pid: std::process::id(),
                    },
                    Err(r) => Response::Refused(r),
                };
            }
            CoreRequest::Unregister { slot, token } => {
                let done = self.registry.unregister_checked(shared, slot, token);
                if done.is_ok() {
                    self.pending_outputs.remove(&slot);
                }
                done
            }
            CoreRequest::ConnectOutputs { slot, token } => self.connect_outputs(slot, token),
            CoreRequest::Claim {
                slot,
                token,
                submodules,
            } => {
                let first =
                    self.registry
                        .claim(shared, &self.tables.submodules, slot, token, &submodules);
                if !matches!(first, Err(Refusal::ClaimHeld { .. })) {
                    first
                } else {
                    // The holder may have died since the last reaping: a program restarted at
                    // once finds its dead predecessor's claims. Look now, not a liveness
                    // period later.
                    let gone = self.reap_dead_clients();
                    if gone.is_empty() {
                        first
                    } else {
                        self.reaped_early.extend(gone);
                        self.registry.claim(
                            &self.shared,
                            &self.tables.submodules,
                            slot,
                            token,
                            &submodules,
                        )
                    }
                }
            }
            CoreRequest::Release {
                slot,
                token,
                submodules,
            } => self.registry.release(shared, slot, token, &submodules),
            CoreRequest::SetMode { mode } => self.set_mode(mode),
            CoreRequest::Status => return Response::Status(Box::new(self.status())),
            CoreRequest::Subscribe {
                subscriber,
                name,
                pid,
                node_id,
                acknowledge_alarms,
            } => {
                self.role.subscribe(
                    subscriber,
                    Subscriber {
                        name,
                        pid,
                        node_id,
                        acknowledges: acknowledge_alarms,
                    },
                );
                Ok(())
            }
            CoreRequest::Unsubscribe { subscriber } => self.role.unsubscribe(subscriber),
            CoreRequest::Histograms => {
                self.stats.collect();
                let cycles = crate::stats::load(&self.shared.counters.cycles);
                return Response::Histograms(Box::new(self.stats.histograms(cycles)));
            }
            CoreRequest::Force {
                space,
                address,
                data,
            } => self
                .change_forces(|f, t| f.force(t, space, address, &data))
                .inspect(|()| {
                    tracing::info!(
                        "forced {space} {address}..{}: {}",
                        address as usize + data.len().saturating_sub(1),
                        hex(&data)
                    )
                }),
            CoreRequest::Restart {
                reply_to,
                configuration,
                clients,
            } => {
                return match self.begin_restart(reply_to, configuration, clients) {
                    Ok(()) => Response::Accepted,
                    Err(r) => Response::Refused(r),
                };
            }
            CoreRequest::SetTypeOfStation { text } => {
                // At most 255 bytes, cut at a character.
                let mut end = text.len().min(255);
                while !text.is_char_boundary(end) {
                    end -= 1;
                }
                tracing::info!("type of station {:?} from the next start on", &text[..end]);
                self.type_of_station = Some(text[..end].to_owned());
                Ok(())
            }
            CoreRequest::Unforce {
                space,
                address,
                length,
            } => match address {
                None => self
                    .change_forces(|f, _| {
                        f.clear();
                        Ok(())
                    })
                    .inspect(|()| tracing::info!("every force ended")),
                Some(a) => self
                    .change_forces(|f, t| f.unforce(t, space, a, length))
                    .inspect(|()| tracing::info!("force of {space} {a} ended")),
            },
        };
        match result {
            Ok(()) => Response::Done,
            Err(r) => Response::Refused(r),
        }
    }

    /// Changes the force table and hands the cycle its new plan; nothing changes when the
    /// cycle has not taken the previous plans (it is stalled).
    fn change_forces(
        &mut self,
        change: impl FnOnce(&mut ForceTable, &Tables) -> Result<(), Refusal>,
    ) -> Result<(), Refusal> {
        let mut next = self.forces.clone();
        change(&mut next, &self.tables)?;
        let plan = Box::new(next.plan(&self.tables));
        self.shared
            .send_force_plan(plan)
            .map_err(|_| Refusal::ServerBusy)?;
        self.forces = next;
        Ok(())
    }

    /// Waits up to `wait` for work: a client's request or what the role reports (the
    /// doorbell rings for both), and hands the role's reports to the subscribers. Without a
    /// doorbell, waits for the role's reports only.
    pub fn idle(&mut self, wait: Duration) {
        if self
            .shared
            .wait_for_control_work(self.rung_before_round, wait)
        {
            self.role.poll(Duration::ZERO, &mut self.notices);
        } else {
            self.role.poll(wait, &mut self.notices);
        }
    }

    /// Publishes what the role reported on its way out; for after its threads have ended
    /// (see [`RoleServices::finish`]).
    pub fn finish(&mut self) {
        self.role.finish(&mut self.notices);
    }

    /// Whether the role holds no connection any more (see [`RoleServices::released`]).
    pub fn released(&self) -> bool {
        self.role.released()
    }

    /// Asks the cycle for a mode; refused while an earlier change is still under way.
    pub fn set_mode(&self, mode: Mode) -> Result<(), Refusal> {
        let pending = Mode::from_u32(self.shared.target_mode.load(Ordering::Acquire))
            .unwrap_or(Mode::Offline);
        if pending != self.shared.mode() {
            return Err(Refusal::ModeChangePending { pending });
        }
        if !self.shared.command(Command::SetMode(mode)) {
            return Err(Refusal::ServerBusy);
        }
        self.shared
            .target_mode
            .store(mode.as_u32(), Ordering::Release);
        Ok(())
    }

    /// The state of the server.
    pub fn status(&self) -> StatusReport {
        let c = &self.shared.counters;
        let clients = self
            .registry
            .clients()
            .map(|(slot, e)| ClientReport {
                slot,
                name: e.name.clone(),
                pid: e.pid,
                role: e.role,
                opfaults: load(&c.client_opfaults[slot as usize % MAX_CLIENTS]),
                last_opfault_cycle: load(&c.client_last_opfault[slot as usize % MAX_CLIENTS]),
                claims: e
                    .claims
                    .iter()
                    .filter_map(|&s| {
                        let t = self.tables.submodules.get(s as usize)?;
                        Some(ClaimReport {
                            submodule: s,
                            device: self.tables.device_name(t.device as usize).to_string(),
                            slot: t.slot,
                            subslot: t.subslot,
                            output_address: t.output_address,
                            output_length: t.output_length,
                        })
                    })
                    .collect(),
            })
            .collect();
        let station = self.role.station();
        StatusReport {
            instance: self.info.instance.clone(),
            server_version: env!("CARGO_PKG_VERSION").to_owned(),
            role: if station.is_some() {
                "device"
            } else {
                "controller"
            }
            .to_owned(),
            station,
            controller: self.role.controller(),
            pid: std::process::id(),
            generation: self.info.generation,
            layout_hash: self.tables.hash,
            mode: self.shared.mode(),
            cycle_ns: self.info.cycle_ns,
            opdone_deadline_ns: self.info.opdone_deadline_ns,
            cycle_count: load(&c.cycles),
            overruns: load(&c.overruns),
            opfaults: load(&c.opfaults),
            realtime: c.realtime.load(Ordering::Relaxed),
            rt_heap_allocations: crate::sys::rt_alloc::rt_heap_allocations(),
            rt_setup_allocations: crate::sys::rt_alloc::rt_setup_allocations(),
            receive_errors: load(&c.receive_errors),
            unpublished_images: load(&c.unpublished_images),
            input_images_locked_bytes: self.shared.input_reserve.ready_bytes() as u64,
            unready_image_loans: self.shared.input_reserve.unready_loans(),
            rejected_writes: load(&c.rejected_writes),
            outputs_in_place: load(&c.outputs_in_place),
            wakeup_latency: self.stats.wakeup(),
            handshake_round_trip: self.stats.handshake(),
            opdone_one_way: self.stats.opdone(),
            cycle_work: self.stats.work(),
            clients,
            devices: self.role.devices(),
            network: self.role.network(),
            subscribers: self.role.subscribers(),
            forces: self.forces.reports(&self.tables),
        }
    }

    /// Removes clients whose process is gone, and cleans up what dead processes left.
    fn reap_dead_clients(&mut self) -> Vec<String> {
        let mut alive = HashSet::new();
        // A dead client's ports are removed a round after it is unregistered: removed first,
        // its output publisher would vanish under the cycle thread's port, which would then
        // unmap the client's samples in the cycle instead of handing the port back.
        let registered: HashSet<String> = self
            .registry
            .clients()
            .map(|(_, c)| c.node_id.clone())
            .collect();
        let listed = Node::<Ipc>::list(iox2_config(), |state| {
            match state {
                NodeState::Alive(v) => {
                    alive.insert(v.id().to_string());
                }
                NodeState::Dead(v) => {
                    if !registered.contains(&v.id().to_string()) {
                        let _ = v.try_remove_stale_resources();
                    }
                }
                NodeState::Inaccessible(id) | NodeState::Undefined(id) => {
                    // Cannot tell: keep such clients rather than drop a live one.
                    alive.insert(id.to_string());
                }
            }
            CallbackProgression::Continue
        });
        if listed.is_err() {
            // An incomplete list says nothing about the clients left out: reap next time.
            return Vec::new();
        }
        let dead: Vec<u32> = self
            .registry
            .clients()
            .filter(|(_, c)| !alive.contains(&c.node_id))
            .map(|(s, _)| s)
            .collect();
        let mut gone: Vec<String> = dead
            .into_iter()
            .filter_map(|slot| {
                self.pending_outputs.remove(&slot);
                self.registry.unregister(&self.shared, slot)
            })
            .map(|c| format!("{} (pid {})", c.name, c.pid))
            .collect();
        gone.extend(self.role.reap(&alive));
        gone
    }

    /// The registry (for tests and shutdown).
    pub fn registry(&self) -> &Registry {
        &self.registry
    }
}

fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The refusal of a request of the role procimgd does not play.
fn wrong_role(role: &str, service: &str) -> Response {
    Response::Refused(Refusal::WrongRole {
        role: role.to_owned(),
        service: service.to_owned(),
    })
}
