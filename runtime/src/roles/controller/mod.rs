// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO controller role: the PC is the PLC. Puts the role together for a configuration:
//! the interface (real, or the simulated plant), the protocol crate's controller on the
//! acyclic thread ([`ControllerRole`]), the factory of the cycle thread's IO system, and the
//! controller's client services ([`ControllerServices`]).

mod interface;
mod pe_jobs;
pub(crate) mod plan;
mod role;
mod services;
pub mod sim_behaviour;
pub mod sim_plant;
mod states;

pub use plan::{device_spec, plan_devices, submodule_spec};
pub use role::{ControllerCommand, ControllerRole};
pub use services::{ControllerLink, ControllerServices};
pub use states::DeviceStates;

use super::{RoleSystem, cycle_io};
use crate::acyclic::{self, DatagramCounters};
use crate::config::{Config, Network};
use crate::cycle::Shared;
use crate::cycle::thread::IoFactory;
use crate::io::pnio::channel::Channel;
use crate::phy::datagram::{self, BindError, Datagrams, InterfaceBindError, UdpDatagrams};
use crate::roles::address::{AddressStartError, InterfaceAddress};
use interface::ControllerInterface;
use procimg_control::ControllerReport;
use procimg_nic::Nic;
use procimg_nic::af_packet::{AfPacket, OpenError};
use procimg_nic::sim_link;
use procimg_profinet::controller::plan::{ControllerIdentity, PlanError};
use procimg_profinet::controller::{Controller, InterfaceSetup, port_id};
use procimg_profinet::port::dcp_station::Settable;
use procimg_profinet::wire::MacAddress;
use std::net::Ipv4Addr;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// The controller's address on the simulated network.
pub const SIM_CONTROLLER_IP: Ipv4Addr = Ipv4Addr::new(192, 168, 0, 1);
/// The controller's MAC address on the simulated network.
pub const SIM_CONTROLLER_MAC: MacAddress = MacAddress([0x02, 0x50, 0x49, 0xff, 0x00, 0x01]);

