// SPDX-License-Identifier: MIT OR Apache-2.0
//! The LLDP-MIB (IEEE 802.1AB-2005, `lldpMIB` 1.0.8802.1.1.2), read-only:
//!
//! ```text
//! lldpStatistics        .1.2   .1-.5 scalars; .6 TxPortTable, .7 RxPortTable (index port)
//! lldpLocalSystemData   .1.3   .1-.6 scalars; .7 lldpLocPortTable (index lldpLocPortNum);
//!                              .8 lldpLocManAddrTable (index subtype, address)
//! lldpRemoteSystemsData .1.4   .1 lldpRemTable (index lldpRemTimeMark, lldpRemLocalPortNum,
//!                              lldpRemIndex); .2 lldpRemManAddrTable (those, subtype, address)
//! ```
//!
//! A management address index is its subtype (1, ipV4) and the address as a
//! length-prefixed octet string (`1.4.a.b.c.d`): LldpManAddress is not IMPLIED.
//! lldpConfiguration (.1.1, the agent's read-write settings) is not served.

use super::Snapshot;
use super::builder::{Builder, integer, octets};
use super::snapshot::{Capabilities, ManagementAddress};
use crate::pdu::{Oid, Value};

/// `lldpMIB`: 1.0.8802.1.1.2.
pub const LLDP_MIB: [u32; 6] = [1, 0, 8802, 1, 1, 2];

/// The address family of an IPv4 management address (AddressFamilyNumbers ipV4).
const IPV4: u32 = 1;
/// lldpLocManAddrLen of an IPv4 address: the subtype byte and the 4 address bytes, as
/// the Management Address TLV counts them.
const IPV4_MAN_ADDR_LEN: u32 = 5;

fn lldp(suffix: &[u32]) -> Oid {
    Oid::from(LLDP_MIB).child(suffix)
}

pub(crate) fn build(s: &Snapshot, b: &mut Builder) {
    statistics(s, b);
    local_system(s, b);
    remote_systems(s, b);
}

fn statistics(s: &Snapshot, b: &mut Builder) {
    let Some(stats) = &s.lldp.statistics else {
        return;
    };
    let group = lldp(&[1, 2]);
    b.scalar(
        group.child(&[1]),
        Value::TimeTicks(stats.rem_tables_last_change),
    );
    // ZeroBasedCounter32 is a Gauge32 on the wire.
    b.scalar(group.child(&[2]), Value::Gauge32(stats.rem_tables_inserts));
    b.scalar(group.child(&[3]), Value::Gauge32(stats.rem_tables_deletes));
    b.scalar(group.child(&[4]), Value::Gauge32(stats.rem_tables_drops));
    b.scalar(group.child(&[5]), Value::Gauge32(stats.rem_tables_ageouts));
    let tx = group.child(&[6, 1]);
    let rx = group.child(&[7, 1]);
    b.columns(&tx, [2]);
    b.columns(&rx, 2..=7);
    for p in &stats.ports {
        let index = [p.num];
        b.cell(&tx, 2, &index, Value::Counter32(p.tx_frames));
        b.cell(&rx, 2, &index, Value::Counter32(p.rx_frames_discarded));
        b.cell(&rx, 3, &index, Value::Counter32(p.rx_frames_errors));
        b.cell(&rx, 4, &index, Value::Counter32(p.rx_frames));
        b.cell(&rx, 5, &index, Value::Counter32(p.rx_tlvs_discarded));
        b.cell(&rx, 6, &index, Value::Counter32(p.rx_tlvs_unrecognized));
        b.cell(&rx, 7, &index, Value::Gauge32(p.rx_ageouts));
    }
}

