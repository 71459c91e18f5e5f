// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimgd as an AgentX subagent (RFC 2741) of net-snmp's snmpd.
//!
//! placeholder
#![deny(missing_docs)]

pub mod mib;
pub mod pdu;
pub mod runner;
pub mod session;
