// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device role's part of the client services: the station in the status report, and a
//! clear refusal of the IO controller's services (record jobs towards devices, activation,
//! alarm acknowledgement, the controller's diagnosis).

use super::station::{Station, StationEvent};
use crate::acyclic::DatagramCounters;
use crate::io::pnio::channel::Channel;
use crate::roles::RoleServices;
use crate::shm::Notices;
use procimg_shm_layout::control::{
    DeviceReport, NetworkReport, Refusal, Request, Response, StationReport, SubscriberReport,
};
use std::collections::HashSet;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::Duration;

/// The device role's client services.
pub struct DeviceServices {
    station: Arc<Station>,
    events: Receiver<StationEvent>,
    channel: Arc<Channel>,
    datagrams: Arc<DatagramCounters>,
}

impl DeviceServices {
    /// The services of `station`, taking the role's `events`; `channel` and `datagrams`
    /// hold the network counters.
    pub fn new(
        station: Arc<Station>,
        events: Receiver<StationEvent>,
        channel: Arc<Channel>,
        datagrams: Arc<DatagramCounters>,
    ) -> DeviceServices {
        DeviceServices {
            station,
            events,
            channel,
            datagrams,
        }
    }
}

/// The name of a request of the controller's services, for the refusal.
fn service_name(request: &Request) -> &'static str {
    match request {
        Request::Subscribe { .. } | Request::Unsubscribe { .. } => "the device event subscription",
        Request::RecordRead { .. } => "reading a record of an IO device",
        Request::RecordWrite { .. } => "writing a record of an IO device",
        Request::ActivateDevice { .. } => "activating an IO device",
        Request::AcknowledgeAlarm { .. } => "acknowledging an IO device's alarm",
        Request::Diagnosis => "the IO system diagnosis",
        _ => "this request",
    }
}

impl RoleServices for DeviceServices {
    fn handle(&mut self, request: Request, _online: bool, _notices: &mut Notices) -> Response {
        Response::Refused(Refusal::WrongRole {
            role: "device".to_owned(),
            service: service_name(&request).to_owned(),
        })
    }

    fn poll(&mut self, wait: Duration, _notices: &mut Notices) {
        // The station logs its events as it notes them; the client notifications of the
        // device role come with its application interface.
        match self.events.recv_timeout(wait) {
            Ok(_) | Err(RecvTimeoutError::Timeout) | Err(RecvTimeoutError::Disconnected) => {}
        }
        while self.events.try_recv().is_ok() {}
    }

    fn reap(&mut self, _alive: &HashSet<String>) -> Vec<String> {
        Vec::new()
    }

    fn devices(&self) -> Vec<DeviceReport> {
        Vec::new()
    }

    fn network(&self) -> NetworkReport {
        crate::roles::network_report(&self.channel, &self.datagrams)
    }

    fn subscribers(&self) -> Vec<SubscriberReport> {
        Vec::new()
    }

    fn station(&self) -> Option<StationReport> {
        Some(self.station.report())
    }

    fn released(&self) -> bool {
        !self.station.has_ar()
    }
}
