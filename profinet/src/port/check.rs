// SPDX-License-Identifier: MIT OR Apache-2.0
//! The topology check of a port, for a station of either role: its LLDP neighbour and its
//! own link compared with what a PDPortDataCheck expects. What a mismatch is called is the
//! standard's: ChannelErrorType 0x8001 "remote mismatch" for the neighbour (the peer's
//! NameOfStation, its port, no peer at all), 0x8000 "data transmission impossible" for the
//! port's own link (down, or another MAU type), each on channel 0x8000 of the port
//! submodule. A device checks what its PLC wrote; the controller checks its own port
//! against the neighbour the configuration gives it.

use crate::port::neighbours::Neighbours;
use crate::port::physical::PortLink;
use crate::wire::record::{PdPortDataCheck, PortCheck};

/// ChannelNumber of a diagnosis of the whole submodule.
pub const WHOLE_SUBMODULE: u16 = 0x8000;
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
    link: &PortLink,
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
