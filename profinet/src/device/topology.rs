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
//!   (AlarmType 0x000E). CheckMAUType and CheckLinkState are checked against the port's own
//!   link, whenever it changes: a MAU type other than the one checked, or a link down where
//!   the check wants it up, is ChannelErrorType 0x8000 "data transmission impossible" (with
//!   ExtChannelErrorType 0x8001 and 0x8000), announced the same way. The check stays after
//!   the AR, as PDev parameters do.

use super::diagnosis::{ChannelDiag, DiagEntry, SubslotAddr};
use super::{Application, Device, DeviceAction, physical};
use crate::port::neighbours::Neighbours;
use crate::wire::alarm::AlarmType;
use crate::wire::record::{
    DCP_BOUNDARY_HELLO, INDEX_PD_PORT_DATA_ADJUST, INDEX_PD_PORT_DATA_CHECK, PEER_TO_PEER_NO_LLDP,
    PdPortDataAdjust, PdPortDataCheck, PortCheck,
};

/// ChannelNumber of a diagnosis of the whole submodule.
const WHOLE_SUBMODULE: u16 = 0x8000;
/// ChannelErrorType "data transmission impossible": the port's own link.
pub const TRANSMISSION_IMPOSSIBLE: u16 = 0x8000;
/// ChannelErrorType "remote mismatch": the neighbour.
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

/// ExtChannelErrorTypes of data transmission impossible.
pub mod transmission {
    /// The link is down.
    pub const LINK_DOWN: u16 = 0x8000;
    /// The port runs another MAU type than the one checked.
    pub const MAU_TYPE: u16 = 0x8001;
}

/// What a check found: ChannelErrorType and ExtChannelErrorType.
pub type Finding = (u16, u16);

/// What the port's neighbourhood and link make of `check`: the mismatches, if any. Of the
/// peers, with several neighbours (a switch without LLDP between) the first is taken.
pub fn topology_findings(
    check: &PdPortDataCheck,
    neighbours: &Neighbours,
    link: &physical::PortLink,
) -> Vec<Finding> {
    let mut found = Vec::new();
    if let Some(expected) = check.peers().and_then(<[_]>::first) {
        let remote = match neighbours.entries().first() {
            None => Some(mismatch::NO_PEER),
            Some(n) if n.peer_station() != Some(expected.chassis_id.as_str()) => {
                Some(mismatch::PEER_NAME)
            }
            Some(n) if n.peer_port() != Some(expected.port_id.as_str()) => {
                Some(mismatch::PEER_PORT)
            }
            Some(_) => None,
        };
        found.extend(remote.map(|e| (REMOTE_MISMATCH, e)));
    }
    for c in &check.checks {
        match c {
            PortCheck::MauType(m) if link.up && link.mau_type != *m => {
                found.push((TRANSMISSION_IMPOSSIBLE, transmission::MAU_TYPE));
            }
            // LinkState 1: up.
            PortCheck::LinkState(1) if !link.up => {
                found.push((TRANSMISSION_IMPOSSIBLE, transmission::LINK_DOWN));
            }
            _ => {}
        }
    }
    found
}

/// The diagnosis entry of a finding.
fn entry((error_type, ext): Finding) -> DiagEntry {
    ChannelDiag::extended(WHOLE_SUBMODULE, error_type, ext, 0).into()
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

    /// What the check depends on now: the neighbour table's change count and the link.
    fn topology_inputs(&self) -> (u64, bool, u16) {
        let link = &self.physical.link;
        (self.station.neighbours().changes, link.up, link.mau_type)
    }

    /// Whether the topology is to be checked again: the check, the neighbourhood or the
    /// link changed.
    pub(super) fn topology_due(&self) -> bool {
        !self.topology.checks.is_empty() && self.topology.seen != Some(self.topology_inputs())
    }

    /// Checks the topology again if it is due: raises and withdraws each port's findings
    /// as diagnosis, with the PortDataChangeNotification alarm.
    pub(super) fn check_topology(&mut self, now_ns: u64, out: &mut Vec<DeviceAction>) {
        if !self.topology_due() {
            return;
        }
        self.topology.seen = Some(self.topology_inputs());
        for i in 0..self.topology.checks.len() {
            let (at, check) = &self.topology.checks[i];
            let at = *at;
            let now = topology_findings(check, self.station.neighbours(), &self.physical.link);
            let before: Vec<Finding> = self
                .topology
                .raised
                .iter()
                .filter(|(a, _)| *a == at)
                .map(|(_, f)| *f)
                .collect();
            let mut alarms = Vec::new();
            for gone in before.iter().filter(|f| !now.contains(f)) {
                alarms.extend(self.diagnosis.remove(at, &entry(*gone).key()));
            }
            for came in now.iter().filter(|f| !before.contains(f)) {
                if let Ok(a) = self.diagnosis.add(at, entry(*came)) {
                    alarms.extend(a);
                }
            }
            self.topology.raised.retain(|(a, _)| *a != at);
            self.topology
                .raised
                .extend(now.into_iter().map(|f| (at, f)));
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
    /// The findings raised as diagnosis, per port.
    pub(super) raised: Vec<(SubslotAddr, Finding)>,
    /// What the check depended on when last made (`None`: check now).
    seen: Option<(u64, bool, u16)>,
}

impl TopologyCheck {
    /// The findings pending as diagnosis on each checked port.
    pub fn mismatches(&self) -> &[(SubslotAddr, Finding)] {
        &self.raised
    }
}
