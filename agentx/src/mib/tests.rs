// SPDX-License-Identifier: MIT OR Apache-2.0
//! The example station's MIB, walked: every instance in OID order with its type, written
//! out by hand from the MIB definitions; Get's exceptions; GetNext's include flag and range
//! end; GetBulk.

use super::*;
use crate::pdu::{GetBulk, Oid, SearchRange, Value, VarBind};

const SYS: &str = "1.3.6.1.2.1.1";
const LLDP: &str = "1.0.8802.1.1.2.1";

fn oid(s: &str) -> Oid {
    s.parse().unwrap()
}

/// The example's walk: (OID, type code, value where it matters).
fn expected_walk() -> Vec<(String, u16)> {
    let (s, t, i, g, c, o) = (4u16, 67u16, 2u16, 66u16, 65u16, 6u16);
    let mut walk: Vec<(String, u16)> = vec![
        (format!("{SYS}.1.0"), s),
        (format!("{SYS}.2.0"), o),
        (format!("{SYS}.3.0"), t),
        (format!("{SYS}.4.0"), s),
        (format!("{SYS}.5.0"), s),
        (format!("{SYS}.6.0"), s),
        (format!("{SYS}.7.0"), i),
        // lldpStatistics
        (format!("{LLDP}.2.1.0"), t),
        (format!("{LLDP}.2.2.0"), g),
        (format!("{LLDP}.2.3.0"), g),
        (format!("{LLDP}.2.4.0"), g),
        (format!("{LLDP}.2.5.0"), g),
        (format!("{LLDP}.2.6.1.2.1"), c),
        (format!("{LLDP}.2.6.1.2.2"), c),
    ];
    for column in 2..=7 {
        let ty = if column == 7 { g } else { c };
        walk.push((format!("{LLDP}.2.7.1.{column}.1"), ty));
        walk.push((format!("{LLDP}.2.7.1.{column}.2"), ty));
    }
    walk.extend([
        // lldpLocalSystemData
        (format!("{LLDP}.3.1.0"), i),
        (format!("{LLDP}.3.2.0"), s),
        (format!("{LLDP}.3.3.0"), s),
        (format!("{LLDP}.3.4.0"), s),
        (format!("{LLDP}.3.5.0"), s),
        (format!("{LLDP}.3.6.0"), s),
        (format!("{LLDP}.3.7.1.2.1"), i),
        (format!("{LLDP}.3.7.1.2.2"), i),
        (format!("{LLDP}.3.7.1.3.1"), s),
        (format!("{LLDP}.3.7.1.3.2"), s),
        (format!("{LLDP}.3.7.1.4.1"), s),
        (format!("{LLDP}.3.7.1.4.2"), s),
        (format!("{LLDP}.3.8.1.3.1.4.192.168.0.50"), i),
        (format!("{LLDP}.3.8.1.4.1.4.192.168.0.50"), i),
        (format!("{LLDP}.3.8.1.5.1.4.192.168.0.50"), i),
        (format!("{LLDP}.3.8.1.6.1.4.192.168.0.50"), o),
        // lldpRemTable: no lldpRemSysDesc (column 10), the neighbour sent none
        (format!("{LLDP}.4.1.1.4.300.1.1"), i),
        (format!("{LLDP}.4.1.1.5.300.1.1"), s),
        (format!("{LLDP}.4.1.1.6.300.1.1"), i),
        (format!("{LLDP}.4.1.1.7.300.1.1"), s),
        (format!("{LLDP}.4.1.1.8.300.1.1"), s),
        (format!("{LLDP}.4.1.1.9.300.1.1"), s),
        (format!("{LLDP}.4.1.1.11.300.1.1"), s),
        (format!("{LLDP}.4.1.1.12.300.1.1"), s),
        // lldpRemManAddrTable: no OID column, the neighbour's address has none
        (format!("{LLDP}.4.2.1.3.300.1.1.1.4.192.168.0.60"), i),
        (format!("{LLDP}.4.2.1.4.300.1.1.1.4.192.168.0.60"), i),
    ]);
    // lldpXPnoLocTable (port 1 only) and lldpXPnoRemTable
    for (column, ty) in [(1, g), (2, g), (3, g), (4, i), (5, i), (6, s)] {
        walk.push((format!("{LLDP}.5.3791.1.2.1.1.{column}.1"), ty));
    }
    for (column, ty) in [(1, g), (2, g), (3, g), (4, i), (5, i), (6, s)] {
        walk.push((format!("{LLDP}.5.3791.1.3.1.1.{column}.300.1.1"), ty));
    }
    walk
}

