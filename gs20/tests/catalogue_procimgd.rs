// SPDX-License-Identifier: MIT OR Apache-2.0
//! The item catalogue's GSDML file as procimgd's station's (`[station] gsdml`), with the
//! built-in PLC (`network = "sim"`): the station waits with the file's identity; a host's
//! items plugged as the bridge plugs them (module = item ID, submodule 1 in subslot 1, slot
//! = position) make the station, which the PLC connects with the file's lengths and whose
//! data flows; items the file does not allow are refused naming it.

use std::time::Duration;

use procimg_client::{
    ArState, AttachOptions, Client, ControlError, Refusal, ServiceOptions, Services,
    StationTreeEntry, StatusReport, TreeRecords,
};
use procimg_gs20::catalogue::{CatalogueIdentity, GsdmlDate, ITEM_SUBSLOT, catalogue_gsdml};
use procimg_gs20::messages::ItemId;
use procimg_testkit::Launch;
use procimg_testkit::exchange::{at, until_the_plc_answers};

/// Generous: a loaded machine may be slow to connect.
const BRING_UP: Duration = Duration::from_secs(30);

/// The host's items at their positions, as the bridge plugs them.
fn tree(items: &[(u16, u16)]) -> Vec<StationTreeEntry> {
    items
        .iter()
        .map(|&(id, slot)| {
            let item = ItemId::from_u16(id).unwrap();
            StationTreeEntry {
                api: 0,
                slot,
                subslot: ITEM_SUBSLOT,
                module_ident: item.module_ident(),
                submodule_ident: ItemId::SUBMODULE_IDENT,
                records: TreeRecords::Station,
            }
        })
        .collect()
}

fn in_data(s: &StatusReport) -> bool {
    s.station
        .as_ref()
        .and_then(|st| st.ar.as_ref())
        .is_some_and(|ar| ar.state == ArState::Data)
}

#[test]
fn procimgd_runs_a_hosts_items_as_the_catalogue_describes_them() {
    let dir = procimg_testkit::files::temp_dir("gs20-catalogue");
    let file = catalogue_gsdml(
        &CatalogueIdentity::default(),
        1_000_000,
        GsdmlDate::new(2025, 1, 31).unwrap(),
    )
    .unwrap();
    let path = dir.path().join(&file.file_name);
    file.write(&path).unwrap();
    let toml = format!(
        "role = \"device\"\ncycle_time = \"1ms\"\nnetwork = \"sim\"\n[station]\n\
         name = \"gs20-host\"\nip = \"192.168.0.50\"\ngsdml = \"{}\"\n",
        path.display()
    );
    let server = Launch::config("gs20-catalogue", &toml)
        .until_cycling()
        .start();
    let station = server.status().station.expect("a station");
    assert_eq!((station.vendor_id, station.device_id), (0x0493, 0x0200));

    // Lives to the end: its close would take the station off the wire.
    let program = Services::open(&server.instance, ServiceOptions::new("gs20-items")).unwrap();
    match program.define_station(&tree(&[(3008, 1), (1001, 65)])) {
        Err(ControlError::Refused(Refusal::BadRequest { message })) => assert!(
            message.contains("slot 65") && message.contains("0..64"),
            "{message}"
        ),
        other => panic!("a slot beyond the catalogue's taken: {other:?}"),
    }

    program
        .define_station(&tree(&[(3008, 1), (1004, 2), (2256, 3)]))
        .unwrap();
    server.wait_status("the AR in data exchange", in_data);

    let mut client = Client::attach(
        &server.instance,
        AttachOptions::synchronous("gs20-catalogue"),
    )
    .unwrap();
    // The image is procimgd's: its inputs are what the station receives, the PLC's Q
    // data (the item's output bytes), its outputs the I data the PLC reads (the item's
    // input bytes).
    let plugged: Vec<(u16, u16, u32, u32, u16, u16)> = client
        .layout()
        .submodules
        .iter()
        .filter(|e| e.slot > 0)
        .map(|e| {
            (
                e.slot,
                e.subslot,
                e.module_ident,
                e.submodule_ident,
                e.output_length,
                e.input_length,
            )
        })
        .collect();
    assert_eq!(
        plugged,
        [
            (1, 1, 3008, 1, 8, 8),
            (2, 1, 1004, 1, 4, 0),
            (3, 1, 2256, 1, 0, 256)
        ]
    );
    // Item 3008's bytes reach the PLC, whose answer (I + 1) comes back.
    let item = at(&client, 1, ITEM_SUBSLOT);
    client.claim_i_data().expect("claim the I data");
    until_the_plc_answers(&mut client, item, &[1, 2, 3, 4, 5, 6, 7, 8], BRING_UP);
    drop(program);
}
