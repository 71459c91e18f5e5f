// SPDX-License-Identifier: MIT OR Apache-2.0
//! A station's Ethernet port as its neighbours see it, for either role: what the port
//! announces by LLDP ([`lldp`]) and what it learns of its neighbours ([`neighbours`]).

pub mod dcp_station;
pub mod lldp;
pub mod neighbours;
