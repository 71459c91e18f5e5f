// SPDX-License-Identifier: MIT OR Apache-2.0
//! Where each region of the input-image and output-sample payloads lies.

use crate::types::{
    ClientSubmoduleStatus, DeviceEntry, IMAGE_MAGIC, LAYOUT_VERSION, LayoutHeader, SubmoduleEntry,
    SubmoduleStatus,
};
use alloc::vec;
use alloc::vec::Vec;
use core::mem::size_of;

/// Largest IO data of one submodule in one direction: a PROFINET frame carries at most 1440
/// bytes of IO data and status, so one submodule can have at most 1439 bytes plus its IOPS.
pub const MAX_SUBMODULE_DATA_LEN: u16 = 1439;

/// Largest payload of any sample (64 MiB): a guard against absurd configurations.
const MAX_PAYLOAD: u64 = 64 << 20;

/// Regions are aligned to this, so each starts on its own cache line.
const REGION_ALIGN: u64 = 64;

/// The sizes and offsets of an image, derived from its submodule table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageLayout {
    /// Entries in the submodule table.
    pub submodule_count: u32,
    /// Bytes of input data.
    pub input_size: u32,
    /// Bytes of output data.
    pub output_size: u32,
    /// Offset of the [`SubmoduleStatus`] array in the input-image payload.
    pub status_offset: u32,
    /// Offset of the output mirror in the input-image payload.
    pub output_mirror_offset: u32,
    /// Bytes of the input-image payload.
    pub input_payload_size: u32,
    /// Offset of the [`ClientSubmoduleStatus`] array in an output-sample payload.
    pub client_status_offset: u32,
    /// Bytes of an output-sample payload.
    pub output_payload_size: u32,
}

/// A part of the output mirror laid out by the caller: `len` bytes in which each listed
/// submodule's outputs lie at a given offset. procimgd makes one per PROFINET output frame,
/// shaped as the frame, so that the frame goes out from the image as it stands and each
/// output byte is copied once, from the client into the image.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MirrorArea {
    /// Bytes of the area.
    pub len: u32,
    /// The submodules in it: index in the submodule table, and where in the area its
    /// outputs start.
    pub placed: Vec<(usize, u32)>,
}

/// Why a submodule table cannot be laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LayoutError {
    /// A submodule has more IO data than a frame can carry.
    SubmoduleTooLong {
        /// Index in the submodule table.
        index: usize,
        /// Its length.
        length: u16,
    },
    /// A mirror area puts a submodule's outputs where they do not fit: outside the area, over
    /// another's, a second time, or for a submodule without outputs or not in the table.
    MisplacedOutputs {
        /// Index in the submodule table.
        index: usize,
    },
    /// The whole image would exceed the payload limit.
    ImageTooLarge {
        /// Bytes the largest payload would need.
        bytes: u64,
    },
}

impl core::fmt::Display for LayoutError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            LayoutError::SubmoduleTooLong { index, length } => write!(
                f,
                "submodule #{index} has {length} bytes of IO data in one direction; \
                 at most {MAX_SUBMODULE_DATA_LEN} fit in a frame: split it"
            ),
            LayoutError::MisplacedOutputs { index } => write!(
                f,
                "submodule #{index}'s outputs were placed in the output mirror where they do \
                 not fit (outside their frame, over another submodule's, or twice): the \
                 frame layout and the submodule table disagree, which is a bug; please \
                 report it with the configuration"
            ),
            LayoutError::ImageTooLarge { bytes } => write!(
                f,
                "the process image would need {bytes} bytes per sample, over the {MAX_PAYLOAD}-byte \
                 limit: use fewer or shorter submodules, or one server per IO system"
            ),
        }
    }
}

impl core::error::Error for LayoutError {}

const fn align_up(x: u64, a: u64) -> u64 {
    x.div_ceil(a) * a
}

impl ImageLayout {
    /// Assigns data and status offsets to `submodules`, packed in table order, and returns the
    /// resulting layout. Addresses, idents and lengths are left as they are.
    pub fn assign(submodules: &mut [SubmoduleEntry]) -> Result<ImageLayout, LayoutError> {
        ImageLayout::assign_framed(submodules, &[])
    }

