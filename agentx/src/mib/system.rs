// SPDX-License-Identifier: MIT OR Apache-2.0
//! MIB-II's `system` group (RFC 3418, SNMPv2-MIB): sysDescr .1 to sysServices .7, each a
//! scalar with instance `.0`. sysORLastChange and sysORTable (.8, .9) are snmpd's.

use super::Snapshot;
use super::builder::{Builder, octets};
use crate::pdu::{Oid, Value};

/// `system`: 1.3.6.1.2.1.1.
pub const SYSTEM: [u32; 7] = [1, 3, 6, 1, 2, 1, 1];

/// sysDescr.
pub const SYS_DESCR: u32 = 1;
/// sysObjectID.
pub const SYS_OBJECT_ID: u32 = 2;
/// sysUpTime.
pub const SYS_UP_TIME: u32 = 3;
/// sysContact.
pub const SYS_CONTACT: u32 = 4;
/// sysName.
pub const SYS_NAME: u32 = 5;
/// sysLocation.
pub const SYS_LOCATION: u32 = 6;
/// sysServices.
pub const SYS_SERVICES: u32 = 7;

pub(crate) fn build(s: &Snapshot, b: &mut Builder) {
    let system = Oid::from(SYSTEM);
    let object = |n: u32| system.child(&[n]);
    b.scalar(object(SYS_DESCR), octets(s.sys_descr.as_bytes()));
    // An OID of no subidentifiers has no BER encoding: zeroDotZero stands for "none".
    let object_id = if s.sys_object_id.is_empty() {
        Oid::from([0, 0])
    } else {
        Oid::new(s.sys_object_id.clone())
    };
    b.scalar(object(SYS_OBJECT_ID), Value::ObjectIdentifier(object_id));
    b.scalar(object(SYS_UP_TIME), Value::TimeTicks(s.sys_up_time_centis));
    b.scalar(object(SYS_CONTACT), octets(s.sys_contact.as_bytes()));
    b.scalar(object(SYS_NAME), octets(s.sys_name.as_bytes()));
    b.scalar(object(SYS_LOCATION), octets(s.sys_location.as_bytes()));
    b.scalar(
        object(SYS_SERVICES),
        Value::Integer(i32::from(s.sys_services & 0x7f)),
    );
}
