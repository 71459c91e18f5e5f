// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device role's configuration: `role = "device"` with its `[station]`, as a user writes
//! it, and the messages for what is wrong, each naming file, line and key.

use procimg_config::station::{DAP_SUBSLOT, INTERFACE_SUBSLOT, PORT_SUBSLOT};
use procimg_config::{Config, ConfigError, Role, parse};
use std::net::Ipv4Addr;

const MINIMAL: &str = r#"
role = "device"
[station]
name = "pc-device"
vendor_id = 0x0493
device_id = 0x0100
[[station.submodule]]
slot = 1
module_ident = 0x10
submodule_ident = 1
input_length = 4
output_length = 2
"#;

fn refused(text: &str) -> String {
    match parse(text, "device.toml") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_demo_parses_and_documents_a_device() {
    let c = Config::demo_device();
    assert_eq!(c.role, Role::Device);
    assert!(c.devices.is_empty());
    let s = c.station.as_ref().expect("the demo has a station");
    assert_eq!(s.name, "procimg-device");
    assert_eq!(s.ip, Some(Ipv4Addr::new(192, 168, 0, 50)));
    assert_eq!((s.vendor_id, s.device_id), (0x0493, 0x0100));
    assert_eq!(s.software_revision.to_string(), "V0.1.0");
    assert_eq!(
        s.submodules.len(),
        5,
        "three DAP submodules and two IO ones"
    );
    assert_eq!(s.submodules[3].accepts[0].initial, [0, 0, 0, 10]);
    assert_eq!(c.submodule_count(), 5);
}

#[test]
fn a_minimal_station_gets_its_access_point_and_addresses() {
    let c = parse(MINIMAL, "device.toml").unwrap();
    let s = c.station.unwrap();
    let places: Vec<(u16, u16)> = s.submodule_configs().map(|m| (m.slot, m.subslot)).collect();
    assert_eq!(
        places,
        [
            (0, DAP_SUBSLOT),
            (0, INTERFACE_SUBSLOT),
            (0, PORT_SUBSLOT),
            (1, 1)
        ]
    );
    assert!(s.submodules[0].im && !s.submodules[3].im);
    let io = &s.submodules[3].submodule;
    assert_eq!((io.input_address, io.output_address), (0, 0));
    // The DAP's submodules have diagnostic addresses after the inputs.
    assert_eq!(s.submodules[0].submodule.diagnostic_address(), Some(4));
    assert_eq!(s.ip, None);
    assert_eq!(s.netmask, Ipv4Addr::UNSPECIFIED);
    assert_eq!(s.device_type, "procimg");
    assert_eq!(s.state_file, None);
}

#[test]
fn the_roles_do_not_mix() {
    let m = refused("role = \"device\"\n[[device]]\nname = \"x\"\n");
    assert!(
        m.contains("device.toml:2") && m.contains("[[station.submodule]]"),
        "{m}"
    );
    let m = refused("[station]\nname = \"x\"\nvendor_id = 1\ndevice_id = 1\n");
    assert!(
        m.contains("role = \\\"device\\\"") || m.contains("role = \"device\""),
        "{m}"
    );
    let m = refused("role = \"device\"\n");
    assert!(m.contains("[station]"), "{m}");
    let m = refused("role = \"plc\"\n");
    assert!(
        m.contains("device.toml:1") && m.contains("\"controller\""),
        "{m}"
    );
}

#[test]
fn station_errors_name_line_and_key() {
    let cases: &[(&str, &str, &str)] = &[
        (
            "name = \"pc-device\"",
            "name = \"PC_Device\"",
            "station.name",
        ),
        (
            "device_id = 0x0100",
            "device_id = 0x0100\nip = \"1.2.3\"",
            "station.ip",
        ),
        (
            "device_id = 0x0100",
            "device_id = 0x0100\nsoftware_revision = \"1.0\"",
            "station.software_revision",
        ),
        (
            "device_id = 0x0100",
            "device_id = 0x0100\norder_number = \"123456789012345678901\"",
            "station.order_number",
        ),
        (
            "device_id = 0x0100",
            "device_id = 0x0100\nip = \"10.0.0.2\"\ngateway = \"10.0.1.1\"",
            "station.gateway",
        ),
        ("slot = 1", "slot = 0", "station.submodule[0].slot"),
        (
            "input_length = 4",
            "input_length = 4\nsubslot = 0x8000",
            "station.submodule[0].subslot",
        ),
        (
            "input_length = 4",
            "input_length = 4\nrecords = [{ index = 0x8000, length = 2 }]",
            "station.submodule[0].records[0].index",
        ),
        (
            "input_length = 4",
            "input_length = 4\nrecords = [{ index = 1, length = 2, data = [1] }]",
            "station.submodule[0].records[0].data",
        ),
        (
            "input_length = 4",
            "input_length = 1440",
            "station.submodule[0].input_length",
        ),
    ];
    for (from, to, key) in cases {
        let text = MINIMAL.replacen(from, to, 1);
        let m = refused(&text);
        assert!(m.contains(key), "{key}: {m}");
        assert!(m.contains("device.toml:"), "{key}: {m}");
    }
}

#[test]
fn a_slot_holds_one_module_and_a_frame_bounds_the_data() {
    let two = format!(
        "{MINIMAL}[[station.submodule]]\nslot = 1\nsubslot = 2\nmodule_ident = 0x11\n\
         submodule_ident = 2\n"
    );
    let m = refused(&two);
    assert!(
        m.contains("station.submodule[1].module_ident") && m.contains("line 9"),
        "{m}"
    );
    let mut big = String::from(MINIMAL);
    for slot in 2..=5 {
        big.push_str(&format!(
            "[[station.submodule]]\nslot = {slot}\nmodule_ident = 0x10\nsubmodule_ident = 1\n\
             input_length = 400\n"
        ));
    }
    let m = refused(&big);
    assert!(m.contains("1440") && m.contains("station.submodule"), "{m}");
}

#[test]
fn errors_are_config_errors() {
    let e = parse("role = \"device\"\n[station]\nvendor_id = 1\n", "d.toml").unwrap_err();
    assert!(matches!(e, ConfigError::Syntax { .. }), "{e:?}");
    // A missing identity is checked after parsing (a GSDML file may give it).
    let e = parse("role = \"device\"\n[station]\nname = \"a\"\n", "d.toml").unwrap_err();
    assert!(matches!(e, ConfigError::Invalid { line: 2, .. }), "{e:?}");
}

/// The sample device's GSDML file of the tests (tests/fixtures/gsdml/README.md).
fn sample_gsdml() -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/gsdml/sample-16real-32bool.xml")
        .display()
        .to_string()
}

