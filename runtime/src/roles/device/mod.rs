// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO device role: the PC is a field device on a PLC. Puts the role together for a
//! configuration with `[station]`: the interface (real, or the simulated link with the
//! demo's PLC), the protocol crate's device engine on the acyclic thread ([`DeviceRole`]),
//! with its cyclic exchange handed to the cycle thread, and the role's client services
//! ([`DeviceServices`]). On a real interface the station owns the interface's IPv4 address
//! (`address.rs`): procimgd gives it the station's and follows DCP's changes.
//!
//! The station's events (its AR's states and end, the PLC's RUN/STOP, DCP Signal and DCP's
//! changes of its name or address) go from the role, as [`StationEvent`]s on a channel, to
//! the client services, which publish each as a notification to the subscribers.
//!
//! The image's server-written part carries the PLC's output data (Q), its client-written
//! part the device's input data (I), one submodule table entry per configured submodule in
//! configuration order: the order the engine maps the AR's cyclic data onto.

mod alarms;
mod application;
use crate::roles::address::{self, InterfaceAddress};
use application::ApplicationSay;
mod diagnosis;
mod identity;
mod notifications;
pub mod program;
mod role;
mod services;
pub mod sim_plc;
mod snmp;
mod state_file;
mod station;

pub use identity::Identity;
pub use role::{DeviceCommand, DeviceRole, Kept};
pub use services::DeviceServices;
pub use station::{ImageApplication, Station, StationEvent, engine, state_name};

