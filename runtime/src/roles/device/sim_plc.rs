// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device demo's PLC (`network = "sim"` in the device role): procimg's own IO controller
//! in a thread of procimgd, on the in-process link and UDP network to the station. It
//! connects the station — DCP, a read of its RealIdentificationData (0xF000), Connect, the
//! parameter records, PrmEnd, ApplicationReady — and then runs the controller's end of the
//! cyclic exchange with a small PLC program: a submodule's output data (Q) is its input data
//! (I) plus one, byte by byte, so that whatever a client of the station writes comes back
//! changed; output bytes without input bytes count the PLC's cycles.
//!
//! What it connects:
//! - A configured station (`[[station.submodule]]`): the configuration's tree, lengths and
//!   record values, its ident numbers following what the read finds plugged at those
//!   positions (the controller's `learn_real_identification`), so that whatever the
//!   managing client plugged is cycled.
//! - A station its program defines (`[station] gsdml`): the tree the read finds, with the
//!   IO lengths and parameter records (their defaults) of the station's GSDML file, as a
//!   PLC that has only that file would plan it (the controller's
//!   `plan_from_real_identification`, [`tree_planner`]). The file is looked up by
//!   `procimg_config::define_station`, the same rule that makes the station procimgd runs
//!   from the program's tree. A tree the file does not allow is warned about, naming the
//!   ident, and the station is connected as procimgd runs it (the device then reports the
//!   differences).
//!
//! Nothing here is the device: the station is procimgd's device role, which cannot tell
//! this PLC from a real one.

use crate::config::{DeviceConfig, SimBehaviour, StationConfig};
use crate::phy::datagram::{SimDatagram, SimDatagramPeer};
use crate::roles::controller::device_spec;
use crate::sys::clock::{now_ns, sleep_until_ns};
use procimg_config::{PlannedSubmodule, ProgramStation, define_station};
use procimg_nic::Nic;
use procimg_nic::sim_link::LinkEnd;
use procimg_profinet::controller::device::TreePlanner;
use procimg_profinet::controller::plan::{
    ControllerIdentity, DevicePlan, PlanError, PlannedRecord,
};
use procimg_profinet::controller::{
    Controller, ControllerAction, DeviceEvent, DeviceState, RecordRequest,
};
use procimg_profinet::cyclic::{Consumer, CyclicAr, Verdict};
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::ethernet::{self, ETHERTYPE_PROFINET};
use procimg_profinet::wire::record::IdentificationData;
use procimg_profinet::wire::rpc::RPC_PORT;
use procimg_profinet::wire::rt::{TIME_UNIT_NS, data_status};
use std::net::{Ipv4Addr, SocketAddrV4};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;

/// The demo PLC's MAC address.
pub const SIM_PLC_MAC: MacAddress = MacAddress([0x02, 0x50, 0x49, 0xfe, 0x00, 0x01]);
/// The station's MAC address on the simulated network.
pub const SIM_STATION_MAC: MacAddress = MacAddress([0x02, 0x50, 0x49, 0xfe, 0x00, 0x02]);
/// The station's address on the simulated network when its configuration gives none (the
/// PLC then assigns it by DCP, as to a new device).
pub const SIM_STATION_IP: Ipv4Addr = Ipv4Addr::new(192, 168, 0, 50);
/// Frame periods the station waits for the PLC's data before it gives up: generous, since
/// the PLC is a thread that a loaded machine may delay (real PLCs: 3).
const SIM_WATCHDOG_FACTOR: u16 = 100;
/// How often the PLC logs what it reads and writes.
const REPORT_EVERY_NS: u64 = 5_000_000_000;
/// IOxS GOOD.
const IOXS_GOOD: u8 = 0x80;
/// How often the PLC program writes the station's first parameter record anew while the
/// data flows (as a program's WRREC of a recipe would), so that a client that took the
/// record sees writes and its answers reach the PLC.
const RECIPE_EVERY_NS: u64 = 2_000_000_000;

