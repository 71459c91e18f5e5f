// SPDX-License-Identifier: MIT OR Apache-2.0
//! A real port's link and counters, as the physical device's records of either role report
//! them: looked at in sysfs once a second (a link that went down is in the records, and its
//! neighbours forgotten, within a second), and before a peer's call where the role wants
//! the counters as they are.

use crate::sys::port_state;
use procimg_profinet::port::physical::{PortCounters, PortLink};
use procimg_profinet::wire::record::{MEDIA_COPPER, MEDIA_UNKNOWN};

/// How often the interface's link is looked at.
const PORT_LOOK_NS: u64 = 1_000_000_000;

/// One interface, and when it is looked at next.
pub struct PortWatch {
    interface: String,
    next_ns: u64,
}

impl PortWatch {
    /// Watches `interface`, from the first [`look`](Self::look) on.
    pub fn new(interface: &str) -> PortWatch {
        PortWatch {
            interface: interface.to_owned(),
            next_ns: 0,
        }
    }

    /// Whether it is time to look again.
    pub fn due(&self, now_ns: u64) -> bool {
        now_ns >= self.next_ns
    }

    /// When it is time to look again.
    pub fn next_ns(&self) -> u64 {
        self.next_ns
    }

    /// The link and counters now; the counters `None` where the interface cannot be read
    /// (then the link is left as it was: `None` too).
    pub fn look(&mut self, now_ns: u64) -> (Option<PortLink>, Option<PortCounters>) {
        self.next_ns = now_ns.saturating_add(PORT_LOOK_NS);
        let Ok(s) = port_state::read(&self.interface) else {
            return (None, None);
        };
        let mau_type = PortLink::mau_type_of(s.speed_mbit.unwrap_or(0), s.full_duplex);
        let link = PortLink {
            up: s.up,
            mau_type,
            media_type: if mau_type == 0 {
                MEDIA_UNKNOWN
            } else {
                MEDIA_COPPER
            },
        };
        let [
            in_octets,
            out_octets,
            in_discards,
            out_discards,
            in_errors,
            out_errors,
        ] = s.counters;
        let counters = PortCounters {
            in_octets,
            out_octets,
            in_discards,
            out_discards,
            in_errors,
            out_errors,
        };
        (Some(link), Some(counters))
    }
}