#[test]
fn a_station_its_program_defines_takes_identity_and_access_point_from_its_gsdml() {
    let text = format!(
        "role = \"device\"\n[station]\nname = \"pc-device\"\ngsdml = \"{}\"\n",
        sample_gsdml()
    );
    let c = parse(&text, "device.toml").unwrap();
    let s = c.station.unwrap();
    let program = s.program.as_ref().expect("defined by its program");
    assert_eq!(program.dap, "DAP1");
    // The file's VendorID and DeviceID, its DAP's ident numbers; slot 0 only.
    let gsdml = procimg_config::gsdml::Gsdml::load(std::path::Path::new(&sample_gsdml())).unwrap();
    assert_eq!(
        (s.vendor_id, s.device_id),
        (gsdml.vendor_id, gsdml.device_id)
    );
    assert_eq!(s.dap.module_ident, gsdml.daps[0].module_ident);
    assert_eq!(s.submodules.len(), 3);
    assert!(s.submodules.iter().all(|m| m.submodule.slot == 0));
}

#[test]
fn a_gsdml_station_has_no_configured_tree_and_its_dap_must_exist() {
    let base = format!(
        "role = \"device\"\n[station]\nname = \"pc-device\"\ngsdml = \"{}\"\n",
        sample_gsdml()
    );
    let m = refused(&format!(
        "{base}[[station.submodule]]\nslot = 1\nmodule_ident = 1\nsubmodule_ident = 1\n"
    ));
    assert!(
        m.contains("station.submodule[0]") && m.contains("program defines its submodules"),
        "{m}"
    );
    let m = refused(&base.replace(
        "name = \"pc-device\"\n",
        "name = \"pc-device\"\ngsdml_dap = \"DAP9\"\n",
    ));
    assert!(
        m.contains("no device access point \"DAP9\"") && m.contains("DAP1"),
        "{m}"
    );
    let m = refused(&format!("{base}[station.dap]\nmodule_ident = 1\n"));
    assert!(m.contains("remove [station.dap]"), "{m}");
    // Without a GSDML file the identity is the configuration's to give.
    let m = refused("role = \"device\"\n[station]\nname = \"pc-device\"\ndevice_id = 1\n");
    assert!(m.contains("vendor_id") && m.contains("gsdml"), "{m}");
}
