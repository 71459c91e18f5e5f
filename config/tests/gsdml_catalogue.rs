// SPDX-License-Identifier: MIT OR Apache-2.0
//! A station's GSDML file with a catalogue: modules none of which is plugged, each allowed
//! in a range of slots, after the station's own. procimg reads the file back as a station
//! its program defines reads it (`define_station`: the modules in their allowed slots, their
//! lengths from the file, the rest refused) and as a controller configuration names its
//! modules; what one file cannot offer is refused with what to do.

use std::ops::RangeInclusive;

use procimg_config::gsdml::Gsdml;
use procimg_config::gsdml::export::{
    Catalogue, CatalogueModule, CatalogueSubmodule, ExportError, GsdmlDate, StationGsdml,
    module_item_id, station_gsdml, station_gsdml_with_catalogue,
};
use procimg_config::{
    Config, PlannedSubmodule, StationConfig, TreeError, define_station, parse, parse_in_dir,
};

fn date() -> GsdmlDate {
    GsdmlDate::new(2025, 1, 31).unwrap()
}

/// A device configuration: `[[station.submodule]]` tables after the identity.
fn station(submodules: &str) -> StationConfig {
    let text = format!(
        "role = \"device\"\n[station]\nname = \"catalogued\"\nvendor_id = 0x0493\n\
         device_id = 0x0200\ndevice_type = \"Catalogued\"\n{submodules}"
    );
    match parse(&text, "device.toml") {
        Ok(c) => c.station.unwrap(),
        Err(e) => panic!("refused: {e}\n{text}"),
    }
}

fn module(ident: u32, slots: RangeInclusive<u16>, lengths: (u16, u16)) -> CatalogueModule {
    CatalogueModule {
        module_ident: ident,
        name: format!("Thing {ident}"),
        allowed_slots: slots,
        submodules: vec![CatalogueSubmodule {
            subslot: 1,
            submodule_ident: 1,
            input_length: lengths.0,
            output_length: lengths.1,
        }],
    }
}

fn catalogue(modules: Vec<CatalogueModule>) -> Catalogue {
    Catalogue {
        modules,
        writer: "catalogue-test gsdml".to_owned(),
        info: "A station of things".to_owned(),
    }
}

/// Three modules in slots 1 to 8: 4 bytes in and out, 2 in, 16 out.
fn three() -> Catalogue {
    catalogue(vec![
        module(0x3004, 1..=8, (4, 4)),
        module(0x1002, 1..=8, (2, 0)),
        module(0x2016, 1..=8, (0, 16)),
    ])
}

fn export(station: &StationConfig, catalogue: &Catalogue) -> Result<StationGsdml, ExportError> {
    station_gsdml_with_catalogue(station, catalogue, 1_000_000, date())
}

fn read_back(file: &StationGsdml) -> Gsdml {
    match Gsdml::parse(&file.xml, &file.file_name) {
        Ok(g) => g,
        Err(e) => panic!("procimg cannot read its file: {e}\n{}", file.xml),
    }
}

fn plug(slot: u16, module_ident: u32) -> PlannedSubmodule {
    PlannedSubmodule {
        api: 0,
        slot,
        subslot: 1,
        module_ident,
        submodule_ident: 1,
    }
}

/// (slot, input length, output length) of the station's submodules after slot 0.
fn lengths(station: &StationConfig) -> Vec<(u16, u16, u16)> {
    station
        .submodule_configs()
        .filter(|s| s.slot > 0)
        .map(|s| (s.slot, s.input_length, s.output_length))
        .collect()
}

