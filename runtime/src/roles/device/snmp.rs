// SPDX-License-Identifier: MIT OR Apache-2.0
//! The station's SNMP: procimgd as an AgentX subagent of the system's SNMP agent (net-snmp's
//! snmpd, which owns UDP 161), serving MIB-II's `system` group (sysName = NameOfStation,
//! sysLocation = the I&M1 location tag), the LLDP-MIB (the local system and port, the
//! management address, the neighbours) and the LLDP-EXT-PNO-MIB.
//!
//! The acyclic thread keeps a [`Snapshot`] of the station up to date ([`SnmpFeed::follow`]),
//! made again when the station changes (its name or address, its neighbours, its I&M) and
//! every second for the times; the subagent's thread answers the agent from it, and
//! without an agent tries again every few seconds, so procimgd runs on whether snmpd runs
//! or not, and attaches when it comes.

use procimg_agentx::mib::{
    Capabilities, ChassisId, LldpView, LocalPort, LocalSystem, ManagementAddress, PnoPort, PortId,
    PortStatistics, RemoteSystem, RtClass2Status, RtClass3Status, Snapshot, Statistics,
};
use procimg_agentx::runner::{self, MasterAddress, RunnerConfig, RunnerEvent};
use procimg_agentx::session::Event;
use procimg_profinet::device::{Application, Device};
use procimg_profinet::port::lldp::NameOfDeviceMode;
use procimg_profinet::port::neighbours::Neighbour;
use procimg_profinet::wire::lldp::{Id, TlvRepr, profinet};
use std::net::Ipv4Addr;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex, PoisonError};

/// sysServices of a PROFINET device: layers 2 (datalink), 3 (internet), 4 (end-to-end)
/// and 7 (applications).
const SYS_SERVICES: u8 = 78;
/// How often the snapshot is made again without a change, for the neighbours' time to
/// live and the counters.
const REFRESH_NS: u64 = 1_000_000_000;

/// What a snapshot is made of that changes without notice: the neighbour table's change
/// count, the name, the address, the I&M writes, the LLDP naming mode.
type MadeOf = (u64, String, [u8; 4], u64, Option<NameOfDeviceMode>);

/// The snapshot the subagent answers from, shared with the acyclic thread that makes it.
#[derive(Clone, Default)]
pub struct SnmpFeed {
    snapshot: Arc<Mutex<Snapshot>>,
    /// What the snapshot was made of, to make it again only on a change.
    made_of: Option<MadeOf>,
    made_at: u64,
    /// The agent's start (the acyclic clock), for sysUpTime and the time marks.
    start_ns: u64,
    if_index: u32,
}

impl SnmpFeed {
    /// A feed for a station on the interface of ifIndex `if_index`, its agent started at
    /// `start_ns`.
    pub fn new(if_index: u32, start_ns: u64) -> SnmpFeed {
        SnmpFeed {
            start_ns,
            if_index,
            ..SnmpFeed::default()
        }
    }

    /// Makes the snapshot again if the station changed or a second went by.
    pub fn follow<A: Application>(&mut self, device: &Device<A>, now_ns: u64) {
        let station = device.station();
        let mode = station.lldp().map(|l| l.station().mode);
        let same = self
            .made_of
            .as_ref()
            .is_some_and(|(changes, name, ip, im, m)| {
                *changes == station.neighbours().changes
                    && name == station.name()
                    && *ip == station.ip()
                    && *im == station.im_write_count()
                    && *m == mode
            });
        if same && now_ns < self.made_at + REFRESH_NS {
            return;
        }
        let snapshot = self.snapshot_of(device, now_ns);
        *self.snapshot.lock().unwrap_or_else(PoisonError::into_inner) = snapshot;
        self.made_of = Some((
            station.neighbours().changes,
            station.name().to_owned(),
            station.ip(),
            station.im_write_count(),
            mode,
        ));
        self.made_at = now_ns;
    }

    /// Hundredths of a second since the agent started.
    fn centis(&self, at_ns: u64) -> u32 {
        (at_ns.saturating_sub(self.start_ns) / 10_000_000) as u32
    }