/// The address the station has on the simulated network.
pub fn station_ip(station: &StationConfig) -> Ipv4Addr {
    station.ip.unwrap_or(SIM_STATION_IP)
}

/// The PLC's address: the station's subnet, host 1 (or 2 if the station is host 1).
pub fn plc_ip(station: &StationConfig) -> Ipv4Addr {
    let [a, b, c, d] = station_ip(station).octets();
    Ipv4Addr::new(a, b, c, if d == 1 { 2 } else { 1 })
}

/// The station as the PLC's configuration would describe it: every submodule expected as
/// configured, each accepted record written with its configured value.
fn as_device(station: &StationConfig) -> DeviceConfig {
    DeviceConfig {
        name: station.name.clone(),
        ip: Some(station_ip(station)),
        vendor_id: station.vendor_id,
        device_id: station.device_id,
        gsdml: None,
        instance: station.instance,
        reduction_ratio: 1,
        watchdog_factor: SIM_WATCHDOG_FACTOR,
        sim: SimBehaviour::None,
        topology: Vec::new(),
        optional: false,
        submodules: station
            .submodules
            .iter()
            .map(|s| {
                let mut sub = s.submodule.clone();
                sub.records = s
                    .accepts
                    .iter()
                    .map(|r| crate::config::ParameterRecord {
                        index: r.index,
                        data: r.initial.clone(),
                    })
                    .collect();
                sub
            })
            .collect(),
    }
}

/// The PLC's plan of the station, for a cycle of `cycle_ns`.
pub fn plan(station: &StationConfig, cycle_ns: u64) -> Result<Vec<DevicePlan>, PlanError> {
    DevicePlan::all(&[device_spec(&as_device(station))], cycle_ns)
}

/// How the PLC plans `station` from the tree it reads, when its program defines it: from
/// the station's GSDML file (see the module docs). `None` for a configured station, whose
/// configured plan the PLC keeps.
pub fn tree_planner(station: &StationConfig, cycle_ns: u64) -> Option<TreePlanner> {
    let program = station.program.clone()?;
    let base = station.clone();
    // Why the last tree could not be planned, so that a station that keeps its tree is
    // not warned about before every Connect.
    let warned = std::cell::Cell::new(None::<String>);
    Some(Box::new(move |current, real| {
        let planned = plan_of_tree(&base, &program, real, cycle_ns, current);
        let last = warned.take();
        match &planned {
            Err(why) if last.as_ref() != Some(why) => {
                tracing::warn!(
                    "demo PLC: station {:?}: {why}; it is connected as procimgd runs it",
                    base.name
                );
                warned.set(Some(why.clone()));
            }
            Err(_) => warned.set(last),
            Ok(p) => tracing::debug!(
                "demo PLC: station {:?} planned from the tree it reports and its GSDML file: \
                 {} submodules",
                base.name,
                p.submodules.len()
            ),
        }
        planned.ok()
    }))
}

/// The plan of the station `base` whose program defines it as `real` reports (after slot
/// 0, which the GSDML file defines), from `program`'s GSDML file, for the device and table
/// entries of `current`; why not, in words.
fn plan_of_tree(
    base: &StationConfig,
    program: &ProgramStation,
    real: &IdentificationData,
    cycle_ns: u64,
    current: &DevicePlan,
) -> Result<DevicePlan, String> {
    let tree: Vec<PlannedSubmodule> = real
        .apis
        .iter()
        .flat_map(|a| {
            a.modules.iter().filter(|m| m.slot != 0).flat_map(move |m| {
                m.submodules.iter().map(move |s| PlannedSubmodule {
                    api: a.api,
                    slot: m.slot,
                    subslot: s.subslot,
                    module_ident: m.module_ident,
                    submodule_ident: s.submodule_ident,
                })
            })
        })
        .collect();
    let dap = program.file.daps.get(program.dap_index).ok_or_else(|| {
        format!(
            "{} has no device access point {}",
            program.file.origin, program.dap
        )
    })?;
    let station = define_station(base, &program.file, dap, &tree)
        .map_err(|e| format!("the tree it reports does not fit its GSDML file: {e}"))?;
    DevicePlan::new(
        current.device,
        current.first_submodule,
        &device_spec(&as_device(&station)),
        cycle_ns,
    )
    .map_err(|e| format!("the tree it reports cannot be planned: {e}"))
}

