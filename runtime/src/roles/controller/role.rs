// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO controller as a [`Role`]: the protocol crate's [`Controller`] with the daemon's
//! bookkeeping around it (the device states the control side reads, the log).

use super::states::DeviceStates;
use crate::roles::address::InterfaceAddress;
use crate::roles::port_watch::PortWatch;
use crate::roles::{CycleReport, DroppedDatagrams, Effect, Role};
use procimg_profinet::controller::{
    AddressError, AlarmTicket, Controller, ControllerAction, DeviceEvent, Reconfiguration,
    RecordRequest, StationAddress,
};
use procimg_profinet::wire::connect::IdentInfo;
use std::net::SocketAddrV4;
use std::sync::Arc;

/// What the client services ask of the controller.
#[derive(Debug)]
pub enum ControllerCommand {
    /// Activate or deactivate a device.
    Activate {
        /// Device index.
        device: usize,
        /// Active or not.
        active: bool,
    },
    /// Reconfigure the IO system (deactivate all, or tailor it).
    Reconfigure(Reconfiguration),
    /// Read or write a record.
    Record(RecordRequest),
    /// Send the AlarmAck of a delivered alarm.
    AcknowledgeAlarm(AlarmTicket),
    /// Read a record of the controller's own interface.
    InterfaceRecord {
        /// The request's reference.
        reference: u64,
        /// The subslot (0x8000 interface, 0x8001 port).
        subslot: u16,
        /// The record index.
        index: u16,
    },
    /// Give the controller's station a new name or IP suite, for a program.
    StationAddress {
        /// The request's reference.
        reference: u64,
        /// What is to change.
        change: StationAddress,
    },
}

/// The controller on the acyclic thread.
pub struct ControllerRole {
    controller: Controller,
    states: Arc<DeviceStates>,
    /// Station names, for the log.
    names: Vec<String>,
    /// The controller's actions before they become effects (kept for its capacity).
    actions: Vec<ControllerAction>,
    /// The last problem logged of each device, so that a retry failing the same way (a
    /// missing device, twice a second) is not a new warning.
    problems: ProblemLog,
    /// The station's address on a real interface, where programs and DCP may change it.
    address: Option<InterfaceAddress>,
    /// The real interface whose link and counters the interface's records report.
    port: Option<PortWatch>,
}

/// The last problem of each device that was logged as a warning, until it comes up.
#[derive(Default)]
struct ProblemLog(Vec<Option<String>>);

impl ProblemLog {
    /// Whether `reason` is new for `device` (then remembered), rather than the same problem
    /// again.
    fn is_new(&mut self, device: usize, reason: &str) -> bool {
        if self.0.len() <= device {
            self.0.resize(device + 1, None);
        }
        let last = &mut self.0[device];
        if last.as_deref() == Some(reason) {
            return false;
        }
        *last = Some(reason.to_owned());
        true
    }

    /// `device` came up: its next problem is news.
    fn clear(&mut self, device: usize) {
        if let Some(last) = self.0.get_mut(device) {
            *last = None;
        }
    }
}

impl ControllerRole {
    /// `controller`, publishing device states to `states`; `names` are the devices' station
    /// names.
    pub fn new(
        controller: Controller,
        states: Arc<DeviceStates>,
        names: Vec<String>,
    ) -> ControllerRole {
        ControllerRole {
            controller,
            states,
            names,
            actions: Vec::new(),
            problems: ProblemLog::default(),
            address: None,
            port: None,
        }
    }

    /// Carries out the station's IP suite on the interface whenever it changes, from now on.
    pub fn with_address(mut self, address: InterfaceAddress) -> ControllerRole {
        self.address = Some(address);
        self
    }

    /// Reports `interface`'s link and counters in the interface's records, looked at every
    /// second.
    pub fn with_port(mut self, interface: &str) -> ControllerRole {
        self.port = Some(PortWatch::new(interface));
        self
    }

    /// Tells the controller the interface's link and counters, if it has a real one.
    fn look_at_port(&mut self, now_ns: u64) {
        let Some(port) = self.port.as_mut() else {
            return;
        };
        let (link, counters) = port.look(now_ns);
        if let Some(link) = link {
            self.controller.set_port_link(link);
        }
        self.controller.set_port_counters(counters);
    }

    /// A program's change of the station's name or address: checked, carried out on the
    /// interface, then taken by the controller; the outcome is an event either way.
    fn change_address(&mut self, reference: u64, change: StationAddress) -> DeviceEvent {
        let result = self
            .controller
            .check_station_address(&change)
            .and_then(|()| match (change.ip_suite, self.address.as_mut()) {
                (Some([ip, mask, gateway]), Some(a)) => a
                    .follow(ip, mask, gateway)
                    .map_err(|e| AddressError::NotCarriedOut(e.to_string())),
                _ => Ok(()),
            })
            .and_then(|()| self.controller.set_station_address(&change));
        DeviceEvent::StationAddress {
            change,
            reference: Some(reference),
            result,
        }
    }

