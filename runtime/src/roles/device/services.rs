// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device role's part of the client services: the station in the status report, its
//! diagnosis and process alarms, its events as notifications to the subscribers, and a clear
//! refusal of the IO controller's services (record jobs towards devices, activation, alarm
//! acknowledgement, the controller's diagnosis).

use super::notifications::notification;
use super::role::DeviceCommand;
use super::station::{Station, StationEvent};
use crate::acyclic::DatagramCounters;
use crate::io::pnio::channel::Channel;
use crate::roles::RoleServices;
use crate::roles::subscribers::{Subscriber, Subscribers};
use crate::shm::Notices;
use procimg_shm_layout::control::{
    DeviceReport, NetworkReport, Refusal, Request, Response, StationReport, SubscriberReport,
};
use std::collections::HashSet;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender};
use std::time::Duration;

/// How long a client's request waits for the acyclic thread to carry it out: it only
/// changes the engine's state and queues frames.
const COMMAND_WAIT: Duration = Duration::from_millis(500);

/// The device role's client services.
pub struct DeviceServices {
    station: Arc<Station>,
    commands: Sender<DeviceCommand>,
    events: Receiver<StationEvent>,
    channel: Arc<Channel>,
    datagrams: Arc<DatagramCounters>,
    subscribers: Subscribers,
}

impl DeviceServices {
    /// The services of `station`, giving the role `commands` and taking its `events`;
    /// `channel` and `datagrams` hold the network counters.
    pub fn new(
        station: Arc<Station>,
        commands: Sender<DeviceCommand>,
        events: Receiver<StationEvent>,
        channel: Arc<Channel>,
        datagrams: Arc<DatagramCounters>,
    ) -> DeviceServices {
        DeviceServices {
            station,
            commands,
            events,
            channel,
            datagrams,
            subscribers: Subscribers::default(),
        }
    }

    /// Publishes `event` to the subscribers.
    fn publish(event: StationEvent, notices: &mut Notices) {
        notices.publish(&notification(event));
    }
}

/// The name of a request of the controller's services, for the refusal.
fn service_name(request: &Request) -> &'static str {
    match request {
        Request::RecordRead { .. } => "reading a record of an IO device",
        Request::RecordWrite { .. } => "writing a record of an IO device",
        Request::ActivateDevice { .. } => "activating an IO device",
        Request::AcknowledgeAlarm { .. } => "acknowledging an IO device's alarm",
        Request::Diagnosis => "the IO system diagnosis",
        _ => "this request",
    }
}

impl DeviceServices {
    /// Has the acyclic thread carry out the command `make` builds and waits for the outcome.
    fn carry_out(
        &self,
        make: impl FnOnce(std::sync::mpsc::SyncSender<Result<(), String>>) -> DeviceCommand,
    ) -> Response {
        let (reply, outcome) = std::sync::mpsc::sync_channel(1);
        let refused = |message: String| Response::Refused(Refusal::BadRequest { message });
        if self.commands.send(make(reply)).is_err() {
            return refused("the device's PROFINET thread has ended".into());
        }
        match outcome.recv_timeout(COMMAND_WAIT) {
            Ok(Ok(())) => Response::Done,
            Ok(Err(why)) => refused(why),
            Err(_) => refused(format!(
                "the device's PROFINET thread did not take the request within {COMMAND_WAIT:?}; \
                 try again"
            )),
        }
    }
}

impl RoleServices for DeviceServices {
    fn handle(&mut self, request: Request, _online: bool, _notices: &mut Notices) -> Response {
        match request {
            // Notifications go to every client of the notification service; announcing
            // makes the subscriber known (status report, reaping). `acknowledge_alarms` is
            // ignored: the station's alarms are the PLC's to acknowledge, none waits for a
            // client, and the status says so.
            Request::Subscribe {
                subscriber,
                name,
                pid,
                node_id,
                acknowledge_alarms: _,
            } => {
                self.subscribers.subscribe(
                    subscriber,
                    Subscriber {
                        name,
                        pid,
                        node_id,
                        acknowledges: false,
                    },
                );
                Response::Done
            }
            Request::Unsubscribe { subscriber } => match self.subscribers.unsubscribe(subscriber) {
                Ok(_) => Response::Done,
                Err(r) => Response::Refused(r),
            },
            Request::StationDiagnosis { change } => {
                self.carry_out(|reply| DeviceCommand::Diagnosis { change, reply })
            }
            Request::StationProcessAlarm {
                api,
                slot,
                subslot,
                usi,
                data,
            } => self.carry_out(|reply| DeviceCommand::ProcessAlarm {
                at: (api, slot, subslot),
                usi,
                data,
                reply,
            }),
            other => Response::Refused(Refusal::WrongRole {
                role: "device".to_owned(),
                service: service_name(&other).to_owned(),
            }),
        }
    }

    fn poll(&mut self, wait: Duration, notices: &mut Notices) {
        // The station has logged its events as it noted them; here they become notifications.
        match self.events.recv_timeout(wait) {
            Ok(event) => Self::publish(event, notices),
            Err(RecvTimeoutError::Timeout) => {}
            // The acyclic thread has ended (procimgd is stopping): wait all the same.
            Err(RecvTimeoutError::Disconnected) => std::thread::sleep(wait),
        }
        while let Ok(event) = self.events.try_recv() {
            Self::publish(event, notices);
        }
    }

    fn finish(&mut self, notices: &mut Notices) {
        // The role's threads have ended: what is left is the AR's end.
        while let Ok(event) = self.events.try_recv() {
            Self::publish(event, notices);
        }
    }

    fn reap(&mut self, alive: &HashSet<String>) -> Vec<String> {
        self.subscribers
            .reap(alive)
            .into_iter()
            .map(|(_, s)| s.to_string())
            .collect()
    }

    fn devices(&self) -> Vec<DeviceReport> {
        Vec::new()
    }

    fn network(&self) -> NetworkReport {
        crate::roles::network_report(&self.channel, &self.datagrams)
    }

    fn subscribers(&self) -> Vec<SubscriberReport> {
        // No alarm waits for a subscriber in the device role.
        self.subscribers.report(|_| 0)
    }

    fn station(&self) -> Option<StationReport> {
        Some(self.station.report())
    }

    fn released(&self) -> bool {
        !self.station.has_ar()
    }
}
