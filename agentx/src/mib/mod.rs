// SPDX-License-Identifier: MIT OR Apache-2.0
//! A read-only MIB view over plain data.
//!
//! The runtime fills a [`Snapshot`]: the MIB-II `system` group's values and an
//! [`LldpView`] (the local system, ports and management addresses, the neighbours, the
//! counters, the PROFINET port data). [`MibView::new`] turns it into the sorted instances
//! of the groups this crate serves, which Get, GetNext and GetBulk read in lexicographic
//! OID order, as `snmpwalk` expects:
//!
//! - `system` (1.3.6.1.2.1.1, [`system`]): sysDescr to sysServices;
//! - the LLDP-MIB (1.0.8802.1.1.2, [`lldp`]): lldpStatistics, lldpLocalSystemData with
//!   lldpLocPortTable and lldpLocManAddrTable, lldpRemTable and lldpRemManAddrTable;
//! - the LLDP-EXT-PNO-MIB (1.0.8802.1.1.2.1.5.3791, [`pno`]): lldpXPnoLocTable and
//!   lldpXPnoRemTable.
//!
//! The MIB is read-only: sets are refused by the session (notWritable).

mod builder;
mod example;
pub mod lldp;
pub mod pno;
mod snapshot;
pub mod system;
mod view;

#[cfg(test)]
mod tests;

pub use snapshot::{
    Capabilities, ChassisId, LldpView, LocalPort, LocalSystem, ManagementAddress, PnoPort, PortId,
    PortStatistics, RemoteSystem, RtClass2Status, RtClass3Status, Snapshot, Statistics,
};
pub use view::MibView;
