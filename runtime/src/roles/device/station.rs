// SPDX-License-Identifier: MIT OR Apache-2.0
//! The station: the device engine built from `[station]`, and what the control side reports
//! of it (name, address, identity, the AR), kept up to date by the acyclic thread.

use super::identity::Identity;
use crate::config::StationConfig;
use procimg_control::{
    self as control, ArReport, NeighbourReport, StationDiagnosis, StationReport,
};
use procimg_profinet::device::{
    Application, ArCheck, ArState, DcpSetCheck, Device, DeviceSetup, DiagnosisStore,
    ParameterRecord, RecordJob, SubslotAddr,
};
use procimg_profinet::port::neighbours::Neighbour;
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::alarm::AlarmType;
use procimg_profinet::wire::lldp::Id;
use procimg_profinet::wire::record::{Im0, SoftwareRevision, blank_padded};
use procimg_profinet::wire::rta_pdu::AbortCode;
use std::sync::Mutex;

/// The device's program as the engine sees it: nothing, since the cycle thread moves the IO
/// data between the image and the frames.
pub struct ImageApplication;

impl Application for ImageApplication {
    fn fill_inputs(&mut self, _: u64, _: &mut [u8], _: &[u8], _: &[u8], _: bool) {}
}

/// What the device tells its client services and the log.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum StationEvent {
    /// The AR reached a state: as the status report shows it (the PLC's RUN/STOP comes with
    /// [`StationEvent::PlcRunning`], and stays as it was).
    Ar(ArReport),
    /// The AR ended: by the PLC's Release (`abort` none), or aborted.
    ArEnded {
        /// The ARUUID.
        ar_uuid: String,
        /// Why it was aborted, if it was.
        abort: Option<AbortCode>,
        /// This side ended it on purpose (procimgd stopping or going OFFLINE).
        planned: bool,
    },
    /// DCP Signal: the engineering tool asks the station to make itself seen.
    Blink,
    /// The port's LLDP neighbours changed: as they are now, and the alias name.
    Neighbours {
        /// The neighbours.
        neighbours: Vec<NeighbourReport>,
        /// The alias name they give the station.
        alias_name: Option<String>,
    },
    /// The DataStatus of the PLC's output frames: RUN (`true`) or STOP, a station problem,
    /// backup rather than primary.
    PlcRunning {
        /// RUN.
        running: bool,
        /// The PLC's StationProblemIndicator says a problem.
        station_problem: bool,
        /// Backup, not primary.
        backup: bool,
    },
    /// DCP set the station's name or IP suite (to a new value, or to keep the value across a
    /// restart), or reset it to factory. The engine has no event for it: the role tells it
    /// from what the engine holds (`identity.rs`).
    Identity {
        /// The name and IP suite now.
        identity: Identity,
        /// DCP set it to be kept across a restart: the engine's count of kept changes grew.
        permanent: bool,
        /// A reset to factory, as told from the state it leaves: no name and no address,
        /// and that kept. A permanent Set of an empty name and address 0.0.0.0 leaves the
        /// same state and is told the same: the station cannot tell them apart afterwards,
        /// and neither can its next start.
        factory_reset: bool,
    },
    /// A client plugged (`idents`: module and submodule ident numbers) or pulled (`None`)
    /// the submodule at `at`; `alarm` is what the PLC got.
    Plug {
        /// Where.
        at: SubslotAddr,
        /// What is plugged now, or `None`.
        idents: Option<(u32, u32)>,
        /// The alarm to the PLC's AR, if one went out.
        alarm: Option<AlarmType>,
    },
    /// The PLC reads or writes a record whose submodule's records a client took.
    Record(RecordJob),
    /// The PLC ended the parameters of the submodule plugged at `0` (its PlugPrmEnd).
    PlugParameterized(SubslotAddr),
    /// A client's alarm ended: the PLC acknowledged it (`status`: the AlarmAck's
    /// PNIOStatus), or its AR ended first (`None`).
    AlarmDone {
        /// The subscriber that sent it.
        subscriber: u64,
        /// Its tag.
        tag: u64,
        /// The AlarmAck's PNIOStatus.
        status: Option<[u8; 4]>,
    },
    /// A PLC connects and a client checks new ARs.
    ArCheck(ArCheck),
    /// DCP sets the station's name or address and a client checks such changes.
    DcpSetCheck(DcpSetCheck),
}

/// What the report's neighbours and access AR were made from: made again when the
/// neighbour table changed (and every second, for the time left to live) or another tool
/// holds the access AR.
#[derive(Default)]
struct Shown {
    neighbour_changes: u64,
    neighbours_at: u64,
    access: Option<procimg_profinet::wire::Uuid>,
}

