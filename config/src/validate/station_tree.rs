// SPDX-License-Identifier: MIT OR Apache-2.0
//! A station its program defines: the program says which (API, slot, subslot) holds which
//! (module, submodule) by ident numbers, as an IO-Base device program plugs, a GOAL
//! application configures its slots, or a GS20-PN host adds its items; the station's GSDML
//! says the rest, as it does for a PLC: the IO lengths, the parameter records with their
//! defaults, and where each module and submodule may go. What the tree makes is a
//! [`StationConfig`] like one from `[[station.submodule]]`, with logical addresses assigned
//! in the same way.

use std::collections::HashMap;
use std::path::Path;

use procimg_shm_layout::NO_ADDRESS;

use super::devices::{Draft, addresses};
pub use super::station::dap_config;
use super::station::{dap_submodules, frame_overflow};
use crate::SubmoduleConfig;
use crate::context::Cx;
use crate::gsdml::{Dap, Gsdml, GsdmlError, Module, Submodule};
use crate::station::{
    AcceptedRecord, MAX_RECORD_LENGTH, MAX_STATION_SLOT, StationConfig, StationSubmodule,
};

/// One submodule as the program plugs it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PlannedSubmodule {
    /// API.
    pub api: u32,
    /// Slot, 1 and up (slot 0 is the device access point, which the GSDML defines).
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// ModuleIdentNumber of the module in the slot.
    pub module_ident: u32,
    /// SubmoduleIdentNumber.
    pub submodule_ident: u32,
}

/// Why a program's tree does not make a station. Each names what the program gave and the
/// GSDML file, and says what to do.
#[derive(Debug, thiserror::Error)]
pub enum TreeError {
    /// No module of the GSDML has the ident number, or the station's DAP does not take it.
    #[error(
        "slot {slot}: module ident 0x{module_ident:08X} is not a module {file} gives the device \
         access point {dap}; plug one of its modules ({known}), or use the GSDML file that \
         describes this module"
    )]
    UnknownModule {
        /// Where.
        slot: u16,
        /// What the program gave.
        module_ident: u32,
        /// The GSDML file.
        file: String,
        /// The DAP's ID.
        dap: String,
        /// The module ident numbers it takes.
        known: String,
    },
    /// The module has no submodule with the ident number.
    #[error(
        "slot {slot} subslot {subslot}: module 0x{module_ident:08X} ({module}) of {file} has no \
         submodule with ident 0x{submodule_ident:08X}; its submodules are {known}"
    )]
    UnknownSubmodule {
        /// Where.
        slot: u16,
        /// Where.
        subslot: u16,
        /// The module.
        module_ident: u32,
        /// Its ID in the file.
        module: String,
        /// What the program gave.
        submodule_ident: u32,
        /// The GSDML file.
        file: String,
        /// The submodule ident numbers it has.
        known: String,
    },
    /// The slot is outside what the GSDML allows: the DAP's `PhysicalSlots`, or the
    /// module's `AllowedInSlots`.
    #[error(
        "slot {slot}: {what} of {file} allows slots {allowed}, not {slot}; plug the module \
         in one of those"
    )]
    Slot {
        /// Where.
        slot: u16,
        /// Which rule: "the device access point's PhysicalSlots", "module 0x... (ID)".
        what: String,
        /// The GSDML file.
        file: String,
        /// The slots allowed.
        allowed: String,
    },
    /// The subslot is not one the module's submodule may go in.
    #[error(
        "slot {slot} subslot {subslot}: submodule 0x{submodule_ident:08X} of module \
         0x{module_ident:08X} goes in subslots {allowed} ({file}), not {subslot}"
    )]
    Subslot {
        /// Where.
        slot: u16,
        /// Where.
        subslot: u16,
        /// The module.
        module_ident: u32,
        /// The submodule.
        submodule_ident: u32,
        /// The GSDML file.
        file: String,
        /// The subslots allowed.
        allowed: String,
    },
    /// Slot 0, subslot 0, a subslot of an interface or port, or a slot beyond the last.
    #[error(
        "slot {slot} subslot {subslot}: not a place for a program's submodule; use slots 1 to \
         {MAX_STATION_SLOT} and subslots 1 to 32767 (slot 0 is the device access point, \
         which the GSDML defines)"
    )]
    Place {
        /// Where.
        slot: u16,
        /// Where.
        subslot: u16,
    },
    /// Two submodules at one place.
    #[error("API {api} slot {slot} subslot {subslot} is plugged twice; plug each place once")]
    Twice {
        /// API.
        api: u32,
        /// Where.
        slot: u16,
        /// Where.
        subslot: u16,
    },
    /// Two module ident numbers in one slot.
    #[error(
        "slot {slot} holds one module, and the program gives it two: 0x{first:08X} and \
         0x{second:08X}; plug the submodules of a slot with the same module ident"
    )]
    TwoModules {
        /// Where.
        slot: u16,
        /// The first ident.
        first: u32,
        /// The other.
        second: u32,
    },
    /// The cyclic data does not fit a frame.
    #[error("{0}")]
    Frame(String),
    /// A parameter record of the GSDML the station cannot accept.
    #[error(
        "slot {slot} subslot {subslot}: parameter record {index} of {file} is {length} bytes, \
         more than the {MAX_RECORD_LENGTH} a station accepts"
    )]
    Record {
        /// Where.
        slot: u16,
        /// Where.
        subslot: u16,
        /// Its index.
        index: u16,
        /// Its length.
        length: usize,
        /// The GSDML file.
        file: String,
    },
    /// The GSDML's description of the submodule is unreadable (its IO data or records).
    #[error("{0}")]
    Gsdml(#[from] GsdmlError),
    /// No logical addresses for the tree.
    #[error("the station's logical addresses: {0}")]
    Addresses(String),
}