    /// Turns the controller's actions into effects, logging its events and publishing the
    /// device states on the way.
    fn hand_over(&mut self, out: &mut Vec<Effect<DeviceEvent>>) {
        for a in self.actions.drain(..) {
            out.push(match a {
                ControllerAction::Frame(f) => Effect::Frame(f),
                ControllerAction::Datagram { to, payload } => Effect::Datagram { to, payload },
                ControllerAction::Neighbour { ip, mac } => Effect::Neighbour { ip, mac },
                ControllerAction::Start(ar) => Effect::Start(ar),
                ControllerAction::Stop { device } => Effect::Stop { device },
                ControllerAction::Event(e) => {
                    if let DeviceEvent::StationAddress {
                        change,
                        reference: None,
                        ..
                    } = &e
                    {
                        follow_dcp(self.address.as_mut(), change);
                    }
                    log_event(&e, &self.names, &self.states, &mut self.problems);
                    Effect::Event(e)
                }
            });
        }
    }
}

impl Role for ControllerRole {
    type Command = ControllerCommand;
    type Event = DeviceEvent;

    fn set_online(&mut self, online: bool, now_ns: u64, out: &mut Vec<Effect<DeviceEvent>>) {
        self.controller
            .set_online(online, now_ns, &mut self.actions);
        self.hand_over(out);
    }

    fn command(&mut self, c: ControllerCommand, now_ns: u64, out: &mut Vec<Effect<DeviceEvent>>) {
        match c {
            ControllerCommand::Activate { device, active } => {
                self.controller
                    .activate(device, active, now_ns, &mut self.actions);
            }
            ControllerCommand::Reconfigure(how) => {
                self.controller.reconfigure(how, now_ns, &mut self.actions);
            }
            ControllerCommand::Record(r) => self.controller.record(r, &mut self.actions),
            ControllerCommand::AcknowledgeAlarm(t) => {
                self.controller
                    .acknowledge_alarm(t, now_ns, &mut self.actions);
            }
            ControllerCommand::InterfaceRecord {
                reference,
                subslot,
                index,
            } => {
                // The counters as they are now.
                self.look_at_port(now_ns);
                let result = self.controller.read_interface_record(subslot, index);
                self.actions
                    .push(ControllerAction::Event(DeviceEvent::InterfaceRecord {
                        reference,
                        subslot,
                        index,
                        result,
                    }));
            }
            ControllerCommand::StationAddress { reference, change } => {
                let event = self.change_address(reference, change);
                self.actions.push(ControllerAction::Event(event));
            }
        }
        self.hand_over(out);
    }

    fn on_frame(&mut self, frame: &[u8], now_ns: u64, out: &mut Vec<Effect<DeviceEvent>>) {
        self.controller.on_frame(frame, now_ns, &mut self.actions);
        self.hand_over(out);
    }

    fn on_datagram(
        &mut self,
        from: SocketAddrV4,
        payload: &[u8],
        now_ns: u64,
        out: &mut Vec<Effect<DeviceEvent>>,
    ) {
        self.controller
            .on_datagram(from, payload, now_ns, &mut self.actions);
        self.hand_over(out);
    }

    fn on_cycle(&mut self, report: CycleReport, now_ns: u64, out: &mut Vec<Effect<DeviceEvent>>) {
        match report {
            CycleReport::DataStarted { device, epoch } => {
                self.controller.on_data_started(device, epoch)
            }
            CycleReport::WatchdogExpired { device, epoch } => {
                self.controller
                    .on_watchdog(device, epoch, now_ns, &mut self.actions)
            }
        }
        self.hand_over(out);
    }

    fn poll(&mut self, now_ns: u64, out: &mut Vec<Effect<DeviceEvent>>) {
        if self.port.as_ref().is_some_and(|p| p.due(now_ns)) {
            self.look_at_port(now_ns);
        }
        self.controller.poll(now_ns, &mut self.actions);
        self.hand_over(out);
    }

    fn deadline(&self) -> Option<u64> {
        let port = self.port.as_ref().map(PortWatch::next_ns);
        self.controller
            .next_deadline_ns()
            .into_iter()
            .chain(port)
            .min()
    }

    fn settling(&self) -> bool {
        self.controller.releasing()
    }

    fn dropped_datagrams(&self) -> DroppedDatagrams {
        let d = self.controller.dropped_datagrams();
        DroppedDatagrams {
            malformed: d.malformed,
            unexpected: d.unexpected,
        }
    }
}

