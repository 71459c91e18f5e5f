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
pub use crate::port::check::{
    Finding, REMOTE_MISMATCH, TRANSMISSION_IMPOSSIBLE, WHOLE_SUBMODULE, mismatch,
    topology_findings, transmission,
};
use crate::wire::alarm::AlarmType;
use crate::wire::record::{
    DCP_BOUNDARY_HELLO, INDEX_PD_PORT_DATA_ADJUST, INDEX_PD_PORT_DATA_CHECK, PEER_TO_PEER_NO_LLDP,
    PdPortDataAdjust, PdPortDataCheck,
};

/// The diagnosis entry of a finding.
pub(crate) fn entry((error_type, ext): Finding) -> DiagEntry {
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