/// The station as the status report shows it.
pub struct Station {
    report: Mutex<StationReport>,
    /// The diagnosis the report shows, as the engine held it: the report's copy is made
    /// again only when the engine's changed.
    diagnosis_shown: Mutex<DiagnosisStore>,
    /// What the report's neighbours and access AR were made from.
    shown: Mutex<Shown>,
}

impl Station {
    /// The station of `config` at MAC address `mac`, before anything happened.
    pub fn new(config: &StationConfig, mac: MacAddress) -> Station {
        Station {
            report: Mutex::new(StationReport {
                name: config.name.clone(),
                mac: mac.to_string(),
                ip: config
                    .ip
                    .map_or_else(|| "0.0.0.0".to_owned(), |ip| ip.to_string()),
                netmask: config.netmask.to_string(),
                gateway: config.gateway.to_string(),
                type_of_station: config.device_type.clone(),
                order_number: config.order_number.clone(),
                serial_number: config.serial_number.clone(),
                hardware_revision: config.hardware_revision,
                vendor_id: config.vendor_id,
                device_id: config.device_id,
                ar: None,
                aborted_ars: 0,
                alarms_acknowledged: 0,
                last_abort: None,
                diagnosis: Vec::new(),
                station_problem: false,
                program: None,
                neighbours: Vec::new(),
                alias_name: None,
                access_ar: None,
            }),
            diagnosis_shown: Mutex::new(DiagnosisStore::new()),
            shown: Mutex::new(Shown::default()),
        }
    }

    /// The report now.
    pub fn report(&self) -> StationReport {
        self.lock().clone()
    }

    /// Whether an AR is up (the shutdown waits for none).
    pub fn has_ar(&self) -> bool {
        self.lock().ar.is_some()
    }

    /// Takes in the counters and the diagnosis of `device`, and whether the station's frames
    /// say a problem (the name and address come with [`StationEvent::Identity`]).
    pub fn refresh<A>(&self, device: &Device<A>, station_problem: bool)
    where
        A: procimg_profinet::device::Application,
    {
        let mut shown = self
            .diagnosis_shown
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let changed = *shown != *device.diagnosis();
        if changed {
            shown.clone_from(device.diagnosis());
        }
        let neighbours = self.neighbours_due(device.station().neighbours().changes);
        let mut r = self.lock();
        r.alarms_acknowledged = device.alarm_acks().count();
        r.station_problem = station_problem;
        if self.access_due(device.ar().access().map(|a| a.ar_uuid())) {
            r.access_ar = device.ar().access().map(|a| {
                tracing::info!(
                    "engineering tool \"{}\" ({}) has a device access AR {}",
                    a.initiator_name(),
                    a.initiator_mac(),
                    a.ar_uuid()
                );
                control::AccessArReport {
                    ar_uuid: a.ar_uuid().to_string(),
                    tool_name: a.initiator_name().to_owned(),
                    tool_mac: a.initiator_mac().to_string(),
                }
            });
        }
        if let Some(now_ns) = neighbours {
            let (list, alias) = (device.station().neighbours(), device.station().alias_name());
            if r.alias_name.as_deref() != alias {
                match alias {
                    Some(a) => tracing::info!("the station's alias name is now {a:?}"),
                    None => tracing::info!("the station has no alias name any more"),
                }
            }
            r.neighbours = list
                .entries()
                .iter()
                .map(|n| neighbour(n, now_ns))
                .collect();
            r.alias_name = alias.map(str::to_owned);
        }
        if changed {
            r.diagnosis = shown
                .iter()
                .flat_map(|(at, entries)| {
                    entries.iter().map(move |e| StationDiagnosis {
                        api: at.api,
                        slot: at.slot,
                        subslot: at.subslot,
                        entry: super::diagnosis::reported(e),
                    })
                })
                .collect();
        }
    }

