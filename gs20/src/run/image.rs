// SPDX-License-Identifier: MIT OR Apache-2.0
//! Where the host's bytes are in procimgd's image: the host's input bytes (Set Bus Data) are
//! the items' I data concatenated in the order added, its output bytes (Adapter Data) their
//! Q data likewise (reference §1.7). Directions are the PLC's, as procimgd names them in the
//! device role: the I data is what a client writes (the image's outputs), the Q data what it
//! reads (the image's inputs).

use procimg_client::Layout;
use procimg_gs20::link::ItemSlot;

/// One item's submodule in the layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Mapped {
    /// Its index in the layout.
    submodule: usize,
    /// The logical address of its I data (the client's write address), if it has any.
    i_address: u32,
    /// Bytes of I data: the item's inputs.
    i_len: usize,
    /// Where its Q data is in the input-image payload.
    q_offset: usize,
    /// Bytes of Q data: the item's outputs.
    q_len: usize,
}

/// The host's items, found in the station's layout.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImageMap {
    items: Vec<Mapped>,
}

/// Why the station procimgd runs is not the host's.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LayoutMismatch {
    /// No submodule at the item's slot.
    #[error(
        "procimgd's station has no submodule at slot {slot}, where the host added item {item}; \
         the station was defined by another program, or the station's GSDML file gives the \
         module other IO lengths than the item's"
    )]
    Missing {
        /// The slot.
        slot: u16,
        /// The item ID.
        item: u16,
    },
    /// A submodule with other ident numbers or lengths.
    #[error(
        "procimgd's station has module 0x{module:08X} with {i_len} bytes of I data and {q_len} \
         of Q data at slot {slot}, where the host added item {item} ({want_i} and {want_q}); \
         write the station's GSDML file with `procimg-gs20 gsdml` so that every item's module \
         has the item's lengths"
    )]
    Different {
        /// The slot.
        slot: u16,
        /// The item ID.
        item: u16,
        /// The module ident found.
        module: u32,
        /// Its I data bytes.
        i_len: u16,
        /// Its Q data bytes.
        q_len: u16,
        /// The item's input bytes.
        want_i: usize,
        /// The item's output bytes.
        want_q: usize,
    },
}

impl ImageMap {
    /// Finds `items` in `layout` (a device role's): each at its slot, subslot 1, with the
    /// item's ident number and lengths.
    pub fn new(layout: &Layout, items: &[ItemSlot]) -> Result<ImageMap, LayoutMismatch> {
        let items = items
            .iter()
            .map(|i| {
                let id = i.item.to_u16();
                let submodule = layout
                    .submodules
                    .iter()
                    .position(|e| (e.api, e.slot, e.subslot) == (0, i.slot, 1))
                    .ok_or(LayoutMismatch::Missing {
                        slot: i.slot,
                        item: id,
                    })?;
                let e = &layout.submodules[submodule];
                let (want_i, want_q) = (i.item.input_len(), i.item.output_len());
                // The device role: the client writes the I data (the image's outputs) and
                // reads the Q data (the image's inputs).
                if e.module_ident != i.item.module_ident()
                    || usize::from(e.output_length) != want_i
                    || usize::from(e.input_length) != want_q
                {
                    return Err(LayoutMismatch::Different {
                        slot: i.slot,
                        item: id,
                        module: e.module_ident,
                        i_len: e.output_length,
                        q_len: e.input_length,
                        want_i,
                        want_q,
                    });
                }
                Ok(Mapped {
                    submodule,
                    i_address: e.output_address,
                    i_len: want_i,
                    q_offset: e.input_offset as usize,
                    q_len: want_q,
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(ImageMap { items })
    }

    /// Bytes of the host's input image.
    pub fn input_len(&self) -> usize {
        self.items.iter().map(|m| m.i_len).sum()
    }

    /// Bytes of the host's output image.
    pub fn output_len(&self) -> usize {
        self.items.iter().map(|m| m.q_len).sum()
    }

    /// The submodules with I data, each with its address and its part of the host's input
    /// image `inputs` (which has [`input_len`](Self::input_len) bytes).
    pub fn input_parts<'a>(
        &'a self,
        inputs: &'a [u8],
    ) -> impl Iterator<Item = (usize, u32, &'a [u8])> + 'a {
        let mut at = 0;
        self.items.iter().filter(|m| m.i_len > 0).map(move |m| {
            let part = inputs.get(at..at + m.i_len).unwrap_or(&[]);
            at += m.i_len;
            (m.submodule, m.i_address, part)
        })
    }

    /// The host's output image from one input-image payload: every item's Q data of the
    /// same image, so never torn. `None` if the payload is shorter than the layout says.
    pub fn outputs(&self, payload: &[u8]) -> Option<Vec<u8>> {
        let mut out = Vec::with_capacity(self.output_len());
        for m in &self.items {
            out.extend_from_slice(payload.get(m.q_offset..m.q_offset + m.q_len)?);
        }
        Some(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_client::Layout;
    use procimg_gs20::messages::ItemId;
    use procimg_shm_layout::{LayoutHeader, NO_ADDRESS, SubmoduleEntry};

    fn entry(slot: u16, module: u32, i: u16, q: u16, i_addr: u32, q_off: u32) -> SubmoduleEntry {
        SubmoduleEntry {
            slot,
            subslot: 1,
            module_ident: module,
            submodule_ident: 1,
            output_length: i,
            input_length: q,
            output_address: if i > 0 { i_addr } else { NO_ADDRESS },
            input_offset: q_off,
            ..SubmoduleEntry::EMPTY
        }
    }

    fn layout(submodules: Vec<SubmoduleEntry>) -> Layout {
        Layout {
            header: LayoutHeader::default(),
            devices: Vec::new(),
            submodules,
        }
    }

    fn items(list: &[(u16, u16)]) -> Vec<ItemSlot> {
        list.iter()
            .map(|&(id, slot)| ItemSlot {
                item: ItemId::from_u16(id).unwrap(),
                slot,
            })
            .collect()
    }

    #[test]
    fn the_host_images_are_the_items_in_the_order_added() {
        // The DAP first, then the items in slot order; the host added slot 3 before slot 1.
        let l = layout(vec![
            entry(0, 1, 0, 0, 0, 0),
            entry(1, 3002, 2, 2, 100, 0),
            entry(3, 2004, 0, 4, 0, 2),
        ]);
        let map = ImageMap::new(&l, &items(&[(2004, 3), (3002, 1)])).unwrap();
        assert_eq!((map.input_len(), map.output_len()), (2, 6));
        let payload = [0xA0, 0xA1, 0xB0, 0xB1, 0xB2, 0xB3, 0xFF];
        assert_eq!(
            map.outputs(&payload).unwrap(),
            [0xB0, 0xB1, 0xB2, 0xB3, 0xA0, 0xA1]
        );
        let parts: Vec<_> = map.input_parts(&[7, 8]).collect();
        assert_eq!(parts, [(1, 100, &[7u8, 8][..])]);
        assert_eq!(map.outputs(&payload[..3]), None);
    }

    #[test]
    fn a_station_that_is_not_the_hosts_is_named() {
        let l = layout(vec![entry(1, 0x10, 8, 8, 0, 0)]);
        let e = ImageMap::new(&l, &items(&[(3008, 1)])).unwrap_err();
        assert!(
            matches!(e, LayoutMismatch::Different { module: 0x10, .. }),
            "{e}"
        );
        let e = ImageMap::new(&l, &items(&[(3008, 2)])).unwrap_err();
        assert_eq!(
            e,
            LayoutMismatch::Missing {
                slot: 2,
                item: 3008
            }
        );
    }
}
