// SPDX-License-Identifier: MIT OR Apache-2.0
//! The catalogue's file read back by procimg: every item a module with its ident numbers and
//! lengths in every slot 1 to 64; procimgd's configuration takes it as its station's
//! (`[station] gsdml`), and a host's items make a station of it where the file allows them.

use super::*;
use procimg_config::gsdml::Gsdml;
use procimg_config::{PlannedSubmodule, TreeError, define_station, parse_in_dir};

const MS: u64 = 1_000_000;

fn date() -> GsdmlDate {
    GsdmlDate::new(2025, 1, 31).unwrap()
}

fn file() -> StationGsdml {
    catalogue_gsdml(&CatalogueIdentity::default(), MS, date()).unwrap()
}

fn read_back(file: &StationGsdml) -> Gsdml {
    match Gsdml::parse(&file.xml, &file.file_name) {
        Ok(g) => g,
        Err(e) => panic!("procimg cannot read the catalogue: {e}\n{}", file.xml),
    }
}

/// The station of procimgd's configuration with the file as its station's GSDML file, as
/// procimgd would load it.
fn configured_station(file: &StationGsdml) -> StationConfig {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join(&file.file_name), &file.xml).unwrap();
    let text = format!(
        "role = \"device\"\nnetwork = \"sim\"\n[station]\nname = \"gs20-host\"\n\
         gsdml = \"{}\"\n",
        file.file_name
    );
    match parse_in_dir(&text, "gs20.toml", dir.path()) {
        Ok(c) => c.station.unwrap(),
        Err(e) => panic!("procimgd's configuration refused the catalogue: {e}"),
    }
}

/// The items at their slots, as the bridge plugs them.
fn tree(items: &[(u16, u16)]) -> Vec<PlannedSubmodule> {
    items
        .iter()
        .map(|&(id, slot)| PlannedSubmodule {
            api: 0,
            slot,
            subslot: ITEM_SUBSLOT,
            module_ident: u32::from(id),
            submodule_ident: ItemId::SUBMODULE_IDENT,
        })
        .collect()
}

fn define(items: &[(u16, u16)]) -> Result<StationConfig, TreeError> {
    let station = configured_station(&file());
    let program = station.program.as_ref().unwrap();
    let gsdml = &program.file;
    define_station(
        &station,
        gsdml,
        &gsdml.daps[program.dap_index],
        &tree(items),
    )
}

#[test]
fn every_item_is_a_module_of_its_id_with_its_lengths_in_every_slot() {
    let file = file();
    assert_eq!(file.file_name, "GSDML-V2.4-procimg-GS20_PN-20250131.xml");
    let gsdml = read_back(&file);
    assert_eq!((gsdml.vendor_id, gsdml.device_id), (0x0493, 0x0200));

    let [dap] = &gsdml.daps[..] else {
        panic!("one device access point: {:?}", gsdml.daps)
    };
    let defaults = DapConfig::default();
    assert_eq!(dap.module_ident, defaults.module_ident);
    let dap_submodules: Vec<(Option<String>, u32)> = dap
        .submodules
        .iter()
        .map(|s| {
            (
                s.subslots.as_ref().map(ToString::to_string),
                s.submodule_ident,
            )
        })
        .collect();
    assert_eq!(
        dap_submodules,
        [
            (Some("1".to_owned()), defaults.submodule_ident),
            (Some("32768".to_owned()), defaults.interface_ident),
            (Some("32769".to_owned()), defaults.port_ident),
        ]
    );
    assert_eq!(dap.physical_slots.as_ref().unwrap().to_string(), "0..64");

    let items: Vec<ItemId> = ItemId::all().collect();
    assert_eq!(items.len(), 27);
    assert_eq!(gsdml.modules.len(), items.len());
    assert_eq!(dap.useable_modules.len(), items.len());
    for (item, module) in items.iter().zip(&gsdml.modules) {
        assert_eq!(module.module_ident, item.module_ident(), "{item}");
        let [submodule] = &module.submodules[..] else {
            panic!("{item}: one submodule, not {:?}", module.submodules)
        };
        assert_eq!(submodule.submodule_ident, ItemId::SUBMODULE_IDENT);
        assert_eq!(
            submodule.subslots.as_ref().map(ToString::to_string),
            Some(ITEM_SUBSLOT.to_string())
        );
        let lengths = gsdml.io_lengths(submodule).unwrap();
        assert_eq!(
            (usize::from(lengths.input), usize::from(lengths.output)),
            (item.input_len(), item.output_len()),
            "{item}"
        );
        assert!(gsdml.records(submodule).unwrap().is_empty());
        let plug = dap
            .useable_modules
            .iter()
            .find(|r| r.target == module.id)
            .unwrap_or_else(|| panic!("{item}: the DAP does not take {}", module.id));
        assert_eq!(plug.allowed.as_ref().unwrap().to_string(), "1..64");
        assert!(
            plug.fixed.is_none() && plug.used.is_none(),
            "plugged in none"
        );
    }
    let names: Vec<Option<&str>> = gsdml.modules.iter().map(|m| m.name.as_deref()).collect();
    assert_eq!(names[0], Some("Item 1001: 1 byte in"));
    assert_eq!(names[17], Some("Item 2256: 256 bytes out"));
    assert_eq!(names[21], Some("Item 3008: 8 bytes in and out"));
}