/// Starts the PLC for the station of `plans` on `link` and `udp` until `stop`, cycling every
/// `cycle_ns`, at SCHED_FIFO `priority` where allowed; `planner`, if given, plans the
/// station from the tree it reports ([`tree_planner`]).
#[allow(clippy::too_many_arguments)]
pub fn spawn(
    plans: Vec<DevicePlan>,
    planner: Option<TreePlanner>,
    ip: Ipv4Addr,
    cycle_ns: u64,
    link: LinkEnd,
    udp: SimDatagramPeer,
    stop: Arc<AtomicBool>,
    priority: u8,
) -> std::io::Result<JoinHandle<()>> {
    std::thread::Builder::new()
        .name("procimg-sim-plc".into())
        .stack_size(crate::sys::rt::HELPER_THREAD_STACK)
        .spawn(move || {
            let _ = crate::sys::rt::set_fifo(priority);
            let id = ControllerIdentity {
                mac: SIM_PLC_MAC,
                ip,
                station_name: "demo-plc".into(),
                vendor_id: 0x0493,
                device_id: 0x0fff,
                instance: 1,
            };
            let names: Vec<String> = plans.iter().map(|p| p.name.clone()).collect();
            let mut controller = Controller::new(id, plans, 0, now_ns());
            // Like an engineering tool, the demo PLC reads what the station has plugged
            // before it connects: whatever the managing client plugged is cycled, and a
            // station its program defines is planned from that and its GSDML file.
            match planner {
                Some(p) => {
                    controller.plan_from_real_identification(0, p);
                }
                None => controller.learn_real_identification(true),
            }
            Plc {
                controller,
                names,
                recipe: None,
                recipe_writes: 0,
                link,
                udp,
                ip,
                cycle_ns: cycle_ns.max(1),
                exchange: None,
                actions: Vec::new(),
            }
            .run(&stop);
        })
}

/// The PLC's end of the cyclic exchange.
struct Exchange {
    ar: Box<CyclicAr>,
    consumer: Consumer,
    /// The station's input data of the last valid frame, per submodule with inputs.
    inputs: Vec<(usize, Vec<u8>)>,
    last_report_ns: u64,
    /// When the program last wrote the parameter record.
    last_recipe_ns: u64,
}

struct Plc {
    controller: Controller,
    names: Vec<String>,
    /// The station's first parameter record in the plan of the running AR, which the
    /// program writes now and then.
    recipe: Option<PlannedRecord>,
    /// Writes of it by the program so far.
    recipe_writes: u32,
    link: LinkEnd,
    udp: SimDatagramPeer,
    ip: Ipv4Addr,
    cycle_ns: u64,
    exchange: Option<Exchange>,
    actions: Vec<ControllerAction>,
}

