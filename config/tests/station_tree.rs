// SPDX-License-Identifier: MIT OR Apache-2.0
//! A station its program defines: the program's tree (places and ident numbers) with the
//! station's GSDML makes the station a `[[station.submodule]]` list would (lengths,
//! parameter records, logical addresses), and a tree the GSDML does not allow is refused
//! with a message naming what the program gave and the file.

use procimg_config::gsdml::Gsdml;
use procimg_config::gsdml::export::{GsdmlDate, station_gsdml};
use procimg_config::{
    Config, DEMO_DEVICE_ORIGIN, DEMO_DEVICE_TOML, PlannedSubmodule, StationConfig, TreeError,
    define_station, parse,
};

/// The demo station and its GSDML file, as `procimg gsdml` writes it.
fn demo() -> (Config, Gsdml) {
    let config = parse(DEMO_DEVICE_TOML, DEMO_DEVICE_ORIGIN).unwrap();
    let file = station_gsdml(
        config.station.as_ref().unwrap(),
        config.cycle_ns,
        GsdmlDate::new(2026, 11, 28).unwrap(),
    )
    .unwrap();
    let gsdml = Gsdml::parse(&file.xml, &file.file_name).unwrap();
    (config, gsdml)
}

fn define(tree: &[PlannedSubmodule]) -> Result<StationConfig, TreeError> {
    let (config, gsdml) = demo();
    let station = config.station.unwrap();
    define_station(&station, &gsdml, &gsdml.daps[0], tree)
}

#[test]
fn the_configured_tree_makes_the_configured_station() {
    let (config, gsdml) = demo();
    let station = config.station.unwrap();
    let defined = define_station(&station, &gsdml, &gsdml.daps[0], &station.tree()).unwrap();
    // Lengths, addresses and parameter records as the configuration has them.
    let plain = |s: &StationConfig| -> Vec<_> {
        s.submodules
            .iter()
            .map(|s| (s.submodule.clone(), s.accepts.clone(), s.plugged))
            .collect()
    };
    assert_eq!(plain(&defined), plain(&station));
    assert_eq!(defined.dap, station.dap);
    assert_eq!(defined.name, station.name);
}

#[test]
fn a_partial_tree_gets_its_lengths_from_the_gsdml_and_addresses_from_zero() {
    let (config, _) = demo();
    let full = config.station.as_ref().unwrap().tree();
    // Only the last submodule of the demo, in its slot.
    let last = *full.last().unwrap();
    let defined = define(&[last]).unwrap();
    let configured = config
        .station
        .as_ref()
        .unwrap()
        .submodule_configs()
        .find(|s| (s.slot, s.subslot) == (last.slot, last.subslot))
        .unwrap()
        .clone();
    let s = &defined.submodules.last().unwrap().submodule;
    assert_eq!(
        (s.input_length, s.output_length),
        (configured.input_length, configured.output_length)
    );
    let first_address = |a: u32, len: u16| if len > 0 { a } else { 0 };
    assert_eq!(first_address(s.input_address, s.input_length), 0);
    assert_eq!(first_address(s.output_address, s.output_length), 0);
    assert_eq!(
        defined.submodules.len(),
        4,
        "the DAP's three and the one plugged"
    );
}

#[test]
fn what_the_gsdml_does_not_allow_is_refused_naming_it() {
    let (config, _) = demo();
    let full = config.station.as_ref().unwrap().tree();
    let first = full[0];
    let message = |tree: &[PlannedSubmodule]| define(tree).unwrap_err().to_string();

    let unknown = PlannedSubmodule {
        module_ident: 0x4242,
        ..first
    };
    let m = message(&[unknown]);
    assert!(
        m.contains("module ident 0x00004242") && m.contains("GSDML-V2.4-procimg-"),
        "{m}"
    );

    let wrong_sub = PlannedSubmodule {
        submodule_ident: 0x4242,
        ..first
    };
    let m = message(&[wrong_sub]);
    assert!(m.contains("no submodule with ident 0x00004242"), "{m}");

    let far = PlannedSubmodule {
        slot: 0x7000,
        ..first
    };
    let m = message(&[far]);
    assert!(
        m.contains("slot 28672") && m.contains("allows slots"),
        "{m}"
    );

    let m = message(&[first, first]);
    assert!(m.contains("plugged twice"), "{m}");

    let m = message(&[PlannedSubmodule { slot: 0, ..first }]);
    assert!(m.contains("slot 0 is the device access point"), "{m}");

    if let Some(other) = full.iter().find(|p| p.module_ident != first.module_ident) {
        let second = PlannedSubmodule {
            subslot: first.subslot + 1,
            ..*other
        };
        let second = PlannedSubmodule {
            slot: first.slot,
            ..second
        };
        let m = message(&[first, second]);
        assert!(m.contains("holds one module"), "{m}");
    }
}