#[test]
fn a_hosts_items_make_procimgds_station_from_the_file() {
    let station = configured_station(&file());
    // VendorID and DeviceID come from the file.
    assert_eq!((station.vendor_id, station.device_id), (0x0493, 0x0200));
    assert_eq!(station.dap, DapConfig::default());

    let defined = define(&[(3008, 1), (1004, 2), (2256, 3), (1001, MAX_SLOT)]).unwrap();
    let lengths: Vec<(u16, u32, u32, u16, u16)> = defined
        .submodule_configs()
        .filter(|s| s.slot > 0)
        .map(|s| {
            (
                s.slot,
                s.module_ident,
                s.submodule_ident,
                s.input_length,
                s.output_length,
            )
        })
        .collect();
    assert_eq!(
        lengths,
        [
            (1, 3008, 1, 8, 8),
            (2, 1004, 1, 4, 0),
            (3, 2256, 1, 0, 256),
            (64, 1001, 1, 1, 0)
        ]
    );
}

#[test]
fn an_unknown_item_and_a_slot_beyond_the_last_are_refused() {
    // 3003 is no item (3 bytes is no size of the catalogue), so the file has no module 3003.
    let e = define(&[(3008, 1), (3003, 2)]).unwrap_err();
    assert!(
        matches!(
            e,
            TreeError::UnknownModule {
                slot: 2,
                module_ident: 3003,
                ..
            }
        ),
        "{e}"
    );
    let e = define(&[(3008, MAX_SLOT + 1)]).unwrap_err();
    assert!(
        matches!(&e, TreeError::Slot { slot: 65, allowed, .. } if allowed == "0..64"),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains("GSDML-V2.4-procimg-GS20_PN-20250131.xml"),
        "{e}"
    );
}

#[test]
fn the_identity_and_the_cycle_are_the_callers() {
    let identity = CatalogueIdentity {
        vendor_id: 0x1234,
        device_id: 0xABCD,
    };
    let file = catalogue_gsdml(&identity, 4 * MS, GsdmlDate::new(2026, 2, 28).unwrap()).unwrap();
    assert_eq!(file.file_name, "GSDML-V2.4-procimg-GS20_PN-20260228.xml");
    let gsdml = read_back(&file);
    assert_eq!((gsdml.vendor_id, gsdml.device_id), (0x1234, 0xABCD));
    assert!(
        file.xml
            .contains("ReductionRatio=\"4 8 16 32 64 128 256 512\""),
        "{}",
        file.xml
    );
    assert!(file.xml.contains("DNS_CompatibleName=\"gs20-pn\""));
    assert!(file.xml.contains("procimg-gs20 gsdml"));

    let e = catalogue_gsdml(&identity, 3 * MS, date()).unwrap_err();
    assert_eq!(e, CatalogueError::Cycle { cycle_ns: 3 * MS });
    let shown = e.to_string();
    assert!(
        shown.contains("3ms") && shown.contains("give the cycle_time of procimgd's configuration"),
        "{shown}"
    );
}
