// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO controller as a [`Role`]: the protocol crate's [`Controller`] with the daemon's
//! bookkeeping around it (the device states the control side reads, the log).

use super::states::DeviceStates;
use crate::roles::{CycleReport, DroppedDatagrams, Effect, Role};
use procimg_profinet::controller::{
    AlarmTicket, Controller, ControllerAction, DeviceEvent, Reconfiguration, RecordRequest,
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
        self.controller.poll(now_ns, &mut self.actions);
        self.hand_over(out);
    }

    fn deadline(&self) -> Option<u64> {
        self.controller.next_deadline_ns()
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
        DeviceEvent::Reconfigured { result } => match result {
            Ok(true) => tracing::info!("IO system tailored"),
            Ok(false) => tracing::info!("IO system deactivated"),
            Err(e) => tracing::warn!("IO system tailoring refused: {e}"),
        },
    }
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
