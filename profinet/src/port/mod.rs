// SPDX-License-Identifier: MIT OR Apache-2.0
//! A station's Ethernet port as its neighbours see it, for either role: what the port
//! announces by LLDP ([`lldp`]), what it learns of its neighbours ([`neighbours`]), its link
//! and counters as the physical device's records report them ([`physical`]) and the
//! topology check of its neighbour and link ([`check`]).

pub mod check;
pub mod dcp_station;
pub mod lldp;
pub mod neighbours;
pub mod physical;