#[test]
fn a_program_plugs_the_catalogues_modules_in_their_slots() {
    let base = station("");
    let file = export(&base, &three()).unwrap();
    assert_eq!(file.file_name, "GSDML-V2.4-procimg-Catalogued-20250131.xml");
    let gsdml = read_back(&file);
    assert_eq!((gsdml.vendor_id, gsdml.device_id), (0x0493, 0x0200));
    let dap = &gsdml.daps[0];
    assert_eq!(dap.module_ident, base.dap.module_ident);
    assert_eq!(dap.physical_slots.as_ref().unwrap().to_string(), "0..8");
    assert_eq!(dap.useable_modules.len(), 3);
    for r in &dap.useable_modules {
        assert_eq!(r.fixed.as_ref().map(ToString::to_string), None);
        assert_eq!(r.allowed.as_ref().unwrap().to_string(), "1..8");
    }
    assert_eq!(
        gsdml.modules[0].name.as_deref(),
        Some("Thing 12292"),
        "the catalogue's name"
    );

    // Any module in any slot, one of them twice; the lengths come from the file.
    let tree = [
        plug(1, 0x3004),
        plug(2, 0x1002),
        plug(3, 0x2016),
        plug(8, 0x3004),
    ];
    let defined = define_station(&base, &gsdml, dap, &tree).unwrap();
    assert_eq!(
        lengths(&defined),
        [(1, 4, 4), (2, 2, 0), (3, 0, 16), (8, 4, 4)]
    );
    assert_eq!(defined.dap, base.dap);

    let e = define_station(&base, &gsdml, dap, &[plug(9, 0x3004)]).unwrap_err();
    assert!(
        matches!(&e, TreeError::Slot { slot: 9, allowed, .. } if allowed == "0..8"),
        "{e}"
    );
    let e = define_station(&base, &gsdml, dap, &[plug(1, 0x3005)]).unwrap_err();
    assert!(
        matches!(
            e,
            TreeError::UnknownModule {
                module_ident: 0x3005,
                ..
            }
        ),
        "{e}"
    );
    assert!(
        e.to_string().contains("0x00003004, 0x00001002, 0x00002016"),
        "{e}"
    );
}

#[test]
fn a_controller_configuration_names_the_catalogues_modules() {
    let file = export(&station(""), &three()).unwrap();
    let scratch = tempfile::tempdir().unwrap();
    let dir = scratch.path();
    std::fs::write(dir.join(&file.file_name), &file.xml).unwrap();
    let text = format!(
        "[[device]]\nname = \"catalogued\"\ngsdml = \"{}\"\n\
         [[device.submodule]]\nslot = 2\nmodule = \"{}\"\n\
         [[device.submodule]]\nslot = 5\nmodule = \"{}\"\n",
        file.file_name,
        module_item_id(0x2016),
        module_item_id(0x3004),
    );
    let config: Config = match parse_in_dir(&text, "plant.toml", dir) {
        Ok(c) => c,
        Err(e) => panic!("the import refused: {e}\n{text}"),
    };
    let device = &config.devices[0];
    let plugged: Vec<(u16, u32, u16, u16)> = device
        .submodules
        .iter()
        .filter(|s| s.slot > 0)
        .map(|s| (s.slot, s.module_ident, s.input_length, s.output_length))
        .collect();
    assert_eq!(plugged, [(2, 0x2016, 0, 16), (5, 0x3004, 4, 4)]);
}

#[test]
fn the_stations_own_modules_stay_fixed_beside_the_catalogue() {
    let base = station(
        "[[station.submodule]]\nslot = 12\nmodule_ident = 0x10\nsubmodule_ident = 1\n\
         input_length = 1\n",
    );
    let file = export(&base, &catalogue(vec![module(0x20, 2..=4, (0, 2))])).unwrap();
    let gsdml = read_back(&file);
    let dap = &gsdml.daps[0];
    assert_eq!(dap.physical_slots.as_ref().unwrap().to_string(), "0..12");
    assert!(file.xml.contains("FixedInSlots=\"12\""), "{}", file.xml);
    assert!(file.xml.contains("AllowedInSlots=\"2..4\""), "{}", file.xml);
    // The PLC's project chooses: the file gives the longest frames procimgd takes.
    assert!(
        file.xml
            .contains("MaxInputLength=\"1440\" MaxOutputLength=\"1440\""),
        "{}",
        file.xml
    );

    let defined = define_station(&base, &gsdml, dap, &[plug(12, 0x10), plug(3, 0x20)]).unwrap();
    assert_eq!(lengths(&defined), [(12, 1, 0), (3, 0, 2)]);
    let e = define_station(&base, &gsdml, dap, &[plug(5, 0x20)]).unwrap_err();
    assert!(
        matches!(&e, TreeError::Slot { slot: 5, allowed, .. } if allowed == "2..4"),
        "{e}"
    );
}

#[test]
fn without_a_catalogue_the_file_is_the_stations() {
    let base = station(
        "[[station.submodule]]\nslot = 1\nmodule_ident = 0x10\nsubmodule_ident = 1\n\
         input_length = 1\n",
    );
    let plain = station_gsdml(&base, 1_000_000, date()).unwrap();
    assert!(!plain.xml.contains("AllowedInSlots"), "{}", plain.xml);
    assert!(
        plain
            .xml
            .contains("MaxInputLength=\"5\" MaxOutputLength=\"4\""),
        "{}",
        plain.xml
    );
    let with_none = export(&base, &catalogue(Vec::new())).unwrap();
    assert_eq!(with_none.file_name, plain.file_name);
    assert!(with_none.xml.contains("catalogue-test gsdml"));
    assert!(with_none.xml.contains("A station of things"));
}

