// SPDX-License-Identifier: MIT OR Apache-2.0
//! The physical device as its records describe it, for a station of either role: the
//! interface submodule (subslot 0x8000 of the device access point, or of the controller's
//! own interface) and its port (0x8001), with what the station knows of its link (set by its
//! runtime: the interface's state, speed and counters) and of its neighbour (from LLDP).
//!
//! The records, all read-only:
//!
//! | index | at | record |
//! |---|---|---|
//! | 0x8080 | the interface (or subslot 0 of its slot) | PDInterfaceDataReal: name, MAC, IP suite |
//! | 0x802A | a port | PDPortDataReal: its name, neighbours, MAU type, link, media |
//! | 0x8072 | the interface or a port | PDPortStatistic: the interface's counters |
//! | 0xF841 | anywhere | PDRealData: each of them in a MultipleBlockHeader |
//!
//! A station with one port counts the same frames on its interface and its port: both
//! report the interface's counters.

use crate::port::neighbours::Neighbours;
use crate::wire::MacAddress;
use crate::wire::lldp::MacPhyStatus;
use crate::wire::record::{
    LINK_DOWN, LINK_UP, MEDIA_COPPER, MultipleBlockHeader, PORT_STATE_UNKNOWN, PdInterfaceDataReal,
    PdPortDataReal, PdPortStatistic, PeerReal,
};

/// The port's link, as the runtime reads it from its interface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PortLink {
    /// Whether the link is up.
    pub up: bool,
    /// The MAU type it runs (IETF RFC 4836; 0: unknown).
    pub mau_type: u16,
    /// PDPortDataReal's MediaType (1 copper, 2 fibre, 0 unknown).
    pub media_type: u32,
}

impl Default for PortLink {
    /// Up, 100BASE-TX full duplex on copper: what a PROFINET port runs.
    fn default() -> PortLink {
        PortLink {
            up: true,
            mau_type: MacPhyStatus::MAU_100BASE_TX_FD,
            media_type: MEDIA_COPPER,
        }
    }
}

impl PortLink {
    /// The MAU type of a link of `mbit_s` Mbit/s, full or half duplex (IETF RFC 4836's
    /// twisted-pair types for 10, 100 and 1000 Mbit/s); 0 for another speed.
    pub const fn mau_type_of(mbit_s: u32, full_duplex: bool) -> u16 {
        match (mbit_s, full_duplex) {
            (10, false) => 10,
            (10, true) => 11,
            (100, false) => 15,
            (100, true) => 16,
            (1000, false) => 29,
            (1000, true) => 30,
            _ => 0,
        }
    }
}

/// The interface's counters, as the kernel counts them (64 bits; the records carry their
/// low 32 bits, as MIB-II's Counter32 wraps).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PortCounters {
    /// Octets received.
    pub in_octets: u64,
    /// Octets sent.
    pub out_octets: u64,
    /// Received frames dropped.
    pub in_discards: u64,
    /// Frames to send dropped.
    pub out_discards: u64,
    /// Receive errors.
    pub in_errors: u64,
    /// Send errors.
    pub out_errors: u64,
}

/// What the device knows of its interface and port.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Physical {
    /// The port's link.
    pub link: PortLink,
    /// The interface's counters; `None` where there are none to read (a simulated link):
    /// PDPortStatistic then marks every counter unsupported.
    pub counters: Option<PortCounters>,
}

/// Whether `subslot` is an interface submodule's (0x8X00).
pub const fn is_interface(subslot: u16) -> bool {
    subslot & 0xf0ff == 0x8000
}

/// Whether `subslot` is a port submodule's (0x8X01–0x8XFF).
pub const fn is_port(subslot: u16) -> bool {
    subslot & 0xf000 == 0x8000 && subslot & 0x00ff != 0
}

/// CounterStatus with every counter marked unsupported.
const NO_COUNTERS: u16 = 0x003f;

