// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device access AR: an engineering tool's AR (PRONETA's, TIA Portal's online access, a
//! commissioning tool's) without IO data or alarms, an IOSAR with ARProperties.DeviceAccess.
//! It lives beside the PLC's IO AR and leaves it alone: the tool reads any record a Read
//! Implicit could (I&M, diagnosis, the physical device's records, ARData, the log book),
//! and writes what the standard lets such an AR write: I&M1 to I&M4. Records of the IO AR's
//! submodules that belong to their parameters stay the IO AR's.
//!
//! It ends with the tool's Release, or when the tool has made no call for its activity
//! timeout (CMInitiatorActivityTimeoutFactor × 100 ms).

use super::connect::AccessPlan;
use crate::wire::record::ArDataEntry;
use crate::wire::{MacAddress, Uuid};
use std::net::SocketAddrV4;

/// A device access AR, from its Connect to its end.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AccessAr {
    pub(super) ar_uuid: Uuid,
    pub(super) session_key: u16,
    /// The tool's NameOfStation (CMInitiatorStationName).
    pub(super) initiator_name: String,
    pub(super) initiator_mac: MacAddress,
    /// Where the tool calls from.
    pub(super) peer: SocketAddrV4,
    timeout_ns: u64,
    /// The AR ends unless the tool calls again before this.
    pub(super) deadline_ns: u64,
    /// As ARData reports it.
    pub(super) described: ArDataEntry,
}

impl AccessAr {
    /// The AR of an accepted device access Connect from `peer` at `now_ns`.
    pub(super) fn new(plan: &AccessPlan, peer: SocketAddrV4, now_ns: u64) -> AccessAr {
        let timeout_ns = u64::from(plan.ar.activity_timeout_factor) * 100_000_000;
        AccessAr {
            ar_uuid: plan.ar.ar_uuid,
            session_key: plan.ar.session_key,
            initiator_name: plan.ar.station_name.clone(),
            initiator_mac: plan.ar.initiator_mac,
            peer,
            timeout_ns,
            deadline_ns: now_ns.saturating_add(timeout_ns),
            described: super::connect::described(&plan.ar, None, &[], Vec::new()),
        }
    }

    /// The tool called at `now_ns`: its timeout starts again.
    pub(super) fn active(&mut self, now_ns: u64) {
        self.deadline_ns = now_ns.saturating_add(self.timeout_ns);
    }

    /// The ARUUID.
    pub fn ar_uuid(&self) -> Uuid {
        self.ar_uuid
    }

    /// The tool's NameOfStation.
    pub fn initiator_name(&self) -> &str {
        &self.initiator_name
    }

    /// The tool's MAC address.
    pub fn initiator_mac(&self) -> MacAddress {
        self.initiator_mac
    }
}