    /// Takes in `event`, and logs it.
    pub fn note(&self, event: &StationEvent) {
        let mut r = self.lock();
        match event {
            StationEvent::Ar(reached) => {
                let report = ArReport {
                    plc_running: r.ar.as_ref().and_then(|a| a.plc_running),
                    ..reached.clone()
                };
                if report.state == control::ArState::Data {
                    tracing::info!(
                        "AR {} with PLC \"{}\" ({}) is in data exchange",
                        report.ar_uuid,
                        report.controller_name,
                        report.controller_mac
                    );
                } else {
                    tracing::debug!("AR {}: {}", report.ar_uuid, report.state);
                }
                r.ar = Some(report);
            }
            StationEvent::ArEnded {
                ar_uuid: uuid,
                abort,
                planned,
            } => {
                r.ar = None;
                match abort {
                    Some(_) if *planned => {
                        tracing::info!("AR {uuid} ended: this device stopped taking part")
                    }
                    Some(code) => {
                        r.aborted_ars += 1;
                        r.last_abort = Some(code.to_string());
                        tracing::warn!("AR {uuid} aborted: {code}");
                    }
                    None => tracing::info!("AR {uuid} released by the PLC"),
                }
            }
            // The report's copy is `refresh`'s, made from the same change.
            StationEvent::Neighbours { neighbours, .. } => match neighbours.first() {
                Some(n) => tracing::info!(
                    "port-001 neighbour: chassis {:?} port {:?} ({}){}",
                    n.chassis_id,
                    n.port_id,
                    n.mac,
                    if neighbours.len() > 1 {
                        format!(" and {} more", neighbours.len() - 1)
                    } else {
                        String::new()
                    }
                ),
                None => tracing::info!("port-001 has no LLDP neighbour any more"),
            },
            StationEvent::Blink => {
                tracing::info!("DCP Signal: station \"{}\" asked to blink", r.name)
            }
            StationEvent::Plug { at, idents, alarm } => {
                let alarm = alarm.map_or(String::new(), |a| format!(", {a} alarm to the PLC"));
                match idents {
                    Some((m, sub)) => tracing::info!(
                        "{at} plugged: module {m:#010x}, submodule {sub:#010x}{alarm}"
                    ),
                    None => tracing::info!("{at} pulled{alarm}"),
                }
            }
            StationEvent::DcpSetCheck(c) => tracing::debug!(
                "DCP Set check {}: {} sets name {:?}, address {:?}{}",
                c.job,
                c.from,
                c.name,
                c.ip_suite.map(|[ip, ..]| std::net::Ipv4Addr::from(ip)),
                if c.reset { ", reset to factory" } else { "" }
            ),
            StationEvent::ArCheck(c) => tracing::debug!(
                "AR check {}: PLC {} ({}) connects AR {}",
                c.job,
                c.controller_mac,
                c.controller_name,
                c.ar_uuid
            ),
            StationEvent::Record(j) => tracing::debug!(
                "record job {}: the PLC {} record {:#06x} of slot {} subslot {:#06x}",
                j.job,
                if j.write { "writes" } else { "reads" },
                j.index,
                j.slot,
                j.subslot
            ),
            StationEvent::PlugParameterized(at) => {
                tracing::debug!("the PLC ended the parameters of {at} (PlugPrmEnd)")
            }
            StationEvent::AlarmDone { tag, status, .. } => match status {
                Some(s) => tracing::debug!("alarm {tag} acknowledged by the PLC: {s:02x?}"),
                None => tracing::debug!("alarm {tag} unacknowledged: the AR ended"),
            },
            StationEvent::PlcRunning {
                running,
                station_problem,
                backup,
            } => {
                tracing::info!(
                    "the PLC is in {}",
                    control::services::plc_state_text(*running, *station_problem, *backup)
                );
                if let Some(ar) = r.ar.as_mut() {
                    ar.plc_running = Some(*running);
                }
            }
            StationEvent::Identity {
                identity,
                permanent,
                factory_reset,
            } => {
                let ip = identity.ip.to_string();
                let kept = if *permanent {
                    ", kept across restarts"
                } else {
                    ""
                };
                if *factory_reset {
                    tracing::info!(
                        "DCP reset the station to factory: no name, no address (was \"{}\" at {})",
                        r.name,
                        r.ip
                    );
                } else if r.name != identity.name || r.ip != ip {
                    tracing::info!(
                        "the station is now \"{}\" at {ip}{kept} (was \"{}\" at {})",
                        identity.name,
                        r.name,
                        r.ip
                    );
                } else {
                    tracing::info!("the station stays \"{}\" at {ip}{kept}", identity.name);
                }
                r.name.clone_from(&identity.name);
                r.ip = ip;
                r.netmask = identity.netmask.to_string();
                r.gateway = identity.gateway.to_string();
            }
        }
    }

    /// Whether the report's neighbours are to be made again, the table's change count being
    /// `changes`: the time now if so.
    fn neighbours_due(&self, changes: u64) -> Option<u64> {
        let mut shown = self.shown();
        let now_ns = crate::sys::clock::now_ns();
        let due = shown.neighbour_changes != changes
            || now_ns.saturating_sub(shown.neighbours_at) >= 1_000_000_000;
        due.then(|| {
            (shown.neighbour_changes, shown.neighbours_at) = (changes, now_ns);
            now_ns
        })
    }

