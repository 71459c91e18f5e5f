// SPDX-License-Identifier: MIT OR Apache-2.0
//! The station the host defines in Config mode: its device or basket, its items by slot,
//! its network settings, MAC and serial number — and the rules of adding them (reference
//! §1.3, §1.6 error bits 1 and 8, §1.7 layout).

use std::collections::BTreeMap;
use std::net::Ipv4Addr;

use crate::frame::MAX_IO_DATA;
use crate::messages::config::AddItemError;
use crate::messages::{
    AddItem, AddressMode, ItemId, MacAddress, NetworkConfigError, SetNetworkConfig,
};

pub use crate::messages::item::MAX_ITEMS;

/// One item at one slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ItemSlot {
    /// The item.
    pub item: ItemId,
    /// The slot (the Add Item position).
    pub slot: u16,
}

/// The baskets the module knows, by basket ID: in the real module a configuration tool
/// stores them in its flash; here the bridge loads them (from a TOML file) and hands them
/// to the link.
pub type Baskets = BTreeMap<u16, Vec<ItemSlot>>;

/// The network settings of a valid Set Network Configuration, owned.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct NetworkSettings {
    /// Static or DHCP.
    pub mode: AddressMode,
    /// The IP address (static mode).
    pub ip: Ipv4Addr,
    /// The subnet mask (static mode).
    pub mask: Ipv4Addr,
    /// The gateway, 0.0.0.0 for none (static mode).
    pub gateway: Ipv4Addr,
    /// The first DNS server, 0.0.0.0 for none.
    pub dns1: Ipv4Addr,
    /// The second DNS server, 0.0.0.0 for none.
    pub dns2: Ipv4Addr,
    /// The host name in lower case: the PROFINET station name.
    pub station_name: String,
}

impl NetworkSettings {
    /// The settings of a frame, if valid (error bit 3 otherwise).
    pub fn from_frame(c: &SetNetworkConfig<'_>) -> Result<NetworkSettings, NetworkConfigError> {
        c.validate()?;
        Ok(NetworkSettings {
            mode: c.mode,
            ip: c.ip,
            mask: c.mask,
            gateway: c.gateway,
            dns1: c.dns1,
            dns2: c.dns2,
            station_name: c.station_name()?,
        })
    }
}

/// How the station is being defined: whichever comes first locks the other out until a
/// reset (§1.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Definition {
    /// Add Device and Add Item.
    Device {
        /// The device ID (Add Item needs it first).
        device_id: u16,
    },
    /// Add Basket.
    Basket {
        /// The basket ID.
        basket_id: u16,
    },
}

/// Why an Add Device, Add Item or Add Basket was not taken (error bit 1).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AddError {
    /// Add Item before Add Device.
    #[error("Add Item before Add Device: send Add Device first")]
    NoDevice,
    /// A second Add Device with another ID.
    #[error(
        "the device is already added as {had}; a second Add Device ({sent}) needs a Request Reset first"
    )]
    DeviceAgain {
        /// The ID taken.
        had: u16,
        /// The ID sent now.
        sent: u16,
    },
    /// The item ID or the slot is invalid.
    #[error(transparent)]
    Item(#[from] AddItemError),
    /// The slot already has another item.
    #[error("slot {slot} already has {had}; give each item its own slot")]
    SlotTaken {
        /// The slot.
        slot: u16,
        /// The item it has.
        had: ItemId,
    },
    /// More items than [`MAX_ITEMS`].
    #[error("the station has its maximum of {MAX_ITEMS} items; use larger items")]
    TooManyItems,
    /// The items' inputs or outputs would exceed 384 bytes.
    #[error(
        "{item} would make the {what} {total} bytes, over the module's 384; use fewer or smaller items"
    )]
    TooManyBytes {
        /// The item.
        item: ItemId,
        /// "inputs" or "outputs".
        what: &'static str,
        /// The total it would make.
        total: usize,
    },
    /// A second Add Basket.
    #[error("a basket is already added ({had}); Add Basket is valid once, until a Request Reset")]
    BasketAgain {
        /// The basket taken.
        had: u16,
    },
    /// No basket of that ID.
    #[error("there is no basket {0}; the baskets are those of the basket file")]
    UnknownBasket(u16),
    /// The basket has no items, or items that do not fit together.
    #[error("basket {basket_id} cannot be used: {reason}")]
    BadBasket {
        /// The basket.
        basket_id: u16,
        /// What is wrong with its items.
        reason: String,
    },
}

/// Why Request Start was refused (error bit 6; §1.3 lists the reasons).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, thiserror::Error)]
pub enum StartRefusal {
    /// Neither a device nor a basket was added ("bus not configured").
    #[error("the station is not defined: send Add Device and Add Item (or Add Basket) first")]
    NoDevice,
    /// A device but no item.
    #[error("the device has no item: send at least one Add Item")]
    NoItems,
    /// No valid Set Network Configuration.
    #[error("no network configuration: send Set Network Configuration first")]
    NoNetworkConfig,
    /// The Ethernet link is down.
    #[error("no network connection: the module's Ethernet link is down; plug in the cable")]
    NoLink,
    /// The network side did not take the station (a bridge's PROFINET stack refused its
    /// modules or its name).
    #[error(
        "the network side did not take the station: an item is no module of its GSDML file, \
         or the host name is no station name; see the bridge's log"
    )]
    NotTaken,
    /// The network side took the station but did not run it in time.
    #[error("the network side did not run the station in time; see the bridge's log")]
    NotRunning,
}

