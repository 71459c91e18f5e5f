// SPDX-License-Identifier: MIT OR Apache-2.0
//! Writing the GSDML file of procimgd's own station (`role = "device"`): what an engineering
//! tool such as TIA Portal needs to configure a PLC that connects to it.
//!
//! [`station_gsdml`] turns a [`StationConfig`] into GSDML V2.4 text and its standard file
//! name, `GSDML-V2.4-procimg-<family>-<yyyymmdd>.xml`; the family is the station's
//! `device_type`, the date is the caller's ([`GsdmlDate`]: nothing here reads a clock).
//! [`StationGsdml::write`] puts it on disk atomically.
//!
//! The file has one device access point (slot 0: the DAP's own submodule, the interface and
//! one port, with `[station.dap]`'s ident numbers and the station's name, instance and I&M0
//! data) and one `ModuleItem` per ModuleIdentNumber, fixed in the slots it is plugged in.
//! Each submodule is a `VirtualSubmoduleItem` fixed in its subslot, with its input and output
//! data as one data item per direction and the parameter records it accepts, whose defaults
//! are their `data`. The IDs a controller configuration names them by are
//! `M_0x<module_ident>` and `M_0x<module_ident>_SS<subslot>`, so importing the file gives
//! back the station's ident numbers, lengths, subslots, APIs and records.
//!
//! A station whose program plugs its modules (`[station] gsdml = "FILE"`) may be offered more:
//! [`station_gsdml_with_catalogue`] adds a [`Catalogue`] of modules the station does not hold
//! when it starts, each allowed in a range of slots (`AllowedInSlots`), none plugged by
//! default, which the PLC's project and the program choose from.
//!
//! A module ident number stands for one set of submodules: a station whose slots of one
//! ModuleIdentNumber hold different submodules cannot be described by one GSDML file, and
//! is refused ([`ExportError::ModuleDiffers`]) rather than given two items of one ident
//! number, which an engineering tool could not tell apart.

mod catalogue;
mod date;
mod document;
mod plan;
mod planned;
mod write;
mod xml;

use core::fmt;

pub use catalogue::{Catalogue, CatalogueModule, CatalogueSubmodule};
pub use date::{DateError, GsdmlDate};
pub use write::{Destination, WriteError};

use crate::station::StationConfig;

/// The vendor named in the file and its name: the station has no vendor name of its own.
pub const VENDOR_NAME: &str = "procimg";

/// The send clock the file offers, in 31.25 µs units: 1 ms, as the examples' devices.
const SEND_CLOCK: u16 = 32;

/// The reduction ratios of RT class 1.
const REDUCTION_RATIOS: [u16; 10] = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512];

/// The GSDML file of a station.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StationGsdml {
    /// The standard file name, `GSDML-V2.4-procimg-<family>-<yyyymmdd>.xml`.
    pub file_name: String,
    /// The XML text (UTF-8, with the XML declaration).
    pub xml: String,
}

/// Why a station cannot be described by a GSDML file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ExportError {
    /// Two slots hold the same module (ModuleIdentNumber) with different submodules; one
    /// GSDML module has one set of submodules.
    ModuleDiffers {
        /// The ModuleIdentNumber.
        module_ident: u32,
        /// The first slot it is in.
        first_slot: u16,
        /// The slot where it differs.
        slot: u16,
        /// How, for the message.
        difference: String,
    },
    /// One slot holds modules of two ident numbers (in different APIs).
    SlotHoldsTwoModules {
        /// The slot.
        slot: u16,
        /// One ModuleIdentNumber.
        first: u32,
        /// The other.
        second: u32,
    },
    /// One subslot is used in two APIs.
    SubslotInTwoApis {
        /// The slot.
        slot: u16,
        /// The subslot.
        subslot: u16,
        /// The two APIs.
        apis: (u32, u32),
    },
    /// A module has the DAP's ModuleIdentNumber.
    DapIdentReused {
        /// Its slot.
        slot: u16,
        /// The ident number.
        module_ident: u32,
    },
    /// Slot 0 lists a submodule that is not one of the DAP's three as `[station.dap]`
    /// describes them (a station built by hand, not by the configuration).
    DapMismatch {
        /// The subslot.
        subslot: u16,
    },
    /// A parameter record's initial data is not as long as the record.
    RecordData {
        /// The slot.
        slot: u16,
        /// The subslot.
        subslot: u16,
        /// The record index.
        index: u16,
    },
    /// No IO cycle a PLC can choose in the file (1 ms send clock times a power of two) is a
    /// whole multiple of the station's cycle time.
    Cycle {
        /// The station's cycle time in ns.
        cycle_ns: u64,
    },
    /// A module of the catalogue cannot be offered as given.
    Catalogue {
        /// Its ModuleIdentNumber.
        module_ident: u32,
        /// Why, and what to do.
        reason: String,
    },
}