    /// Whether the report's access AR is to be made again, the device's being `now`.
    fn access_due(&self, now: Option<procimg_profinet::wire::Uuid>) -> bool {
        let mut shown = self.shown();
        let due = shown.access != now;
        shown.access = now;
        due
    }

    fn shown(&self) -> std::sync::MutexGuard<'_, Shown> {
        self.shown
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, StationReport> {
        // A panic elsewhere does not make the report wrong: take it as it is.
        self.report.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The engine's AR state as clients are told it, none without an AR: the one place the two
/// enums meet, so a state added on either side fails to compile here until it is given a name.
pub fn reported(state: ArState) -> Option<control::ArState> {
    match state {
        ArState::Idle => None,
        ArState::Connected => Some(control::ArState::Connected),
        ArState::Parameterized => Some(control::ArState::Parameterized),
        ArState::WaitAppReadyConfirm => Some(control::ArState::WaitingForApplicationReadyConfirm),
        ArState::Data => Some(control::ArState::Data),
    }
}

/// How messages name the engine's AR state: its word in the status report, "none" without
/// an AR.
pub fn state_name(state: ArState) -> &'static str {
    reported(state).map_or("none", control::ArState::as_str)
}

/// The device engine of `station` on an interface with MAC `mac`, with its cyclic exchange
/// handed over to a cycle of `cycle_ns`.
pub fn engine(station: &StationConfig, mac: MacAddress, cycle_ns: u64) -> Device<ImageApplication> {
    let mut device = Device::new(DeviceSetup {
        name: station.name.clone(),
        mac,
        ip: station.ip.map(|ip| ip.octets()),
        vendor_id: station.vendor_id,
        device_id: station.device_id,
        instance: station.instance,
        submodules: station
            .submodule_configs()
            .map(crate::roles::plugged)
            .collect(),
        application: ImageApplication,
        im0: im0(station),
    });
    // Submodules not plugged at start keep their place and wait for a client to plug them.
    for s in station.submodules.iter().filter(|s| !s.plugged) {
        let c = &s.submodule;
        let at = SubslotAddr::new(c.api, c.slot, c.subslot);
        // Configured and plugged, with no AR yet: a pull cannot be refused.
        let _ = device.pull_submodule(at, 0, &mut Vec::new());
    }
    device
        .station_mut()
        .set_type_of_station(&station.device_type);
    device.set_parameter_records(&parameter_records(station));
    device.hand_over_cyclic(cycle_ns);
    device
}

/// The user records the station accepts: each submodule's configured `records`.
fn parameter_records(station: &StationConfig) -> Vec<ParameterRecord> {
    station
        .submodules
        .iter()
        .flat_map(|s| {
            let c = &s.submodule;
            s.accepts.iter().map(|r| ParameterRecord {
                at: SubslotAddr::new(c.api, c.slot, c.subslot),
                index: r.index,
                length: r.length,
                initial: r.initial.clone(),
            })
        })
        .collect()
}

/// I&M0 of the station, from the configuration (the texts are checked there to fit).
fn im0(station: &StationConfig) -> Im0 {
    let v = station.software_revision;
    Im0 {
        vendor_id: station.vendor_id,
        order_id: blank_padded(&station.order_number).unwrap_or([b' '; 20]),
        serial_number: blank_padded(&station.serial_number).unwrap_or([b' '; 16]),
        hardware_revision: station.hardware_revision,
        software_revision: SoftwareRevision {
            prefix: u8::try_from(v.prefix).unwrap_or(b'V'),
            functional_enhancement: v.functional,
            bug_fix: v.bug_fix,
            internal_change: v.internal,
        },
        revision_counter: 0,
        profile_id: 0,
        profile_specific_type: 0,
        im_version: (1, 1),
        im_supported: 0,
    }
}

/// A neighbour as the status report and the notifications show it, at `now_ns`.
pub fn neighbour(n: &Neighbour, now_ns: u64) -> NeighbourReport {
    let id = |id: &Id| match id {
        Id::Local(s) => s.clone(),
        Id::MacAddress(m) => m.to_string(),
        other => other.to_string(),
    };
    NeighbourReport {
        chassis_id: id(&n.chassis_id),
        port_id: id(&n.port_id),
        station: n.peer_station().map(str::to_owned),
        port: n.peer_port().map(str::to_owned),
        mac: n.mac().to_string(),
        ip: n
            .management_ipv4()
            .map(|ip| std::net::Ipv4Addr::from(ip).to_string()),
        mau_type: n.mac_phy().map(|m| m.mau_type),
        ttl_left_s: n.expires_ns().saturating_sub(now_ns) / 1_000_000_000,
    }
}
