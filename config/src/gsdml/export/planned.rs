// SPDX-License-Identifier: MIT OR Apache-2.0
//! What a GSDML file's modules are made of, as the plan has them: a module, its submodules,
//! where it goes, and the frame bytes each takes. Shared by the station's plan (`plan`) and
//! the catalogue's (`catalogue`), which builds on these without the plan.

use std::ops::RangeInclusive;

use crate::station::{AcceptedRecord, StationSubmodule};

/// Where a module goes.
pub(super) enum Slots {
    /// The station has it plugged in these slots, ascending (`FixedInSlots`).
    Fixed(Vec<u16>),
    /// A catalogue module: the PLC's project may plug it in any of these (`AllowedInSlots`).
    Allowed(RangeInclusive<u16>),
}

impl Slots {
    /// The first slot it is plugged in or allowed in.
    pub fn first(&self) -> u16 {
        match self {
            Slots::Fixed(slots) => slots.first().copied().unwrap_or(0),
            Slots::Allowed(slots) => *slots.start(),
        }
    }
}

/// One `ModuleItem`.
pub(super) struct PlannedModule<'s> {
    pub module_ident: u32,
    /// Its name in the file; `None`: "Module 0x…".
    pub name: Option<&'s str>,
    pub slots: Slots,
    /// Its submodules (for a station's module, those of its first slot; the other slots'
    /// are the same), by subslot.
    pub submodules: Vec<FileSubmodule<'s>>,
}

/// One `VirtualSubmoduleItem` of a module: what the file says of a submodule.
pub(super) struct FileSubmodule<'s> {
    pub api: u32,
    pub subslot: u16,
    pub submodule_ident: u32,
    pub input_length: u16,
    pub output_length: u16,
    /// Whether it has I&M data of its own.
    pub im: bool,
    /// The parameter records it accepts.
    pub accepts: &'s [AcceptedRecord],
}

impl<'s> From<&'s StationSubmodule> for FileSubmodule<'s> {
    fn from(s: &'s StationSubmodule) -> FileSubmodule<'s> {
        let sub = &s.submodule;
        FileSubmodule {
            api: sub.api,
            subslot: sub.subslot,
            submodule_ident: sub.submodule_ident,
            input_length: sub.input_length,
            output_length: sub.output_length,
            im: s.im,
            accepts: &s.accepts,
        }
    }
}

/// The C_SDU bytes of the DAP's three submodules, which have no data: an IOPS in the input
/// frame and an IOCS in the output frame each.
pub(super) const DAP_FRAME_BYTES: (usize, usize) = (3, 3);

/// The bytes a submodule with these lengths takes in the input and the output frame's
/// C_SDU, as procimg's station check counts them: its data with its IOPS, the consumer's
/// IOCS in the other frame, and without data an IOPS in the input frame and an IOCS in the
/// output frame.
pub(super) fn frame_bytes(input_length: u16, output_length: u16) -> (usize, usize) {
    match (usize::from(input_length), usize::from(output_length)) {
        (0, 0) => (1, 1),
        (i, 0) => (i + 1, 1),
        (0, o) => (1, o + 1),
        (i, o) => (i + 2, o + 2),
    }
}
