// SPDX-License-Identifier: MIT OR Apache-2.0
//! An engine as procimgd runs it, in this process: the control side on a thread of its own
//! (it answers the clients' registrations and claims), the cycle engine on the benchmark's
//! thread with a null or a PROFINET IO system, and asynchronous clients on the benchmark's
//! thread too, each writing its share of the outputs every cycle.
//!
//! The clients do their work between cycles and are not timed: what is timed is
//! `Engine::run_cycle` alone, which merges the samples the clients sent since the last cycle.
//! Asynchronous clients are used because a synchronous client's OPDONE would have to arrive
//! inside the cycle from another thread, which times the scheduler of this 2-vCPU machine
//! rather than the server; the merge itself is the same code for both.
//!
//! Each client registers and claims through the client library; its output samples are then
//! sent by a [`Writer`] with the bytes the library's buffered write (`data_write_cache` of
//! every submodule, then `data_write_cache_flush`) would send. The library resolves every
//! address by a linear search, which makes writing 4096 submodules take milliseconds per
//! cycle on the client side: that would stretch each benchmark to minutes without changing
//! what the server does.

use super::loop_nic::{LoopNic, NicCounters, OWN_MAC};
use super::null_io::NullIo;
use super::shape::{self, Shape};
use iceoryx2::node::Node;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::port::update_connections::UpdateConnections;
use iceoryx2::prelude::ServiceName;
use procimg_client::{ControlHandle, DEFAULT_CONTROL_TIMEOUT};
use procimg_control::{ClientRole, CoreRequest, Response};
use procimg_profinet::controller::cyclic::CyclicAr;
use procimg_runtime::config::Config;
use procimg_runtime::cycle::{Engine, EngineSettings, Publication, Shared};
use procimg_runtime::image::{Image, Tables};
use procimg_runtime::io::pnio::PnioIo;
use procimg_runtime::io::pnio::channel::{Channel, ToCycle};
use procimg_runtime::io::{CycleTime, IoSystem};
use procimg_runtime::roles::controller::{ControllerServices, SIM_CONTROLLER_IP};
use procimg_runtime::server::{Control, ServerInfo};
use procimg_runtime::shm::outputs::IpcThreadsafe;
use procimg_runtime::shm::{ControlPorts, CyclePorts};
use procimg_runtime::shm::{Ipc, server_node_of};
use procimg_runtime::stats::stats_channel;
use procimg_runtime::sys::clock::now_ns;
use procimg_shm_layout::{
    CLIENT_SET_OUTPUT_IOPS, CLIENT_WROTE_OUTPUTS, IMAGE_MAGIC, IOXS_GOOD, ImageHeader, Mode,
    OutputHeader,
};
use procimg_testkit::world::{self, Setup, World};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

/// Which IO system the engine drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Io {
    /// [`NullIo`]: the engine alone.
    Null,
    /// [`PnioIo`] over a [`LoopNic`]: one input and one output frame per device and cycle.
    Pnio,
    /// The same in the IO device role: the shape's one device is procimgd's station, the
    /// loop interface plays the PLC (one output frame consumed, one input frame produced
    /// per cycle), the image's directions are the device's.
    PnioDevice,
}

/// Cycles of the configuration's cycle time the bring-up of [`exchanges`] may take.
const BRING_UP_CYCLES: u64 = 1_000;

/// The exchanges the controller hands over to the cycle thread once every device of
/// `config` is up: the simulated devices brought up in the test kit's world, so that the
/// cycle runs exactly what procimgd's controller sets up.
pub fn exchanges(config: &Config) -> Vec<CyclicAr> {
    let plans = procimg_runtime::roles::controller::plan_devices(config)
        .expect("the shape fits PROFINET frames");
    let id = world::controller_identity(OWN_MAC, SIM_CONTROLLER_IP, "procimgd-bench");
    let setup = Setup {
        period_ns: config.cycle_ns,
        start_ns: config.cycle_ns,
        ..Setup::new(id, plans)
    };
    let mut w = World::direct(
        setup,
        procimg_runtime::roles::controller::sim_plant::devices(config),
    );
    w.set_online(true);
    let up = w.step_until_running(BRING_UP_CYCLES);
    assert!(
        up.is_some(),
        "the devices did not come up: {:?}, {:?}",
        w.states(),
        w.events()
    );
    w.port().exchanges().cloned().collect()
}

