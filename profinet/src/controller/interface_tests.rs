// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller's own interface: its records, its settable name and address, its port
//! check and alarms.

use super::*;
use crate::port::dcp_station::Settable;
use crate::port::lldp::LldpStation;
use crate::port::physical::PortLink;
use crate::wire::alarm::AlarmType;
use crate::wire::dcp::{self, Block, BlockRepr, ServiceId, ServiceType, block_error};
use crate::wire::ethernet::{Frame, profinet_frame};
use crate::wire::record::{PdInterfaceDataReal, PdPortDataReal, RecordErrorCode};
use plan::ControllerIdentity;

const OWN: MacAddress = MacAddress([2, 0, 0, 0, 0, 1]);
const TOOL: MacAddress = MacAddress([2, 0, 0, 0, 0, 0x77]);
const PEER: MacAddress = MacAddress([2, 0, 0, 0, 0, 0x42]);

fn controller(setup: InterfaceSetup) -> Controller {
    let id = ControllerIdentity {
        mac: OWN,
        ip: Ipv4Addr::new(192, 168, 0, 1),
        station_name: "plc-line-1".into(),
        vendor_id: 0x0493,
        device_id: 0x0fff,
        instance: 1,
    };
    let mut c = Controller::new(id, Vec::new(), 0, 1);
    c.set_up_interface(InterfaceSetup {
        netmask: Ipv4Addr::new(255, 255, 255, 0),
        ..setup
    });
    c.answer_dcp("procimg controller");
    c.announce_by_lldp(|_| {});
    c
}

fn settable() -> InterfaceSetup {
    InterfaceSetup {
        settable: Settable::all(true),
        ..InterfaceSetup::default()
    }
}

/// The LLDP frame of a neighbour named `name` on its `port`.
fn neighbour_frame(name: &str, port: u8) -> Vec<u8> {
    LldpStation::new(name, PEER, PEER, Some([192, 168, 0, 9]), port)
        .frame()
        .unwrap()
}

fn events(out: &[ControllerAction]) -> Vec<&DeviceEvent> {
    out.iter()
        .filter_map(|a| match a {
            ControllerAction::Event(e) => Some(e),
            _ => None,
        })
        .collect()
}

fn alarms(out: &[ControllerAction]) -> Vec<&AlarmNotification> {
    events(out)
        .into_iter()
        .filter_map(|e| match e {
            DeviceEvent::InterfaceAlarm(a) => Some(&**a),
            _ => None,
        })
        .collect()
}

#[test]
fn the_interface_and_port_records_describe_the_controllers_station() {
    let mut c = controller(InterfaceSetup::default());
    c.on_frame(&neighbour_frame("io-dev-1", 2), 0, &mut Vec::new());
    let data = c.read_interface_record(INTERFACE_SUBSLOT, 0x8080).unwrap();
    let real = PdInterfaceDataReal::parse(&data).unwrap();
    assert_eq!(real.chassis_id, "plc-line-1");
    assert_eq!(
        (real.mac, real.ip, real.mask),
        (OWN, [192, 168, 0, 1], [255, 255, 255, 0])
    );

    let data = c.read_interface_record(PORT_SUBSLOT, 0x802a).unwrap();
    let port = PdPortDataReal::parse(&data).unwrap();
    assert_eq!(port.own_port_id, "port-001");
    assert_eq!(port.peers.len(), 1);
    assert_eq!(port.peers[0].chassis_id, "io-dev-1");
    assert_eq!(port.peers[0].port_id, "port-002");

    assert!(!c.read_interface_record(0, 0xf841).unwrap().is_empty());
    assert!(c.read_interface_record(PORT_SUBSLOT, 0x8072).is_ok());
    assert_eq!(
        c.read_interface_record(PORT_SUBSLOT, 0x1234),
        Err(RecordErrorCode::InvalidIndex)
    );
    assert_eq!(
        c.read_interface_record(0x8002, 0x802a),
        Err(RecordErrorCode::InvalidSlotSubslot)
    );
    // No diagnosis pending: an empty record, not an error.
    assert!(c.read_interface_record(PORT_SUBSLOT, 0x800c).is_ok());
}

#[test]
fn a_program_sets_the_name_and_address_only_where_the_configuration_lets_it() {
    let mut fixed = controller(InterfaceSetup::default());
    let change = StationAddress {
        name: Some("plc-line-2".into()),
        ip_suite: None,
        permanent: false,
    };
    assert!(matches!(
        fixed.set_station_address(&change),
        Err(AddressError::NotAllowed { .. })
    ));
    assert_eq!(fixed.station_address().0, "plc-line-1");

    let mut c = controller(settable());
    c.set_station_address(&change).unwrap();
    let suite = [
        Ipv4Addr::new(10, 0, 0, 1),
        Ipv4Addr::new(255, 0, 0, 0),
        Ipv4Addr::UNSPECIFIED,
    ];
    c.set_station_address(&StationAddress {
        name: None,
        ip_suite: Some(suite),
        permanent: true,
    })
    .unwrap();
    assert_eq!(c.station_address(), ("plc-line-2", suite));
    let real =
        PdInterfaceDataReal::parse(&c.read_interface_record(INTERFACE_SUBSLOT, 0x8080).unwrap())
            .unwrap();
    assert_eq!(
        (real.chassis_id.as_str(), real.ip),
        ("plc-line-2", [10, 0, 0, 1])
    );
    // The port announces the new name.
    let mut out = Vec::new();
    c.poll(0, &mut out);
    let lldp = out.iter().any(|a| match a {
        ControllerAction::Frame(f) => f.windows(10).any(|w| w == b"plc-line-2"),
        _ => false,
    });
    assert!(lldp, "LLDP names the station anew");

    for bad in [
        StationAddress {
            name: Some("Not A Name".into()),
            ip_suite: None,
            permanent: false,
        },
        StationAddress {
            name: Some(String::new()),
            ip_suite: None,
            permanent: false,
        },
        StationAddress {
            name: None,
            ip_suite: Some([
                Ipv4Addr::new(10, 0, 0, 1),
                Ipv4Addr::new(255, 0, 255, 0),
                suite[2],
            ]),
            permanent: false,
        },
    ] {
        assert!(c.set_station_address(&bad).is_err(), "{bad:?}");
    }
    assert_eq!(c.station_address(), ("plc-line-2", suite));
}

