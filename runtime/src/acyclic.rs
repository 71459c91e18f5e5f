// SPDX-License-Identifier: MIT OR Apache-2.0
//! The acyclic PROFINET side: a normal-priority thread that drives the sans-IO
//! [`Controller`] with the frames the cycle thread hands over, the datagrams of port 34964,
//! the mode the cycle runs in and the time, and carries out what it asks for.

use crate::cycle::Shared;
use crate::io::pnio::channel::{Channel, FromCycle, ToCycle};
use crate::phy::datagram::Datagrams;
use crate::sys::clock::now_ns;
use procimg_profinet::controller::{
    Action, AlarmTicket, Controller, DeviceEvent, DeviceState, RecordRequest,
};
use procimg_shm_layout::Mode;
use std::sync::Arc;
use std::sync::atomic::{AtomicU8, AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, Sender};
use std::thread::JoinHandle;
use std::time::Duration;

/// The longest the loop sleeps: alarm retransmissions and the mode are checked this often.
const MAX_WAIT: Duration = Duration::from_millis(5);

/// What clients and the control side can ask of the controller.
#[derive(Debug)]
pub enum ControllerCommand {
    /// Activate or deactivate a device.
    Activate {
        /// Device index.
        device: usize,
        /// Active or not.
        active: bool,
    },
    /// Read or write a record.
    Record(RecordRequest),
    /// Send the AlarmAck of a delivered alarm.
    AcknowledgeAlarm(AlarmTicket),
}

/// What the controller thread publishes for the control side: the device states and the
/// datagrams of port 34964 it dropped.
pub struct DeviceStates {
    states: Box<[AtomicU8]>,
    /// RPC datagrams that did not parse.
    pub malformed_datagrams: AtomicU64,
    /// RPC datagrams nothing was waiting for.
    pub unexpected_datagrams: AtomicU64,
}

const STATES: [DeviceState; 9] = [
    DeviceState::Offline,
    DeviceState::Deactivated,
    DeviceState::Searching,
    DeviceState::SettingIp,
    DeviceState::Connecting,
    DeviceState::Parameterizing,
    DeviceState::WaitingForApplicationReady,
    DeviceState::Running,
    DeviceState::Failed,
];

impl DeviceStates {
    /// `n` devices, all offline.
    pub fn new(n: usize) -> DeviceStates {
        DeviceStates {
            states: (0..n).map(|_| AtomicU8::new(0)).collect(),
            malformed_datagrams: AtomicU64::new(0),
            unexpected_datagrams: AtomicU64::new(0),
        }
    }

    fn set(&self, d: usize, s: DeviceState) {
        if let (Some(a), Some(i)) = (self.states.get(d), STATES.iter().position(|&x| x == s)) {
            a.store(i as u8, Ordering::Release);
        }
    }

    /// The state of device `d`.
    pub fn get(&self, d: usize) -> Option<DeviceState> {
        let i = self.states.get(d)?.load(Ordering::Acquire) as usize;
        STATES.get(i).copied()
    }

    /// Number of devices.
    pub fn len(&self) -> usize {
        self.states.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.states.is_empty()
    }

    /// Whether no device has a connection (each is offline or deactivated).
    pub fn all_released(&self) -> bool {
        (0..self.len()).all(|d| {
            matches!(
                self.get(d),
                Some(DeviceState::Offline | DeviceState::Deactivated)
            )
        })
    }
}

/// Where device events go besides the log.
pub type EventSink = Sender<DeviceEvent>;

/// What the acyclic thread works with.
pub struct AcyclicSetup {
    /// The controller.
    pub controller: Controller,
    /// The hand-over to the cycle thread.
    pub channel: Arc<Channel>,
    /// UDP port 34964.
    pub datagrams: Box<dyn Datagrams>,
    /// The mode and the stop flag.
    pub shared: Arc<Shared>,
    /// Where device states are published.
    pub states: Arc<DeviceStates>,
    /// Commands from clients.
    pub commands: Receiver<ControllerCommand>,
    /// Where device events go besides the log.
    pub events: Option<EventSink>,
    /// Station names, for messages.
    pub names: Vec<String>,
}