    fn snapshot_of<A: Application>(&self, device: &Device<A>, now_ns: u64) -> Snapshot {
        let station = device.station();
        let announced = station.lldp().map(|l| l.station());
        let sys_descr = announced
            .map(|s| s.system_identification.clone())
            .unwrap_or_default();
        let location = String::from_utf8_lossy(&station.im_records().im1.tag_location)
            .trim_end()
            .to_owned();
        let ip = station.ip();
        let port_id = announced.map_or_else(|| Id::Local("port-001".into()), |s| s.port_id());
        let chassis_id = announced.map_or_else(
            || Id::MacAddress(station.mac()),
            procimg_profinet::port::lldp::LldpStation::chassis_id,
        );
        let neighbours = station.neighbours();
        let stats = neighbours.stats;
        let rt2 = if device.ar().state() == procimg_profinet::device::ArState::Data {
            RtClass2Status::Running
        } else {
            RtClass2Status::Off
        };
        Snapshot {
            sys_descr: sys_descr.clone(),
            sys_object_id: Vec::new(),
            sys_up_time_centis: self.centis(now_ns),
            sys_contact: String::new(),
            sys_name: station.name().to_owned(),
            sys_location: location,
            sys_services: SYS_SERVICES,
            lldp: LldpView {
                local: LocalSystem {
                    chassis_id: chassis(&chassis_id),
                    sys_name: station.name().to_owned(),
                    sys_desc: sys_descr,
                    capabilities: Capabilities {
                        supported: Capabilities::STATION_ONLY,
                        enabled: Capabilities::STATION_ONLY,
                    },
                },
                ports: vec![LocalPort {
                    num: 1,
                    id: port(&port_id),
                    description: "port-001".to_owned(),
                    pno: Some(PnoPort {
                        rt_class2: rt2,
                        rt_class3: RtClass3Status::Off,
                        name_of_station: station.name().to_owned(),
                        ..PnoPort::default()
                    }),
                }],
                management_addresses: (ip != [0; 4])
                    .then(|| ManagementAddress::on_if_index(Ipv4Addr::from(ip), self.if_index))
                    .into_iter()
                    .collect(),
                remotes: neighbours
                    .entries()
                    .iter()
                    .map(|n| self.remote(n))
                    .collect(),
                statistics: Some(Statistics {
                    rem_tables_last_change: self.centis(
                        neighbours
                            .entries()
                            .iter()
                            .map(|n| n.updated_ns)
                            .max()
                            .unwrap_or(self.start_ns),
                    ),
                    rem_tables_inserts: stats.inserts as u32,
                    rem_tables_deletes: stats.deletes as u32,
                    rem_tables_drops: stats.drops as u32,
                    rem_tables_ageouts: stats.ageouts as u32,
                    ports: vec![PortStatistics {
                        num: 1,
                        rx_frames: stats.frames_in as u32,
                        rx_frames_discarded: stats.frames_discarded as u32,
                        rx_frames_errors: stats.frames_discarded as u32,
                        rx_ageouts: stats.ageouts as u32,
                        ..PortStatistics::default()
                    }],
                }),
            },
        }
    }