impl Plc {
    fn run(mut self, stop: &AtomicBool) {
        let start = now_ns();
        self.controller.set_online(true, start, &mut self.actions);
        let mut next_cycle = start;
        let mut k: u64 = 0;
        while !stop.load(Ordering::Acquire) {
            let now = now_ns();
            let Plc {
                controller,
                link,
                exchange,
                actions,
                ..
            } = &mut self;
            while let Ok(true) = link.receive(&mut |frame| {
                if !exchange
                    .as_mut()
                    .is_some_and(|x| x.take(frame, now, controller))
                {
                    controller.on_frame(frame, now, actions);
                }
            }) {}
            while let Ok(g) = self.udp.rx.try_recv() {
                self.controller
                    .on_datagram(g.from, &g.payload, now, &mut self.actions);
            }
            self.controller.poll(now, &mut self.actions);
            if now >= next_cycle {
                self.cycle(k, now);
                k += 1;
                let missed = (now - next_cycle) / self.cycle_ns;
                next_cycle += self.cycle_ns * (missed + 1);
            }
            self.carry_out(now);
            let wake = self
                .controller
                .next_deadline_ns()
                .map_or(next_cycle, |d| d.min(next_cycle));
            sleep_until_ns(wake.max(now + 20_000));
        }
        let mut out = Vec::new();
        self.controller.set_online(false, now_ns(), &mut out);
        self.actions.extend(out);
        self.carry_out(now_ns());
    }

    /// One PLC cycle: the output frame if due, the watchdog.
    fn cycle(&mut self, k: u64, now: u64) {
        let Some(x) = self.exchange.as_mut() else {
            return;
        };
        if x.ar.due(k) {
            let every = u64::from(x.ar.timing.every_cycles.max(1));
            let frame = x.fill_outputs(
                (k / every) as u32,
                k.wrapping_mul(self.cycle_ns / TIME_UNIT_NS) as u16,
            );
            let _ = self.link.send(frame);
        }
        if x.consumer.expired(now) {
            let (device, epoch) = (x.ar.device, x.ar.epoch);
            self.exchange = None;
            tracing::warn!("demo PLC: no input data from the station within the watchdog");
            self.controller
                .on_watchdog(device, epoch, now, &mut self.actions);
        } else if let Some(r) = self.recipe.as_ref().filter(|_| {
            x.consumer.receiving() && now.saturating_sub(x.last_recipe_ns) >= RECIPE_EVERY_NS
        }) {
            x.last_recipe_ns = now;
            self.recipe_writes += 1;
            // The value: the write's number, big-endian, in the record's last bytes.
            let mut data = vec![0u8; r.data.len()];
            let n = self.recipe_writes.to_be_bytes();
            let k = data.len().min(4);
            let at = data.len() - k;
            data[at..].copy_from_slice(&n[4 - k..]);
            tracing::info!(
                "demo PLC: writes record {} of slot {} subslot {:#06x}: {data:02x?}",
                r.index,
                r.slot,
                r.subslot
            );
            self.controller.record(
                RecordRequest {
                    reference: u64::from(self.recipe_writes),
                    device: x.ar.device,
                    api: r.api,
                    slot: r.slot,
                    subslot: r.subslot,
                    index: r.index,
                    max_len: 0,
                    write: Some(data),
                },
                &mut self.actions,
            );
        } else if now.saturating_sub(x.last_report_ns) >= REPORT_EVERY_NS && x.consumer.receiving()
        {
            x.last_report_ns = now;
            for (sub, data) in &x.inputs {
                tracing::info!(
                    "demo PLC: reads I = {:02x?} of submodule {sub}",
                    &data[..data.len().min(16)]
                );
            }
        }
    }

