// SPDX-License-Identifier: MIT OR Apache-2.0
//! Logical address assignment in the input (I) and output (Q) spaces.
//!
//! Explicit addresses are placed first (and checked for overlaps); then every submodule
//! without one gets, in configuration order, the lowest address at which its range fits.
//!
//! A submodule without any IO data (a DAP, interface or port submodule, a module that only
//! has records and alarms) has a *diagnostic address* instead, as the IO-Base manual puts
//! it: a logical address in the I space with input length 0, by which record jobs and
//! alarms name it. It takes one byte of the I space, so no input range overlaps it. Those
//! without an explicit `diagnostic_address` are assigned last, so that adding or removing
//! one never moves an input range.

use super::context::Cx;
use super::error::ConfigError;
use procimg_shm_layout::NO_ADDRESS;

/// Last usable logical address: [`NO_ADDRESS`] itself marks "no address".
pub const LAST_ADDRESS: u32 = NO_ADDRESS - 1;

/// One of the two logical address spaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Space {
    /// Inputs (device to controller).
    Input,
    /// Outputs (controller to device).
    Output,
}

impl Space {
    fn letter(self) -> char {
        match self {
            Space::Input => 'I',
            Space::Output => 'Q',
        }
    }

    fn address_key(self) -> &'static str {
        match self {
            Space::Input => "input_address",
            Space::Output => "output_address",
        }
    }

    /// The key an item's address comes from.
    fn key_of(self, item: &Item<'_>) -> &'static str {
        if item.diagnostic {
            DIAGNOSTIC_ADDRESS_KEY
        } else {
            self.address_key()
        }
    }

    fn length_key(self) -> &'static str {
        match self {
            Space::Input => "input_length",
            Space::Output => "output_length",
        }
    }

    fn noun(self) -> &'static str {
        match self {
            Space::Input => "input",
            Space::Output => "output",
        }
    }
}

/// The key of a data-less submodule's diagnostic address.
pub(super) const DIAGNOSTIC_ADDRESS_KEY: &str = "diagnostic_address";

/// A submodule's wish in one space.
pub(super) struct Item<'a> {
    /// Key path of the submodule, `device[1].submodule[0]`.
    pub key: &'a str,
    /// Name of its device.
    pub device_name: &'a str,
    /// Its slot.
    pub slot: u16,
    /// Its subslot.
    pub subslot: u16,
    /// Bytes of data in this space.
    pub length: u16,
    /// Span of the submodule's table (its `[[device.submodule]]` header).
    pub span: core::ops::Range<usize>,
    /// The address given in the file, with the span of its value.
    pub explicit: Option<(u32, core::ops::Range<usize>)>,
    /// In the I space: the submodule has no IO data at all, and this is its diagnostic
    /// address (one byte; `length` is 0).
    pub diagnostic: bool,
}

impl Item<'_> {
    /// Bytes the item takes in the space.
    fn extent(&self) -> u16 {
        if self.diagnostic { 1 } else { self.length }
    }
}

/// A range already placed: first and last address, and the item it belongs to.
#[derive(Clone, Copy)]
struct Placed {
    first: u64,
    last: u64,
    item: usize,
}

fn describe(space: Space, first: u64, last: u64) -> String {
    format!("{} {first}..{last}", space.letter())
}

/// The lowest address at which `length` bytes fit between the ranges `placed`, and where
/// the new range goes in it.
fn first_fit(placed: &[Placed], length: u64) -> (u64, usize) {
    let mut candidate: u64 = 0;
    for (i, p) in placed.iter().enumerate() {
        if candidate + length <= p.first {
            return (candidate, i);
        }
        candidate = candidate.max(p.last + 1);
    }
    (candidate, placed.len())
}

/// Assigns the addresses of `items` in `space`: the explicit ones as given, the others first
/// fit, diagnostic addresses after all IO data. Other items of length 0 get [`NO_ADDRESS`].
pub(super) fn assign(
    cx: &Cx<'_>,
    space: Space,
    items: &[Item<'_>],
) -> Result<Vec<u32>, ConfigError> {
    let mut addresses = vec![NO_ADDRESS; items.len()];
    // Sorted by `first`, never overlapping.
    let mut placed: Vec<Placed> = Vec::new();

    for (index, item) in items.iter().enumerate() {
        let Some((address, span)) = &item.explicit else {
            continue;
        };
        let key = format!("{}.{}", item.key, space.key_of(item));
        if item.extent() == 0 {
            return Err(cx.invalid(
                span.clone(),
                key,
                format!(
                    "an {noun} address is given but {len_key} is 0; remove the address or set \
                     {len_key}",
                    noun = space.noun(),
                    len_key = space.length_key(),
                ),
            ));
        }
        let first = u64::from(*address);
        let last = first + u64::from(item.extent()) - 1;
        if last > u64::from(LAST_ADDRESS) {
            return Err(cx.invalid(
                span.clone(),
                key,
                format!(
                    "{} runs past the last logical address {LAST_ADDRESS} (0x{LAST_ADDRESS:X}); \
                     give a lower address or leave it out to have one assigned",
                    describe(space, first, last)
                ),
            ));
        }
        let at = placed.partition_point(|p| p.first <= first);
        let before = at.checked_sub(1).and_then(|i| placed.get(i));
        let clash = before
            .filter(|p| p.last >= first)
            .or_else(|| placed.get(at).filter(|p| p.first <= last));
        if let Some(other) = clash {
            let other_item = items.get(other.item);
            let (name, slot, subslot) = other_item
                .map(|o| (o.device_name, o.slot, o.subslot))
                .unwrap_or_default();
            let other_line = other_item
                .and_then(|o| o.explicit.as_ref())
                .map(|(_, s)| format!(" (line {})", cx.line(s.start)))
                .unwrap_or_default();
            return Err(cx.invalid(
                span.clone(),
                key,
                format!(
                    "{} overlaps {} of device {name:?} slot {slot} subslot {subslot}{other_line}; \
                     give one of them another address or leave it out to have one assigned",
                    describe(space, first, last),
                    describe(space, other.first, other.last),
                ),
            ));
        }
        placed.insert(
            at,
            Placed {
                first,
                last,
                item: index,
            },
        );
        addresses[index] = *address;
    }

    // IO data first, then diagnostic addresses.
    for diagnostic in [false, true] {
        for (index, item) in items.iter().enumerate() {
            if item.explicit.is_some() || item.extent() == 0 || item.diagnostic != diagnostic {
                continue;
            }
            let length = u64::from(item.extent());
            let (candidate, at) = first_fit(&placed, length);
            let last = candidate + length - 1;
            let address = u32::try_from(candidate)
                .ok()
                .filter(|_| last <= u64::from(LAST_ADDRESS));
            let Some(address) = address else {
                // Unreachable with the limits on submodule count and length, but not worth a
                // panic.
                return Err(cx.invalid(
                    item.span.clone(),
                    format!("{}.{}", item.key, space.key_of(item)),
                    format!(
                        "no room is left in the {} space for {length} bytes; give explicit \
                         addresses lower down",
                        space.letter()
                    ),
                ));
            };
            placed.insert(
                at,
                Placed {
                    first: candidate,
                    last,
                    item: index,
                },
            );
            addresses[index] = address;
        }
    }
    Ok(addresses)
}