#[test]
fn the_view_holds_the_expected_instances_in_order() {
    let view = MibView::new(&Snapshot::example());
    let got: Vec<(String, u16)> = view
        .instances()
        .iter()
        .map(|v| (v.name.to_string(), v.value.type_code()))
        .collect();
    // 1.0.8802… sorts before 1.3.6…: the LLDP-MIB first, then the system group.
    let mut expected = expected_walk();
    expected.rotate_left(7);
    assert_eq!(got, expected);
}

/// Walks a subtree as snmpwalk does: GetNext from the root, excluding each name found,
/// until a name leaves the subtree or the range's end is reached.
fn walk(view: &MibView, root: &Oid, end: &Oid) -> Vec<VarBind> {
    let mut found = Vec::new();
    let mut range = SearchRange {
        start: root.clone(),
        include: false,
        end: end.clone(),
    };
    loop {
        let v = view.get_next(&range);
        if v.value == Value::EndOfMibView || !v.name.starts_with(root.as_slice()) {
            return found;
        }
        range.start = v.name.clone();
        found.push(v);
    }
}

#[test]
fn get_next_walks_each_registered_subtree() {
    let view = MibView::new(&Snapshot::example());
    let lldp = walk(&view, &oid("1.0.8802.1.1.2"), &oid("1.0.8802.1.1.3"));
    let system = walk(&view, &oid(SYS), &oid("1.3.6.1.2.1.2"));
    let names: Vec<String> = system
        .iter()
        .chain(&lldp)
        .map(|v| v.name.to_string())
        .collect();
    let expected: Vec<String> = expected_walk().into_iter().map(|(o, _)| o).collect();
    assert_eq!(names, expected);
    // The values are the snapshot's.
    let get = |s: &str| view.get(&oid(s));
    assert_eq!(get(&format!("{SYS}.5.0")), Value::string("plc-station"));
    assert_eq!(get(&format!("{SYS}.6.0")), Value::string("hall 3"));
    assert_eq!(get(&format!("{SYS}.7.0")), Value::Integer(78));
    assert_eq!(get(&format!("{SYS}.3.0")), Value::TimeTicks(4242));
    assert_eq!(
        get(&format!("{SYS}.2.0")),
        Value::ObjectIdentifier(oid("1.3.6.1.4.1.24686"))
    );
    assert_eq!(
        get(&format!("{LLDP}.3.5.0")),
        Value::OctetString(vec![0x01])
    );
    assert_eq!(get(&format!("{LLDP}.3.7.1.3.2")), Value::string("port-002"));
    assert_eq!(
        get(&format!("{LLDP}.3.8.1.3.1.4.192.168.0.50")),
        Value::Integer(5)
    );
    assert_eq!(
        get(&format!("{LLDP}.4.1.1.7.300.1.1")),
        Value::string("port-001.io-device-1")
    );
    assert_eq!(
        get(&format!("{LLDP}.5.3791.1.2.1.1.4.1")),
        Value::Integer(2)
    );
    assert_eq!(
        get(&format!("{LLDP}.5.3791.1.3.1.1.3.300.1.1")),
        Value::Gauge32(240)
    );
}

#[test]
fn get_tells_missing_instances_from_missing_objects() {
    let view = MibView::new(&Snapshot::example());
    // sysName without .0, and a port that does not exist: the objects exist.
    assert_eq!(view.get(&oid(&format!("{SYS}.5"))), Value::NoSuchInstance);
    assert_eq!(view.get(&oid(&format!("{SYS}.5.1"))), Value::NoSuchInstance);
    assert_eq!(
        view.get(&oid(&format!("{LLDP}.3.7.1.3.9"))),
        Value::NoSuchInstance
    );
    // lldpRemSysDesc is a column we serve, without a value for this neighbour.
    assert_eq!(
        view.get(&oid(&format!("{LLDP}.4.1.1.10.300.1.1"))),
        Value::NoSuchInstance
    );
    // sysORLastChange and lldpConfiguration are not ours.
    assert_eq!(view.get(&oid(&format!("{SYS}.8.0"))), Value::NoSuchObject);
    assert_eq!(
        view.get(&oid(&format!("{LLDP}.1.1.0"))),
        Value::NoSuchObject
    );
    assert_eq!(view.get(&oid("1.3.6.1.2.1")), Value::NoSuchObject);
}