/// The device's end of the controller's exchanges: what a device consumes is what the
/// controller produces, and the other way round.
fn mirrored(ars: Vec<CyclicAr>) -> Vec<CyclicAr> {
    ars.into_iter()
        .map(|ar| {
            CyclicAr::from_maps(
                ar.device,
                ar.epoch,
                (OWN_MAC, ar.peer),
                ar.output,
                ar.input,
                ar.timing,
                ar.submodules,
            )
        })
        .collect()
}

/// The PROFINET IO system of `config` over a [`LoopNic`], with every device's exchange
/// already handed to it (it starts them at its first `receive`); with `device`, the
/// device's end of the one exchange.
pub fn pnio_io(
    config: &Config,
    device: bool,
    counters: Arc<NicCounters>,
) -> (PnioIo<LoopNic>, Arc<Channel>) {
    let ars = if device {
        mirrored(exchanges(config))
    } else {
        exchanges(config)
    };
    let nic = LoopNic::new(&ars, counters);
    // Every device is up: their exchanges cover the whole submodule table, in order.
    let ranges = ars.iter().map(|ar| ar.submodules.clone()).collect();
    let channel = Arc::new(Channel::new());
    for ar in ars {
        let queued = channel.to_cycle.push(ToCycle::Start(Box::new(ar))).is_ok();
        assert!(queued, "more devices than the start queue holds");
    }
    let io = PnioIo::new(nic, channel.clone(), ranges, config.cycle_ns);
    (io, channel)
}

/// Sends one client's output samples: every submodule it owns written, IOPS GOOD.
struct Writer {
    publisher: Publisher<IpcThreadsafe, [u8], OutputHeader>,
    /// The payload as the client library would fill it.
    payload: Vec<u8>,
    header: OutputHeader,
}

impl Writer {
    /// The publisher of the client registered with `control` as `header` says, connected to
    /// the server's subscriber, as the client library does it.
    fn new(
        node: &Node<IpcThreadsafe>,
        control: &ControlHandle,
        generation: u64,
        tables: &Tables,
        mine: &[usize],
        header: OutputHeader,
    ) -> Writer {
        let reg = procimg_client::Registration {
            generation,
            token: header.client_token,
            role: procimg_client::ClientRole::Asynchronous,
        };
        let (_, publisher) = procimg_client::output_publisher(
            node,
            control.instance(),
            reg,
            tables.layout.output_payload_size as usize,
        )
        .expect("output publisher");
        control
            .request_done(CoreRequest::ConnectOutputs {
                slot: header.client_slot,
                token: header.client_token,
            })
            .expect("the server connects to the outputs");
        // Connected now, so that the first sample already reaches the server.
        publisher
            .update_connections()
            .expect("connect to the server's subscriber");
        let mut payload = vec![0u8; tables.layout.output_payload_size as usize];
        for &s in mine {
            let e = tables.submodules[s];
            let at = e.output_offset as usize;
            payload[at..at + e.output_length as usize].fill(s as u8);
            let cs = e.client_status_offset as usize;
            payload[cs..cs + 4].copy_from_slice(&[
                IOXS_GOOD,
                0,
                CLIENT_WROTE_OUTPUTS | CLIENT_SET_OUTPUT_IOPS,
                0,
            ]);
        }
        Writer {
            publisher,
            payload,
            header,
        }
    }

    fn send(&mut self, k: u64) {
        let sample = self
            .publisher
            .loan_slice_uninit(self.payload.len())
            .expect("loan an output sample");
        let mut sample = sample.write_from_slice(&self.payload);
        self.header.cycle_number = k;
        self.header.sent_ns = now_ns();
        *sample.user_header_mut() = self.header;
        let delivered = sample.send().expect("send outputs");
        assert_eq!(delivered, 1, "the server's subscriber took the sample");
    }
}

/// One client: registered and holding its claims, as the client library does it.
struct BenchClient {
    writer: Option<Writer>,
    control: ControlHandle,
    slot: u32,
    token: u64,
    /// A node of its own: procimgd takes a second registration from one node for a retry of
    /// the first, and replaces it. Dropped after the writer, whose port lives on it.
    node: Node<IpcThreadsafe>,
}

