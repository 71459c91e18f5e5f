// SPDX-License-Identifier: MIT OR Apache-2.0
//! From a station's submodules to GSDML modules: the submodules of each slot, grouped by
//! ModuleIdentNumber into one module per ident number, with the slots it is plugged in; the
//! catalogue's modules after them; and the refusals for what one GSDML file cannot describe.

use std::collections::BTreeMap;

use super::ExportError;
use super::catalogue::{self, Catalogue};
use super::planned::{DAP_FRAME_BYTES, PlannedModule, Slots, frame_bytes};
use crate::station::{
    AcceptedRecord, DAP_SUBSLOT, INTERFACE_SUBSLOT, MAX_CR_DATA, PORT_SUBSLOT, StationConfig,
    StationSubmodule,
};

/// What the file describes.
pub(super) struct Plan<'s> {
    /// Whether the DAP's own submodule has writable I&M1 to I&M4 (`im` of slot 0 subslot 1;
    /// it always has them when the station lists no slot 0).
    pub dap_im: bool,
    /// The modules: the station's, in the order of the first slot each is plugged in, then
    /// the catalogue's in its order.
    pub modules: Vec<PlannedModule<'s>>,
    /// The highest slot used or allowed (0: only the DAP).
    pub max_slot: u16,
    /// Bytes of the input and the output frame's C_SDU: IO data, IOPS and IOCS.
    pub input_bytes: usize,
    /// Likewise of the output frame.
    pub output_bytes: usize,
}

/// Groups the station's submodules into modules and adds the catalogue's; refuses what one
/// GSDML cannot describe.
pub(super) fn plan<'s>(
    station: &'s StationConfig,
    catalogue: Option<&'s Catalogue>,
) -> Result<Plan<'s>, ExportError> {
    let dap = &station.dap;
    let mut dap_im = true;
    let mut slots: BTreeMap<u16, Vec<&StationSubmodule>> = BTreeMap::new();
    for s in &station.submodules {
        let sub = &s.submodule;
        if let Some(r) = s
            .accepts
            .iter()
            .find(|r| r.initial.len() != usize::from(r.length))
        {
            return Err(ExportError::RecordData {
                slot: sub.slot,
                subslot: sub.subslot,
                index: r.index,
            });
        }
        if sub.slot != 0 {
            slots.entry(sub.slot).or_default().push(s);
            continue;
        }
        // Slot 0 is the DAP, which the file describes from [station.dap]; what the station
        // lists there has to be that, or the PLC would expect something else than it finds.
        let ident = match sub.subslot {
            DAP_SUBSLOT => dap.submodule_ident,
            INTERFACE_SUBSLOT => dap.interface_ident,
            PORT_SUBSLOT => dap.port_ident,
            _ => {
                return Err(ExportError::DapMismatch {
                    subslot: sub.subslot,
                });
            }
        };
        let standard = sub.api == 0
            && sub.module_ident == dap.module_ident
            && sub.submodule_ident == ident
            && sub.has_no_data()
            && s.accepts.is_empty();
        if !standard {
            return Err(ExportError::DapMismatch {
                subslot: sub.subslot,
            });
        }
        if sub.subslot == DAP_SUBSLOT {
            dap_im = s.im;
        }
    }

    for subs in slots.values_mut() {
        subs.sort_by_key(|s| (s.submodule.subslot, s.submodule.api));
    }
    let mut modules: Vec<PlannedModule<'_>> = Vec::new();
    let mut by_ident: BTreeMap<u32, usize> = BTreeMap::new();
    for (&slot, subs) in &slots {
        let module_ident = subs[0].submodule.module_ident;
        if let Some(other) = subs
            .iter()
            .find(|s| s.submodule.module_ident != module_ident)
        {
            return Err(ExportError::SlotHoldsTwoModules {
                slot,
                first: module_ident,
                second: other.submodule.module_ident,
            });
        }
        if let Some(pair) = subs
            .windows(2)
            .find(|w| w[0].submodule.subslot == w[1].submodule.subslot)
        {
            return Err(ExportError::SubslotInTwoApis {
                slot,
                subslot: pair[0].submodule.subslot,
                apis: (pair[0].submodule.api, pair[1].submodule.api),
            });
        }
        if module_ident == dap.module_ident {
            return Err(ExportError::DapIdentReused { slot, module_ident });
        }
        match by_ident.get(&module_ident) {
            Some(&m) => {
                // The station's modules are all fixed in their slots.
                if let Slots::Fixed(plugged) = &mut modules[m].slots {
                    let first_slot = plugged[0];
                    if let Some(difference) =
                        difference(first_slot, &slots[&first_slot], slot, subs)
                    {
                        return Err(ExportError::ModuleDiffers {
                            module_ident,
                            first_slot,
                            slot,
                            difference,
                        });
                    }
                    plugged.push(slot);
                }
            }
            None => {
                by_ident.insert(module_ident, modules.len());
                modules.push(PlannedModule {
                    module_ident,
                    name: None,
                    slots: Slots::Fixed(vec![slot]),
                    submodules: subs.iter().map(|&s| s.into()).collect(),
                });
            }
        }
    }

    let mut max_slot = slots.keys().next_back().copied().unwrap_or(0);
    let (mut input_bytes, mut output_bytes) = DAP_FRAME_BYTES;
    for s in slots.values().flatten() {
        let (i, o) = frame_bytes(s.submodule.input_length, s.submodule.output_length);
        input_bytes += i;
        output_bytes += o;
    }
    if let Some(catalogue) = catalogue {
        let planned = catalogue::plan(catalogue, dap.module_ident, &modules)?;
        max_slot = planned
            .iter()
            .filter_map(|m| match &m.slots {
                Slots::Allowed(allowed) => Some(*allowed.end()),
                Slots::Fixed(_) => None,
            })
            .fold(max_slot, u16::max);
        modules.extend(planned);
        // The PLC's project chooses the modules, so the frames may be as long as procimgd
        // takes them.
        (input_bytes, output_bytes) = (MAX_CR_DATA, MAX_CR_DATA);
    }

    Ok(Plan {
        dap_im,
        modules,
        max_slot,
        input_bytes,
        output_bytes,
    })
}