    /// As [`ImageLayout::assign`], with the output mirror made of `areas` first, one after
    /// another, each on its own cache line, every placed submodule's outputs where its area
    /// puts them; the outputs of the submodules in no area follow, packed in table order.
    pub fn assign_framed(
        submodules: &mut [SubmoduleEntry],
        areas: &[MirrorArea],
    ) -> Result<ImageLayout, LayoutError> {
        let mut input_size: u64 = 0;
        let mut output_size: u64 = 0;
        for (index, s) in submodules.iter().enumerate() {
            for length in [s.input_length, s.output_length] {
                if length > MAX_SUBMODULE_DATA_LEN {
                    return Err(LayoutError::SubmoduleTooLong { index, length });
                }
            }
            input_size += s.input_length as u64;
            output_size += s.output_length as u64;
        }
        let n = submodules.len() as u64;
        let status_offset = align_up(input_size, REGION_ALIGN);
        let output_mirror_offset = align_up(
            status_offset + n * size_of::<SubmoduleStatus>() as u64,
            REGION_ALIGN,
        );
        // Where each area starts, and each placed submodule's outputs.
        let mut placed: Vec<Option<u64>> = vec![None; submodules.len()];
        let mut at = output_mirror_offset;
        for area in areas {
            let mut used = vec![false; area.len as usize];
            for &(index, offset) in &area.placed {
                let len = submodules
                    .get(index)
                    .map_or(0, |s| s.output_length as usize);
                let start = offset as usize;
                let span = used.get_mut(start..start.saturating_add(len));
                let free = span.is_some_and(|span| {
                    let free = span.len() == len && span.iter().all(|u| !u);
                    span.fill(true);
                    free
                });
                let slot = placed.get_mut(index).filter(|p| p.is_none());
                match slot {
                    Some(slot) if free && len > 0 => *slot = Some(at + offset as u64),
                    _ => return Err(LayoutError::MisplacedOutputs { index }),
                }
            }
            at = align_up(at + area.len as u64, REGION_ALIGN);
        }
        let packed_at = at;
        let unplaced: u64 = submodules
            .iter()
            .zip(&placed)
            .filter(|(_, p)| p.is_none())
            .map(|(s, _)| s.output_length as u64)
            .sum();
        let input_payload_size = align_up(packed_at + unplaced, REGION_ALIGN).max(64);
        let client_status_offset = align_up(output_size, REGION_ALIGN);
        let output_payload_size = align_up(
            client_status_offset + n * size_of::<ClientSubmoduleStatus>() as u64,
            REGION_ALIGN,
        )
        .max(64);
        let largest = input_payload_size.max(output_payload_size);
        if largest > MAX_PAYLOAD {
            return Err(LayoutError::ImageTooLarge { bytes: largest });
        }

        let (mut input_at, mut output_at) = (0u32, 0u32);
        let mut packed_at = packed_at as u32;
        for (i, (s, placed)) in submodules.iter_mut().zip(placed).enumerate() {
            let i = i as u32;
            s.input_offset = input_at;
            s.output_offset = output_at;
            s.output_mirror_offset = match placed {
                Some(at) => at as u32,
                None => {
                    packed_at += s.output_length as u32;
                    packed_at - s.output_length as u32
                }
            };
            s.status_offset = status_offset as u32 + i * size_of::<SubmoduleStatus>() as u32;
            s.client_status_offset =
                client_status_offset as u32 + i * size_of::<ClientSubmoduleStatus>() as u32;
            input_at += s.input_length as u32;
            output_at += s.output_length as u32;
        }
        Ok(ImageLayout {
            submodule_count: n as u32,
            input_size: input_size as u32,
            output_size: output_size as u32,
            status_offset: status_offset as u32,
            output_mirror_offset: output_mirror_offset as u32,
            input_payload_size: input_payload_size as u32,
            client_status_offset: client_status_offset as u32,
            output_payload_size: output_payload_size as u32,
        })
    }

    /// Offset of the device table in the layout payload.
    pub const fn device_table_offset() -> u32 {
        0
    }

    /// Offset of the submodule table in the layout payload for `devices` devices.
    pub const fn submodule_table_offset(devices: u32) -> u32 {
        align_up(devices as u64 * size_of::<DeviceEntry>() as u64, 8) as u32
    }

    /// Bytes of the layout payload for `devices` devices and this layout's submodules.
    pub const fn layout_payload_size(&self, devices: u32) -> u32 {
        let end = Self::submodule_table_offset(devices) as u64
            + self.submodule_count as u64 * size_of::<SubmoduleEntry>() as u64;
        if end == 0 { 8 } else { end as u32 }
    }

    /// The layout header describing this layout, for a server in `role`
    /// ([`crate::ROLE_CONTROLLER`] or [`crate::ROLE_DEVICE`]).
    #[allow(clippy::too_many_arguments)]
    pub const fn header(
        &self,
        role: u32,
        device_count: u32,
        layout_hash: u64,
        generation: u64,
        cycle_ns: u64,
        opdone_deadline_ns: u64,
    ) -> LayoutHeader {
        LayoutHeader {
            magic: IMAGE_MAGIC,
            layout_version: LAYOUT_VERSION,
            header_size: size_of::<LayoutHeader>() as u32,
            layout_hash,
            generation,
            cycle_ns,
            opdone_deadline_ns,
            device_count,
            submodule_count: self.submodule_count,
            input_size: self.input_size,
            output_size: self.output_size,
            input_payload_size: self.input_payload_size,
            output_payload_size: self.output_payload_size,
            device_table_offset: Self::device_table_offset(),
            submodule_table_offset: Self::submodule_table_offset(device_count),
            status_offset: self.status_offset,
            output_mirror_offset: self.output_mirror_offset,
            client_status_offset: self.client_status_offset,
            role,
        }
    }

