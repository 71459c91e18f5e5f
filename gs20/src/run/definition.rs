// SPDX-License-Identifier: MIT OR Apache-2.0
//! The host's station as procimgd's station: the tree (one module per item, slot = the Add
//! Item position) and the identity (the network configuration's host name and addresses,
//! the serial number) that `define_station_as` takes.

use procimg_client::{DefinedIdentity, StationTreeEntry, TreeRecords};
use procimg_gs20::link::Station;
use procimg_gs20::messages::{AddressMode, ItemId};

/// The tree of the host's items, in the order added: each item is the module of its ID at
/// its slot, with its one submodule in subslot 1 (the catalogue's ident numbers), whose
/// records the station answers (an item has no parameter records).
pub fn tree(station: &Station) -> Vec<StationTreeEntry> {
    station
        .items
        .iter()
        .map(|i| StationTreeEntry {
            api: 0,
            slot: i.slot,
            subslot: 1,
            module_ident: i.item.module_ident(),
            submodule_ident: ItemId::SUBMODULE_IDENT,
            records: TreeRecords::Station,
        })
        .collect()
}

/// The station's identity from the host's configuration: the host name is the
/// NameOfStation; static addresses are the station's IP suite, DHCP leaves it without an
/// address for the PLC to assign by DCP (PROFINET's way of giving a device its address:
/// procimgd runs no DHCP client); the serial number, in decimal, is I&M0's.
pub fn identity(station: &Station) -> DefinedIdentity {
    let network = station.network.as_ref();
    DefinedIdentity {
        name: network.map(|n| n.station_name.clone()),
        ip: network.map(|n| match n.mode {
            AddressMode::Static => [n.ip.octets(), n.mask.octets(), n.gateway.octets()],
            // The link takes no other mode; DHCP and an unknown one alike get no address.
            _ => [[0; 4]; 3],
        }),
        serial_number: station.serial.map(|s| s.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_gs20::link::{ItemSlot, NetworkSettings};
    use std::net::Ipv4Addr;

    fn station(mode: AddressMode) -> Station {
        Station {
            items: vec![
                ItemSlot {
                    item: ItemId::from_u16(3008).unwrap(),
                    slot: 1,
                },
                ItemSlot {
                    item: ItemId::from_u16(1004).unwrap(),
                    slot: 5,
                },
            ],
            network: Some(NetworkSettings {
                mode,
                ip: Ipv4Addr::new(192, 168, 0, 50),
                mask: Ipv4Addr::new(255, 255, 255, 0),
                gateway: Ipv4Addr::new(192, 168, 0, 1),
                dns1: Ipv4Addr::UNSPECIFIED,
                dns2: Ipv4Addr::UNSPECIFIED,
                station_name: "gs20-host".into(),
            }),
            serial: Some(42),
            ..Station::default()
        }
    }

    #[test]
    fn each_item_is_the_module_of_its_id_at_its_slot() {
        let t = tree(&station(AddressMode::Static));
        let got: Vec<_> = t
            .iter()
            .map(|e| (e.api, e.slot, e.subslot, e.module_ident, e.submodule_ident))
            .collect();
        assert_eq!(got, [(0, 1, 1, 3008, 1), (0, 5, 1, 1004, 1)]);
        assert!(t.iter().all(|e| e.records == TreeRecords::Station));
    }

    #[test]
    fn static_addresses_are_the_stations_and_dhcp_leaves_it_to_the_plc() {
        let id = identity(&station(AddressMode::Static));
        assert_eq!(id.name.as_deref(), Some("gs20-host"));
        assert_eq!(
            id.ip,
            Some([[192, 168, 0, 50], [255, 255, 255, 0], [192, 168, 0, 1]])
        );
        assert_eq!(id.serial_number.as_deref(), Some("42"));
        let id = identity(&station(AddressMode::Dhcp));
        assert_eq!(id.ip, Some([[0; 4]; 3]));
        assert_eq!(identity(&Station::default()), DefinedIdentity::default());
    }
}
