// SPDX-License-Identifier: MIT OR Apache-2.0
//! The port as the PLC parameterizes and checks it: PDPortDataAdjust's boundaries, the
//! topology check of PDPortDataCheck against the LLDP neighbour.

use super::*;
use crate::port::lldp::{Announcer, LldpStation};
use crate::wire::record::{
    CheckedPeer, INDEX_PD_PORT_DATA_ADJUST, INDEX_PD_PORT_DATA_CHECK, PEER_TO_PEER_NO_LLDP,
    PdPortDataAdjust, PdPortDataCheck, PortAdjust, PortCheck,
};
use crate::wire::rta_pdu::{self, RtaPdu};

/// The p-net sample device with an address, the captured S7's AR connected.
fn connected() -> Device<TestApp> {
    let mut dev = Device::new(DeviceSetup {
        ip: Some(DEVICE_IP),
        ..pnet_spec(TestApp::None)
    });
    assert_eq!(
        status(&call(&mut dev, &rpc_pdu("cm/connect_req"), MS)),
        PnioStatus::OK
    );
    dev
}

/// Writes `data` to record `index` of the port (slot 0, subslot 0x8001) in the AR.
fn write_port(dev: &mut Device<TestApp>, index: u16, data: &[u8], now: u64) -> PnioStatus {
    let ar = dev.ar().ar_uuid().unwrap();
    let h = IodHeader::write_request(7, ar, 0, 0, 0x8001, index, data.len() as u32);
    let mut blocks = h.to_bytes().to_vec();
    blocks.extend_from_slice(data);
    let mut activity = ACTIVITY;
    activity.0[0] ^= index as u8;
    status(&call(
        dev,
        &request(opnum::WRITE, activity, 3, &blocks, false),
        now,
    ))
}

/// An S7's port announcing itself as `port` of station `name`.
fn neighbour(name: &str, port: u8, now: u64) -> Vec<u8> {
    let mut a = Announcer::new(LldpStation::new(name, S7_MAC, S7_MAC, None, port));
    a.poll(now).expect("an announcement")
}

#[test]
fn a_peer_to_peer_boundary_keeps_the_ports_lldp_in() {
    let mut dev = connected();
    let adjust = PdPortDataAdjust {
        slot: 0,
        subslot: 0x8001,
        adjusts: vec![PortAdjust::PeerToPeerBoundary {
            boundary: PEER_TO_PEER_NO_LLDP,
            properties: 0,
        }],
    };
    let w = write_port(
        &mut dev,
        INDEX_PD_PORT_DATA_ADJUST,
        &adjust.to_vec().unwrap(),
        MS,
    );
    assert_eq!(w, PnioStatus::OK);
    assert!(dev.station().lldp_boundary());
    // Twenty seconds: no announcement goes out; the neighbour's still come in.
    let sent = run_until(&mut dev, 20_000 * MS);
    let out: Vec<DeviceAction> = sent.into_iter().map(|(_, a)| a).collect();
    assert!(lldp_announcement(&out).is_none());
    let mut out = Vec::new();
    dev.on_frame(&neighbour("plc", 1, 20_000 * MS), 20_000 * MS, &mut out);
    assert_eq!(dev.station().neighbours().entries().len(), 1);
}

#[test]
fn the_check_is_read_back_in_pd_expected_data() {
    use crate::wire::record::{INDEX_PD_EXPECTED_DATA, MultipleBlockHeader};
    let mut dev = connected();
    let check = check_plc_port_1();
    let w = write_port(&mut dev, INDEX_PD_PORT_DATA_CHECK, &check, MS);
    assert_eq!(w, PnioStatus::OK);
    let ar = dev.ar().ar_uuid().unwrap();
    let h = IodHeader::read_request(8, ar, 0, 0, 0, INDEX_PD_EXPECTED_DATA, 4096);
    let mut activity = ACTIVITY;
    activity.0[2] ^= 0x33;
    let r = call(
        &mut dev,
        &request(opnum::READ, activity, 4, &h.to_bytes(), false),
        2 * MS,
    );
    assert_eq!(status(&r), PnioStatus::OK);
    let (_, data, _) = IodHeader::split(&r.blocks).unwrap();
    let m = MultipleBlockHeader::parse(data).unwrap();
    assert_eq!((m.slot, m.subslot), (0, 0x8001));
    assert_eq!(
        PdPortDataCheck::parse(&m.blocks).unwrap(),
        PdPortDataCheck::parse(&check).unwrap()
    );
}

