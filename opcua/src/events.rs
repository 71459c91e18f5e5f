// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimgd's notifications as OPC UA events: a device's failure and return, its alarms
//! (with their data), a stop request. Each comes from the device's object in the tree (or
//! the instance's), so a client subscribes to one device or, on the Server object, to all.

use opcua::crypto::random;
use opcua::nodes::{BaseEventType, Event};
use opcua::server::ServerHandle;
use opcua::types::{NodeId, ObjectTypeId, UAString};
use procimg_client::{Notification, ServiceOptions, Services};
use std::time::Duration;

/// How long one wait for a notification lasts (the stop flag is looked at in between).
const WAIT: Duration = Duration::from_millis(200);

/// An event of a notification: its source (a tree path below the instance), severity and
/// message; `None` for the notifications that are no events.
pub fn event_of(n: &Notification) -> Option<(String, u16, String)> {
    let device = |name: &str| format!("Devices/{name}");
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
        Notification::StopRequest { reason } => (
            String::new(),
            600,
            format!("procimgd asks its programs to stop: {reason}"),
        ),
        _ => return None,
    })
}

/// Raises the events of `instance`'s notifications in `handle`'s server, their sources in
/// namespace `ns`, until `stop` says so.
pub fn run(instance: &str, ns: u16, handle: ServerHandle, stop: impl Fn() -> bool) {
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
        let Some((path, severity, message)) = event_of(&n) else {
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
        let event = BaseEventType::new_now(
            ObjectTypeId::BaseEventType,
            random::byte_string(16),
            message,
        )
        .set_source_node(source.clone())
        .set_source_name(UAString::from(name))
        .set_severity(severity);
        handle
            .subscriptions()
            .notify_events([(&event as &dyn Event, &source)].into_iter());
    }
}