/// Starts the acyclic thread.
pub fn spawn(setup: AcyclicSetup) -> std::io::Result<JoinHandle<()>> {
    let AcyclicSetup {
        mut controller,
        channel,
        mut datagrams,
        shared,
        states,
        commands,
        events,
        names,
    } = setup;
    std::thread::Builder::new()
        .name("procimg-pnio".into())
        .spawn(move || {
            let mut out = Vec::new();
            let mut online = None;
            let mut buf = vec![0u8; 65536];
            loop {
                let now = now_ns();
                if shared.stop.load(Ordering::Acquire) {
                    controller.set_online(false, now, &mut out);
                    carry_out(
                        &mut out,
                        &channel,
                        datagrams.as_mut(),
                        &states,
                        &events,
                        &names,
                    );
                    break;
                }
                let want = !shared.release_all.load(Ordering::Acquire)
                    && (shared.mode() != Mode::Offline
                        || Mode::from_u32(shared.target_mode.load(Ordering::Acquire))
                            .is_some_and(|m| m != Mode::Offline));
                if online != Some(want) {
                    online = Some(want);
                    controller.set_online(want, now, &mut out);
                }
                while let Ok(c) = commands.try_recv() {
                    match c {
                        ControllerCommand::Activate { device, active } => {
                            controller.activate(device, active, now, &mut out);
                        }
                        ControllerCommand::Record(r) => controller.record(r, &mut out),
                        ControllerCommand::AcknowledgeAlarm(t) => {
                            controller.acknowledge_alarm(t, now, &mut out);
                        }
                    }
                }
                while let Some(r) = channel.from_cycle.pop() {
                    match r {
                        FromCycle::Received(frame) => {
                            controller.on_frame(frame.bytes(), now, &mut out);
                            channel.recycle(frame);
                        }
                        FromCycle::DataStarted { device, epoch } => {
                            controller.on_data_started(device, epoch)
                        }
                        FromCycle::WatchdogExpired { device, epoch } => {
                            controller.on_watchdog(device, epoch, now, &mut out)
                        }
                        FromCycle::Retired(ar) => drop(ar),
                    }
                }
                controller.poll(now, &mut out);
                carry_out(
                    &mut out,
                    &channel,
                    datagrams.as_mut(),
                    &states,
                    &events,
                    &names,
                );
                let wait = controller
                    .deadline()
                    .map_or(MAX_WAIT, |d| {
                        Duration::from_nanos(d.saturating_sub(now_ns()))
                    })
                    .min(MAX_WAIT);
                match datagrams.recv_from(&mut buf, wait) {
                    Ok(Some((n, from))) => {
                        controller.on_datagram(from, &buf[..n], now_ns(), &mut out);
                        let dropped = controller.dropped_datagrams();
                        states
                            .malformed_datagrams
                            .store(dropped.malformed, Ordering::Relaxed);
                        states
                            .unexpected_datagrams
                            .store(dropped.unexpected, Ordering::Relaxed);
                        carry_out(
                            &mut out,
                            &channel,
                            datagrams.as_mut(),
                            &states,
                            &events,
                            &names,
                        );
                    }
                    Ok(None) => {}
                    Err(e) => {
                        tracing::warn!("PROFINET RPC socket: {e}");
                        std::thread::sleep(wait);
                    }
                }
            }
        })
}

fn carry_out(
    out: &mut Vec<Action>,
    channel: &Channel,
    datagrams: &mut dyn Datagrams,
    states: &DeviceStates,
    events: &Option<EventSink>,
    names: &[String],
) {
    for a in out.drain(..) {
        match a {
            Action::Frame(f) => {
                channel.send(&f);
            }
            Action::Datagram { to, payload } => {
                if let Err(e) = datagrams.send_to(to, &payload) {
                    tracing::warn!("cannot send to {to}: {e}");
                }
            }
            Action::Start(ar) => {
                if let Err(ToCycle::Start(ar)) = channel.to_cycle.push(ToCycle::Start(ar)) {
                    tracing::warn!(
                        "the cycle thread is not taking commands; device {} stays down",
                        ar.device
                    );
                }
            }
            Action::Stop { device } => {
                let _ = channel.to_cycle.push(ToCycle::Stop { device });
            }
            Action::Event(e) => {
                log_event(&e, names, states);
                if let Some(tx) = events {
                    let _ = tx.send(e);
                }
            }
        }
    }
}

fn log_event(e: &DeviceEvent, names: &[String], states: &DeviceStates) {
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
            tracing::info!("device {:?} is in data exchange", name(*device))
        }
        DeviceEvent::Problem { device, reason, .. } => {
            tracing::warn!("device {:?}: {reason}", name(*device))
        }
        DeviceEvent::ModuleDiff { device, diff } => {
            for (api, slot, subslot, st) in diff.submodules() {
                tracing::warn!(
                    "device {:?}: API {api} slot {slot} subslot {subslot:#06x} differs from \
                     the configuration: {st:?}",
                    name(*device)
                );
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
    }
}
