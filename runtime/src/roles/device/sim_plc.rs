// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device demo's PLC (`network = "sim"` in the device role): procimg's own IO controller
//! in a thread of procimgd, on the in-process link and UDP network to the station. It
//! connects the station as configured — DCP, Connect, the parameter records with their
//! configured values, PrmEnd, ApplicationReady — and then runs the controller's end of the
//! cyclic exchange with a small PLC program: a submodule's output data (Q) is its input data
//! (I) plus one, byte by byte, so that whatever a client of the station writes comes back
//! changed; output bytes without input bytes count the PLC's cycles.
//!
//! Nothing here is the device: the station is procimgd's device role, which cannot tell
//! this PLC from a real one.

use crate::config::{DeviceConfig, SimBehaviour, StationConfig};
use crate::phy::datagram::{SimDatagram, SimDatagramPeer};
use crate::roles::controller::device_spec;
use crate::sys::clock::{now_ns, sleep_until_ns};
use procimg_nic::Nic;
use procimg_nic::sim_link::LinkEnd;
use procimg_profinet::controller::plan::{
    ControllerIdentity, DevicePlan, PlanError, PlannedRecord,
};
use procimg_profinet::controller::{
    Controller, ControllerAction, DeviceEvent, DeviceState, RecordRequest,
};
use procimg_profinet::cyclic::{Consumer, CyclicAr, Verdict};
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::ethernet::{self, ETHERTYPE_PROFINET};
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

/// Starts the PLC for the station of `plans` on `link` and `udp` until `stop`, cycling every
/// `cycle_ns`, at SCHED_FIFO `priority` where allowed.
pub fn spawn(
    plans: Vec<DevicePlan>,
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
            let recipe = plans.first().and_then(|p| p.records.first().cloned());
            let mut controller = Controller::new(id, plans, 0, now_ns());
            // Like an engineering tool, the demo PLC reads what the station has plugged
            // before it connects: whatever the managing client plugged is cycled.
            controller.learn_real_identification(true);
            Plc {
                controller,
                names,
                recipe,
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
    /// The station's first parameter record, which the program writes now and then.
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
        DeviceEvent::Activation { .. } => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_profinet::cyclic::VerdictKind;
    use procimg_profinet::cyclic::trial::TrialSetup;

    const MS: u64 = 1_000_000;

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