fn log_event(e: &DeviceEvent, names: &[String], states: &DeviceStates, problems: &mut ProblemLog) {
    let name = |d: usize| names.get(d).map_or("?", String::as_str);
    match e {
        DeviceEvent::State { device, state } => {
            states.set(*device, *state);
            tracing::debug!("device {:?}: {state}", name(*device));
        }
        DeviceEvent::Failure {
            device,
            reason,
            planned: false,
            ..
        } => tracing::warn!("device {:?} failed: {reason}", name(*device)),
        DeviceEvent::Failure {
            device,
            reason,
            planned: true,
            ..
        } => tracing::info!("device {:?} left data exchange: {reason}", name(*device)),
        DeviceEvent::Return { device } => {
            problems.clear(*device);
            tracing::info!("device {:?} is in data exchange", name(*device))
        }
        DeviceEvent::Problem { device, reason, .. } => {
            if problems.is_new(*device, reason) {
                tracing::warn!("device {:?}: {reason}", name(*device))
            } else {
                tracing::debug!("device {:?}: still: {reason}", name(*device))
            }
        }
        DeviceEvent::ModuleDiff { device, diff } => {
            for (api, slot, subslot, st) in diff.submodules() {
                // A ModuleDiffBlock also lists the right submodules that have diagnosis or
                // want maintenance: news, not a configuration fault.
                if st.is_usable() && st.ident_info() == IdentInfo::Ok {
                    tracing::info!(
                        "device {:?}: API {api} slot {slot} subslot {subslot:#06x} reports: \
                         {st} (record 0x800A of the subslot says which)",
                        name(*device)
                    );
                } else {
                    tracing::warn!(
                        "device {:?}: API {api} slot {slot} subslot {subslot:#06x} differs \
                         from the configuration: {st}",
                        name(*device)
                    );
                }
            }
        }
        DeviceEvent::Alarm {
            device,
            notification,
            ..
        } => tracing::info!(
            "device {:?}: alarm {:?} at slot {} subslot {:#06x}",
            name(*device),
            notification.alarm_type,
            notification.slot,
            notification.subslot
        ),
        DeviceEvent::Record(r) => tracing::debug!(
            "device {:?}: record {:#06x} done: {:?}",
            name(r.request.device),
            r.request.index,
            r.result.as_ref().map(|d| d.data.len())
        ),
        DeviceEvent::Activation { device, active } => tracing::info!(
            "device {:?} {}",
            name(*device),
            if *active { "activated" } else { "deactivated" }
        ),
        DeviceEvent::Signal => {
            tracing::info!("DCP Signal: the controller's station flashes its LED");
        }
        DeviceEvent::InterfaceAlarm(n) => tracing::info!(
            "the controller's port: alarm {:?}{}",
            n.alarm_type,
            if n.specifier.submodule_diagnosis {
                " (a diagnosis is pending: the neighbour or the link is not as configured)"
            } else {
                " (no diagnosis pending)"
            }
        ),
        DeviceEvent::StationAddress {
            change,
            reference,
            result,
        } => {
            let by = if reference.is_some() {
                "a program"
            } else {
                "DCP"
            };
            let what = describe_change(change);
            match result {
                Ok(()) => tracing::info!("the controller's station: {by} set {what}"),
                Err(e) => {
                    tracing::warn!("the controller's station: {by} could not set {what}: {e}")
                }
            }
        }
        DeviceEvent::InterfaceRecord {
            subslot,
            index,
            result,
            ..
        } => tracing::debug!(
            "the controller's interface: record {index:#06x} of subslot {subslot:#06x} read: {:?}",
            result.as_ref().map(Vec::len)
        ),
        DeviceEvent::Reconfigured { result } => match result {
            Ok(true) => tracing::info!("IO system tailored"),
            Ok(false) => tracing::info!("IO system deactivated"),
            Err(e) => tracing::warn!("IO system tailoring refused: {e}"),
        },
    }
}

/// DCP gave the station a new IP suite: the interface (`address`, where procimgd holds it)
/// follows, before the DCP answer goes (the tool reaches the station at its new address as
/// soon as it has the answer).
fn follow_dcp(address: Option<&mut InterfaceAddress>, change: &StationAddress) {
    if let (Some([ip, mask, gateway]), Some(a)) = (change.ip_suite, address)
        && let Err(e) = a.follow(ip, mask, gateway)
    {
        // Logged: the station goes on with the address DCP gave it.
        tracing::error!("{e}");
    }
}

/// A change of the station's name or address in words.
fn describe_change(change: &StationAddress) -> String {
    let mut parts = Vec::new();
    if let Some(name) = &change.name {
        parts.push(format!("the name {name:?}"));
    }
    if let Some([ip, mask, gateway]) = change.ip_suite {
        parts.push(format!(
            "the address {ip}, netmask {mask}, gateway {gateway}"
        ));
    }
    let kept = if change.permanent {
        ", kept across restarts"
    } else {
        ""
    };
    format!("{}{kept}", parts.join(" and "))
}

#[cfg(test)]
mod tests {
    use super::ProblemLog;

    #[test]
    fn the_same_problem_again_is_no_news_until_the_device_comes_up() {
        let mut log = ProblemLog::default();
        let missing = "no device named \"gone\" answered DCP Identify";
        assert!(log.is_new(3, missing));
        assert!(!log.is_new(3, missing));
        assert!(
            log.is_new(1, missing),
            "another device's problem is its own"
        );
        assert!(
            log.is_new(3, "Connect refused"),
            "a different problem is news"
        );
        assert!(
            log.is_new(3, missing),
            "and so is the first one again after it"
        );
        log.clear(3);
        assert!(
            log.is_new(3, missing),
            "after coming up, the problem is news again"
        );
        log.clear(99);
    }
}
