// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller's own station on its interface, as its programs ask for it (IO-Base's
//! CONFIG_NAME_ADDR_INFO and communication counters): its name, type and address, and the
//! interface's Ethernet counters as the kernel counts them, since procimgd started or a
//! program reset them.

use procimg_control::{ControllerReport, InterfaceCounters};

/// The controller's station and its interface's counters.
pub struct ControllerInterface {
    /// Everything but the counters.
    report: ControllerReport,
    /// The real interface, if there is one (the simulated network has no counters).
    interface: Option<String>,
    /// The kernel's counts at the last reset.
    baseline: InterfaceCounters,
}

impl ControllerInterface {
    /// The station `report` describes (its counters ignored), on `interface` if real.
    pub fn new(report: ControllerReport, interface: Option<String>) -> ControllerInterface {
        let mut me = ControllerInterface {
            report,
            interface,
            baseline: InterfaceCounters::default(),
        };
        me.reset();
        me
    }

    /// The kernel's counts now, if the interface has any.
    fn raw(&self) -> Option<InterfaceCounters> {
        let s = crate::sys::port_state::read(self.interface.as_deref()?).ok()?;
        let [_, _, rx_dropped, tx_dropped, rx_errors, tx_errors] = s.counters;
        let [rx_packets, tx_packets, collisions] = s.frames;
        Some(InterfaceCounters {
            frames_sent: tx_packets,
            send_collisions: collisions,
            send_errors: tx_errors.saturating_add(tx_dropped),
            frames_received: rx_packets,
            receive_errors: rx_errors,
            received_dropped: rx_dropped,
        })
    }

    /// The station with its counters since the last reset.
    pub fn report(&self) -> ControllerReport {
        let b = &self.baseline;
        ControllerReport {
            counters: self.raw().map(|c| InterfaceCounters {
                frames_sent: c.frames_sent.saturating_sub(b.frames_sent),
                send_collisions: c.send_collisions.saturating_sub(b.send_collisions),
                send_errors: c.send_errors.saturating_sub(b.send_errors),
                frames_received: c.frames_received.saturating_sub(b.frames_received),
                receive_errors: c.receive_errors.saturating_sub(b.receive_errors),
                received_dropped: c.received_dropped.saturating_sub(b.received_dropped),
            }),
            ..self.report.clone()
        }
    }

    /// Takes the station's new name or IP suite.
    pub fn take_address(&mut self, change: &procimg_profinet::controller::StationAddress) {
        if let Some(name) = &change.name {
            self.report.station_name.clone_from(name);
        }
        if let Some([ip, mask, gateway]) = change.ip_suite {
            self.report.ip = ip.to_string();
            self.report.netmask = mask.to_string();
            self.report.gateway = gateway.to_string();
        }
    }

    /// Starts the counters again from 0.
    pub fn reset(&mut self) {
        self.baseline = self.raw().unwrap_or_default();
    }
}
