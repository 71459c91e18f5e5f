// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller's own interface through the real procimgd, on the simulated network, as
//! the Rust client sees it (what IO-Base's `PNIO_interface_*` stand on): its records, its
//! diagnostic addresses, and its station's name, which a program may change only where
//! `[interface]` lets it, and never to an invalid one.

use procimg_client::{
    AddressChangeError, ControllerAddress, RecordError, ServiceOptions, Services,
};
use procimg_config::DEMO_TOML;
use procimg_profinet::wire::record::{PdInterfaceDataReal, PdPortDataReal};
use procimg_testkit::Launch;
use std::net::Ipv4Addr;
use std::time::Duration;

const WAIT: Duration = Duration::from_secs(10);

fn rename(name: &str) -> ControllerAddress {
    ControllerAddress {
        name: Some(name.into()),
        ..ControllerAddress::default()
    }
}

#[test]
fn the_interfaces_records_and_a_name_set_by_a_program() {
    let config = format!(
        "{DEMO_TOML}\n[interface]\nstation_name = \"plc-sim\"\nname_by_program = true\n\
         diagnostic_address = 8190\nport_diagnostic_address = 8189\n"
    );
    let server = Launch::config("ifs", &config).until_cycling().start();
    let own = server
        .status()
        .controller
        .expect("the controller's station");
    assert_eq!(
        (
            own.station_name.as_str(),
            own.interface_address,
            own.port_address
        ),
        ("plc-sim", 8190, 8189)
    );
    assert!(own.name_by_program && !own.address_by_program);
    let mut services =
        Services::open(&server.instance, ServiceOptions::new("ifs")).expect("services");

    let data = services
        .read_interface_record(0x8000, 0x8080, 4096, WAIT)
        .expect("PDInterfaceDataReal");
    let real = PdInterfaceDataReal::parse(&data).expect("a PDInterfaceDataReal block");
    assert_eq!(
        (real.chassis_id.as_str(), real.ip),
        ("plc-sim", [192, 168, 0, 1])
    );
    let port = PdPortDataReal::parse(
        &services
            .read_interface_record(0x8001, 0x802a, 4096, WAIT)
            .expect("PDPortDataReal"),
    )
    .expect("a PDPortDataReal block");
    assert_eq!(port.own_port_id, "port-001");
    // Cut to the length asked for, with AdditionalValue1 saying there is more.
    let cut = services
        .read_interface_record(0x8000, 0x8080, 8, WAIT)
        .expect("8 bytes");
    assert_eq!(cut, data[..8]);
    match services.read_interface_record(0x8001, 0x1234, 4096, WAIT) {
        Err(RecordError::Failed { status, .. }) => {
            assert_eq!(
                (status.error_code, status.error_decode, status.error_code1),
                (0xde, 0x80, 0xb0)
            )
        }
        other => panic!("an unknown index: {other:?}"),
    }

    // The name may change; the address is the configuration's.
    services
        .change_controller_address(&rename("plc-sim-2"), WAIT)
        .expect("rename");
    assert_eq!(
        server.status().controller.unwrap().station_name,
        "plc-sim-2"
    );
    let real = PdInterfaceDataReal::parse(
        &services
            .read_interface_record(0, 0x8080, 4096, WAIT)
            .expect("PDInterfaceDataReal at subslot 0"),
    )
    .unwrap();
    assert_eq!(real.chassis_id, "plc-sim-2");
    let readdress = ControllerAddress {
        ip_suite: Some([
            Ipv4Addr::new(192, 168, 0, 2),
            Ipv4Addr::new(255, 255, 255, 0),
            Ipv4Addr::UNSPECIFIED,
        ]),
        ..ControllerAddress::default()
    };
    match services.change_controller_address(&readdress, WAIT) {
        Err(AddressChangeError::Refused(why)) => {
            assert!(why.contains("address_by_program"), "{why}")
        }
        other => panic!("a fixed address changed: {other:?}"),
    }
    for bad in ["Not A Name", "port-001", ""] {
        match services.change_controller_address(&rename(bad), WAIT) {
            Err(AddressChangeError::Refused(_)) => {}
            other => panic!("{bad:?}: {other:?}"),
        }
    }
    let now = server.status().controller.unwrap();
    assert_eq!(
        (now.station_name.as_str(), now.ip.as_str()),
        ("plc-sim-2", "192.168.0.1")
    );
}

#[test]
fn without_the_configurations_leave_the_name_stays() {
    let server = Launch::demo("ifn").until_cycling().start();
    let mut services =
        Services::open(&server.instance, ServiceOptions::new("ifn")).expect("services");
    let before = server.status().controller.unwrap().station_name;
    match services.change_controller_address(&rename("plc-other"), WAIT) {
        Err(AddressChangeError::Refused(why)) => {
            assert!(why.contains("name_by_program"), "{why}")
        }
        other => panic!("the configuration's name changed: {other:?}"),
    }
    assert_eq!(server.status().controller.unwrap().station_name, before);
}