/// The station as its physical records need it.
pub(crate) struct PhysicalView<'a> {
    pub(crate) name: &'a str,
    pub(crate) mac: MacAddress,
    pub(crate) ip_suite: [[u8; 4]; 3],
    /// The port's own LLDP Port ID (`port-001`, or `port-001.<name>`).
    pub(crate) own_port_id: String,
    pub(crate) physical: &'a Physical,
    pub(crate) neighbours: &'a Neighbours,
}

impl PhysicalView<'_> {
    pub(crate) fn interface_data_real(&self) -> PdInterfaceDataReal {
        let [ip, mask, gateway] = self.ip_suite;
        PdInterfaceDataReal {
            chassis_id: self.name.to_owned(),
            mac: self.mac,
            ip,
            mask,
            gateway,
        }
    }

    pub(crate) fn port_data_real(&self, slot: u16, subslot: u16) -> PdPortDataReal {
        let link = &self.physical.link;
        PdPortDataReal {
            slot,
            subslot,
            own_port_id: self.own_port_id.clone(),
            peers: self
                .neighbours
                .entries()
                .iter()
                .map(|n| PeerReal {
                    port_id: n.peer_port_id(),
                    chassis_id: n.peer_chassis_id(),
                    line_delay: n.line_delay_ns() & 0x7fff_ffff,
                    mac: n.mac(),
                })
                .collect(),
            mau_type: if link.up { link.mau_type } else { 0 },
            domain_boundary: 0,
            multicast_boundary: 0,
            port_state: PORT_STATE_UNKNOWN,
            link: if link.up { LINK_UP } else { LINK_DOWN },
            media_type: link.media_type,
        }
    }

    pub(crate) fn statistic(&self) -> PdPortStatistic {
        let low = |v: u64| v as u32;
        match self.physical.counters {
            Some(c) => PdPortStatistic {
                counter_status: Some(0),
                in_octets: low(c.in_octets),
                out_octets: low(c.out_octets),
                in_discards: low(c.in_discards),
                out_discards: low(c.out_discards),
                in_errors: low(c.in_errors),
                out_errors: low(c.out_errors),
            },
            None => PdPortStatistic {
                counter_status: Some(NO_COUNTERS),
                ..PdPortStatistic::default()
            },
        }
    }

    /// PDRealData: a MultipleBlockHeader for the interface (PDInterfaceDataReal and
    /// PDPortStatistic) and one for each port (PDPortDataReal and PDPortStatistic), of the
    /// submodules `real` names by API, slot and subslot, in its order.
    pub(crate) fn real_data(
        &self,
        real: impl IntoIterator<Item = (u32, u16, u16)>,
    ) -> crate::wire::EmitResult<Vec<u8>> {
        let mut out = Vec::new();
        for (api, slot, subslot) in real
            .into_iter()
            .filter(|&(_, _, subslot)| is_interface(subslot) || is_port(subslot))
        {
            let mut blocks = if is_interface(subslot) {
                self.interface_data_real().to_vec()?
            } else {
                self.port_data_real(slot, subslot).to_vec()?
            };
            blocks.extend(self.statistic().to_vec()?);
            out.extend(
                MultipleBlockHeader {
                    api,
                    slot,
                    subslot,
                    blocks,
                }
                .to_vec()?,
            );
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subslot_kinds() {
        assert!(is_interface(0x8000) && is_interface(0x8100));
        assert!(!is_interface(0x8001) && !is_interface(1));
        assert!(is_port(0x8001) && is_port(0x8102));
        assert!(!is_port(0x8000) && !is_port(0x0001) && !is_port(0x9001));
    }

    #[test]
    fn mau_types_of_twisted_pair_speeds() {
        assert_eq!(PortLink::mau_type_of(100, true), 16);
        assert_eq!(PortLink::mau_type_of(1000, true), 30);
        assert_eq!(PortLink::mau_type_of(10_000, true), 0);
    }
}