#[test]
fn the_file_is_well_formed_and_its_head_comment_stays_a_comment() {
    let mut c = three();
    c.writer = "odd -- writer --->".to_owned();
    c.modules[0].name = "a <name> & \"more\"".to_owned();
    let file = export(&station(""), &c).unwrap();
    let doc = match roxmltree::Document::parse(&file.xml) {
        Ok(d) => d,
        Err(e) => panic!("not well-formed: {e}\n{}", file.xml),
    };
    let comments: Vec<&str> = doc
        .root()
        .children()
        .filter(|n| n.is_comment())
        .filter_map(|n| n.text())
        .collect();
    assert_eq!(comments.len(), 1, "{}", file.xml);
    assert!(
        comments[0].contains("odd - - writer - - -"),
        "{}",
        comments[0]
    );
    let gsdml = read_back(&file);
    assert_eq!(
        gsdml.modules[0].name.as_deref(),
        Some("a <name> & \"more\"")
    );
    // Every ID is unique, and every TextId has its text.
    let mut ids: Vec<&str> = doc
        .descendants()
        .filter_map(|n| n.attribute("ID"))
        .collect();
    let count = ids.len();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), count, "IDs repeat");
    let texts: Vec<&str> = doc
        .descendants()
        .filter(|n| n.tag_name().name() == "Text")
        .filter_map(|n| n.attribute("TextId"))
        .collect();
    for n in doc.descendants().filter(|n| n.tag_name().name() != "Text") {
        if let Some(id) = n.attribute("TextId") {
            assert!(texts.contains(&id), "no text {id}");
        }
    }
}

#[track_caller]
fn refused(station: &StationConfig, c: Catalogue, phrases: &[&str]) {
    let e = match export(station, &c) {
        Ok(g) => panic!("exported:\n{}", g.xml),
        Err(e) => e,
    };
    assert!(matches!(e, ExportError::Catalogue { .. }), "{e:?}");
    let shown = e.to_string();
    for phrase in phrases {
        assert!(shown.contains(phrase), "{phrase:?} not in: {shown}");
    }
}

#[test]
fn what_one_file_cannot_offer_is_refused() {
    let plain = station("");
    refused(
        &plain,
        catalogue(vec![module(1, 1..=4, (1, 0))]),
        &[
            "catalogue module 0x00000001",
            "device access point's",
            "give it another",
        ],
    );
    refused(
        &plain,
        catalogue(vec![
            module(0x20, 1..=4, (1, 0)),
            module(0x20, 5..=6, (1, 0)),
        ]),
        &["in the catalogue twice"],
    );
    let plugged =
        station("[[station.submodule]]\nslot = 3\nmodule_ident = 0x20\nsubmodule_ident = 1\n");
    refused(
        &plugged,
        catalogue(vec![module(0x20, 1..=4, (1, 0))]),
        &["plugged in slot 3", "leave it out of the catalogue"],
    );
    // Slot 0, an empty range (5 to 4), beyond the last slot.
    for slots in [0..=4, RangeInclusive::new(5, 4), 1..=0x8000] {
        let (a, b) = (*slots.start(), *slots.end());
        refused(
            &plain,
            catalogue(vec![module(0x20, slots, (1, 0))]),
            &[&format!("slots {a}..{b}"), "allow slots from 1 to 32767"],
        );
    }
    let mut bare = module(0x20, 1..=4, (1, 0));
    bare.submodules.clear();
    refused(&plain, catalogue(vec![bare]), &["no submodule"]);
    let mut misplaced = module(0x20, 1..=4, (1, 0));
    misplaced.submodules[0].subslot = 0x8000;
    refused(&plain, catalogue(vec![misplaced]), &["subslot 32768"]);
    let mut doubled = module(0x20, 1..=4, (1, 0));
    doubled.submodules.push(doubled.submodules[0]);
    refused(
        &plain,
        catalogue(vec![doubled]),
        &["two of its submodules are in subslot 1"],
    );
    // 3 for the DAP, 1437 + IOPS: one byte over.
    refused(
        &plain,
        catalogue(vec![module(0x20, 1..=4, (1437, 0))]),
        &["1441 bytes", "make its submodules shorter"],
    );
    export(&plain, &catalogue(vec![module(0x20, 1..=4, (1436, 0))])).unwrap();
}