    fn remote(&self, n: &Neighbour) -> RemoteSystem {
        let text = |pick: fn(&TlvRepr) -> Option<&String>| n.tlvs.iter().find_map(pick).cloned();
        let capabilities = n.tlvs.iter().find_map(|t| match t {
            TlvRepr::SystemCapabilities {
                capabilities,
                enabled,
            } => Some(Capabilities {
                supported: *capabilities,
                enabled: *enabled,
            }),
            _ => None,
        });
        let pno = n.port_status().map(|(rt2, rt3)| PnoPort {
            line_delay_ns: n.line_delay_ns(),
            rt_class2: match rt2 {
                profinet::PORT_STATUS_OFF => RtClass2Status::Off,
                profinet::PORT_STATUS_UP => RtClass2Status::Running,
                _ => RtClass2Status::Configured,
            },
            rt_class3: match rt3 & 0x7 {
                0 => RtClass3Status::Off,
                1 => RtClass3Status::Configured,
                2 => RtClass3Status::Up,
                3 => RtClass3Status::Down,
                _ => RtClass3Status::Running,
            },
            name_of_station: n.peer_station().unwrap_or_default().to_owned(),
            ..PnoPort::default()
        });
        RemoteSystem {
            time_mark: self.centis(n.since_ns),
            local_port: 1,
            index: n.index,
            chassis_id: chassis(&n.chassis_id),
            port_id: port(&n.port_id),
            port_description: text(|t| match t {
                TlvRepr::PortDescription(s) => Some(s),
                _ => None,
            }),
            sys_name: text(|t| match t {
                TlvRepr::SystemName(s) => Some(s),
                _ => None,
            }),
            sys_desc: text(|t| match t {
                TlvRepr::SystemDescription(s) => Some(s),
                _ => None,
            }),
            capabilities,
            management_addresses: n
                .management_ipv4()
                .map(|ip| ManagementAddress::on_if_index(Ipv4Addr::from(ip), 0))
                .into_iter()
                .collect(),
            pno,
        }
    }

    /// The subagent's thread: serves the snapshot to the agent at `master` until `stop`.
    pub fn spawn(
        &self,
        master: MasterAddress,
        stop: Arc<AtomicBool>,
    ) -> std::io::Result<std::thread::JoinHandle<()>> {
        let snapshot = self.snapshot.clone();
        let start = std::time::Instant::now();
        std::thread::Builder::new()
            .name("snmp-agentx".into())
            .spawn(move || {
                let config = RunnerConfig {
                    master,
                    ..RunnerConfig::default()
                };
                let mut told_missing = false;
                let take = || {
                    let mut s = snapshot
                        .lock()
                        .unwrap_or_else(PoisonError::into_inner)
                        .clone();
                    // sysUpTime as of the request, not of the snapshot.
                    s.sys_up_time_centis = (start.elapsed().as_millis() / 10) as u32;
                    s
                };
                runner::run(&config, &stop, take, |event| {
                    log(&event, &mut told_missing);
                });
            })
    }
}

/// Logs what the subagent's runner reports: the agent's absence once (until it comes).
fn log(event: &RunnerEvent, told_missing: &mut bool) {
    match event {
        RunnerEvent::Connected(master) => {
            *told_missing = false;
            tracing::info!("SNMP: attached to the SNMP agent at {master} (AgentX)");
        }
        RunnerEvent::ConnectFailed(master, e) if !*told_missing => {
            *told_missing = true;
            tracing::info!(
                "SNMP: no SNMP agent at {master} ({e}); procimgd tries again every few \
                 seconds. Install and start net-snmp's snmpd with `master agentx` (Debian's \
                 default), or set [station] snmp_agentx = \"off\""
            );
        }
        RunnerEvent::ConnectFailed(..) => {}
        RunnerEvent::Disconnected(why) => {
            tracing::warn!("SNMP: the SNMP agent went away ({why}); procimgd tries again")
        }
        RunnerEvent::Session(Event::RegistrationRefused { subtree, error, .. }) => tracing::warn!(
            "SNMP: the SNMP agent refused to let procimgd serve {subtree} ({error:?}); another \
             subagent serves it"
        ),
        RunnerEvent::Session(Event::OpenRefused { error }) => {
            tracing::warn!("SNMP: the SNMP agent refused procimgd's session ({error:?})")
        }
        RunnerEvent::Session(e) => tracing::debug!("SNMP: {e:?}"),
    }
}

fn chassis(id: &Id) -> ChassisId {
    match id {
        Id::MacAddress(m) => ChassisId::mac(m.0),
        Id::Local(s) => ChassisId::local(s),
        Id::Other { subtype, id } => ChassisId {
            subtype: *subtype,
            id: id.clone(),
        },
    }
}

fn port(id: &Id) -> PortId {
    match id {
        Id::MacAddress(m) => PortId::mac(m.0),
        Id::Local(s) => PortId::local(s),
        Id::Other { subtype, id } => PortId {
            subtype: *subtype,
            id: id.clone(),
        },
    }
}
