// SPDX-License-Identifier: MIT OR Apache-2.0
//! The port as the PLC parameterizes and checks it.
//!
//! - PDPortDataAdjust: a peer-to-peer boundary keeps LLDP in, a DCP boundary the Hello;
//!   taken after every Write of the AR, and kept after the AR as PDev parameters are.
//! - PDPortDataCheck: the topology check. With CheckPeers written, the port's LLDP neighbour
//!   is compared with the peer the PLC's project names, after the write and whenever the
//!   neighbourhood changes (a neighbour comes, goes, ages out, the link drops). A mismatch
//!   is a diagnosis of the port submodule, channel 0x8000, ChannelErrorType 0x8001 "remote
//!   mismatch" with the ExtChannelErrorType saying which (the peer's NameOfStation, its port,
//!   no peer at all), announced and withdrawn by the PortDataChangeNotification alarm
//!   (AlarmType 0x000E). The check stays after the AR, as PDev parameters do.

use super::diagnosis::{ChannelDiag, DiagEntry, SubslotAddr};
use super::{Application, Device, DeviceAction, physical};
use crate::port::neighbours::Neighbours;
use crate::wire::alarm::AlarmType;
use crate::wire::record::{
    DCP_BOUNDARY_HELLO, INDEX_PD_PORT_DATA_ADJUST, INDEX_PD_PORT_DATA_CHECK, PEER_TO_PEER_NO_LLDP,
    PdPortDataAdjust, PdPortDataCheck,
};

/// ChannelNumber of a diagnosis of the whole submodule.
const WHOLE_SUBMODULE: u16 = 0x8000;
/// ChannelErrorType "remote mismatch".
pub const REMOTE_MISMATCH: u16 = 0x8001;

/// ExtChannelErrorTypes of a remote mismatch.
pub mod mismatch {
    /// The peer's NameOfStation is not the one checked.
    pub const PEER_NAME: u16 = 0x8000;
    /// The peer's port is not the one checked.
    pub const PEER_PORT: u16 = 0x8001;
    /// No peer answers on the port.
    pub const NO_PEER: u16 = 0x8005;
}

/// What the port's neighbourhood makes of `check`: the mismatch, if there is one. Only the
/// peers are checked; with several neighbours (a switch without LLDP between) the first is
/// taken.
pub fn topology_mismatch(check: &PdPortDataCheck, neighbours: &Neighbours) -> Option<u16> {
    let expected = check.peers()?.first()?;
    let Some(n) = neighbours.entries().first() else {
        return Some(mismatch::NO_PEER);
    };
    if n.peer_station() != Some(expected.chassis_id.as_str()) {
        Some(mismatch::PEER_NAME)
    } else if n.peer_port() != Some(expected.port_id.as_str()) {
        Some(mismatch::PEER_PORT)
    } else {
        None
    }
}

/// The diagnosis entry of a mismatch.
fn entry(ext: u16) -> DiagEntry {
    ChannelDiag::extended(WHOLE_SUBMODULE, REMOTE_MISMATCH, ext, 0).into()
}

impl<A: Application> Device<A> {
    /// Applies the PDPortDataAdjust the AR wrote to a port, if it wrote one.
    pub(super) fn adjust_ports(&mut self) {
        let Some(ar) = self.ar.current.as_ref() else {
            return;
        };
        let adjust = ar
            .records
            .iter()
            .filter(|((_, _, subslot, index), _)| {
                *index == INDEX_PD_PORT_DATA_ADJUST && physical::is_port(*subslot)
            })
            .find_map(|(_, data)| PdPortDataAdjust::parse(data).ok());
        if let Some(a) = adjust {
            let lldp = a
                .peer_to_peer_boundary()
                .is_some_and(|b| b & PEER_TO_PEER_NO_LLDP != 0);
            let hello = a
                .dcp_boundary()
                .is_some_and(|b| b & DCP_BOUNDARY_HELLO != 0);
            self.station.set_boundaries(lldp, hello);
        }
        let checks: Vec<(SubslotAddr, PdPortDataCheck)> = ar
            .records
            .iter()
            .filter(|((_, _, subslot, index), _)| {
                *index == INDEX_PD_PORT_DATA_CHECK && physical::is_port(*subslot)
            })
            .filter_map(|(&(api, slot, subslot, _), data)| {
                Some((
                    SubslotAddr::new(api, slot, subslot),
                    PdPortDataCheck::parse(data).ok()?,
                ))
            })
            .collect();
        if !checks.is_empty() && checks != self.topology.checks {
            self.topology.checks = checks;
            self.topology.seen = None;
        }
    }

    /// Whether the topology is to be checked again: the check or the neighbourhood changed.
    pub(super) fn topology_due(&self) -> bool {
        !self.topology.checks.is_empty()
            && self.topology.seen != Some(self.station.neighbours().changes)
    }

    /// Checks the topology again if it is due: raises, changes or withdraws each port's
    /// mismatch diagnosis, with the PortDataChangeNotification alarm.
    pub(super) fn check_topology(&mut self, now_ns: u64, out: &mut Vec<DeviceAction>) {
        if !self.topology_due() {
            return;
        }
        self.topology.seen = Some(self.station.neighbours().changes);
        for i in 0..self.topology.checks.len() {
            let (at, check) = &self.topology.checks[i];
            let at = *at;
            let now = topology_mismatch(check, self.station.neighbours());
            let before = self
                .topology
                .raised
                .iter()
                .find(|(a, _)| *a == at)
                .map(|(_, e)| *e);
            if now == before {
                continue;
            }
            let mut alarms = Vec::new();
            if let Some(e) = before {
                alarms.extend(self.diagnosis.remove(at, &entry(e).key()));
            }
            if let Some(e) = now
                && let Ok(a) = self.diagnosis.add(at, entry(e))
            {
                alarms.extend(a);
            }
            self.topology.raised.retain(|(a, _)| *a != at);
            self.topology.raised.extend(now.map(|e| (at, e)));
            for a in &mut alarms {
                a.alarm_type = AlarmType::PortDataChange;
            }
            self.send_diagnosis(alarms, now_ns, out);
        }
    }
}

/// The topology checks the PLC wrote and what they found.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TopologyCheck {
    /// Each port's PDPortDataCheck.
    pub(super) checks: Vec<(SubslotAddr, PdPortDataCheck)>,
    /// The mismatch diagnosis raised per port.
    pub(super) raised: Vec<(SubslotAddr, u16)>,
    /// The neighbour table's change count when last checked (`None`: check now).
    seen: Option<u64>,
}

impl TopologyCheck {
    /// The mismatch (ExtChannelErrorType) pending on each checked port.
    pub fn mismatches(&self) -> &[(SubslotAddr, u16)] {
        &self.raised
    }
}
