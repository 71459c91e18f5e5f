// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimgd's notifications as OPC UA events: in the controller role a device's failure and
//! return and its alarms (with their data); in the device role the AR's life (a PLC
//! connecting, in data exchange, the AR's end and why) and the PLC's RUN/STOP; in both a stop
//! request. Each comes from the device's (the station's) object in the tree, or the
//! instance's, so a client subscribes to one device or, on the Server object, to all. Each is
//! of procimg's type for it ([`crate::event_types`]), its fields what the notification says;
//! the stop request is a BaseEventType.

use crate::event_types::{AlarmEvent, ArEvent, DeviceEvent, PlcStateEvent};
use opcua::crypto::random;
use opcua::nodes::{BaseEventType, Event};
use opcua::server::ServerHandle;
use opcua::types::{ByteString, NodeId, ObjectTypeId, UAString};
use procimg_client::{ArState, Notification, ServiceOptions, Services};
use std::time::Duration;

/// How long one wait for a notification lasts (the stop flag is looked at in between).
const WAIT: Duration = Duration::from_millis(200);

/// An event of a notification: its source (a tree path below the instance), severity and
/// message; `None` for the notifications that are no events. `station` is the name the tree
/// gives the station in the device role (its notifications do not name it).
pub fn event_of(n: &Notification, station: &str) -> Option<(String, u16, String)> {
    let device = |name: &str| format!("Devices/{name}");
    let plc = |name: &str, mac: &str| {
        if name.is_empty() {
            format!("PLC {mac}")
        } else {
            format!("PLC {name} ({mac})")
        }
    };
    Some(match n {
        Notification::DeviceFailure { name, reason, .. } => {
            (device(name), 800, format!("device {name} failed: {reason}"))
        }
        Notification::DeviceReturn { name, .. } => (
            device(name),
            300,
            format!("device {name} returned to data exchange"),
        ),
        Notification::Alarm(a) => {
            let data: Vec<String> = a.payload.iter().map(|b| format!("{b:02x}")).collect();
            (
                device(&a.device_name),
                if a.high_priority { 700 } else { 500 },
                format!(
                    "alarm 0x{:04x} from {} slot {} subslot 0x{:04x}: {}{}{}",
                    a.alarm_type,
                    a.device_name,
                    a.slot,
                    a.subslot,
                    a.text,
                    if data.is_empty() { "" } else { "; data " },
                    data.join(" ")
                ),
            )
        }
        Notification::StationAr {
            state,
            controller_name,
            controller_mac,
            ..
        } => (
            device(station),
            if *state == ArState::Data { 300 } else { 200 },
            format!(
                "AR of {} with station {station}: {state}",
                plc(controller_name, controller_mac)
            ),
        ),
        Notification::StationArEnded {
            reason,
            aborted,
            planned,
            ..
        } => (
            device(station),
            if *aborted && !*planned { 700 } else { 400 },
            format!("AR with station {station} ended: {reason}"),
        ),
        Notification::StationPlcRunning {
            running,
            station_problem,
            ..
        } => (
            device(station),
            if *running { 300 } else { 500 },
            format!(
                "the PLC of station {station} is in {}{}",
                if *running { "RUN" } else { "STOP" },
                if *station_problem {
                    " and reports a station problem"
                } else {
                    ""
                }
            ),
        ),
        Notification::StopRequest { reason } => (
            String::new(),
            600,
            format!("procimgd asks its programs to stop: {reason}"),
        ),
        _ => return None,
    })
}