/// Why the IO system could not be started.
#[derive(Debug, thiserror::Error)]
pub enum NetworkError {
    /// A device cannot be planned.
    // Not a `source`: the message already holds it, and error chains would repeat it.
    #[error("{origin}: {problem}")]
    Plan {
        /// Configuration file.
        origin: String,
        /// What is wrong.
        problem: PlanError,
    },
    /// The interface could not be opened.
    // Not a `source`: the message already holds it, and error chains would repeat it.
    #[error("{origin}: network: {}", open_advice(error))]
    Open {
        /// Configuration file.
        origin: String,
        /// What the system said.
        error: OpenError,
    },
    /// The interface has no IPv4 address.
    #[error(
        "network interface \"{0}\" has no IPv4 address: give it one in the devices' subnet \
         (ip addr add 192.168.0.1/24 dev {0})"
    )]
    NoAddress(String),
    /// Port 34964 is taken.
    #[error(transparent)]
    Bind(#[from] BindError),
    /// Port 34964 is taken on the interface.
    #[error(transparent)]
    InterfaceBind(InterfaceBindError),
    /// The station's address could not be taken over (`[interface] address_by_program`).
    // Not a `source`: the message already holds it, and error chains would repeat it.
    #[error("{origin}: {error}")]
    Address {
        /// Configuration file.
        origin: String,
        /// What went wrong.
        error: AddressStartError,
    },
    /// A thread could not be started.
    #[error("cannot start the {0} thread: {1}")]
    Thread(&'static str, std::io::Error),
}

/// Starts the controller for `config` (and, with `network = "sim"`, the simulated plant).
/// The controller follows the mode of `shared` and ends when `shared.stop` is set.
pub fn start(config: &Config, shared: Arc<Shared>) -> Result<RoleSystem, NetworkError> {
    let plans = plan_devices(config).map_err(|problem| NetworkError::Plan {
        origin: config.origin.clone(),
        problem,
    })?;
    let plant_stop = Arc::new(AtomicBool::new(false));
    let mut threads = Vec::new();
    let device_submodules: Vec<_> = plans
        .iter()
        .map(|p| p.first_submodule..p.first_submodule + p.submodules.len())
        .collect();
    let channel = Arc::new(Channel::new());
    let (ch, cycle_ns) = (channel.clone(), config.cycle_ns);
    // The interface's index, for the LLDP announcements of a real port (the management
    // address names the port by it, as the LLDP-MIB's ifIndex).
    let mut if_index = None;
    let iface = &config.interface;
    let mut address = None;
    let (io, udp, mac, ip): (IoFactory, Box<dyn Datagrams>, MacAddress, Ipv4Addr) =
        match &config.network {
            Network::Sim => {
                let devices = sim_plant::devices(config);
                let (ours, plant) = sim_link::link_with_depth(
                    SIM_CONTROLLER_MAC,
                    MacAddress::default(),
                    // Sized for every configured device: the controller's frames to the
                    // absent ones wait in the link too, until the plant empties it.
                    sim_plant::link_depth(config.devices.len()),
                );
                let (udp, peer) = datagram::sim_network(SIM_CONTROLLER_IP);
                threads.push(
                    sim_plant::spawn(
                        devices,
                        plant,
                        peer,
                        plant_stop.clone(),
                        sim_priority(config.cycle_thread.priority),
                    )
                    .map_err(|e| NetworkError::Thread("simulated plant", e))?,
                );
                (
                    cycle_io(ours, ch, device_submodules, cycle_ns),
                    Box::new(udp),
                    SIM_CONTROLLER_MAC,
                    SIM_CONTROLLER_IP,
                )
            }
            Network::Interface(name) => {
                let nic = AfPacket::open(name, super::NIC_RX_TIMEOUT).map_err(|error| {
                    NetworkError::Open {
                        origin: config.origin.clone(),
                        error,
                    }
                })?;
                let ip = procimg_nic::interfaces::ipv4(name)
                    .ok_or_else(|| NetworkError::NoAddress(name.clone()))?;
                let mut udp = if iface.address_by_program {
                    // The station's address may change under the socket: it listens on the
                    // interface, whatever address it has.
                    let netmask = netmask_of(crate::sys::netlink::interface_index(name).ok(), ip);
                    address = Some(
                        InterfaceAddress::take(name, Some(ip), netmask, Ipv4Addr::UNSPECIFIED)
                            .map_err(|error| NetworkError::Address {
                                origin: config.origin.clone(),
                                error,
                            })?,
                    );
                    UdpDatagrams::on_interface(name).map_err(NetworkError::InterfaceBind)?
                } else {
                    UdpDatagrams::bind(ip)?
                };
                // The devices' MAC addresses from DCP go to the interface's neighbour table,
                // so that no RPC call waits for ARP (see `ControllerAction::Neighbour`).
                match crate::sys::netlink::interface_index(name) {
                    Ok(index) => {
                        udp = udp.with_neighbours_on(index);
                        if_index = Some(index);
                    }
                    Err(e) => tracing::warn!(
                        "no index of interface {name:?} ({e}); RPC calls wait for ARP"
                    ),
                }
                let mac = nic.mac();
                (
                    cycle_io(nic, ch, device_submodules, cycle_ns),
                    Box::new(udp),
                    mac,
                    ip,
                )
            }
        };
    if matches!(config.network, Network::Sim) && iface.address_by_program {
        tracing::warn!(
            "{}: [interface] address_by_program: on the simulated network the controller's \
             address stays {SIM_CONTROLLER_IP}",
            config.origin
        );
    }
    let station_name = config.controller_station_name();
    let netmask = netmask_of(if_index, ip);
    let interface = ControllerInterface::new(
        ControllerReport {
            station_name: station_name.clone(),
            type_of_station: iface.type_of_station.clone(),
            interface: config.network.to_string(),
            mac: mac.to_string(),
            ip: ip.to_string(),
            netmask: netmask.to_string(),
            gateway: Ipv4Addr::UNSPECIFIED.to_string(),
            counters: None,
            interface_address: iface.diagnostic_address,
            port_address: iface.port_diagnostic_address,
            name_by_program: iface.name_by_program,
            address_by_program: iface.address_by_program,
        },
        match &config.network {
            Network::Interface(name) => Some(name.clone()),
            Network::Sim => None,
        },
    );
    let id = ControllerIdentity {
        mac,
        ip,
        station_name,
        vendor_id: 0x0493,
        device_id: 0x0fff,
        instance: 1,
    };
    let names: Vec<String> = plans.iter().map(|p| p.name.clone()).collect();
    let states = Arc::new(DeviceStates::new(plans.len()));
    let datagrams = Arc::new(DatagramCounters::default());
    let boot_time = (crate::sys::clock::now_ns() / 1_000_000_000) as u32;
    // AR and activity UUIDs nobody can guess or repeat across restarts.
    let mut seed = [0u8; 8];
    if !crate::sys::random::fill(&mut seed) {
        seed = crate::sys::clock::now_ns().to_le_bytes();
    }
    let mut controller = Controller::new(id, plans, boot_time, u64::from_le_bytes(seed));
    // Where each device starts (an optional one deactivated), before any event says more.
    for (d, state) in controller.states().enumerate() {
        states.set(d, state);
    }
    // On a real network the controller's port tells its neighbour who it is, as every
    // PROFINET station's port does; its devices learn their neighbour from it.
    if let (Network::Interface(_), Some(index)) = (&config.network, if_index) {
        controller.announce_by_lldp(|port| port.if_index = index);
        // Its station answers DCP too: engineering tools find it, and a Signal flashes it.
        controller.answer_dcp(&iface.type_of_station);
    }
    controller.set_up_interface(InterfaceSetup {
        settable: Settable {
            name: iface.name_by_program,
            ip: iface.address_by_program && address.is_some(),
        },
        peer: config
            .controller_port_peer()
            .map(|(device, subslot)| (device.to_owned(), port_id(subslot))),
        check_link: iface.check_link,
        netmask,
        gateway: Ipv4Addr::UNSPECIFIED,
    });
    let mut role = ControllerRole::new(controller, states.clone(), names.clone());
    if let Some(a) = address {
        role = role.with_address(a);
    }
    if let Network::Interface(name) = &config.network {
        role = role.with_port(name);
    }
    let (commands, command_rx) = std::sync::mpsc::channel();
    let (events, event_rx) = std::sync::mpsc::channel();
    threads.push(
        acyclic::spawn(acyclic::AcyclicSetup {
            role,
            channel: channel.clone(),
            datagrams: udp,
            shared,
            counters: datagrams.clone(),
            commands: command_rx,
            events: Some(events),
            settle_for: acyclic::SETTLE_WAIT,
            priority: config.cycle_thread.status_priority,
        })
        .map_err(|e| NetworkError::Thread("PROFINET controller", e))?,
    );
    let link = ControllerLink {
        commands,
        events: event_rx,
        states,
        channel: channel.clone(),
        datagrams,
    };
    Ok(RoleSystem {
        io: Some(io),
        services: Some(Box::new(
            ControllerServices::new(names, Some(link)).with_interface(interface),
        )),
        threads,
        stop: Some(Box::new(move || plant_stop.store(true, Ordering::Release))),
    })
}

/// The subnet mask of `ip` on the interface of index `if_index`, as the kernel has it;
/// 255.255.255.0 where it cannot be read (the simulated network).
fn netmask_of(if_index: Option<u32>, ip: Ipv4Addr) -> Ipv4Addr {
    let prefix = if_index
        .and_then(|index| {
            let mut nl = crate::sys::netlink::Netlink::open().ok()?;
            let addresses = nl.addresses(index).ok()?;
            addresses.into_iter().find(|a| a.ip == ip).map(|a| a.prefix)
        })
        .unwrap_or(24);
    Ipv4Addr::from(u32::MAX.checked_shl(32 - u32::from(prefix)).unwrap_or(0))
}

/// The simulated devices' priority: they stand for field devices, which answer in real time,
/// so they run SCHED_FIFO (where allowed) below the cycle thread; at normal priority a loaded
/// machine starves them past their watchdog.
pub(crate) fn sim_priority(cycle_priority: u8) -> u8 {
    cycle_priority.saturating_sub(10).max(1)
}

/// `error`, with what to do about it in procimgd's words.
fn open_advice(error: &OpenError) -> String {
    match error {
        OpenError::NoSuchInterface { .. } => format!(
            "{error}; set `network` to one of them, or to \"sim\" for the simulated devices"
        ),
        OpenError::NoMac { .. } => format!("{error}; set `network` to an Ethernet interface"),
        OpenError::NotPermitted { .. } => {
            let exe = std::env::current_exe()
                .map(|p| p.display().to_string())
                .unwrap_or_else(|_| "procimgd".to_owned());
            format!(
                "{error}; run procimgd as root, or grant it the capabilities it uses \
                 (sudo setcap cap_net_raw,cap_net_admin,cap_sys_nice,cap_ipc_lock+ep {exe}; \
                 cap_net_admin gives the devices' MAC addresses to the neighbour table)"
            )
        }
        OpenError::Down { .. } | OpenError::Io { .. } => error.to_string(),
    }
}
