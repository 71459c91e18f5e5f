// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the program plugs and pulls, carried out on procimgd's station through the Rust
//! client, and the IO-Base codes of procimgd's refusals.

use super::Pos;
use crate::iobase::errors::*;
use procimg_client::{Client, ControlError, PlugRefusal, Refusal};
use std::collections::BTreeMap;

/// What procimgd has at each position, as far as this library knows: the configured ident
/// numbers at first, then what the library plugged (`Some`) or pulled (`None`).
pub(crate) type Occupants = BTreeMap<Pos, Option<(u32, u32)>>;

/// Plugs `idents` at `at` on procimgd as the module doc says: into an empty position; a
/// submodule there with the same ident numbers is taken; one with others is pulled first.
pub(crate) fn plug(client: &Client, occupants: &mut Occupants, at: Pos, idents: (u32, u32)) -> u32 {
    match client.plug_submodule(at, idents.0, idents.1) {
        Ok(()) => {
            occupants.insert(at, Some(idents));
            return PNIO_OK;
        }
        Err(e) if !already_plugged(&e) => return code_of(&e),
        Err(_) => {}
    }
    if occupants.get(&at) == Some(&Some(idents)) {
        return PNIO_OK;
    }
    let code = pull(client, occupants, at);
    if code != PNIO_OK {
        return code;
    }
    match client.plug_submodule(at, idents.0, idents.1) {
        Ok(()) => {
            occupants.insert(at, Some(idents));
            PNIO_OK
        }
        Err(e) => code_of(&e),
    }
}

/// Pulls what procimgd has at `at` (nothing there is as good as pulled).
pub(crate) fn pull(client: &Client, occupants: &mut Occupants, at: Pos) -> u32 {
    match client.pull_submodule(at) {
        Ok(()) => {
            occupants.insert(at, None);
            PNIO_OK
        }
        Err(e) if not_plugged(&e) => {
            occupants.insert(at, None);
            PNIO_OK
        }
        Err(e) => code_of(&e),
    }
}

/// Why procimgd refused a plug, pull or return, if it did.
fn plug_refusal(e: &ControlError) -> Option<PlugRefusal> {
    match e {
        ControlError::Refused(Refusal::StationPlug { refused, .. }) => Some(*refused),
        _ => None,
    }
}

/// procimgd refused a plug because a submodule is plugged there.
fn already_plugged(e: &ControlError) -> bool {
    plug_refusal(e) == Some(PlugRefusal::AlreadyPlugged)
}

/// procimgd refused a pull because nothing is plugged there.
fn not_plugged(e: &ControlError) -> bool {
    plug_refusal(e) == Some(PlugRefusal::NotPlugged)
}

/// The IO-Base code for a failed request: a plug or pull between the PLC's Connect and data
/// exchange is out of sequence, one at a position the station lacks a parameter error; no
/// answer from procimgd is no firmware communication.
pub(crate) fn code_of(e: &ControlError) -> u32 {
    match e {
        ControlError::Refused(Refusal::StationPlug { refused, .. }) => match refused {
            PlugRefusal::ArStartingUp | PlugRefusal::NotInDataExchange => PNIO_ERR_SEQUENCE,
            PlugRefusal::NotConfigured | PlugRefusal::AlreadyPlugged | PlugRefusal::NotPlugged => {
                PNIO_ERR_PRM_ADD
            }
        },
        ControlError::Refused(Refusal::BadRequest { .. }) => PNIO_ERR_PRM_ADD,
        ControlError::Refused(_) | ControlError::NotDevice { .. } => PNIO_ERR_INTERNAL,
        _ => PNIO_ERR_NO_FW_COMMUNICATION,
    }
}