impl BenchClient {
    /// Registers an asynchronous client named `name` with a node of its own, and claims
    /// `mine`.
    fn register(instance: &str, name: &str, mine: &[usize]) -> BenchClient {
        let node = server_node_of::<IpcThreadsafe>(instance, name).expect("client node");
        let control = ControlHandle::open(instance, name).expect("control handle");
        let registered = control.request(
            CoreRequest::Register {
                name: name.to_string(),
                pid: std::process::id(),
                role: ClientRole::Asynchronous,
                newcycle: false,
                node_id: node.id().to_string(),
            },
            DEFAULT_CONTROL_TIMEOUT,
        );
        let Ok(Response::Registered { slot, token, .. }) = registered else {
            panic!("registration: {registered:?}");
        };
        for chunk in mine.chunks(512) {
            let submodules = chunk.iter().map(|&s| s as u32).collect();
            control
                .request_done(CoreRequest::Claim {
                    slot,
                    token,
                    submodules,
                })
                .expect("claim");
        }
        BenchClient {
            writer: None,
            control,
            slot,
            token,
            node,
        }
    }

    fn writer(&mut self) -> &mut Writer {
        self.writer.as_mut().expect("made with the client")
    }
}

impl Drop for BenchClient {
    fn drop(&mut self) {
        // The writer first; unregistering ends the claims.
        self.writer = None;
        let _ = self.control.request_done(CoreRequest::Unregister {
            slot: self.slot,
            token: self.token,
        });
    }
}

/// The control thread, polling fast while clients attach and leave and slowly while the
/// benchmark measures (so that it takes as little of the machine as possible).
struct ControlThread {
    stop: Arc<AtomicBool>,
    quiet: Arc<AtomicBool>,
    handle: Option<JoinHandle<()>>,
}

impl ControlThread {
    fn start(instance: &str, generation: u64, tables: &Tables, shared: Arc<Shared>) -> Self {
        let (stop, quiet) = (
            Arc::new(AtomicBool::new(false)),
            Arc::new(AtomicBool::new(false)),
        );
        let (tables, instance) = (tables.clone(), instance.to_string());
        let (s, q) = (stop.clone(), quiet.clone());
        let (ready_tx, ready_rx) = std::sync::mpsc::channel();
        let (_, collector) = stats_channel();
        // iceoryx2 ports stay on the thread that made them: the control ports are made there.
        let handle = std::thread::spawn(move || {
            let ports = ControlPorts::create(
                &instance,
                generation,
                &tables,
                shape::CYCLE_NS,
                shape::CYCLE_NS / 2,
            )
            .expect("control ports");
            let info = ServerInfo {
                instance,
                generation,
                cycle_ns: shape::CYCLE_NS,
                opdone_deadline_ns: shape::CYCLE_NS / 2,
            };
            let services = Box::new(ControllerServices::unlinked(&tables));
            let mut control = Control::new(info, tables, ports, shared, collector, services);
            let _ = ready_tx.send(());
            while !s.load(Ordering::Acquire) {
                control.poll();
                let ms = if q.load(Ordering::Acquire) { 50 } else { 1 };
                std::thread::sleep(Duration::from_millis(ms));
            }
        });
        ready_rx.recv().expect("the control thread started");
        ControlThread {
            stop,
            quiet,
            handle: Some(handle),
        }
    }
}

impl Drop for ControlThread {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Release);
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

/// An engine with its IO system and clients.
pub struct Rig {
    /// Instance name.
    pub instance: String,
    /// The tables.
    pub tables: Tables,
    /// Shared state (counters).
    pub shared: Arc<Shared>,
    /// The PROFINET channel (counters), with [`Io::Pnio`].
    pub channel: Option<Arc<Channel>>,
    /// What the loop interface saw.
    pub nic: Arc<NicCounters>,
    clients: Vec<BenchClient>,
    engine: Option<Engine>,
    control: Option<ControlThread>,
    k: u64,
}