impl fmt::Display for ExportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ExportError::ModuleDiffers {
                module_ident,
                first_slot,
                slot,
                difference,
            } => write!(
                f,
                "slots {first_slot} and {slot} both hold module_ident 0x{module_ident:08X}, but \
                 with different submodules ({difference}); a GSDML module has one set of \
                 submodules, so give one of the slots another module_ident, or give both the \
                 same submodules"
            ),
            ExportError::SlotHoldsTwoModules {
                slot,
                first,
                second,
            } => write!(
                f,
                "slot {slot} holds module_ident 0x{first:08X} in one API and 0x{second:08X} in \
                 another; a GSDML file plugs one module per slot, so give the slot's \
                 submodules one module_ident, or move some to another slot"
            ),
            ExportError::SubslotInTwoApis {
                slot,
                subslot,
                apis: (a, b),
            } => write!(
                f,
                "slot {slot} subslot {subslot} is used in API {a} and in API {b}; a GSDML \
                 module has one submodule per subslot, so move one of them to another subslot"
            ),
            ExportError::DapIdentReused { slot, module_ident } => write!(
                f,
                "the module in slot {slot} has module_ident 0x{module_ident:08X}, the device \
                 access point's ([station.dap] module_ident); give it another, so that the PLC \
                 can tell them apart"
            ),
            ExportError::DapMismatch { subslot } => write!(
                f,
                "slot 0 subslot 0x{subslot:04X} is not one of the device access point's \
                 submodules as [station.dap] describes them (subslots 1, 0x8000 and 0x8001 \
                 without IO data or records); build the station from a configuration file"
            ),
            ExportError::RecordData {
                slot,
                subslot,
                index,
            } => write!(
                f,
                "record {index} of slot {slot} subslot {subslot}: its data is not as long as \
                 the record; give exactly `length` bytes of data"
            ),
            ExportError::Cycle { cycle_ns } => write!(
                f,
                "the cycle_time of {} is not a whole number of 31.25 µs that divides a PLC IO \
                 cycle of 1 ms times a power of two (1 ms to 512 ms); choose a cycle_time such \
                 as \"1ms\", \"2ms\", \"4ms\" or \"500us\"",
                crate::format_duration(*cycle_ns)
            ),
            ExportError::Catalogue {
                module_ident,
                reason,
            } => write!(f, "catalogue module 0x{module_ident:08X}: {reason}"),
        }
    }
}

impl core::error::Error for ExportError {}

/// The PLC IO cycles the file offers.
pub(super) struct Timing {
    pub send_clock: u16,
    /// The reduction ratios whose IO cycle is a whole multiple of the station's cycle.
    pub reduction_ratios: Vec<u16>,
    /// The shortest IO cycle of those, in 31.25 µs units.
    pub min_device_interval: u32,
}

fn timing(cycle_ns: u64) -> Result<Timing, ExportError> {
    let unit = crate::CYCLE_UNIT_NS;
    let cycle_units = cycle_ns / unit;
    if cycle_units == 0 || !cycle_ns.is_multiple_of(unit) {
        return Err(ExportError::Cycle { cycle_ns });
    }
    // procimgd's device serves IO cycles that are whole multiples of its own cycle.
    let reduction_ratios: Vec<u16> = REDUCTION_RATIOS
        .into_iter()
        .filter(|&rr| (u64::from(SEND_CLOCK) * u64::from(rr)).is_multiple_of(cycle_units))
        .collect();
    let Some(&shortest) = reduction_ratios.first() else {
        return Err(ExportError::Cycle { cycle_ns });
    };
    Ok(Timing {
        send_clock: SEND_CLOCK,
        reduction_ratios,
        min_device_interval: u32::from(SEND_CLOCK) * u32::from(shortest),
    })
}

