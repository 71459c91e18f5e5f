// SPDX-License-Identifier: MIT OR Apache-2.0

use super::*;
use crate::wire::lldp::{ManagementAddress, Repr};

const PLC_MAC: MacAddress = MacAddress([0x28, 0x63, 0x36, 0x8a, 0x1b, 0x01]);
const S: u64 = 1_000_000_000;

/// What an S7's port announces in naming mode 1: Port ID `port-001.plc`, Chassis ID its
/// system identification.
fn s7(ttl: u16, port: &str) -> Vec<u8> {
    Repr {
        chassis_id: Id::Local("SIMATIC S7-1500 6ES7 515-2AM02-0AB0 S C-X4U 2 V3.0.2".into()),
        port_id: Id::Local(format!("{port}.plc")),
        ttl,
        tlvs: vec![
            TlvRepr::ProfinetPortStatus {
                rtclass2: 0,
                rtclass3: 0,
            },
            TlvRepr::ProfinetChassisMac(PLC_MAC),
            TlvRepr::MacPhy(MacPhyStatus::FAST_ETHERNET),
            TlvRepr::ManagementAddress(ManagementAddress::ipv4([192, 168, 0, 1], 1)),
        ],
    }
    .to_vec()
    .unwrap()
}

#[test]
fn a_neighbour_comes_is_refreshed_changes_and_ages_out() {
    let mut n = Neighbours::default();
    assert_eq!(
        n.on_lldpdu(PLC_MAC, &s7(20, "port-001"), 0),
        Some(NeighbourChange::Added(1))
    );
    let e = &n.entries()[0];
    assert_eq!(e.peer_station(), Some("plc"));
    assert_eq!(e.peer_port(), Some("port-001"));
    assert_eq!(e.mac(), PLC_MAC);
    assert_eq!(e.management_ipv4(), Some([192, 168, 0, 1]));
    assert_eq!(e.mac_phy(), Some(MacPhyStatus::FAST_ETHERNET));
    assert_eq!(n.alias_name().as_deref(), Some("port-001.plc"));
    // The same again 5 s later: refreshed, no change.
    assert_eq!(n.on_lldpdu(PLC_MAC, &s7(20, "port-001"), 5 * S), None);
    assert_eq!(n.next_deadline_ns(), Some(25 * S));
    assert!(n.age(24 * S).is_empty());
    // Another port of the same PLC: another neighbour (the LLDP-MIB's key is chassis and
    // port), and no alias while there are two.
    assert_eq!(
        n.on_lldpdu(PLC_MAC, &s7(20, "port-002"), 6 * S),
        Some(NeighbourChange::Added(2))
    );
    assert_eq!(n.alias_name(), None);
    assert_eq!(n.age(25 * S), vec![1]);
    assert_eq!(n.age(26 * S), vec![2]);
    assert!(n.entries().is_empty());
    assert_eq!(n.stats.ageouts, 2);
    assert_eq!(n.stats.inserts, 2);
}

#[test]
fn ttl_zero_withdraws_and_a_changed_tlv_is_a_change() {
    let mut n = Neighbours::default();
    n.on_lldpdu(PLC_MAC, &s7(20, "port-001"), 0);
    let mut other =
        lldp::Repr::parse(&Packet::new_checked(&s7(20, "port-001")[..]).unwrap()).unwrap();
    other.tlvs.pop();
    assert_eq!(
        n.on_lldpdu(PLC_MAC, &other.to_vec().unwrap(), S),
        Some(NeighbourChange::Changed(1))
    );
    assert_eq!(n.entries()[0].management_ipv4(), None);
    assert_eq!(
        n.on_lldpdu(PLC_MAC, &s7(0, "port-001"), 2 * S),
        Some(NeighbourChange::Removed(1))
    );
    assert!(n.entries().is_empty());
    // A withdrawal of someone unknown changes nothing.
    assert_eq!(n.on_lldpdu(PLC_MAC, &s7(0, "port-001"), 3 * S), None);
}

#[test]
fn mode_zero_names_and_mac_identifiers() {
    let mut n = Neighbours::default();
    let pdu = Repr {
        chassis_id: Id::Local("ctl".into()),
        port_id: Id::Local("port-001".into()),
        ttl: 20,
        tlvs: vec![],
    };
    n.on_lldpdu(PLC_MAC, &pdu.to_vec().unwrap(), 0);
    assert_eq!(n.alias_name().as_deref(), Some("port-001.ctl"));
    assert_eq!(n.entries()[0].peer_chassis_id(), "ctl");
    // A switch that names itself by MAC.
    let mut n = Neighbours::default();
    let pdu = Repr {
        chassis_id: Id::MacAddress(PLC_MAC),
        port_id: Id::MacAddress(PLC_MAC),
        ttl: 120,
        tlvs: vec![],
    };
    n.on_lldpdu(PLC_MAC, &pdu.to_vec().unwrap(), 0);
    let e = &n.entries()[0];
    assert_eq!(e.peer_station(), None);
    assert_eq!(e.peer_chassis_id(), PLC_MAC.to_string());
    assert_eq!(n.alias_name(), None);
}

#[test]
fn a_full_table_makes_room_and_garbage_is_counted() {
    let mut n = Neighbours::default();
    for i in 0..MAX_NEIGHBOURS + 2 {
        n.on_lldpdu(PLC_MAC, &s7(20, &format!("port-{i:03}")), i as u64 * S);
    }
    assert_eq!(n.entries().len(), MAX_NEIGHBOURS);
    assert_eq!(n.stats.drops, 2);
    assert_eq!(n.entries()[0].peer_port(), Some("port-002"));
    assert_eq!(n.on_lldpdu(PLC_MAC, &[0xff; 7], 0), None);
    assert_eq!(n.stats.frames_discarded, 1);
}

proptest::proptest! {
    #[test]
    fn any_bytes_leave_the_table_sound(frames in proptest::collection::vec(
        proptest::collection::vec(proptest::prelude::any::<u8>(), 0..80), 0..20)) {
        let mut n = Neighbours::default();
        for (i, f) in frames.iter().enumerate() {
            n.on_lldpdu(PLC_MAC, f, i as u64 * S);
            proptest::prop_assert!(n.entries().len() <= MAX_NEIGHBOURS);
        }
        let _ = n.age(u64::MAX);
        proptest::prop_assert!(n.entries().is_empty());
    }
}
