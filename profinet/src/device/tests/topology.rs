// SPDX-License-Identifier: MIT OR Apache-2.0
//! The port as the PLC parameterizes and checks it: PDPortDataAdjust's boundaries, the
//! topology check of PDPortDataCheck against the LLDP neighbour.

use super::*;
use crate::port::lldp::{Announcer, LldpStation};
use crate::wire::record::{
    CheckedPeer, INDEX_PD_PORT_DATA_ADJUST, INDEX_PD_PORT_DATA_CHECK, PEER_TO_PEER_NO_LLDP,
    PdPortDataAdjust, PdPortDataCheck, PortAdjust, PortCheck,
};

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
fn the_check_is_kept_as_written_and_read_back_in_pd_expected_data() {
    let mut dev = connected();
    let check = PdPortDataCheck {
        slot: 0,
        subslot: 0x8001,
        checks: vec![PortCheck::Peers(vec![CheckedPeer {
            port_id: "port-001".into(),
            chassis_id: "plc".into(),
        }])],
    };
    let w = write_port(
        &mut dev,
        INDEX_PD_PORT_DATA_CHECK,
        &check.to_vec().unwrap(),
        MS,
    );
    assert_eq!(w, PnioStatus::OK);
}