    /// The layout a header describes (as a client reads it).
    pub const fn from_header(h: &LayoutHeader) -> ImageLayout {
        ImageLayout {
            submodule_count: h.submodule_count,
            input_size: h.input_size,
            output_size: h.output_size,
            status_offset: h.status_offset,
            output_mirror_offset: h.output_mirror_offset,
            input_payload_size: h.input_payload_size,
            client_status_offset: h.client_status_offset,
            output_payload_size: h.output_payload_size,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sub(i: u16, o: u16) -> SubmoduleEntry {
        SubmoduleEntry {
            input_length: i,
            output_length: o,
            ..SubmoduleEntry::EMPTY
        }
    }

    #[test]
    fn regions_do_not_overlap_and_entries_point_inside() {
        let mut t = [sub(2, 0), sub(4, 4), sub(0, 0), sub(0, 8)];
        let l = ImageLayout::assign(&mut t).unwrap();
        assert_eq!((l.input_size, l.output_size), (6, 12));
        assert_eq!(t[1].input_offset, 2);
        assert_eq!(t[3].output_offset, 4);
        assert!(l.status_offset >= l.input_size);
        assert!(l.output_mirror_offset >= l.status_offset + 16);
        assert!(l.input_payload_size >= l.output_mirror_offset + l.output_size);
        assert_eq!(t[3].output_mirror_offset, l.output_mirror_offset + 4);
        assert_eq!(t[2].status_offset, l.status_offset + 8);
        assert!(l.output_payload_size >= l.client_status_offset + 16);
    }

    #[test]
    fn placed_outputs_lie_in_their_areas_and_the_rest_follow_packed() {
        let mut t = [sub(2, 0), sub(0, 4), sub(0, 3), sub(0, 8), sub(0, 2)];
        let areas = [
            MirrorArea {
                len: 30,
                placed: vec![(3, 20), (1, 10)],
            },
            MirrorArea {
                len: 10,
                placed: vec![(4, 5)],
            },
        ];
        let l = ImageLayout::assign_framed(&mut t, &areas).unwrap();
        let m = l.output_mirror_offset;
        assert_eq!(t[3].output_mirror_offset, m + 20);
        assert_eq!(t[1].output_mirror_offset, m + 10);
        // The second area on the next cache line, the unplaced submodule behind it.
        assert_eq!(t[4].output_mirror_offset, m + 64 + 5);
        assert_eq!(t[2].output_mirror_offset, m + 128);
        assert!(l.input_payload_size >= m + 128 + 3);
        // Output offsets (the client's sample) stay packed in table order.
        assert_eq!(
            (t[1].output_offset, t[2].output_offset, t[3].output_offset),
            (0, 4, 7)
        );
        assert_eq!(l.output_size, 17);
    }

    #[test]
    fn misplaced_outputs_are_refused() {
        let area = |placed| [MirrorArea { len: 16, placed }];
        let mut t = [sub(0, 4), sub(0, 4), sub(2, 0)];
        for (placed, index) in [
            (vec![(0, 13)], 0),        // past the area's end
            (vec![(0, 0), (1, 3)], 1), // over another's
            (vec![(0, 0), (0, 8)], 0), // twice
            (vec![(2, 0)], 2),         // no outputs
            (vec![(7, 0)], 7),         // not in the table
        ] {
            assert_eq!(
                ImageLayout::assign_framed(&mut t, &area(placed)),
                Err(LayoutError::MisplacedOutputs { index })
            );
        }
    }

    #[test]
    fn too_long_submodule_is_refused() {
        let mut t = [sub(1440, 0)];
        assert_eq!(
            ImageLayout::assign(&mut t),
            Err(LayoutError::SubmoduleTooLong {
                index: 0,
                length: 1440
            })
        );
    }

    #[test]
    fn header_round_trips() {
        let mut t = [sub(3, 5)];
        let l = ImageLayout::assign(&mut t).unwrap();
        let h = l.header(crate::ROLE_CONTROLLER, 1, 7, 9, 1_000_000, 500_000);
        assert_eq!(ImageLayout::from_header(&h), l);
        assert_eq!(h.submodule_table_offset, 264);
    }
}