/// The station as the host defined it so far.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Station {
    /// Device or basket, whichever came first.
    pub definition: Option<Definition>,
    /// The items in the order added: the IO layout (§1.7).
    pub items: Vec<ItemSlot>,
    /// The last valid network configuration.
    pub network: Option<NetworkSettings>,
    /// Set MAC's address.
    pub mac: Option<MacAddress>,
    /// Set Serial Number's number.
    pub serial: Option<u32>,
}

impl Station {
    /// Bytes of input data (Set Bus Data): the items' inputs, concatenated.
    pub fn input_len(&self) -> usize {
        self.items.iter().map(|i| i.item.input_len()).sum()
    }

    /// Bytes of output data (Adapter Data): the items' outputs, concatenated.
    pub fn output_len(&self) -> usize {
        self.items.iter().map(|i| i.item.output_len()).sum()
    }

    /// Where each item's input bytes are in Set Bus Data, in the order added.
    pub fn input_offsets(&self) -> Vec<(ItemSlot, usize)> {
        offsets(&self.items, ItemId::input_len)
    }

    /// Where each item's output bytes are in Adapter Data, in the order added.
    pub fn output_offsets(&self) -> Vec<(ItemSlot, usize)> {
        offsets(&self.items, ItemId::output_len)
    }

    /// The error bit 0 condition: no device or basket, or a device without items.
    pub fn is_incomplete(&self) -> bool {
        self.items.is_empty()
    }

    /// Add Device (after the lockout check). Sending the same ID again is taken as a retry
    /// of a command whose response was lost, not as an error.
    pub(crate) fn add_device(&mut self, device_id: u16) -> Result<(), AddError> {
        match self.definition {
            Some(Definition::Device { device_id: had }) if had != device_id => {
                Err(AddError::DeviceAgain {
                    had,
                    sent: device_id,
                })
            }
            _ => {
                self.definition = Some(Definition::Device { device_id });
                Ok(())
            }
        }
    }

    /// Add Item (after the lockout check). The same item at the same slot again is a retry
    /// and changes nothing.
    pub(crate) fn add_item(&mut self, add: &AddItem) -> Result<(), AddError> {
        if self.definition.is_none() {
            return Err(AddError::NoDevice);
        }
        let (item, slot) = add.validate()?;
        if let Some(had) = self.items.iter().find(|i| i.slot == slot) {
            return if had.item == item {
                Ok(())
            } else {
                Err(AddError::SlotTaken {
                    slot,
                    had: had.item,
                })
            };
        }
        let new = ItemSlot { item, slot };
        check_fits(&self.items, new)?;
        self.items.push(new);
        Ok(())
    }

    /// Add Basket (after the lockout check): the basket's items become the station's.
    pub(crate) fn add_basket(&mut self, basket_id: u16, baskets: &Baskets) -> Result<(), AddError> {
        if let Some(Definition::Basket { basket_id: had }) = self.definition {
            return Err(AddError::BasketAgain { had });
        }
        let items = baskets
            .get(&basket_id)
            .ok_or(AddError::UnknownBasket(basket_id))?;
        let bad = |reason: String| AddError::BadBasket { basket_id, reason };
        if items.is_empty() {
            return Err(bad("it has no items".into()));
        }
        let mut taken: Vec<ItemSlot> = Vec::with_capacity(items.len());
        for &i in items {
            if !(1..=AddItem::MAX_SLOT).contains(&i.slot) || taken.iter().any(|t| t.slot == i.slot)
            {
                return Err(bad(format!("slot {} is invalid or used twice", i.slot)));
            }
            check_fits(&taken, i).map_err(|e| bad(e.to_string()))?;
            taken.push(i);
        }
        self.definition = Some(Definition::Basket { basket_id });
        self.items = taken;
        Ok(())
    }

    /// The first reason the station cannot start yet, link aside.
    pub(crate) fn start_refusal(&self) -> Option<StartRefusal> {
        if self.definition.is_none() {
            Some(StartRefusal::NoDevice)
        } else if self.items.is_empty() {
            Some(StartRefusal::NoItems)
        } else if self.network.is_none() {
            Some(StartRefusal::NoNetworkConfig)
        } else {
            None
        }
    }
}

/// Whether `new` fits after `items`: the item count and the bytes each way.
fn check_fits(items: &[ItemSlot], new: ItemSlot) -> Result<(), AddError> {
    if items.len() >= MAX_ITEMS {
        return Err(AddError::TooManyItems);
    }
    let total =
        |f: fn(ItemId) -> usize| items.iter().map(|i| f(i.item)).sum::<usize>() + f(new.item);
    for (what, f) in [
        ("inputs", ItemId::input_len as fn(ItemId) -> usize),
        ("outputs", ItemId::output_len),
    ] {
        let total = total(f);
        if total > MAX_IO_DATA {
            return Err(AddError::TooManyBytes {
                item: new.item,
                what,
                total,
            });
        }
    }
    Ok(())
}

fn offsets(items: &[ItemSlot], len: fn(ItemId) -> usize) -> Vec<(ItemSlot, usize)> {
    let mut at = 0;
    items
        .iter()
        .map(|&i| {
            let here = at;
            at += len(i.item);
            (i, here)
        })
        .collect()
}