/// The station `base` (its identity) as the device access point `dap` of `gsdml` in slot 0
/// (its submodule, interface and port with the file's ident numbers) and the program's
/// `tree` after it, each submodule's IO lengths and parameter records from the file.
/// Nothing of `base`'s submodules stays.
pub fn define_station(
    base: &StationConfig,
    gsdml: &Gsdml,
    dap: &Dap,
    tree: &[PlannedSubmodule],
) -> Result<StationConfig, TreeError> {
    let file = gsdml.origin.clone();
    let dap_idents = dap_config(dap);
    let mut submodules = dap_submodules(&dap_idents);
    let mut places: HashMap<(u32, u16, u16), ()> = HashMap::new();
    let mut slots: HashMap<(u32, u16), u32> = HashMap::new();
    for p in tree {
        if p.slot == 0 || p.slot > MAX_STATION_SLOT || p.subslot == 0 || p.subslot >= 0x8000 {
            return Err(TreeError::Place {
                slot: p.slot,
                subslot: p.subslot,
            });
        }
        if places.insert((p.api, p.slot, p.subslot), ()).is_some() {
            return Err(TreeError::Twice {
                api: p.api,
                slot: p.slot,
                subslot: p.subslot,
            });
        }
        if let Some(&first) = slots.get(&(p.api, p.slot))
            && first != p.module_ident
        {
            return Err(TreeError::TwoModules {
                slot: p.slot,
                first,
                second: p.module_ident,
            });
        }
        slots.insert((p.api, p.slot), p.module_ident);
        if let Some(physical) = &dap.physical_slots
            && !physical.contains(u32::from(p.slot))
        {
            return Err(TreeError::Slot {
                slot: p.slot,
                what: format!("the device access point {}'s PhysicalSlots", dap.id),
                file,
                allowed: physical.to_string(),
            });
        }
        let module = module_of(gsdml, dap, p)?;
        let submodule = submodule_of(gsdml, module, p)?;
        let lengths = gsdml.io_lengths(submodule)?;
        let mut accepts = Vec::new();
        for r in gsdml.records(submodule)? {
            let length = u16::try_from(r.data.len())
                .ok()
                .filter(|&l| l > 0 && l <= MAX_RECORD_LENGTH)
                .ok_or_else(|| TreeError::Record {
                    slot: p.slot,
                    subslot: p.subslot,
                    index: r.index,
                    length: r.data.len(),
                    file: file.clone(),
                })?;
            // Indexes above 0x7FFF are PROFINET's, answered by the station itself.
            if r.index <= 0x7FFF {
                accepts.push(AcceptedRecord {
                    index: r.index,
                    length,
                    initial: r.data,
                });
            }
        }
        submodules.push(StationSubmodule {
            submodule: SubmoduleConfig {
                api: p.api,
                slot: p.slot,
                subslot: p.subslot,
                module_ident: p.module_ident,
                submodule_ident: p.submodule_ident,
                input_length: lengths.input,
                output_length: lengths.output,
                input_address: NO_ADDRESS,
                output_address: NO_ADDRESS,
                rt_class: 1,
                records: Vec::new(),
            },
            accepts,
            // I&M of its own where the file says the PLC may write its I&M records.
            im: submodule.writeable_im.is_some(),
            plugged: true,
        });
    }
    if let Some(message) = frame_overflow(&submodules) {
        return Err(TreeError::Frame(message));
    }
    assign_addresses(&base.name, &mut submodules)?;
    Ok(StationConfig {
        dap: dap_idents,
        submodules,
        ..base.clone()
    })
}