/// The event of notification `n`, one [`event_of`] makes an event of (`station` named as
/// there), of procimg's type for it in namespace `types` (a BaseEventType where procimg has
/// none), its base made by `base` from the type's NodeId.
pub fn typed_event(
    n: &Notification,
    station: &str,
    types: u16,
    base: impl FnOnce(NodeId) -> BaseEventType,
) -> Box<dyn Event + Send + Sync> {
    let of = |name: &str| NodeId::new(types, name);
    let text = |s: &str| UAString::from(s);
    match n {
        Notification::DeviceFailure { name, reason, .. } => Box::new(DeviceEvent {
            base: base(of("DeviceEventType")),
            own_namespace_index: types,
            device: text(name),
            in_data_exchange: false,
            reason: text(reason),
        }),
        Notification::DeviceReturn { name, .. } => Box::new(DeviceEvent {
            base: base(of("DeviceEventType")),
            own_namespace_index: types,
            device: text(name),
            in_data_exchange: true,
            reason: UAString::null(),
        }),
        Notification::Alarm(a) => Box::new(AlarmEvent {
            base: base(of("AlarmEventType")),
            own_namespace_index: types,
            device: text(&a.device_name),
            alarm_type: a.alarm_type,
            slot: a.slot,
            subslot: a.subslot,
            high_priority: a.high_priority,
            text: text(&a.text),
            data: ByteString::from(a.payload.clone()),
        }),
        Notification::StationAr {
            state,
            controller_name,
            controller_mac,
            ..
        } => Box::new(ArEvent {
            base: base(of("ArEventType")),
            own_namespace_index: types,
            station: text(station),
            plc: text(controller_name),
            plc_mac: text(controller_mac),
            ar_state: text(state.as_str()),
            reason: UAString::null(),
            aborted: false,
        }),
        Notification::StationArEnded {
            reason, aborted, ..
        } => Box::new(ArEvent {
            base: base(of("ArEventType")),
            own_namespace_index: types,
            station: text(station),
            plc: UAString::null(),
            plc_mac: UAString::null(),
            ar_state: text("ended"),
            reason: text(reason),
            aborted: *aborted,
        }),
        Notification::StationPlcRunning {
            running,
            station_problem,
            ..
        } => Box::new(PlcStateEvent {
            base: base(of("PlcStateEventType")),
            own_namespace_index: types,
            station: text(station),
            running: *running,
            station_problem: *station_problem,
        }),
        // The stop request.
        _ => Box::new(base(ObjectTypeId::BaseEventType.into())),
    }
}

/// Raises the events of `instance`'s notifications in `handle`'s server, their sources in
/// namespace `ns` (in the device role the station, as `station` names it now), of procimg's
/// types in namespace `types`, until `stop` says so.
pub fn run(
    instance: &str,
    station: impl Fn() -> String,
    (ns, types): (u16, u16),
    handle: ServerHandle,
    stop: impl Fn() -> bool,
) {
    let mut services = None;
    while !stop() {
        if services.is_none() {
            services = Services::open(instance, ServiceOptions::new("procimg-opcua events")).ok();
            if services.is_none() {
                std::thread::sleep(WAIT);
                continue;
            }
        }
        let Some(s) = services.as_mut() else { continue };
        let Some(n) = s.next(WAIT) else { continue };
        let station = station();
        let Some((path, severity, message)) = event_of(&n, &station) else {
            continue;
        };
        let source = if path.is_empty() {
            NodeId::new(ns, instance)
        } else {
            NodeId::new(ns, format!("{instance}/{path}"))
        };
        let name = path
            .rsplit('/')
            .next()
            .filter(|p| !p.is_empty())
            .unwrap_or(instance);
        let base = |type_id: NodeId| {
            BaseEventType::new_now(type_id, random::byte_string(16), message)
                .set_source_node(source.clone())
                .set_source_name(UAString::from(name))
                .set_severity(severity)
        };
        let event = typed_event(&n, &station, types, base);
        handle
            .subscriptions()
            .notify_events([(event.as_ref() as &dyn Event, &source)].into_iter());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_station_s_ar_and_plc_come_from_the_station_s_object() {
        let data = Notification::StationAr {
            state: ArState::Data,
            ar_uuid: "0f2c0a43-1b53-4a8f-9e57-8c4bd8b1f7a2".into(),
            controller_mac: "02:50:49:fe:00:01".into(),
            controller_name: "plc-1".into(),
        };
        let (source, severity, message) = event_of(&data, "station-a").unwrap();
        assert_eq!((source.as_str(), severity), ("Devices/station-a", 300));
        assert_eq!(
            message,
            "AR of PLC plc-1 (02:50:49:fe:00:01) with station station-a: data"
        );
        let ended = Notification::StationArEnded {
            ar_uuid: "0f2c0a43-1b53-4a8f-9e57-8c4bd8b1f7a2".into(),
            reason: "IO data timeout".into(),
            aborted: true,
            planned: false,
            abort_code: None,
        };
        let (_, severity, message) = event_of(&ended, "station-a").unwrap();
        assert_eq!(severity, 700);
        assert!(message.ends_with("ended: IO data timeout"), "{message}");
        let stop = Notification::StationPlcRunning {
            running: false,
            station_problem: true,
            backup: false,
        };
        let (_, severity, message) = event_of(&stop, "station-a").unwrap();
        assert_eq!(severity, 500);
        assert!(
            message.contains("STOP and reports a station problem"),
            "{message}"
        );
    }
}