    fn carry_out(&mut self, now: u64) {
        for a in std::mem::take(&mut self.actions) {
            match a {
                ControllerAction::Frame(f) => {
                    let _ = self.link.send(&f);
                }
                // The simulated network resolves no addresses.
                ControllerAction::Neighbour { .. } => {}
                ControllerAction::Datagram { to, payload } => {
                    let _ = self.udp.tx.send(SimDatagram {
                        from: SocketAddrV4::new(self.ip, RPC_PORT),
                        to,
                        payload,
                    });
                }
                ControllerAction::Start(ar) => {
                    // The plan the AR was connected with, which the tree read may have made.
                    self.recipe = self
                        .controller
                        .plan(ar.device)
                        .and_then(|p| p.records.first().cloned());
                    self.exchange = Some(Exchange {
                        consumer: Consumer::of(&ar, now),
                        ar,
                        inputs: Vec::new(),
                        last_report_ns: now,
                        last_recipe_ns: now,
                    })
                }
                ControllerAction::Stop { .. } => self.exchange = None,
                ControllerAction::Event(e) => {
                    log(&e, &self.names);
                    // What a PLC program sees first: the station's I data as its frames
                    // carried it when the ApplicationReady came (zeros where the station
                    // marks it BAD).
                    if let (
                        DeviceEvent::State {
                            state: DeviceState::Running,
                            ..
                        },
                        Some(x),
                    ) = (&e, &self.exchange)
                    {
                        for (sub, data) in &x.inputs {
                            tracing::info!(
                                "demo PLC: I data at the ApplicationReady: submodule {sub} = \
                                 {:02x?}",
                                &data[..data.len().min(16)]
                            );
                        }
                    }
                    // The PLC program takes every alarm at once (an OB that returns).
                    if let DeviceEvent::Alarm { ticket, .. } = e {
                        let mut acks = Vec::new();
                        self.controller.acknowledge_alarm(ticket, now, &mut acks);
                        self.actions.extend(acks);
                    }
                }
            }
        }
    }
}

impl Exchange {
    /// Takes `frame` if it is the station's input frame: its data, and the first one
    /// reported to the controller. `false` for any other frame.
    fn take(&mut self, frame: &[u8], now: u64, controller: &mut Controller) -> bool {
        let Ok(eth) = ethernet::Frame::new_checked(frame) else {
            return false;
        };
        if eth.ethertype() != ETHERTYPE_PROFINET {
            return false;
        }
        let c_sdu = match self.consumer.consume(eth.src(), eth.payload(), now) {
            Verdict::Accepted { c_sdu, first, .. } => {
                if first {
                    controller.on_data_started(self.ar.device, self.ar.epoch);
                }
                c_sdu
            }
            Verdict::Foreign => return false,
            Verdict::Invalid { .. } | Verdict::Stale | Verdict::TooShort => return true,
        };
        for o in self.ar.input.objects.iter().filter(|o| o.len > 0) {
            let (Some(d), Some(&iops)) = (c_sdu.get(o.data..o.data + o.len), c_sdu.get(o.iops))
            else {
                continue;
            };
            // Data its provider marks BAD is not used: the program sees zeros.
            let fresh = |v: &mut Vec<u8>| {
                v.clear();
                if iops & IOXS_GOOD != 0 {
                    v.extend_from_slice(d);
                } else {
                    v.resize(d.len(), 0);
                }
            };
            match self.inputs.iter_mut().find(|(s, _)| *s == o.submodule) {
                Some((_, v)) => fresh(v),
                None => {
                    let mut v = Vec::new();
                    fresh(&mut v);
                    self.inputs.push((o.submodule, v));
                }
            }
        }
        true
    }

    /// The PLC program: a submodule's output bytes are its input bytes plus one; output
    /// bytes without an input byte are `count`, big-endian, repeated; every status GOOD.
    /// Returns the frame to send.
    fn fill_outputs(&mut self, count: u32, cycle_counter: u16) -> &[u8] {
        let (output, c_sdu) = self.ar.c_sdu_mut();
        let word = count.to_be_bytes();
        for o in &output.objects {
            let inputs = self
                .inputs
                .iter()
                .find(|(s, _)| *s == o.submodule)
                .map_or(&[][..], |(_, v)| &v[..]);
            if let Some(d) = c_sdu.get_mut(o.data..o.data + o.len) {
                for (i, b) in d.iter_mut().enumerate() {
                    *b = inputs.get(i).map_or(word[i % 4], |v| v.wrapping_add(1));
                }
            }
            if let Some(b) = c_sdu.get_mut(o.iops) {
                *b = IOXS_GOOD;
            }
        }
        for c in &output.iocs {
            if let Some(b) = c_sdu.get_mut(c.offset) {
                *b = IOXS_GOOD;
            }
        }
        self.ar.seal(cycle_counter, data_status::OPERATE)
    }
}

