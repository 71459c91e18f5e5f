// SPDX-License-Identifier: MIT OR Apache-2.0
//! The live one-line view `procimgd --demo` prints each second: mode, cycle, timing, clients
//! and the first input bytes of every device, read from the published image like any client.

use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::ServiceName;
use procimg_control::{StatusReport, input_service};
use procimg_runtime::image::Tables;
use procimg_runtime::shm::{Ipc, server_node};
use procimg_shm_layout::{ImageHeader, ioxs_is_good};
use std::fmt::Write as _;

pub struct DemoView {
    tables: Tables,
    // Keeps the node (and with it the subscriber's resources) alive.
    _node: Option<iceoryx2::node::Node<Ipc>>,
    inputs: Option<Subscriber<Ipc, [u8], ImageHeader>>,
}

impl DemoView {
    pub fn new(instance: &str, generation: u64, tables: &Tables) -> DemoView {
        let node = server_node(instance, "view").ok();
        let inputs = node.as_ref().and_then(|n| {
            let name = ServiceName::new(&input_service(instance, generation)).ok()?;
            n.service_builder(&name)
                .publish_subscribe::<[u8]>()
                .user_header::<ImageHeader>()
                .open()
                .ok()?
                .subscriber_builder()
                .buffer_size(1)
                .create()
                .ok()
        });
        DemoView {
            tables: tables.clone(),
            _node: node,
            inputs,
        }
    }

    pub fn print(&mut self, status: &StatusReport) {
        let mut line = format!(
            "cycle {:>8}  {:<8} wake p99 {:>4} µs  OPDONE p99 {:>4} µs  clients {}",
            status.cycle_count,
            status.mode.name(),
            status.wakeup_latency.p99_ns / 1000,
            status.handshake_round_trip.p99_ns / 1000,
            status.clients.len()
        );
        let mut newest = None;
        if let Some(sub) = &self.inputs {
            while let Ok(Some(s)) = sub.receive() {
                newest = Some(s);
            }
        }
        if let Some(sample) = newest {
            let payload = sample.payload();
            for (d, dev) in self.tables.devices.iter().enumerate() {
                let first = dev.first_submodule as usize;
                let subs = &self.tables.submodules[first..first + dev.submodule_count as usize];
                let Some(s) = subs.iter().find(|s| s.input_length > 0) else {
                    continue;
                };
                let at = s.input_offset as usize;
                let n = (s.input_length as usize).min(4);
                let good = payload
                    .get(s.status_offset as usize)
                    .is_some_and(|&b| ioxs_is_good(b));
                let _ = write!(line, " | {} ", self.tables.device_name(d));
                for b in payload.get(at..at + n).unwrap_or(&[]) {
                    let _ = write!(line, "{b:02x}");
                }
                if !good {
                    line.push_str(" BAD");
                }
            }
        }
        eprintln!("{line}");
    }
}