fn local_system(s: &Snapshot, b: &mut Builder) {
    let local = &s.lldp.local;
    let group = lldp(&[1, 3]);
    b.scalar(
        group.child(&[1]),
        integer(u32::from(local.chassis_id.subtype)),
    );
    b.scalar(group.child(&[2]), octets(&local.chassis_id.id));
    b.scalar(group.child(&[3]), octets(local.sys_name.as_bytes()));
    b.scalar(group.child(&[4]), octets(local.sys_desc.as_bytes()));
    b.scalar(group.child(&[5]), bits(local.capabilities.supported));
    b.scalar(group.child(&[6]), bits(local.capabilities.enabled));

    let ports = group.child(&[7, 1]);
    b.columns(&ports, 2..=4);
    for p in &s.lldp.ports {
        let index = [p.num];
        b.cell(&ports, 2, &index, integer(u32::from(p.id.subtype)));
        b.cell(&ports, 3, &index, octets(&p.id.id));
        b.cell(&ports, 4, &index, octets(p.description.as_bytes()));
    }

    let addresses = group.child(&[8, 1]);
    b.columns(&addresses, 3..=6);
    for a in &s.lldp.management_addresses {
        let index = address_index(a);
        b.cell(&addresses, 3, &index, integer(IPV4_MAN_ADDR_LEN));
        b.cell(&addresses, 4, &index, integer(u32::from(a.if_subtype)));
        b.cell(&addresses, 5, &index, integer(a.if_id));
        if !a.object_id.is_empty() {
            let oid = Value::ObjectIdentifier(Oid::new(a.object_id.clone()));
            b.cell(&addresses, 6, &index, oid);
        }
    }
}

fn remote_systems(s: &Snapshot, b: &mut Builder) {
    let group = lldp(&[1, 4]);
    let remotes = group.child(&[1, 1]);
    let addresses = group.child(&[2, 1]);
    b.columns(&remotes, 4..=12);
    b.columns(&addresses, 3..=5);
    for r in &s.lldp.remotes {
        let index = [r.time_mark, r.local_port, r.index];
        b.cell(
            &remotes,
            4,
            &index,
            integer(u32::from(r.chassis_id.subtype)),
        );
        b.cell(&remotes, 5, &index, octets(&r.chassis_id.id));
        b.cell(&remotes, 6, &index, integer(u32::from(r.port_id.subtype)));
        b.cell(&remotes, 7, &index, octets(&r.port_id.id));
        let texts = [
            (8, &r.port_description),
            (9, &r.sys_name),
            (10, &r.sys_desc),
        ];
        for (column, text) in texts {
            if let Some(text) = text {
                b.cell(&remotes, column, &index, octets(text.as_bytes()));
            }
        }
        if let Some(Capabilities { supported, enabled }) = r.capabilities {
            b.cell(&remotes, 11, &index, bits(supported));
            b.cell(&remotes, 12, &index, bits(enabled));
        }
        for a in &r.management_addresses {
            let index: Vec<u32> = index.iter().copied().chain(address_index(a)).collect();
            b.cell(&addresses, 3, &index, integer(u32::from(a.if_subtype)));
            b.cell(&addresses, 4, &index, integer(a.if_id));
            if !a.object_id.is_empty() {
                let oid = Value::ObjectIdentifier(Oid::new(a.object_id.clone()));
                b.cell(&addresses, 5, &index, oid);
            }
        }
    }
}

/// The index of a management address: subtype ipV4, length 4, the four bytes.
fn address_index(a: &ManagementAddress) -> [u32; 6] {
    let [w, x, y, z] = a.ipv4.octets().map(u32::from);
    [IPV4, 4, w, x, y, z]
}

/// LldpSystemCapabilitiesMap as SNMP BITS: capability bit n (the TLV's bit n) is bit
/// `7 - n % 8` of octet `n / 8`. One octet while only the eight capabilities of 2005 are
/// set, two when a later one is.
pub(crate) fn bits(capabilities: u16) -> Value {
    let reversed = capabilities.reverse_bits().to_be_bytes();
    let len = if capabilities > 0xff { 2 } else { 1 };
    octets(&reversed[..len])
}