/// What the file says about a submodule: everything but where it is and its addresses.
fn shape(s: &StationSubmodule) -> (u32, u16, u32, u16, u16, bool, Vec<&AcceptedRecord>) {
    let sub = &s.submodule;
    let mut records: Vec<&AcceptedRecord> = s.accepts.iter().collect();
    records.sort_by_key(|r| r.index);
    (
        sub.api,
        sub.subslot,
        sub.submodule_ident,
        sub.input_length,
        sub.output_length,
        s.im,
        records,
    )
}

/// How the submodules of a module in `first_slot` and in `slot` differ, if they do.
fn difference(
    first_slot: u16,
    first: &[&StationSubmodule],
    slot: u16,
    other: &[&StationSubmodule],
) -> Option<String> {
    if first.len() != other.len() {
        return Some(format!(
            "slot {first_slot} has {} submodule(s), slot {slot} {}",
            first.len(),
            other.len()
        ));
    }
    first
        .iter()
        .zip(other)
        .find(|(a, b)| shape(a) != shape(b))
        .map(|(a, b)| {
            let (a, b) = (describe(a), describe(b));
            if a == b {
                format!("both have {a}, but the records' data differ")
            } else {
                format!("slot {first_slot} has {a}, slot {slot} {b}")
            }
        })
}

/// A submodule in a message: "subslot 1 (API 0, submodule 0x00000001, 8 bytes in, 8 out,
/// records 1, I&M)".
fn describe(s: &StationSubmodule) -> String {
    let sub = &s.submodule;
    let mut records: Vec<String> = s
        .accepts
        .iter()
        .map(|r| format!("{} ({} bytes)", r.index, r.length))
        .collect();
    records.sort();
    let records = if records.is_empty() {
        "none".to_owned()
    } else {
        records.join(" ")
    };
    format!(
        "subslot {} (API {}, submodule_ident 0x{:08X}, {} bytes in, {} out, records {records}{})",
        sub.subslot,
        sub.api,
        sub.submodule_ident,
        sub.input_length,
        sub.output_length,
        if s.im { ", I&M" } else { "" }
    )
}
