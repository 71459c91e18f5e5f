// SPDX-License-Identifier: MIT OR Apache-2.0
//! The Config commands that define the station (reference §1.3, §1.5): Add Basket, Add
//! Device, Add Item, Set MAC, Set Serial Number, and the three requests without data.

use core::fmt;

use super::item::{ItemId, ItemIdError};
use super::{Message, ParseError, Reader, Writer};
use crate::frame::{EmitError, FrameId};

/// Add Basket (0x01, LEN 2): select a basket (a stored group of items) by its ID.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AddBasket {
    /// The basket ID (arbitrary, chosen by whoever made the basket file).
    pub basket_id: u16,
}

/// Add Device (0x02, LEN 2): the device ID, before the items.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AddDevice {
    /// The device ID. The reference does not say what it selects (§1.5 gives only its
    /// type); it is kept as sent.
    pub device_id: u16,
}

/// Add Item (0x03, LEN 6): one item at one slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AddItem {
    /// The item ID as sent (see [`ItemId`]; [`AddItem::validate`] checks it).
    pub item_id: u16,
    /// The position, which is the PLC's slot number (§1.7).
    pub position: u32,
}

/// Why an Add Item cannot be taken (error bit 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, thiserror::Error)]
pub enum AddItemError {
    /// The item ID is not in the catalogue.
    #[error(transparent)]
    Item(#[from] ItemIdError),
    /// The position is no slot an item can have.
    #[error(
        "position {position} is no slot for an item: use 1 to {} (slot 0 is the module's \
         own, the DAP), the slot the PLC's project has the module in",
        AddItem::MAX_SLOT
    )]
    Slot {
        /// The position sent.
        position: u32,
    },
}

impl AddItem {
    /// The last slot an item may have: the item catalogue's last
    /// ([`super::item::MAX_SLOT`], 64).
    pub const MAX_SLOT: u16 = super::item::MAX_SLOT;

    /// The item and its slot, if both are valid.
    ///
    /// The reference says only "position = slot". Chosen: slots 1 to [`AddItem::MAX_SLOT`];
    /// slot 0 is the DAP (the module itself) in PROFINET, and the catalogue's GSDML file
    /// allows the items no other slots, so that a host learns of a position the PLC's
    /// project could not match at Add Item, not at Request Start.
    pub fn validate(&self) -> Result<(ItemId, u16), AddItemError> {
        let item = ItemId::from_u16(self.item_id)?;
        match u16::try_from(self.position) {
            Ok(slot @ 1..=AddItem::MAX_SLOT) => Ok((item, slot)),
            _ => Err(AddItemError::Slot {
                position: self.position,
            }),
        }
    }
}

/// A MAC address, most significant octet first.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MacAddress(pub [u8; 6]);

impl MacAddress {
    /// Whether the address can be a station's own: not a group address (bit 0 of the
    /// first octet) and not all zeros.
    pub fn is_unicast(&self) -> bool {
        self.0[0] & 1 == 0 && self.0 != [0; 6]
    }
}

impl fmt::Display for MacAddress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [a, b, c, d, e, g] = self.0;
        write!(f, "{a:02x}:{b:02x}:{c:02x}:{d:02x}:{e:02x}:{g:02x}")
    }
}

/// Set MAC (0x11, LEN 6): the module's MAC address.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SetMac {
    /// The address.
    pub mac: MacAddress,
}

/// Set Serial Number (0x12, LEN 4): the serial number (for I&M0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SetSerialNumber {
    /// The serial number.
    pub serial: u32,
}

/// Request Status (0x20, LEN 0): Standby → Config; in any mode, ask for the status.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct RequestStatus;

/// Request Reset (0x21, LEN 0): reset the module (back to Standby).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct RequestReset;

/// Request Start (0x22, LEN 0): Config → Pending → Run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct RequestStart;

impl<'a> Message<'a> for AddBasket {
    const ID: FrameId = FrameId::AddBasket;

    fn parse_payload(payload: &'a [u8]) -> Result<AddBasket, ParseError> {
        let mut r = Reader::new(Self::ID, payload)?;
        let basket_id = r.u16()?;
        r.end()?;
        Ok(AddBasket { basket_id })
    }

    fn payload_len(&self) -> usize {
        2
    }

    fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
        Writer::new(out).u16(self.basket_id).finish()
    }
}

impl<'a> Message<'a> for AddDevice {
    const ID: FrameId = FrameId::AddDevice;

    fn parse_payload(payload: &'a [u8]) -> Result<AddDevice, ParseError> {
        let mut r = Reader::new(Self::ID, payload)?;
        let device_id = r.u16()?;
        r.end()?;
        Ok(AddDevice { device_id })
    }

    fn payload_len(&self) -> usize {
        2
    }

    fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
        Writer::new(out).u16(self.device_id).finish()
    }
}

impl<'a> Message<'a> for AddItem {
    const ID: FrameId = FrameId::AddItem;

    fn parse_payload(payload: &'a [u8]) -> Result<AddItem, ParseError> {
        let mut r = Reader::new(Self::ID, payload)?;
        let item_id = r.u16()?;
        let position = r.u32()?;
        r.end()?;
        Ok(AddItem { item_id, position })
    }

    fn payload_len(&self) -> usize {
        6
    }

    fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
        Writer::new(out)
            .u16(self.item_id)
            .u32(self.position)
            .finish()
    }
}

impl<'a> Message<'a> for SetMac {
    const ID: FrameId = FrameId::SetMac;

    fn parse_payload(payload: &'a [u8]) -> Result<SetMac, ParseError> {
        let mut r = Reader::new(Self::ID, payload)?;
        let mac = MacAddress(r.take()?);
        r.end()?;
        Ok(SetMac { mac })
    }

    fn payload_len(&self) -> usize {
        6
    }

    fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
        Writer::new(out).bytes(&self.mac.0).finish()
    }
}

impl<'a> Message<'a> for SetSerialNumber {
    const ID: FrameId = FrameId::SetSerialNumber;

    fn parse_payload(payload: &'a [u8]) -> Result<SetSerialNumber, ParseError> {
        let mut r = Reader::new(Self::ID, payload)?;
        let serial = r.u32()?;
        r.end()?;
        Ok(SetSerialNumber { serial })
    }

    fn payload_len(&self) -> usize {
        4
    }

    fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
        Writer::new(out).u32(self.serial).finish()
    }
}

/// The three requests without data.
macro_rules! empty_message {
    ($($ty:ident),+) => {$(
        impl<'a> Message<'a> for $ty {
            const ID: FrameId = FrameId::$ty;

            fn parse_payload(payload: &'a [u8]) -> Result<$ty, ParseError> {
                Reader::new(Self::ID, payload)?.end()?;
                Ok($ty)
            }

            fn payload_len(&self) -> usize {
                0
            }

            fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
                Writer::new(out).finish()
            }
        }
    )+};
}

empty_message!(RequestStatus, RequestReset, RequestStart);