/// The module `p` plugs: one the DAP takes, allowed in `p`'s slot.
fn module_of<'g>(
    gsdml: &'g Gsdml,
    dap: &Dap,
    p: &PlannedSubmodule,
) -> Result<&'g Module, TreeError> {
    let useable = |m: &Module| dap.useable_modules.iter().find(|r| r.target == m.id);
    let Some((module, plug)) = gsdml
        .modules
        .iter()
        .filter(|m| m.module_ident == p.module_ident)
        .find_map(|m| useable(m).map(|r| (m, r)))
    else {
        let known: Vec<String> = dap
            .useable_modules
            .iter()
            .filter_map(|r| gsdml.module(&r.target))
            .map(|m| format!("0x{:08X}", m.module_ident))
            .collect();
        return Err(TreeError::UnknownModule {
            slot: p.slot,
            module_ident: p.module_ident,
            file: gsdml.origin.clone(),
            dap: dap.id.clone(),
            known: if known.is_empty() {
                "none".to_owned()
            } else {
                known.join(", ")
            },
        });
    };
    if plug.allows(u32::from(p.slot)) == Some(false) {
        return Err(TreeError::Slot {
            slot: p.slot,
            what: format!("module 0x{:08X} ({})", module.module_ident, module.id),
            file: gsdml.origin.clone(),
            allowed: plug.positions(),
        });
    }
    Ok(module)
}

/// The submodule `p` plugs into `module`: one of its own (fixed in subslots) or a pluggable
/// one it takes, allowed in `p`'s subslot.
fn submodule_of<'g>(
    gsdml: &'g Gsdml,
    module: &'g Module,
    p: &PlannedSubmodule,
) -> Result<&'g Submodule, TreeError> {
    let subslot = u32::from(p.subslot);
    let subslot_error = |allowed: String| TreeError::Subslot {
        slot: p.slot,
        subslot: p.subslot,
        module_ident: p.module_ident,
        submodule_ident: p.submodule_ident,
        file: gsdml.origin.clone(),
        allowed,
    };
    let own: Vec<&Submodule> = module
        .submodules
        .iter()
        .filter(|s| s.submodule_ident == p.submodule_ident && s.api == p.api)
        .collect();
    if let Some(s) = own
        .iter()
        .find(|s| s.subslots.as_ref().is_none_or(|l| l.contains(subslot)))
    {
        return Ok(s);
    }
    for r in &module.useable_submodules {
        let Some(s) = gsdml.pluggable(&r.target) else {
            continue;
        };
        if s.submodule_ident != p.submodule_ident || s.api != p.api {
            continue;
        }
        return match r.allows(subslot) {
            Some(false) => Err(subslot_error(r.positions())),
            _ => Ok(s),
        };
    }
    if let Some(s) = own.first() {
        let allowed = s
            .subslots
            .as_ref()
            .map_or_else(|| "1".to_owned(), ToString::to_string);
        return Err(subslot_error(allowed));
    }
    let known: Vec<String> = module
        .submodules
        .iter()
        .map(|s| s.submodule_ident)
        .chain(
            module
                .useable_submodules
                .iter()
                .filter_map(|r| gsdml.pluggable(&r.target))
                .map(|s| s.submodule_ident),
        )
        .map(|i| format!("0x{i:08X}"))
        .collect();
    Err(TreeError::UnknownSubmodule {
        slot: p.slot,
        subslot: p.subslot,
        module_ident: p.module_ident,
        module: module.id.clone(),
        submodule_ident: p.submodule_ident,
        file: gsdml.origin.clone(),
        known: if known.is_empty() {
            "none".to_owned()
        } else {
            known.join(", ")
        },
    })
}

/// Logical addresses for every submodule, assigned as for `[[station.submodule]]` without
/// explicit addresses.
fn assign_addresses(name: &str, submodules: &mut [StationSubmodule]) -> Result<(), TreeError> {
    let cx = Cx {
        text: "",
        origin: "the station its program defined",
        dir: Path::new("."),
        interface: None,
    };
    let drafts: Vec<Draft> = submodules
        .iter()
        .map(|s| Draft {
            key: format!("slot {} subslot {}", s.submodule.slot, s.submodule.subslot),
            span: 0..0,
            input_address: None,
            output_address: None,
            diagnostic_address: None,
        })
        .collect();
    let named: Vec<(&str, &Draft, &SubmoduleConfig)> = drafts
        .iter()
        .zip(submodules.iter())
        .map(|(d, s)| (name, d, &s.submodule))
        .collect();
    let [inputs, outputs] =
        addresses(&cx, &named).map_err(|e| TreeError::Addresses(e.to_string()))?;
    for ((s, input), output) in submodules.iter_mut().zip(inputs).zip(outputs) {
        s.submodule.input_address = input;
        s.submodule.output_address = output;
    }
    Ok(())
}