/// The standard file name of the station's GSDML file,
/// `GSDML-V2.4-procimg-<family>-<yyyymmdd>.xml`: the family is the station's `device_type`
/// with every run of characters other than ASCII letters and digits as one `_` (the name's
/// parts are separated by `-`).
pub fn station_file_name(station: &StationConfig, date: GsdmlDate) -> String {
    let mut family = String::new();
    for c in station.device_type.chars() {
        if c.is_ascii_alphanumeric() {
            family.push(c);
        } else if !family.is_empty() && !family.ends_with('_') {
            family.push('_');
        }
    }
    let family = family.trim_end_matches('_');
    let family = if family.is_empty() { "device" } else { family };
    format!("GSDML-V2.4-{VENDOR_NAME}-{family}-{}.xml", date.compact())
}

/// The GSDML file of `station`, whose device runs with a cycle of `cycle_ns` (the
/// configuration's `cycle_time`), dated `date`.
pub fn station_gsdml(
    station: &StationConfig,
    cycle_ns: u64,
    date: GsdmlDate,
) -> Result<StationGsdml, ExportError> {
    export(station, None, cycle_ns, date)
}

/// The GSDML file of `station` as [`station_gsdml`] writes it, with the modules of
/// `catalogue` after the station's own: each a `ModuleItem` the device access point takes
/// in its allowed slots (`PhysicalSlots` reaching the highest), plugged in none. Since the
/// PLC's project chooses among them, the file gives the longest frames procimgd takes
/// (1440 bytes of data and status each way) as the device's maximum.
pub fn station_gsdml_with_catalogue(
    station: &StationConfig,
    catalogue: &Catalogue,
    cycle_ns: u64,
    date: GsdmlDate,
) -> Result<StationGsdml, ExportError> {
    export(station, Some(catalogue), cycle_ns, date)
}

fn export(
    station: &StationConfig,
    catalogue: Option<&Catalogue>,
    cycle_ns: u64,
    date: GsdmlDate,
) -> Result<StationGsdml, ExportError> {
    let timing = timing(cycle_ns)?;
    let plan = plan::plan(station, catalogue)?;
    Ok(StationGsdml {
        file_name: station_file_name(station, date),
        xml: document::document(station, catalogue, &plan, &timing),
    })
}

/// The ID of the `ModuleItem` of `module_ident` in a file [`station_gsdml`] wrote: what a
/// controller configuration's `module` names it by.
pub fn module_item_id(module_ident: u32) -> String {
    document::module_id(module_ident)
}

/// The ID of the `VirtualSubmoduleItem` in `subslot` of that module: what a controller
/// configuration's `submodule` names it by.
pub fn submodule_item_id(module_ident: u32, subslot: u16) -> String {
    document::submodule_id(module_ident, subslot)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reduction_ratios_follow_the_cycle() {
        let t = timing(1_000_000).unwrap();
        assert_eq!(t.reduction_ratios, REDUCTION_RATIOS);
        assert_eq!(t.min_device_interval, 32);
        let t = timing(250_000).unwrap();
        assert_eq!(t.reduction_ratios, REDUCTION_RATIOS);
        let t = timing(4_000_000).unwrap();
        assert_eq!(t.reduction_ratios, [4, 8, 16, 32, 64, 128, 256, 512]);
        assert_eq!(t.min_device_interval, 128);
        assert_eq!(timing(512_000_000).unwrap().reduction_ratios, [512]);
        for bad in [0, 3_000_000, 750_000, 1_000_001] {
            let e = timing(bad).err().unwrap();
            assert!(e.to_string().contains("cycle_time"), "{e}");
        }
    }
}
