// SPDX-License-Identifier: MIT OR Apache-2.0
//! The PROFINET roles procimgd plays, and the one interface each plugs into.
//!
//! A role is the protocol's side of one end of a PROFINET AR: the IO controller (the PC is
//! the PLC, [`controller`]) or the IO device (the PC is a field device on another PLC). The
//! daemon around it is the same for every role, and a role meets it in three places:
//!
//! - **the cycle thread** runs the cyclic exchange of every AR the role has set up
//!   ([`crate::io::pnio`]): it consumes one frame into the image and produces one frame from
//!   it, whichever end of the AR it is; the role hands it ARs to start and stop;
//! - **the acyclic thread** ([`crate::acyclic`]) drives the role's sans-IO state machines
//!   through [`Role`]: frames and datagrams in, reports of the cycle in, commands from
//!   clients in, `poll(now)`; [`Effect`]s out, which the thread carries out;
//! - **the control side** ([`crate::server::Control`]) answers the core requests (claims,
//!   modes, status, forces) itself and hands the role's requests (records, activation,
//!   alarms, diagnosis) to the role's [`RoleServices`], which also turns what the role
//!   reports into notifications for subscribers.
//!
//! Starting a role ([`controller::start`]) gives a [`RoleSystem`]: the factory of the cycle
//! thread's IO system, the running acyclic thread, and the role's client services.

pub mod address;
pub mod controller;
pub mod device;
pub mod port_watch;
pub mod subscribers;

use crate::cycle::thread::IoFactory;
use crate::io::pnio::PnioIo;
use crate::io::pnio::channel::Channel;
use crate::shm::Notices;
use crate::stats::load;
use procimg_control::{
    ControllerRequest, DeviceReport, DeviceRequest, NetworkReport, Refusal, Response,
    StationReport, SubscriberReport,
};
use procimg_nic::Nic;
use procimg_profinet::cyclic::CyclicAr;
use std::collections::HashSet;
use std::net::SocketAddrV4;
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;
use subscribers::Subscriber;

/// What a role asks the acyclic thread to do.
#[derive(Debug)]
pub enum Effect<E> {
    /// Send an Ethernet frame (DCP, alarms) through the cycle thread's interface.
    Frame(Vec<u8>),
    /// Send a UDP datagram from port 34964.
    Datagram {
        /// The peer.
        to: SocketAddrV4,
        /// The RPC PDU.
        payload: Vec<u8>,
    },
    /// Tell the network stack that the peer at `ip` has the MAC address `mac` (DCP found it
    /// there), before datagrams go to it: they then leave at once instead of waiting in the
    /// stack's ARP queue, where a repeated call would wait beside the first one and reach the
    /// peer together with it.
    Neighbour {
        /// The peer's IP address.
        ip: std::net::Ipv4Addr,
        /// Its MAC address.
        mac: procimg_profinet::wire::MacAddress,
    },
    /// Start (or replace) the cyclic exchange of an AR on the cycle thread.
    Start(Box<CyclicAr>),
    /// Stop the cyclic exchange of the AR of peer `device`.
    Stop {
        /// The peer's index (a device of the controller, an AR of the device role).
        device: usize,
    },
    /// Tell the role's client services (and the log) what happened.
    Event(E),
}

/// What the cycle thread reports about an AR's cyclic exchange.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CycleReport {
    /// The first valid frame of the AR arrived.
    DataStarted {
        /// The peer's index.
        device: usize,
        /// The AR's epoch.
        epoch: u32,
    },
    /// No frame within the watchdog time: the cycle thread stopped the exchange.
    WatchdogExpired {
        /// The peer's index.
        device: usize,
        /// The AR's epoch.
        epoch: u32,
    },
}

/// Datagrams of port 34964 the role dropped, published by the acyclic thread for the status
/// report.
#[derive(Default)]
pub struct DatagramCounters {
    /// RPC datagrams that did not parse.
    pub malformed: std::sync::atomic::AtomicU64,
    /// RPC datagrams nothing was waiting for.
    pub unexpected: std::sync::atomic::AtomicU64,
}

/// Datagrams of port 34964 the role dropped, for the status report.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DroppedDatagrams {
    /// Datagrams that did not parse.
    pub malformed: u64,
    /// Datagrams nothing was waiting for.
    pub unexpected: u64,
}

/// One role's protocol state machines as the acyclic thread drives them. Sans-IO: time comes
/// in as `now_ns` (`CLOCK_MONOTONIC`), everything to send goes out as [`Effect`]s.
pub trait Role: Send + 'static {
    /// What the role's client services ask of it.
    type Command: Send + 'static;
    /// What the role tells its client services.
    type Event: Send + 'static;

    /// The role goes online (the cycle is, or is becoming, CLEAR or OPERATE) or offline
    /// (it releases its ARs).
    fn set_online(&mut self, online: bool, now_ns: u64, out: &mut Vec<Effect<Self::Event>>);
    /// A command from the client services.
    fn command(&mut self, command: Self::Command, now_ns: u64, out: &mut Vec<Effect<Self::Event>>);
    /// An acyclic PROFINET frame (DCP, alarms) the cycle thread received.
    fn on_frame(&mut self, frame: &[u8], now_ns: u64, out: &mut Vec<Effect<Self::Event>>);
    /// A datagram on port 34964.
    fn on_datagram(
        &mut self,
        from: SocketAddrV4,
        payload: &[u8],
        now_ns: u64,
        out: &mut Vec<Effect<Self::Event>>,
    );
    /// What the cycle thread reports.
    fn on_cycle(&mut self, report: CycleReport, now_ns: u64, out: &mut Vec<Effect<Self::Event>>);
    /// Timers: retransmissions, timeouts, the next step of a connection.
    fn poll(&mut self, now_ns: u64, out: &mut Vec<Effect<Self::Event>>);
    /// When [`Role::poll`] wants to be called next, if at a time of its own.
    fn deadline(&self) -> Option<u64>;
    /// The datagrams dropped so far.
    fn dropped_datagrams(&self) -> DroppedDatagrams;
    /// Whether the role, gone offline, still waits for a peer's answer (a Release): a
    /// stopping procimgd keeps its socket open for it a little.
    fn settling(&self) -> bool {
        false
    }
}

