// SPDX-License-Identifier: MIT OR Apache-2.0
//! A catalogue of modules in a station's GSDML file: modules the station does not hold when
//! it starts, which the PLC's project may plug in any slot each allows, for a station whose
//! program plugs its modules (`[station] gsdml = "FILE"`: a GS20-PN host's items, a GOAL
//! application's slots). procimg's station check reads them back as it reads any module
//! (`define_station`: the DAP's `UseableModules`, the module's `AllowedInSlots`).

use std::ops::RangeInclusive;

use super::ExportError;
use super::planned::{DAP_FRAME_BYTES, FileSubmodule, PlannedModule, Slots, frame_bytes};
use crate::station::{MAX_CR_DATA, MAX_STATION_SLOT};

/// The modules a station's program may plug, beyond those the station has plugged, and what
/// the file says of itself.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Catalogue {
    /// The modules, in the order the file lists them.
    pub modules: Vec<CatalogueModule>,
    /// The program that writes the file, for the comment at its head, e.g.
    /// "procimg-gs20 gsdml".
    pub writer: String,
    /// What the device is, for the file's `DeviceIdentity` info text.
    pub info: String,
}

/// A module of the catalogue.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CatalogueModule {
    /// Its ModuleIdentNumber; the file's `ModuleItem` is named by it as a station's module
    /// is ([`super::module_item_id`]).
    pub module_ident: u32,
    /// Its name in the engineering tool's catalogue.
    pub name: String,
    /// The slots the PLC's project may plug it in: 1 to 32767.
    pub allowed_slots: RangeInclusive<u16>,
    /// Its submodules, each fixed in its subslot: at least one.
    pub submodules: Vec<CatalogueSubmodule>,
}

/// A submodule of a catalogue module: in API 0, without parameter records or I&M data of
/// its own (what a catalogue of IO items needs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CatalogueSubmodule {
    /// Its subslot, 1 to 32767.
    pub subslot: u16,
    /// Its SubmoduleIdentNumber.
    pub submodule_ident: u32,
    /// Bytes of input data (the device provides, the PLC reads).
    pub input_length: u16,
    /// Bytes of output data (the PLC writes, the device reads).
    pub output_length: u16,
}

/// The catalogue's modules as the file lists them, after the station's own `fixed` ones;
/// refuses a module one GSDML file cannot offer as given.
pub(super) fn plan<'c>(
    catalogue: &'c Catalogue,
    dap_ident: u32,
    fixed: &[PlannedModule<'_>],
) -> Result<Vec<PlannedModule<'c>>, ExportError> {
    let mut planned: Vec<PlannedModule<'c>> = Vec::new();
    for m in &catalogue.modules {
        let refuse = |reason: String| ExportError::Catalogue {
            module_ident: m.module_ident,
            reason,
        };
        if m.module_ident == dap_ident {
            return Err(refuse(
                "it has the device access point's module ident; give it another, so that the \
                 PLC can tell them apart"
                    .to_owned(),
            ));
        }
        if let Some(f) = fixed.iter().find(|f| f.module_ident == m.module_ident) {
            return Err(refuse(format!(
                "the station has it plugged in slot {}; a GSDML file has one module per ident \
                 number, so leave it out of the catalogue or give it another ident",
                f.slots.first()
            )));
        }
        if planned.iter().any(|p| p.module_ident == m.module_ident) {
            return Err(refuse(
                "it is in the catalogue twice; list each module once".to_owned(),
            ));
        }
        let (first, last) = (*m.allowed_slots.start(), *m.allowed_slots.end());
        if first == 0 || first > last || last > MAX_STATION_SLOT {
            return Err(refuse(format!(
                "slots {first}..{last} are no slots a module may be allowed in; allow slots from \
                 1 to {MAX_STATION_SLOT} (slot 0 is the device access point's)"
            )));
        }
        if m.submodules.is_empty() {
            return Err(refuse(
                "it has no submodule; give it at least one".to_owned(),
            ));
        }
        let mut submodules: Vec<FileSubmodule<'c>> = Vec::new();
        let (mut input_bytes, mut output_bytes) = DAP_FRAME_BYTES;
        for s in &m.submodules {
            if s.subslot == 0 || s.subslot > 0x7FFF {
                return Err(refuse(format!(
                    "subslot {} is no subslot for a module's submodule; use 1 to 32767",
                    s.subslot
                )));
            }
            if submodules.iter().any(|f| f.subslot == s.subslot) {
                return Err(refuse(format!(
                    "two of its submodules are in subslot {}; give each its own",
                    s.subslot
                )));
            }
            let (i, o) = frame_bytes(s.input_length, s.output_length);
            input_bytes += i;
            output_bytes += o;
            submodules.push(FileSubmodule {
                api: 0,
                subslot: s.subslot,
                submodule_ident: s.submodule_ident,
                input_length: s.input_length,
                output_length: s.output_length,
                im: false,
                accepts: &[],
            });
        }
        if input_bytes.max(output_bytes) > MAX_CR_DATA {
            return Err(refuse(format!(
                "plugged alone, its data and status would take {} bytes of a frame, more than \
                 the {MAX_CR_DATA} of one RT frame; make its submodules shorter",
                input_bytes.max(output_bytes)
            )));
        }
        submodules.sort_by_key(|s| s.subslot);
        planned.push(PlannedModule {
            module_ident: m.module_ident,
            name: Some(m.name.as_str()).filter(|n| !n.trim().is_empty()),
            slots: Slots::Allowed(m.allowed_slots.clone()),
            submodules,
        });
    }
    Ok(planned)
}