impl Rig {
    /// A rig of `shape` with `io` and `clients` clients, the outputs split evenly between
    /// them (client i owns a contiguous share of the submodules), already in OPERATE.
    pub fn new(instance: &str, shape: Shape, io: Io, clients: usize) -> Rig {
        let config = shape::config(instance, shape);
        let tables = match io {
            Io::PnioDevice => Tables::from_config(&shape::as_station(&config)),
            _ => Tables::from_config(&config),
        }
        .expect("the shape lays out");
        let generation = now_ns();
        let shared = Arc::new(Shared::new(tables.submodules.len()));
        shared
            .target_mode
            .store(Mode::Operate.as_u32(), Ordering::Release);
        let control = (clients > 0)
            .then(|| ControlThread::start(instance, generation, &tables, shared.clone()));
        let ports = CyclePorts::create(instance, generation, &tables).expect("cycle ports");
        let nic = Arc::new(NicCounters::default());
        let (io, channel): (Box<dyn IoSystem>, _) = match io {
            Io::Null => (Box::new(NullIo), None),
            Io::Pnio | Io::PnioDevice => {
                let (io, channel) = pnio_io(&config, io == Io::PnioDevice, nic.clone());
                (Box::new(io), Some(channel))
            }
        };
        let settings = EngineSettings {
            cycle_ns: config.cycle_ns,
            opdone_deadline_ns: config.opdone_deadline_ns,
            late_policy: config.late_policy,
            output_timing: config.output_timing,
            opdone_wait: config.cycle_thread.opdone_wait,
            opdone_spin_ns: config.cycle_thread.opdone_spin_ns,
            generation,
        };
        let (recorder, _) = stats_channel();
        let engine = Engine::new(settings, &tables, ports, io, shared.clone(), recorder);
        let n = tables.submodules.len();
        let clients = (0..clients)
            .map(|i| {
                let mine: Vec<usize> = (i * n / clients..(i + 1) * n / clients).collect();
                let mut client = BenchClient::register(instance, &format!("{instance}-{i}"), &mine);
                // The control side records the claim before it answers.
                assert_eq!(shared.owner(mine[0]), client.token, "the claim is recorded");
                let header = OutputHeader {
                    magic: IMAGE_MAGIC,
                    layout_hash: tables.hash,
                    cycle_number: 0,
                    client_token: client.token,
                    client_slot: client.slot,
                    flags: 0,
                    sent_ns: 0,
                };
                let writer = Writer::new(
                    &client.node,
                    &client.control,
                    generation,
                    &tables,
                    &mine,
                    header,
                );
                client.writer = Some(writer);
                client
            })
            .collect();
        let mut rig = Rig {
            instance: instance.to_string(),
            tables,
            shared,
            channel,
            nic,
            clients,
            engine: Some(engine),
            control,
            k: 0,
        };
        // OFFLINE → CLEAR → OPERATE, every Join applied, every connection set up.
        for _ in 0..8 {
            rig.prepare();
            rig.cycle();
        }
        assert_eq!(rig.engine().mode(), Mode::Operate);
        if let Some(c) = &rig.control {
            c.quiet.store(true, Ordering::Release);
        }
        rig
    }

    fn engine(&mut self) -> &mut Engine {
        self.engine.as_mut().expect("the engine lives until drop")
    }

    /// What happens between two cycles, untimed: every client sends all its outputs (one
    /// sample each); the engine sets up connections, as the cycle thread does before every
    /// cycle.
    pub fn prepare(&mut self) {
        let k = self.k;
        for c in &mut self.clients {
            c.writer().send(k);
        }
        self.engine().maintain_connections();
    }

    /// Runs one cycle; returns the ns it took.
    pub fn cycle(&mut self) -> u64 {
        self.k += 1;
        let k = self.k;
        let t0 = now_ns();
        self.engine().run_cycle(k, t0);
        now_ns() - t0
    }

    /// `iters` cycles, each prepared untimed; the sum of the cycles' times.
    pub fn timed_cycles(&mut self, iters: u64) -> Duration {
        let mut ns = 0;
        for _ in 0..iters {
            self.prepare();
            ns += self.cycle();
        }
        Duration::from_nanos(ns)
    }

    /// Panics unless the cycles measured did the work they claim: no write refused, and with
    /// PROFINET every frame taken and no watchdog run out.
    pub fn verify(&self) {
        let c = &self.shared.counters;
        assert_eq!(
            c.rejected_writes.load(Ordering::Relaxed),
            0,
            "writes refused"
        );
        assert_eq!(
            c.receive_errors.load(Ordering::Relaxed),
            0,
            "receive errors"
        );
        if let Some(ch) = &self.channel {
            let n = &ch.counters;
            let bad = [&n.malformed, &n.unknown, &n.stale, &n.watchdog_expiries]
                .map(|a| a.load(Ordering::Relaxed));
            assert_eq!(bad, [0; 4], "frames refused or exchanges stopped");
            let per_device = n.cyclic_frames.load(Ordering::Relaxed) / self.k;
            assert!(per_device >= self.tables.devices.len() as u64 - 1);
        }
    }
}

impl Drop for Rig {
    fn drop(&mut self) {
        // Clients unregister through the control thread, so they go first; the engine's
        // ports after the control side, as procimgd ends.
        self.clients.clear();
        self.control = None;
        self.engine = None;
    }
}