use super::controller::{NetworkError, sim_priority};
use super::{NIC_RX_TIMEOUT, RoleSystem, cycle_io};
use crate::acyclic::{self, DatagramCounters};
use crate::config::{Config, Network, StationConfig};
use crate::cycle::Shared;
use crate::cycle::thread::IoFactory;
use crate::io::pnio::channel::Channel;
use crate::phy::datagram::{self, Datagrams, UdpDatagrams};
use procimg_nic::Nic;
use procimg_nic::af_packet::AfPacket;
use procimg_nic::sim_link;
use procimg_profinet::wire::MacAddress;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Why the device role could not start.
#[derive(Debug, thiserror::Error)]
pub enum DeviceStartError {
    /// The configuration has no `[station]`.
    #[error(
        "{0}: the device role needs a [station] table; add one (see `procimgd --print-demo-device-config`)"
    )]
    NoStation(String),
    /// The station could not take its interface's address.
    #[error("{origin}: {error}")]
    Address {
        /// Configuration file.
        origin: String,
        /// What went wrong.
        error: address::AddressStartError,
    },
    /// Port 34964 could not be opened on the interface.
    #[error("{origin}: {error}")]
    Bind {
        /// Configuration file.
        origin: String,
        /// What went wrong.
        error: datagram::InterfaceBindError,
    },
    /// The state file could not be read.
    #[error(transparent)]
    StateFile(#[from] state_file::StateFileError),
    /// The network could not be set up.
    #[error(transparent)]
    Network(#[from] NetworkError),
}

/// Starts the device of `config` (and, with `network = "sim"`, the demo's PLC). The device
/// takes part while the mode of `shared` is CLEAR or OPERATE and ends when `shared.stop` is
/// set, aborting its AR.
pub fn start(
    config: &Config,
    shared: Arc<Shared>,
    program: Option<Arc<program::StationProgram>>,
) -> Result<RoleSystem, DeviceStartError> {
    let configured = config
        .station
        .as_ref()
        .ok_or_else(|| DeviceStartError::NoStation(config.origin.clone()))?;
    // What the last run kept overrides the configuration's first-start values.
    let kept = match &configured.state_file {
        Some(path) => Some(Kept::new(path.clone(), state_file::load(path)?)),
        None => None,
    };
    let station = &kept
        .as_ref()
        .map_or_else(|| configured.clone(), |k| with_kept(configured, &k.state));
    // A station its program defines, without its program yet.
    let waiting = program.as_ref().is_some_and(|p| p.definer().is_none());
    let plc_stop = Arc::new(AtomicBool::new(false));
    let mut threads = Vec::new();
    let channel = Arc::new(Channel::new());
    let (ch, cycle_ns) = (channel.clone(), config.cycle_ns);
    // One peer, the PLC, whose AR covers the whole table.
    let all = std::iter::once(0..station.submodules.len()).collect::<Vec<_>>();
    type Parts = (
        IoFactory,
        Box<dyn Datagrams>,
        MacAddress,
        StationConfig,
        Option<InterfaceAddress>,
    );
    let (io, udp, mac, station, address): Parts = match &config.network {
        Network::Sim => {
            let (ours, plc_end) = sim_link::link(sim_plc::SIM_STATION_MAC, sim_plc::SIM_PLC_MAC);
            let mut station = station.clone();
            station.ip = Some(sim_plc::station_ip(&station));
            let (udp, peer) = datagram::sim_network(sim_plc::station_ip(&station));
            let plans =
                sim_plc::plan(&station, cycle_ns).map_err(|problem| NetworkError::Plan {
                    origin: config.origin.clone(),
                    problem,
                })?;
            threads.push(
                sim_plc::spawn(
                    plans,
                    sim_plc::tree_planner(&station, cycle_ns),
                    sim_plc::plc_ip(&station),
                    cycle_ns,
                    plc_end,
                    peer,
                    plc_stop.clone(),
                    sim_priority(config.cycle_thread.priority),
                )
                .map_err(|e| NetworkError::Thread("demo PLC", e))?,
            );
            (
                cycle_io(ours, ch, all, cycle_ns),
                Box::new(udp),
                sim_plc::SIM_STATION_MAC,
                station,
                None,
            )
        }
        Network::Interface(name) => {
            let nic = AfPacket::open(name, NIC_RX_TIMEOUT).map_err(|error| NetworkError::Open {
                origin: config.origin.clone(),
                error,
            })?;
            let address =
                InterfaceAddress::take(name, station.ip, station.netmask, station.gateway)
                    .map_err(|error| DeviceStartError::Address {
                        origin: config.origin.clone(),
                        error,
                    })?;
            let udp = UdpDatagrams::on_interface(name).map_err(|error| DeviceStartError::Bind {
                origin: config.origin.clone(),
                error,
            })?;
            let mac = nic.mac();
            (
                cycle_io(nic, ch, all, cycle_ns),
                Box::new(udp),
                mac,
                station.clone(),
                Some(address),
            )
        }
    };
    let shown = Arc::new(Station::new(&station, mac));
    let mut device = engine(&station, mac, cycle_ns);
    device.station_mut().set_hello(station.dcp_hello);
    // LLDP's management address names the port by its interface index (the MIB's ifIndex).
    if let Network::Interface(name) = &config.network
        && let Ok(index) = crate::sys::netlink::interface_index(name)
        && let Some(lldp) = device.station_mut().lldp_mut()
    {
        lldp.update(|s| s.if_index = index);
    }
    let ip = station.ip.map_or([0; 4], |ip| ip.octets());
    let (mask, gateway) = match station.ip {
        Some(_) => (station.netmask.octets(), station.gateway.octets()),
        None => ([0; 4], [0; 4]),
    };
    device.station_mut().set_ip_suite(ip, mask, gateway);
    if let Some(im) = kept.as_ref().and_then(|k| k.state.im.as_ref()) {
        // Checked when the file was loaded.
        if let Ok(records) = state_file::im_records(im) {
            device.station_mut().set_im_records(records);
        }
    }
    // The station's SNMP subagent: on a real interface unless turned off.
    let snmp = snmp_master(&station, &config.network).map(|master| {
        let if_index = match &config.network {
            Network::Interface(name) => crate::sys::netlink::interface_index(name).unwrap_or(0),
            Network::Sim => 0,
        };
        (
            snmp::SnmpFeed::new(if_index, crate::sys::clock::now_ns()),
            master,
        )
    });
    if let Some((feed, master)) = &snmp {
        threads.push(
            feed.spawn(master.clone(), plc_stop.clone())
                .map_err(|e| NetworkError::Thread("SNMP subagent", e))?,
        );
    }
    let datagrams = Arc::new(DatagramCounters::default());
    let (commands, command_rx) = std::sync::mpsc::channel();
    let (events, event_rx) = std::sync::mpsc::channel();
    let mut services = DeviceServices::new(
        shown.clone(),
        ApplicationSay::new(
            station
                .submodule_configs()
                .map(|s| procimg_profinet::device::SubslotAddr::new(s.api, s.slot, s.subslot)),
        ),
        commands,
        event_rx,
        channel.clone(),
        datagrams.clone(),
    )
    .with_program(program);
    // Before the acyclic thread takes its first frame: a PLC that connects at once meets
    // the station's program.
    services.resume_program();
    threads.push(
        acyclic::spawn(acyclic::AcyclicSetup {
            role: {
                let role = DeviceRole::new(device, shown.clone(), channel.clone())
                    .waiting_for_program(waiting);
                let role = match kept {
                    Some(k) => role.with_state_file(k),
                    None => role,
                };
                let role = match &config.network {
                    Network::Interface(name) => role.with_port(name),
                    Network::Sim => role,
                };
                let role = match &snmp {
                    Some((feed, _)) => role.with_snmp(feed.clone()),
                    None => role,
                };
                match address {
                    Some(a) => role.with_address(a),
                    None => role,
                }
            },
            channel,
            datagrams: udp,
            shared,
            counters: datagrams,
            commands: command_rx,
            events: Some(events),
            settle_for: acyclic::SETTLE_WAIT,
            priority: config.cycle_thread.status_priority,
        })
        .map_err(|e| NetworkError::Thread("PROFINET device", e))?,
    );
    tracing::info!(
        "station \"{}\" (vendor 0x{:04X}, device 0x{:04X}) at {} on {}",
        station.name,
        station.vendor_id,
        station.device_id,
        station
            .ip
            .map_or_else(|| "no address".to_owned(), |ip| ip.to_string()),
        config.network
    );
    Ok(RoleSystem {
        io: Some(io),
        services: Some(Box::new(services)),
        threads,
        stop: Some(Box::new(move || plc_stop.store(true, Ordering::Release))),
    })
}

/// Where the station's SNMP subagent attaches (`[station] snmp_agentx`), if it has one: the
/// agent's standard socket on a real interface unless told otherwise, none on the simulated
/// network; an address that does not parse is logged and leaves the station without SNMP.
fn snmp_master(
    station: &StationConfig,
    network: &Network,
) -> Option<procimg_agentx::runner::MasterAddress> {
    use procimg_config::SnmpMaster;
    match (&station.snmp_agentx, network) {
        (SnmpMaster::Off, _) | (SnmpMaster::Standard, Network::Sim) => None,
        (SnmpMaster::Standard, Network::Interface(_)) => Some(Default::default()),
        (SnmpMaster::At(text), _) => match procimg_agentx::runner::MasterAddress::parse(text) {
            Ok(m) => Some(m),
            Err(e) => {
                tracing::warn!(
                    "[station] snmp_agentx = {text:?}: {e}; the station runs without SNMP"
                );
                None
            }
        },
    }
}

/// `station` with what the state file kept: a name or address DCP set permanently.
fn with_kept(station: &StationConfig, kept: &state_file::KeptState) -> StationConfig {
    let mut s = station.clone();
    if let Some(name) = &kept.name {
        s.name.clone_from(name);
    }
    if let Some(ip) = kept.ip {
        s.ip = (!ip.is_unspecified()).then_some(ip);
        s.netmask = kept.netmask.unwrap_or(s.netmask);
        s.gateway = kept.gateway.unwrap_or(s.gateway);
    }
    s
}