/// A DCP Set request from the tool.
fn dcp_set(blocks: Vec<Block>) -> Vec<u8> {
    let repr = dcp::Repr {
        frame_id: dcp::FRAME_ID_GET_SET,
        service_id: ServiceId::Set,
        service_type: ServiceType::Request,
        xid: 7,
        response_delay: 0,
        blocks,
    };
    profinet_frame(OWN, TOOL, None, &repr.to_vec().unwrap())
}

/// The BlockErrors of the Set response among `out`.
fn set_errors(out: &[ControllerAction]) -> Vec<u8> {
    out.iter()
        .filter_map(|a| match a {
            ControllerAction::Frame(f) => {
                let eth = Frame::new_checked(&f[..]).ok()?;
                let p = dcp::Packet::new_checked(eth.payload()).ok()?;
                dcp::Repr::parse(&p).ok()
            }
            _ => None,
        })
        .flat_map(|r| r.blocks)
        .filter_map(|b| match b.value {
            BlockRepr::ControlResponse { error, .. } => Some(error),
            _ => None,
        })
        .collect()
}

#[test]
fn dcp_sets_the_name_where_allowed_and_the_runtime_is_told() {
    let mut c = controller(settable());
    let mut out = Vec::new();
    c.on_frame(
        &dcp_set(vec![Block::new(
            1,
            BlockRepr::NameOfStation("plc-line-9".into()),
        )]),
        0,
        &mut out,
    );
    assert_eq!(set_errors(&out), [block_error::OK]);
    let told = events(&out).into_iter().any(|e| {
        matches!(e, DeviceEvent::StationAddress { change, reference: None, result: Ok(()) }
            if change.name.as_deref() == Some("plc-line-9") && change.permanent)
    });
    assert!(told);
    assert_eq!(c.station_address().0, "plc-line-9");
    assert_eq!(c.identity().station_name, "plc-line-9");

    // A reset to factory would leave the controller nameless: refused.
    out.clear();
    c.on_frame(
        &dcp_set(vec![Block::new(0, BlockRepr::ResetToFactory(2))]),
        0,
        &mut out,
    );
    assert_eq!(set_errors(&out), [block_error::SET_NOT_POSSIBLE]);
    assert_eq!(c.station_address().0, "plc-line-9");
}

#[test]
fn the_ports_neighbour_is_checked_and_a_mismatch_raised_and_withdrawn_by_alarm() {
    let mut c = controller(InterfaceSetup {
        peer: Some(("io-dev-1".into(), "port-002".into())),
        check_link: true,
        ..InterfaceSetup::default()
    });
    let mut out = Vec::new();
    c.poll(0, &mut out);
    // No neighbour yet: "remote mismatch, no peer detected".
    let a = alarms(&out);
    assert_eq!(a.len(), 1);
    assert_eq!(a[0].alarm_type, AlarmType::PortDataChange);
    assert_eq!((a[0].slot, a[0].subslot), (0, PORT_SUBSLOT));
    assert_eq!(a[0].submodule_ident, PORT_SUBMODULE_IDENT);
    assert!(a[0].specifier.channel_diagnosis);
    assert!(
        !c.read_interface_record(PORT_SUBSLOT, 0x800a)
            .unwrap()
            .is_empty()
    );

    // The wrong neighbour: the finding changes (one goes, one comes).
    out.clear();
    c.on_frame(&neighbour_frame("io-dev-2", 2), 0, &mut out);
    assert_eq!(alarms(&out).len(), 2);

    // The cable goes to the right one (the link drops in between, taking the old neighbour
    // with it): the link's finding comes and goes, the mismatch goes.
    let down = PortLink {
        up: false,
        ..PortLink::default()
    };
    c.set_port_link(down);
    out.clear();
    c.poll(1, &mut out);
    c.set_port_link(PortLink::default());
    c.on_frame(&neighbour_frame("io-dev-1", 2), 1, &mut out);
    let a = alarms(&out);
    assert!(a.len() >= 2);
    assert!(
        !a.last().unwrap().specifier.submodule_diagnosis,
        "nothing pending"
    );
    assert!(
        c.read_interface_record(PORT_SUBSLOT, 0x800a)
            .unwrap()
            .is_empty()
    );

    // Unchanged inputs: no alarm again.
    out.clear();
    c.poll(1, &mut out);
    assert!(alarms(&out).is_empty());

    // The link goes down: the neighbour goes with it, two findings come.
    c.set_port_link(down);
    out.clear();
    c.poll(2, &mut out);
    assert_eq!(alarms(&out).len(), 2);
}
