// SPDX-License-Identifier: MIT OR Apache-2.0
//! The item catalogue as a GSDML file: the station a GS20-PN host defines, described for
//! the PLC's engineering tool and for procimgd.
//!
//! The reference's module ships a sample GSDML that the user adapts (§1.1); its chapter is
//! missing. Here the file is written from the item rule instead ([`ItemId`]): every item of
//! the catalogue is a module whose ModuleIdentNumber is the item ID
//! ([`ItemId::module_ident`]), with one submodule ([`ItemId::SUBMODULE_IDENT`] in
//! [`ITEM_SUBSLOT`]) of the item's input and output bytes, allowed in every slot 1 to
//! [`MAX_SLOT`] and plugged in none. The device access point is procimgd's default one
//! (module 1, submodule 1, interface 0x8000, port 0x8001). So whatever items a host adds,
//! at whatever positions, the PLC's project can hold the same modules in the same slots;
//! and procimgd, given the file as its station's (`[station] gsdml = "FILE"`), takes the
//! host's items as the station's modules with the lengths the file gives them.

use std::ops::RangeInclusive;

use procimg_config::StationConfig;
use procimg_config::gsdml::export::{
    Catalogue, CatalogueModule, CatalogueSubmodule, ExportError, station_gsdml_with_catalogue,
};
use procimg_config::station::{DapConfig, SoftwareVersion};

pub use procimg_config::gsdml::export::{GsdmlDate, StationGsdml, WriteError};

use crate::messages::{ItemId, ItemKind};

pub use crate::messages::item::MAX_SLOT;

/// The subslot of an item's one submodule.
pub const ITEM_SUBSLOT: u16 = 1;

/// The VendorID the file has unless told otherwise: 0x0493, as procimg's demo station.
/// It is another vendor's ID, borrowed: a product needs a VendorID of its own, which
/// PROFIBUS & PROFINET International assigns, and the DeviceIDs under it are the vendor's
/// to give.
pub const DEFAULT_VENDOR_ID: u16 = 0x0493;

/// The DeviceID the file has unless told otherwise: 0x0200, beside the demo station's
/// 0x0100 under the same borrowed VendorID, so that a PLC's project does not take one for
/// the other.
pub const DEFAULT_DEVICE_ID: u16 = 0x0200;

/// The type of station the file names (its product family and device access point), and
/// so its file name: `GSDML-V2.4-procimg-GS20_PN-<yyyymmdd>.xml`.
pub const DEVICE_TYPE: &str = "GS20-PN";

/// The station name the file proposes to the engineering tool (`DNS_CompatibleName`); the
/// host's Set Network Configuration gives the running station its own.
pub const STATION_NAME: &str = "gs20-pn";

/// The PROFINET identity of the described device: what procimgd's station reports in DCP
/// and the PLC checks against its project. procimgd takes both from the file when its
/// `[station]` gives none.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CatalogueIdentity {
    /// `DeviceIdentity/@VendorID`.
    pub vendor_id: u16,
    /// `DeviceIdentity/@DeviceID`.
    pub device_id: u16,
}

impl Default for CatalogueIdentity {
    fn default() -> Self {
        CatalogueIdentity {
            vendor_id: DEFAULT_VENDOR_ID,
            device_id: DEFAULT_DEVICE_ID,
        }
    }
}

/// Why the catalogue's GSDML file cannot be written.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CatalogueError {
    /// No IO cycle the file can offer suits the station's cycle time.
    #[error(
        "a cycle time of {} cannot be described: the PLC's IO cycles (1 ms times a power of \
         two, up to 512 ms) must be whole multiples of it; give the cycle_time of procimgd's \
         configuration, a whole number of 31.25 µs such as 1ms, 2ms, 4ms or 500us",
        procimg_config::format_duration(*cycle_ns)
    )]
    Cycle {
        /// The cycle time given, in ns.
        cycle_ns: u64,
    },
    /// The exporter refused the catalogue itself (a fault of this crate, not of the input).
    #[error("the item catalogue cannot be written as GSDML ({0}); please report this")]
    Export(ExportError),
}

/// The GSDML file of the item catalogue for a station of `identity` whose procimgd runs with
/// a cycle of `cycle_ns` (its configuration's `cycle_time`), dated `date`: its standard
/// file name (`GSDML-V2.4-procimg-GS20_PN-<yyyymmdd>.xml`) and text.
pub fn catalogue_gsdml(
    identity: &CatalogueIdentity,
    cycle_ns: u64,
    date: GsdmlDate,
) -> Result<StationGsdml, CatalogueError> {
    station_gsdml_with_catalogue(&station(identity), &catalogue(), cycle_ns, date).map_err(|e| {
        match e {
            ExportError::Cycle { cycle_ns } => CatalogueError::Cycle { cycle_ns },
            e => CatalogueError::Export(e),
        }
    })
}

/// The items as the catalogue's modules, in [`ItemId::all`]'s order.
fn catalogue() -> Catalogue {
    let modules = ItemId::all()
        .map(|item| CatalogueModule {
            module_ident: item.module_ident(),
            name: name(item),
            allowed_slots: slots(),
            submodules: vec![CatalogueSubmodule {
                subslot: ITEM_SUBSLOT,
                submodule_ident: ItemId::SUBMODULE_IDENT,
                // At most 256: the sizes of the catalogue.
                input_length: item.input_len() as u16,
                output_length: item.output_len() as u16,
            }],
        })
        .collect();
    Catalogue {
        modules,
        writer: "procimg-gs20 gsdml".to_owned(),
        info: format!(
            "{DEVICE_TYPE}: procimgd as a GS20-PN compatible PROFINET IO device \
             (procimg-gs20); its modules are the items its host adds, item ID = \
             ModuleIdentNumber, position = slot"
        ),
    }
}

fn slots() -> RangeInclusive<u16> {
    1..=MAX_SLOT
}

/// "Item 3008: 8 bytes in and out", as the engineering tool's catalogue lists it.
fn name(item: ItemId) -> String {
    let n = item.size();
    let unit = if n == 1 { "byte" } else { "bytes" };
    let what = match item.kind() {
        ItemKind::Input => "in",
        ItemKind::Output => "out",
        ItemKind::InputOutput => "in and out",
    };
    format!("Item {}: {n} {unit} {what}", item.to_u16())
}

/// The station the file describes, apart from its modules: the identity, procimgd's
/// default device access point and I&M0 revisions, nothing plugged. The name and address
/// are the host's (Set Network Configuration), so the file proposes a name only.
fn station(identity: &CatalogueIdentity) -> StationConfig {
    StationConfig {
        name: STATION_NAME.to_owned(),
        ip: None,
        netmask: std::net::Ipv4Addr::UNSPECIFIED,
        gateway: std::net::Ipv4Addr::UNSPECIFIED,
        vendor_id: identity.vendor_id,
        device_id: identity.device_id,
        instance: 1,
        device_type: DEVICE_TYPE.to_owned(),
        order_number: String::new(),
        serial_number: String::new(),
        hardware_revision: 1,
        // procimgd's default software_revision, which its I&M0 reports unless configured.
        software_revision: SoftwareVersion {
            prefix: 'V',
            functional: 0,
            bug_fix: 1,
            internal: 0,
        },
        state_file: None,
        dcp_hello: false,
        snmp_agentx: Default::default(),
        dap: DapConfig::default(),
        submodules: Vec::new(),
        program: None,
    }
}

#[cfg(test)]
mod tests;