fn log(e: &DeviceEvent, names: &[String]) {
    let name = |d: usize| names.get(d).map_or("?", String::as_str);
    match e {
        DeviceEvent::State { device, state } => {
            tracing::debug!("demo PLC: station {:?} {state}", name(*device))
        }
        DeviceEvent::Return { device } => {
            tracing::info!("demo PLC: station {:?} in data exchange", name(*device))
        }
        DeviceEvent::Failure { device, reason, .. } => {
            tracing::warn!("demo PLC: station {:?} failed: {reason}", name(*device))
        }
        DeviceEvent::Problem { device, reason, .. } => {
            tracing::warn!("demo PLC: station {:?}: {reason}", name(*device))
        }
        DeviceEvent::ModuleDiff { device, diff } => {
            for (api, slot, subslot, st) in diff.submodules() {
                tracing::warn!(
                    "demo PLC: station {:?}: API {api} slot {slot} subslot {subslot:#06x} \
                     differs: {st:?}",
                    name(*device)
                );
            }
        }
        DeviceEvent::Alarm {
            device,
            notification,
            ..
        } => tracing::info!(
            "demo PLC: {} alarm from station {:?} slot {} subslot {:#06x} ({:?}), acknowledged",
            notification.alarm_type,
            name(*device),
            notification.slot,
            notification.subslot,
            notification.specifier
        ),
        DeviceEvent::Record(r) => {
            let what = format!(
                "record {} of station {:?} slot {} subslot {:#06x}",
                r.request.index,
                name(r.request.device),
                r.request.slot,
                r.request.subslot
            );
            match &r.result {
                Ok(_) => tracing::info!("demo PLC: {what} written"),
                Err(f) => tracing::warn!("demo PLC: writing {what} failed: {}", f.reason),
            }
        }
        // Of a controller's own station, which the demo PLC does not run.
        DeviceEvent::Activation { .. }
        | DeviceEvent::Reconfigured { .. }
        | DeviceEvent::Signal
        | DeviceEvent::InterfaceAlarm(_)
        | DeviceEvent::StationAddress { .. }
        | DeviceEvent::InterfaceRecord { .. } => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_profinet::cyclic::VerdictKind;
    use procimg_profinet::cyclic::trial::TrialSetup;

    const MS: u64 = 1_000_000;

    /// A module that only the GSDML file of the planner test has: 40 bytes each way.
    const ONLY_IN_THE_FILE: u32 = 0x4242;

    /// The demo station as a program defines it from a GSDML file that also has
    /// [`ONLY_IN_THE_FILE`] in slot 3; procimgd's table has the demo's tree.
    fn program_station() -> StationConfig {
        let mut station = crate::config::Config::demo_device().station.unwrap();
        let mut described = station.clone();
        let mut extra = described.submodules.last().unwrap().clone();
        extra.submodule.slot = 3;
        extra.submodule.module_ident = ONLY_IN_THE_FILE;
        extra.submodule.submodule_ident = 1;
        extra.submodule.input_length = 40;
        extra.submodule.output_length = 40;
        extra.accepts.clear();
        described.submodules.push(extra);
        let date = procimg_config::gsdml::export::GsdmlDate::new(2026, 1, 2).unwrap();
        let file = procimg_config::gsdml::export::station_gsdml(&described, MS, date).unwrap();
        let gsdml = procimg_config::gsdml::Gsdml::parse(&file.xml, &file.file_name).unwrap();
        station.program = Some(ProgramStation {
            gsdml: file.file_name.into(),
            dap: gsdml.daps[0].id.clone(),
            file: Arc::new(gsdml),
            dap_index: 0,
        });
        station
    }

    fn real(tree: &[(u16, u32)]) -> IdentificationData {
        use procimg_profinet::wire::record::{IdentApi, IdentificationKind, RecordVersion};
        IdentificationData {
            kind: IdentificationKind::Real,
            version: RecordVersion::V1_1,
            apis: IdentApi::group(tree.iter().map(|&(slot, m)| (0, slot, m, 1, 1))),
        }
    }

    /// For a station its program defines, the PLC plans the tree it reads with the lengths
    /// and record defaults of the GSDML file, not procimgd's table; a tree the file does
    /// not allow gets no plan. A configured station keeps its configured plan.
    #[test]
    fn the_plc_plans_a_program_defined_station_from_the_tree_read_and_its_gsdml() {
        let station = program_station();
        let plans = plan(&station, MS).unwrap();
        assert!(!plans[0].has_submodule(0, 3, 1));
        let planner = tree_planner(&station, MS).expect("a planner");
        let learned = planner(
            &plans[0],
            &real(&[(0, 1), (1, 0x10), (3, ONLY_IN_THE_FILE)]),
        )
        .expect("a plan of the tree");
        let io: Vec<(u16, u16, u16)> = learned
            .submodules
            .iter()
            .filter(|s| s.slot > 0)
            .map(|s| (s.slot, s.input_length, s.output_length))
            .collect();
        assert_eq!(io, [(1, 8, 8), (3, 40, 40)]);
        let records: Vec<(u16, u16, &[u8])> = learned
            .records
            .iter()
            .map(|r| (r.slot, r.index, &r.data[..]))
            .collect();
        assert_eq!(records, [(1, 1, &[0, 0, 0, 10][..])]);
        assert_eq!(
            (learned.device, learned.first_submodule),
            (plans[0].device, plans[0].first_submodule)
        );
        assert!(planner(&plans[0], &real(&[(3, 0x4343)])).is_none());

        let configured = crate::config::Config::demo_device().station.unwrap();
        assert!(tree_planner(&configured, MS).is_none());
    }

    /// The demo PLC judges the station's frames as the protocol crate's consumer does: it
    /// hands the controller only what is not the exchange's, keeps the data of accepted
    /// frames and gives up when the rule says.
    #[test]
    fn the_demo_plc_judges_the_consumer_trial_as_the_consumer_does() {
        let station = crate::config::Config::demo_device().station.unwrap();
        let plans = plan(&station, MS).unwrap();
        let ar = CyclicAr::new(
            &plans[0],
            1,
            SIM_PLC_MAC,
            SIM_STATION_MAC,
            plans[0].frame_ids,
        );
        let id = ControllerIdentity {
            mac: SIM_PLC_MAC,
            ip: plc_ip(&station),
            station_name: "demo-plc".into(),
            vendor_id: 0x0493,
            device_id: 0x0fff,
            instance: 1,
        };
        let mut controller = Controller::new(id, plans, 0, 0);
        let trial = TrialSetup {
            peer: SIM_STATION_MAC,
            own: SIM_PLC_MAC,
            frame_id: ar.input.frame_id,
            data_length: ar.input.data_length,
            timing: ar.timing,
            first_at_ns: MS,
            first_counter: 0x0100,
        }
        .trial();
        let mut x = Exchange {
            consumer: Consumer::of(&ar, 0),
            ar: Box::new(ar),
            inputs: Vec::new(),
            last_report_ns: 0,
            last_recipe_ns: 0,
        };
        for f in &trial.frames {
            let ours = x.take(&f.frame, f.at_ns, &mut controller);
            assert_eq!(ours, f.verdict != VerdictKind::Foreign, "{:?}", f.verdict);
        }
        assert_eq!(x.consumer.counts(), trial.counts);
        let o = x.ar.input.objects.iter().find(|o| o.len > 0).unwrap();
        let (_, held) = x.inputs.iter().find(|(s, _)| *s == o.submodule).unwrap();
        assert_eq!(&held[..], &trial.last_c_sdu[o.data..o.data + o.len]);
        assert!(!x.consumer.expired(trial.expires_at_ns - 1));
        assert!(x.consumer.expired(trial.expires_at_ns));
    }
}
