// SPDX-License-Identifier: MIT OR Apache-2.0
//! The item ID rule (reference §1.5): decimal `D·1000 + n`, D the direction, n the bytes.

use core::fmt;

/// The most items a station takes (error bit 1, "maximum number of items reached").
///
/// The reference names the limit but not its value (§1.1). Chosen: 64, with the 384 bytes
/// per direction the tighter bound for all but the smallest items.
pub const MAX_ITEMS: usize = 64;

/// The highest slot an item may have: N of the catalogue's slots 1..=N and of the DAP's
/// `PhysicalSlots` 0..=N.
///
/// The reference does not say how many slots or items the module has (§1.1: only an error
/// "maximum number of items already added" exists). Taken: the limit of items,
/// [`MAX_ITEMS`] = 64, so that a host may give each of its most items a slot of its own.
pub const MAX_SLOT: u16 = MAX_ITEMS as u16;

/// What an item exchanges (the thousands digit of its ID).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ItemKind {
    /// 1: n bytes of input (host → PLC, PROFINET input data).
    Input = 1,
    /// 2: n bytes of output (PLC → host, PROFINET output data).
    Output = 2,
    /// 3: n bytes of input and n bytes of output.
    InputOutput = 3,
}

impl ItemKind {
    /// Every kind.
    pub const ALL: [ItemKind; 3] = [ItemKind::Input, ItemKind::Output, ItemKind::InputOutput];

    /// The kind of a thousands digit; `None` outside 1–3.
    pub const fn from_digit(d: u16) -> Option<ItemKind> {
        Some(match d {
            1 => ItemKind::Input,
            2 => ItemKind::Output,
            3 => ItemKind::InputOutput,
            _ => return None,
        })
    }
}

/// An item ID of the catalogue: `D·1000 + n` (3008 = 8 bytes in and 8 bytes out).
///
/// The reference's table lists n = 1, 2, 4, 8, 16, 32, 64, 128 and then 512; it skips 256,
/// and 512 contradicts the module's maximum of 384 bytes per direction (§1.1). Chosen: the
/// powers of two from 1 to 256 ([`ItemId::SIZES`]): 512 is refused (it could never fit),
/// 256 is taken as what the table meant in its place. Other n (3, 10, …) are not items of
/// the catalogue — the GSDML has no module for them — and are refused too, so that the
/// host learns at Add Item (error bit 1), not at the PLC's connect.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ItemId {
    kind: ItemKind,
    size: u16,
}

impl ItemId {
    /// The byte counts n an item may have.
    pub const SIZES: [u16; 9] = [1, 2, 4, 8, 16, 32, 64, 128, 256];

    /// The item of `kind` with `size` bytes (each way, for [`ItemKind::InputOutput`]).
    pub const fn new(kind: ItemKind, size: u16) -> Result<ItemId, ItemIdError> {
        if !size.is_power_of_two() || size > 256 {
            return Err(ItemIdError::Size {
                id: kind as u16 * 1000 + size % 1000,
                size,
            });
        }
        Ok(ItemId { kind, size })
    }

    /// The item of a raw ID as Add Item sends it.
    pub const fn from_u16(id: u16) -> Result<ItemId, ItemIdError> {
        let Some(kind) = ItemKind::from_digit(id / 1000) else {
            return Err(ItemIdError::Kind { id });
        };
        match ItemId::new(kind, id % 1000) {
            Ok(item) => Ok(item),
            Err(_) => Err(ItemIdError::Size {
                id,
                size: id % 1000,
            }),
        }
    }

    /// The raw ID, `D·1000 + n`.
    pub const fn to_u16(self) -> u16 {
        self.kind as u16 * 1000 + self.size
    }

    /// What the item exchanges.
    pub const fn kind(self) -> ItemKind {
        self.kind
    }

    /// n: its bytes (each way, for input and output).
    pub const fn size(self) -> u16 {
        self.size
    }

    /// Its input bytes (host → PLC).
    pub const fn input_len(self) -> usize {
        match self.kind {
            ItemKind::Input | ItemKind::InputOutput => self.size as usize,
            ItemKind::Output => 0,
        }
    }

    /// Its output bytes (PLC → host).
    pub const fn output_len(self) -> usize {
        match self.kind {
            ItemKind::Output | ItemKind::InputOutput => self.size as usize,
            ItemKind::Input => 0,
        }
    }

    /// The ModuleIdentNumber of the item's module in the catalogue's GSDML and in the
    /// station the bridge defines: the item ID itself (3008 → 0x00000BC0), so that a PLC
    /// project and a host's Add Item name one thing by one number.
    pub const fn module_ident(self) -> u32 {
        self.to_u16() as u32
    }

    /// The SubmoduleIdentNumber of the item's one submodule: 1 in every item module.
    pub const SUBMODULE_IDENT: u32 = 1;

    /// The whole catalogue, by kind and then by size (1001 … 1256, 2001 …, 3001 … 3256):
    /// what a GSDML of the items lists.
    pub fn all() -> impl Iterator<Item = ItemId> {
        ItemKind::ALL.into_iter().flat_map(|kind| {
            ItemId::SIZES
                .into_iter()
                .map(move |size| ItemId { kind, size })
        })
    }
}

impl fmt::Display for ItemId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let what = match self.kind {
            ItemKind::Input => "in",
            ItemKind::Output => "out",
            ItemKind::InputOutput => "in and out",
        };
        write!(f, "item {} ({} bytes {what})", self.to_u16(), self.size)
    }
}

impl TryFrom<u16> for ItemId {
    type Error = ItemIdError;

    fn try_from(id: u16) -> Result<ItemId, ItemIdError> {
        ItemId::from_u16(id)
    }
}

/// Why a number is not an item ID of the catalogue (error bit 1 at Add Item).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, thiserror::Error)]
pub enum ItemIdError {
    /// The thousands digit is not 1, 2 or 3.
    #[error(
        "item ID {id}: the thousands digit must be 1 (input), 2 (output) or 3 (both); an \
         item ID is D·1000 + n, e.g. 3008 for 8 bytes in and out"
    )]
    Kind {
        /// The ID.
        id: u16,
    },
    /// n is not one of the catalogue's sizes.
    #[error(
        "item ID {id}: {size} bytes is no item size of the catalogue; use 1, 2, 4, 8, 16, 32, \
         64, 128 or 256 bytes (several items for other sizes)"
    )]
    Size {
        /// The ID.
        id: u16,
        /// Its n.
        size: u16,
    },
}
