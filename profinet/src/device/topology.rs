// SPDX-License-Identifier: MIT OR Apache-2.0
//! The port as the PLC parameterizes it: what its PDPortDataAdjust sets (a peer-to-peer
//! boundary keeps LLDP in, a DCP boundary keeps the Hello in), taken after every Write of
//! the AR, and kept after the AR as PDev parameters are.

use super::{Application, Device, physical};
use crate::wire::record::{
    DCP_BOUNDARY_HELLO, INDEX_PD_PORT_DATA_ADJUST, PEER_TO_PEER_NO_LLDP, PdPortDataAdjust,
};

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
    }
}