/// The S7 expects `port-001` of station `plc` on the device's port.
fn check_plc_port_1() -> Vec<u8> {
    PdPortDataCheck {
        slot: 0,
        subslot: 0x8001,
        checks: vec![PortCheck::Peers(vec![CheckedPeer {
            port_id: "port-001".into(),
            chassis_id: "plc".into(),
        }])],
    }
    .to_vec()
    .unwrap()
}

/// The PortDataChangeNotification alarms among `out` and those that follow as the S7
/// acknowledges each (the device sends one low-priority alarm at a time): whether the port
/// has a diagnosis after each.
fn port_alarms(dev: &mut Device<TestApp>, out: &[DeviceAction], t: u64) -> Vec<bool> {
    let mut seen = Vec::new();
    let mut out = out.to_vec();
    loop {
        let next = frames(&out).iter().find_map(|f| {
            let pdu = RtaPdu::parse(&rta_pdu::Packet::new_checked(f.get(18..)?).ok()?).ok()?;
            let n = pdu.notification()?.clone();
            Some((pdu.header, n))
        });
        let Some((header, n)) = next else {
            return seen;
        };
        assert_eq!(n.alarm_type, crate::wire::alarm::AlarmType::PortDataChange);
        assert_eq!((n.slot, n.subslot), (0, 0x8001));
        seen.push(n.specifier.submodule_diagnosis);
        out = super::diagnosis::ack_rta(dev, &header, Priority::Low, t);
    }
}

/// `name`'s port `port` withdrawing itself (TTL 0).
fn withdrawal(name: &str, port: u8) -> Vec<u8> {
    let mut r = LldpStation::new(name, S7_MAC, S7_MAC, None, port).repr();
    r.ttl = 0;
    r.frame(S7_MAC).unwrap()
}