#[test]
fn get_next_honours_include_and_the_range_end() {
    let view = MibView::new(&Snapshot::example());
    let sys_name = oid(&format!("{SYS}.5.0"));
    let range = |start: &Oid, include: bool, end: &str| SearchRange {
        start: start.clone(),
        include,
        end: if end.is_empty() {
            Oid::null()
        } else {
            oid(end)
        },
    };
    assert_eq!(view.get_next(&range(&sys_name, true, "")).name, sys_name);
    assert_eq!(
        view.get_next(&range(&sys_name, false, "")).name,
        oid(&format!("{SYS}.6.0"))
    );
    // The master bounds a range at the next registration: sysLocation lies beyond it.
    let bounded = view.get_next(&range(&sys_name, false, &format!("{SYS}.6")));
    assert_eq!(bounded, VarBind::new(sys_name.clone(), Value::EndOfMibView));
    // After the last instance (sysServices.0, as 1.3 sorts after 1.0): endOfMibView named
    // by the start.
    let last = oid(&format!("{SYS}.7.0"));
    assert_eq!(
        view.get_next(&range(&last, false, "")).value,
        Value::EndOfMibView
    );
    // From before the system group, unbounded: its first instance.
    assert_eq!(
        view.get_next(&range(&oid("1.3.6.1.2.1"), false, "")).name,
        oid(&format!("{SYS}.1.0"))
    );
}

#[test]
fn get_bulk_repeats_from_the_previous_names_and_stops_at_the_end() {
    let view = MibView::new(&Snapshot::example());
    let from = |s: &str, end: &str| SearchRange {
        start: oid(s),
        include: false,
        end: oid(end),
    };
    let bulk = GetBulk {
        non_repeaters: 1,
        max_repetitions: 3,
        ranges: vec![
            from(SYS, "1.3.6.1.2.1.2"),
            from(&format!("{SYS}.4"), "1.3.6.1.2.1.2"),
            from(&format!("{LLDP}.3.7.1.3"), "1.0.8802.1.1.3"),
        ],
    };
    let names: Vec<String> = view
        .get_bulk(&bulk)
        .iter()
        .map(|v| v.name.to_string())
        .collect();
    assert_eq!(
        names,
        [
            format!("{SYS}.1.0"),
            format!("{SYS}.4.0"),
            format!("{LLDP}.3.7.1.3.1"),
            format!("{SYS}.5.0"),
            format!("{LLDP}.3.7.1.3.2"),
            format!("{SYS}.6.0"),
            format!("{LLDP}.3.7.1.4.1"),
        ]
    );
    // Repeaters that run off the end: the round of endOfMibView ends the answer.
    let bulk = GetBulk {
        non_repeaters: 0,
        max_repetitions: 50,
        ranges: vec![from(&format!("{SYS}.6"), "1.3.6.1.2.1.2")],
    };
    let got = view.get_bulk(&bulk);
    assert_eq!(got.len(), 3);
    assert_eq!(got[1].name, oid(&format!("{SYS}.7.0")));
    assert_eq!(
        got[2],
        VarBind::new(oid(&format!("{SYS}.7.0")), Value::EndOfMibView)
    );
}

#[test]
fn capabilities_are_bits_from_the_first_octets_top() {
    assert_eq!(
        lldp::bits(Capabilities::STATION_ONLY),
        Value::OctetString(vec![0x01])
    );
    assert_eq!(
        lldp::bits(Capabilities::STATION_ONLY | Capabilities::BRIDGE),
        Value::OctetString(vec![0x21])
    );
    assert_eq!(lldp::bits(1 << 8), Value::OctetString(vec![0x00, 0x80]));
    assert_eq!(lldp::bits(0), Value::OctetString(vec![0x00]));
}

#[test]
fn duplicate_indices_keep_the_first_row() {
    let mut s = Snapshot::example();
    let mut twin = s.lldp.ports[0].clone();
    twin.description = "the second port 1".into();
    s.lldp.ports.push(twin);
    let view = MibView::new(&s);
    assert_eq!(
        view.get(&oid(&format!("{LLDP}.3.7.1.4.1"))),
        Value::string("procimg port 1")
    );
    let mut names: Vec<&Oid> = view.instances().iter().map(|v| &v.name).collect();
    let len = names.len();
    names.dedup();
    assert_eq!(names.len(), len);
}

#[test]
fn an_empty_snapshot_serves_the_system_group_and_the_local_scalars() {
    let view = MibView::new(&Snapshot::default());
    assert_eq!(
        view.get(&oid(&format!("{SYS}.2.0"))),
        Value::ObjectIdentifier(oid("0.0"))
    );
    assert_eq!(view.instances().len(), 7 + 6);
}
