// SPDX-License-Identifier: MIT OR Apache-2.0
//! What a session tells the master: who the subagent is, how long the master waits for
//! it, and which subtrees it serves.

use std::time::Duration;

use crate::mib::lldp::LLDP_MIB;
use crate::mib::system::{SYS_DESCR, SYS_SERVICES, SYSTEM};
use crate::pdu::Oid;

/// The priority of the `system` registration: better (lower) than the 127 with which
/// snmpd registers its own system group, so that snmpd answers sysName and sysLocation
/// from procimgd. See [`SessionConfig::procimgd`].
pub const SYSTEM_PRIORITY: u8 = 1;
/// AgentX's default priority, for subtrees that nobody else serves.
pub const DEFAULT_PRIORITY: u8 = 127;

/// One subtree (or range of subtrees) the subagent registers (agentx-Register-PDU).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Registration {
    /// The subtree, or with `range` the first of the subtrees.
    pub subtree: Oid,
    /// Lower wins among registrations of the same subtree.
    pub priority: u8,
    /// `(range_subid, upper_bound)`: subidentifier `range_subid` (1-based, of the whole
    /// OID) of `subtree` runs up to `upper_bound`, registering each subtree on the way.
    pub range: Option<(u8, u32)>,
    /// Seconds the master waits for answers in this subtree; 0 for the session's.
    pub timeout: u8,
    /// INSTANCE_REGISTRATION: `subtree` is one object instance.
    pub instance: bool,
}

impl Registration {
    /// A whole subtree at a priority.
    pub fn subtree(subtree: impl Into<Oid>, priority: u8) -> Registration {
        Registration {
            subtree: subtree.into(),
            priority,
            range: None,
            timeout: 0,
            instance: false,
        }
    }
}

/// How the session opens and what it registers.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SessionConfig {
    /// o.id: an OID naming the subagent; null for none.
    pub id: Oid,
    /// o.descr: the subagent's name in snmpd's log.
    pub description: String,
    /// o.timeout: seconds the master waits for this subagent's answers (0: the master's
    /// default, 1 s in net-snmp).
    pub timeout: u8,
    /// The subtrees to register, in this order.
    pub registrations: Vec<Registration>,
    /// How long to wait for the master's answer to Open, Register, Ping or Close before
    /// giving the session up.
    pub response_timeout: Duration,
}

impl SessionConfig {
    /// procimgd's session: "procimgd", a 5 s timeout, and two registrations:
    ///
    /// - sysDescr to sysServices (1.3.6.1.2.1.1.1 to .7) as one range registration at
    ///   [`SYSTEM_PRIORITY`]. net-snmp's snmpd registers each of these objects itself (as
    ///   subtrees one level below `system`, priority 127); in its registry the more
    ///   specific subtree wins before priority is looked at, so registering `system`
    ///   whole changes nothing (at any priority), the same subtrees at 127 are refused
    ///   (duplicateRegistration), and at a better priority they are taken over (tried
    ///   with net-snmp 5.9.3). sysUpTime is taken over too: managers see the snapshot's.
    ///   sysORLastChange and sysORTable stay snmpd's.
    /// - the LLDP-MIB (1.0.8802.1.1.2) at the default priority; it includes the
    ///   LLDP-EXT-PNO-MIB under lldpExtensions.
    pub fn procimgd() -> SessionConfig {
        let first_system_object = Oid::from(SYSTEM).child(&[SYS_DESCR]);
        SessionConfig {
            id: Oid::null(),
            description: "procimgd".into(),
            timeout: 5,
            registrations: vec![
                Registration {
                    range: Some((8, SYS_SERVICES)),
                    ..Registration::subtree(first_system_object, SYSTEM_PRIORITY)
                },
                Registration::subtree(LLDP_MIB, DEFAULT_PRIORITY),
            ],
            response_timeout: Duration::from_secs(5),
        }
    }
}

impl Default for SessionConfig {
    fn default() -> SessionConfig {
        SessionConfig::procimgd()
    }
}