/// The PROFINET IO system alone, driven with injected time (one cycle per call pair).
pub struct PnioRig {
    io: PnioIo<LoopNic>,
    /// The image the frames go to and come from.
    pub image: Image,
    /// The PROFINET channel (counters).
    pub channel: Arc<Channel>,
    /// What the loop interface saw.
    pub nic: Arc<NicCounters>,
    k: u64,
}

impl PnioRig {
    /// The IO system of `shape` with every device exchanging.
    pub fn new(shape: Shape) -> PnioRig {
        let config = shape::config("bench-pnio", shape);
        let tables = Tables::from_config(&config).expect("the shape lays out");
        let nic = Arc::new(NicCounters::default());
        let (io, channel) = pnio_io(&config, false, nic.clone());
        let mut rig = PnioRig {
            io,
            image: Image::new(&tables),
            channel,
            nic,
            k: 0,
        };
        rig.receive();
        rig
    }

    fn time(&self) -> CycleTime {
        CycleTime {
            cycle: self.k,
            now_ns: self.k * shape::CYCLE_NS,
        }
    }

    /// One cycle's receive: every device's input frame into the image.
    pub fn receive(&mut self) {
        self.k += 1;
        let t = self.time();
        self.io.receive(t, Mode::Operate, &mut self.image);
    }

    /// One cycle's send: every device's output frame built from the image.
    pub fn send(&mut self) {
        let t = self.time();
        self.io.send(t, Mode::Operate, &mut self.image);
    }

    /// Panics unless every frame was taken and every exchange still runs.
    pub fn verify(&self) {
        let n = &self.channel.counters;
        let bad = [&n.malformed, &n.unknown, &n.stale, &n.watchdog_expiries]
            .map(|a| a.load(Ordering::Relaxed));
        assert_eq!(bad, [0; 4], "frames refused or exchanges stopped");
    }
}

/// The input publication of `Engine::run_cycle` (engine.rs) with nothing received and no
/// client writing, on the server's real input port, with one subscriber connected: carry
/// every input and output over from the last image into the sample loaned for this one,
/// write the status bytes and the header, send, loan the next.
pub struct PublishRig {
    image: Image,
    /// The samples the image is built in and published from.
    publication: Publication,
    header: ImageHeader,
    layout: procimg_shm_layout::ImageLayout,
    /// Bytes the last publication carried over.
    last_carried: usize,
    // Dropped before the publisher's ports.
    _reader: Subscriber<Ipc, [u8], ImageHeader>,
    _reader_node: Node<Ipc>,
    ports: CyclePorts,
}

impl PublishRig {
    /// The publisher of an image of `shape`.
    pub fn new(instance: &str, shape: Shape) -> PublishRig {
        let tables = Tables::from_config(&shape::config(instance, shape)).expect("lays out");
        let generation = now_ns();
        let ports = CyclePorts::create(instance, generation, &tables).expect("cycle ports");
        let reader_node =
            procimg_runtime::shm::server_node(instance, "reader").expect("reader node");
        let name = procimg_control::input_service(instance, generation);
        let reader = reader_node
            .service_builder(&ServiceName::new(&name).expect("service name"))
            .publish_subscribe::<[u8]>()
            .user_header::<ImageHeader>()
            .open()
            .expect("open the input service")
            .subscriber_builder()
            .create()
            .expect("reader");
        let header = ImageHeader::new(tables.hash, generation);
        PublishRig {
            image: Image::new(&tables),
            publication: Publication::new(),
            header,
            layout: tables.layout,
            last_carried: 0,
            _reader: reader,
            _reader_node: reader_node,
            ports,
        }
    }

    /// Bytes copied into the sample by the last publication: the status bytes and padding,
    /// and what was carried over (nothing once every sample holds the image, since nothing
    /// arrives here).
    pub fn bytes(&self) -> usize {
        let l = &self.layout;
        (l.input_payload_size - l.input_size - l.output_size) as usize + self.last_carried
    }

    /// One publication; whether it was sent.
    pub fn publish(&mut self) -> bool {
        let carried = self.image.carried_bytes();
        self.publication.begin(&mut self.ports, &mut self.image);
        self.image.carry_over_inputs();
        self.header.cycle.cycle_number += 1;
        let sent =
            self.publication
                .finish(&mut self.ports, &mut self.image, &mut self.header, false);
        self.publication.loan_next(&mut self.ports, &mut self.image);
        self.image.carry_over_outputs();
        self.last_carried = (self.image.carried_bytes() - carried) as usize;
        sent
    }
}