#[test]
fn a_vendors_gsdml_gives_lengths_and_places() {
    // A sample device's file (tests/fixtures/gsdml/README.md): M1 16 × Float32 in, slot 1
    // only; M3 16 × Float32 out, slot 3 only; the DAP's PhysicalSlots 0..4.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/gsdml/sample-16real-32bool.xml");
    let gsdml = Gsdml::load(&path).unwrap();
    let dap = gsdml.dap("DAP1").unwrap();
    let (config, _) = demo();
    let station = config.station.unwrap();
    let at = |slot, module_ident| PlannedSubmodule {
        api: 0,
        slot,
        subslot: 1,
        module_ident,
        submodule_ident: 1,
    };
    let defined = define_station(&station, &gsdml, dap, &[at(1, 0x101), at(3, 0x103)]).unwrap();
    let lengths: Vec<(u16, u16, u16)> = defined
        .submodule_configs()
        .filter(|s| s.slot > 0)
        .map(|s| (s.slot, s.input_length, s.output_length))
        .collect();
    assert_eq!(lengths, [(1, 64, 0), (3, 0, 64)]);
    // The DAP's ident numbers are the file's.
    assert_eq!(defined.dap.module_ident, 1);
    assert_eq!(defined.dap.interface_ident, 0x8000);
    assert_eq!(defined.dap.port_ident, 0x8001);
    // M1 in slot 2: its ModuleItemRef allows slot 1 only.
    let m = define_station(&station, &gsdml, dap, &[at(2, 0x101)])
        .unwrap_err()
        .to_string();
    assert!(
        m.contains("slot 2: module 0x00000101 (M1)") && m.contains("allows slots 1"),
        "{m}"
    );
    // Slot 5 is beyond the DAP's PhysicalSlots.
    let m = define_station(&station, &gsdml, dap, &[at(5, 0x101)])
        .unwrap_err()
        .to_string();
    assert!(m.contains("PhysicalSlots") && m.contains("0..4"), "{m}");
}

#[test]
fn a_submodule_has_its_own_i_and_m_where_the_gsdml_lets_the_plc_write_it() {
    // The demo with slot 1 carrying I&M of its own.
    let toml = DEMO_DEVICE_TOML.replacen(
        "records = [{ index = 1, length = 4, data = [0, 0, 0, 10] }]",
        "records = [{ index = 1, length = 4, data = [0, 0, 0, 10] }]\nim = true",
        1,
    );
    assert_ne!(toml, DEMO_DEVICE_TOML, "the demo's slot 1 as expected");
    let config = parse(&toml, DEMO_DEVICE_ORIGIN).unwrap();
    let station = config.station.unwrap();
    let file = station_gsdml(
        &station,
        config.cycle_ns,
        GsdmlDate::new(2026, 11, 28).unwrap(),
    )
    .unwrap();
    let gsdml = Gsdml::parse(&file.xml, &file.file_name).unwrap();
    let defined = define_station(&station, &gsdml, &gsdml.daps[0], &station.tree()).unwrap();
    let im: Vec<(u16, bool)> = defined
        .submodules
        .iter()
        .filter(|s| s.submodule.slot != 0)
        .map(|s| (s.submodule.slot, s.im))
        .collect();
    assert!(im.contains(&(1, true)), "{im:?}");
    assert!(
        im.iter().filter(|(slot, _)| *slot != 1).all(|(_, im)| !im),
        "{im:?}"
    );
}

#[test]
fn the_device_demo_defined_by_its_program_waits_with_its_device_access_point() {
    let demo = Config::demo_device();
    let config = Config::demo_device_program();
    let station = config.station.as_ref().unwrap();
    let configured = demo.station.as_ref().unwrap();
    assert_eq!(
        (station.vendor_id, station.device_id, &station.name),
        (configured.vendor_id, configured.device_id, &configured.name)
    );
    assert!(station.submodules.iter().all(|s| s.submodule.slot == 0));
    let program = station.program.as_ref().expect("defined by its program");
    // The demo's own tree is one its program may define.
    let file = &program.file;
    let defined = define_station(
        station,
        file,
        &file.daps[program.dap_index],
        &configured.tree(),
    )
    .unwrap();
    assert_eq!(defined.submodules.len(), configured.submodules.len());
}