#[test]
fn the_topology_check_follows_the_neighbour() {
    use crate::device::physical::PortLink;
    use crate::device::topology::{REMOTE_MISMATCH, mismatch};
    let (mut dev, mut t) = pnet_in_data(TestApp::None);
    let at = SubslotAddr::new(0, 0, 0x8001);
    let mut out = Vec::new();
    let mut frame = |dev: &mut Device<TestApp>, f: &[u8], t: u64| {
        out.clear();
        dev.on_frame(f, t, &mut out);
        let alarms = port_alarms(dev, &out, t);
        (dev.topology().mismatches().to_vec(), alarms)
    };

    // Written while nothing answers on the port: no peer, a fault on the port.
    let check = check_plc_port_1();
    let ar = dev.ar().ar_uuid().unwrap();
    let h = IodHeader::write_request(
        9,
        ar,
        0,
        0,
        0x8001,
        INDEX_PD_PORT_DATA_CHECK,
        check.len() as u32,
    );
    let mut blocks = h.to_bytes().to_vec();
    blocks.extend_from_slice(&check);
    let mut activity = ACTIVITY;
    activity.0[1] ^= 0x5a;
    let mut o = Vec::new();
    dev.on_datagram(
        S7_CLIENT,
        crate::wire::rpc::RPC_PORT,
        &request(opnum::WRITE, activity, 3, &blocks, false),
        t,
        &mut o,
    );
    assert_eq!(
        dev.topology().mismatches(),
        &[(at, (REMOTE_MISMATCH, mismatch::NO_PEER))]
    );
    assert_eq!(port_alarms(&mut dev, &o, t), [true]);
    assert!(dev.diagnosis().has_fault_at(at));

    // The expected neighbour: the diagnosis goes.
    t += MS;
    assert_eq!(
        frame(&mut dev, &neighbour("plc", 1, t), t),
        (vec![], vec![false])
    );
    assert!(!dev.diagnosis().has_fault_at(at));
    // Its port 1 goes and its port 2 answers: the wrong port.
    assert_eq!(
        frame(&mut dev, &neighbour("plc", 2, t), t),
        (vec![], vec![])
    );
    assert_eq!(
        frame(&mut dev, &withdrawal("plc", 1), t),
        (
            vec![(at, (REMOTE_MISMATCH, mismatch::PEER_PORT))],
            vec![true]
        )
    );
    // The link drops: no peer (at the next poll); one mismatch goes, the other comes.
    dev.set_port_link(PortLink {
        up: false,
        ..PortLink::default()
    });
    assert_eq!(dev.next_deadline_ns(), Some(0));
    o.clear();
    dev.poll(t, &mut o);
    assert_eq!(
        dev.topology().mismatches(),
        &[(at, (REMOTE_MISMATCH, mismatch::NO_PEER))]
    );
    assert_eq!(port_alarms(&mut dev, &o, t), [false, true]);
    // Another station: the wrong name.
    dev.set_port_link(PortLink::default());
    assert_eq!(
        frame(&mut dev, &neighbour("other", 1, t), t),
        (
            vec![(at, (REMOTE_MISMATCH, mismatch::PEER_NAME))],
            vec![false, true]
        )
    );
    // The diagnosis record says so: ChannelErrorType 0x8001 with its extended type.
    let pending = dev
        .diagnosis()
        .iter()
        .find(|(a, _)| *a == at)
        .map(|(_, e)| e.to_vec());
    let entries = pending.expect("the port's diagnosis");
    assert_eq!(entries.len(), 1);
    match &entries[0] {
        DiagEntry::Channel(c) => assert_eq!(
            (c.channel_number, c.error_type, c.ext_error_type),
            (0x8000, 0x8001, mismatch::PEER_NAME)
        ),
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_ports_own_link_is_checked_against_mau_type_and_link_state() {
    use crate::device::physical::PortLink;
    use crate::device::topology::{TRANSMISSION_IMPOSSIBLE, topology_findings, transmission};
    use crate::port::neighbours::Neighbours;
    let check = PdPortDataCheck {
        slot: 0,
        subslot: 0x8001,
        checks: vec![PortCheck::MauType(16), PortCheck::LinkState(1)],
    };
    let none = Neighbours::default();
    let link = |up, mau_type| PortLink {
        up,
        mau_type,
        ..PortLink::default()
    };
    assert!(topology_findings(&check, &none, &link(true, 16)).is_empty());
    assert_eq!(
        topology_findings(&check, &none, &link(true, 30)),
        [(TRANSMISSION_IMPOSSIBLE, transmission::MAU_TYPE)]
    );
    assert_eq!(
        topology_findings(&check, &none, &link(false, 0)),
        [(TRANSMISSION_IMPOSSIBLE, transmission::LINK_DOWN)]
    );
}

#[test]
fn dcp_identify_by_alias_answers_once_the_neighbour_names_the_port() {
    use crate::wire::dcp::{self as wire_dcp, BlockRepr};
    let mut dev = Device::new(pnet_spec(TestApp::None));
    let mut by_alias = wire_dcp::Repr::identify_by_name(7, 1, "unused");
    by_alias.blocks[0].value = BlockRepr::AliasName("port-001.plc".into());
    let identify = crate::dcp_client::frame(MacAddress::DCP_IDENTIFY, S7_MAC, &by_alias).unwrap();
    let answers = |dev: &mut Device<TestApp>, t: u64| {
        let mut out = Vec::new();
        dev.on_frame(&identify, t, &mut out);
        let until = dev.next_deadline_ns().unwrap_or(t).max(t) + 1_000 * MS;
        dev.poll(until, &mut out);
        frames(&out)
            .iter()
            .filter(|f| f.get(12..14) == Some(&[0x88, 0x92][..]))
            .count()
    };
    // No neighbour: no alias, no answer.
    assert_eq!(answers(&mut dev, 0), 0);
    // The S7's port 1 as neighbour: the alias is "port-001.plc", and the Identify by it
    // is answered.
    let mut out = Vec::new();
    dev.on_frame(&neighbour("plc", 1, MS), MS, &mut out);
    assert_eq!(dev.station().alias_name(), Some("port-001.plc"));
    assert_eq!(answers(&mut dev, 2 * MS), 1);
}

#[test]
fn a_malformed_check_or_adjust_is_refused_as_an_invalid_parameter() {
    let mut dev = connected();
    let mut check = check_plc_port_1();
    // A CheckPeers whose BlockLength runs past the record.
    check[15] = 0xff;
    let refused = crate::wire::record::RecordError::write(
        crate::wire::record::RecordErrorCode::InvalidParameter,
        0,
    )
    .status();
    assert_eq!(
        write_port(&mut dev, INDEX_PD_PORT_DATA_CHECK, &check, MS),
        refused
    );
    assert_eq!(
        write_port(&mut dev, INDEX_PD_PORT_DATA_ADJUST, &[0x02, 0x02, 0x00], MS),
        refused
    );
    assert!(dev.topology().mismatches().is_empty());
}