/// Answers the requests of one group of the control protocol (the IO controller's or the IO
/// device's): a role's services implement it for their own group only.
pub trait Answers<R> {
    /// Answers `request`. `online` says whether the cycle is, or is becoming, CLEAR or
    /// OPERATE.
    fn handle(&mut self, request: R, online: bool, notices: &mut Notices) -> Response;
}

/// A role's part of the client services, on the control side.
pub trait RoleServices: Send {
    /// The role's name in refusals: "controller" or "device".
    fn name(&self) -> &'static str;
    /// The IO controller's services, if this role is the IO controller; the control side
    /// refuses the IO controller's requests otherwise.
    fn controller_services(&mut self) -> Option<&mut dyn Answers<ControllerRequest>> {
        None
    }
    /// The IO device's station services, if this role is the IO device; the control side
    /// refuses the station's requests otherwise.
    fn device_services(&mut self) -> Option<&mut dyn Answers<DeviceRequest>> {
        None
    }
    /// Announces a notification subscriber.
    fn subscribe(&mut self, id: u64, subscriber: Subscriber);
    /// Withdraws a subscriber.
    fn unsubscribe(&mut self, id: u64) -> Result<(), Refusal>;
    /// Waits up to `wait` for what the role reports and publishes it to the subscribers;
    /// handles the role's timeouts.
    fn poll(&mut self, wait: Duration, notices: &mut Notices);
    /// Publishes what the role reported on its way out, once its threads have ended (the
    /// device role: its AR's end). By default nothing: the IO controller's subscribers learn
    /// of the shutdown from the next server's [`Notification::ServerStarted`].
    ///
    /// [`Notification::ServerStarted`]: procimg_control::services::Notification::ServerStarted
    fn finish(&mut self, _notices: &mut Notices) {}
    /// Forgets subscribers whose process is gone (`alive`: the live iceoryx2 node ids);
    /// returns who they were.
    fn reap(&mut self, alive: &HashSet<String>) -> Vec<String>;
    /// The state of every peer, for the status report.
    fn devices(&self) -> Vec<DeviceReport>;
    /// The interface and datagram counters, for the status report.
    fn network(&self) -> NetworkReport;
    /// The announced subscribers, for the status report.
    fn subscribers(&self) -> Vec<SubscriberReport>;
    /// In the device role, the station and its AR, for the status report (`None`: the
    /// server is an IO controller).
    fn station(&self) -> Option<StationReport> {
        None
    }
    /// In the controller role, the controller's own station, for the status report.
    fn controller(&self) -> Option<procimg_control::ControllerReport> {
        None
    }
    /// Whether the role holds no connection any more: the server waits for this on shutdown,
    /// so that every peer is released before the cyclic data ends.
    fn released(&self) -> bool;
}

/// A started role.
pub struct RoleSystem {
    /// Builds the cycle thread's IO system (taken once, for the cycle thread).
    pub io: Option<IoFactory>,
    /// The role's client services, for the control side (taken once).
    pub services: Option<Box<dyn RoleServices>>,
    /// The role's threads (the acyclic thread, a simulated plant): they end with the cycle.
    pub threads: Vec<JoinHandle<()>>,
    /// Called before joining the threads, to stop those that do not end with the cycle.
    pub stop: Option<Box<dyn FnOnce() + Send>>,
}

impl RoleSystem {
    /// Waits for the role's threads, after the cycle has been told to stop.
    pub fn join(mut self) {
        if let Some(stop) = self.stop.take() {
            stop();
        }
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }
}

/// How long the cycle thread's receive may block: not at all.
pub(crate) const NIC_RX_TIMEOUT: Duration = Duration::ZERO;

/// The cycle thread's IO system over `nic`, built on the cycle thread itself. Made for the
/// backend's own type, so that no frame goes through a dynamic call.
pub(crate) fn cycle_io<N: Nic + 'static>(
    nic: N,
    channel: Arc<Channel>,
    peer_submodules: Vec<core::ops::Range<usize>>,
    cycle_ns: u64,
) -> IoFactory {
    Box::new(move || Box::new(PnioIo::new(nic, channel, peer_submodules, cycle_ns)))
}

/// The interface and datagram counters, for the status report.
pub(crate) fn network_report(channel: &Channel, datagrams: &DatagramCounters) -> NetworkReport {
    let c = &channel.counters;
    NetworkReport {
        cyclic_frames: load(&c.cyclic_frames),
        malformed: load(&c.malformed),
        unknown: load(&c.unknown),
        stale: load(&c.stale),
        dropped: load(&c.dropped),
        sent_in_place: load(&c.sent_in_place),
        sent_copied: load(&c.sent_copied),
        send_errors: load(&c.send_errors),
        watchdog_expiries: load(&c.watchdog_expiries),
        malformed_datagrams: load(&datagrams.malformed),
        unexpected_datagrams: load(&datagrams.unexpected),
    }
}

/// A configured submodule as the device engine has it plugged (the demo's simulated devices,
/// the device role's station).
pub(crate) fn plugged(
    s: &crate::config::SubmoduleConfig,
) -> procimg_profinet::device::PluggedSubmodule {
    controller::plan::submodule_spec(s).plugged()
}
