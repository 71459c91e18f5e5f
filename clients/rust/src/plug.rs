// SPDX-License-Identifier: MIT OR Apache-2.0
//! In the device role: the managing client plugs and pulls the station's submodules, as
//! IO-Base's `PNIO_sub_plug`/`PNIO_sub_pull` and GOAL's and GS20-PN's add/remove item do.
//!
//! The image is fixed from the start: only the configured positions exist, each with its
//! configured IO lengths and its place in the image. A submodule configured with
//! `plugged = false` starts pulled and waits for a plug; any plugged one may be pulled and
//! plugged again. What the PLC sees:
//!
//! - without an AR, the next Connect finds the tree as it is (its ModuleDiffBlock names
//!   what is missing or different);
//! - in data exchange, a Pull alarm (the submodule's data turns BAD at once), a Plug alarm
//!   when the plugged submodule is the one the PLC expects (the PLC writes its parameters
//!   again, then its data turns GOOD), or a Plug Wrong Submodule alarm (other ident
//!   numbers: its data stays BAD);
//! - between the PLC's Connect and data exchange, plug and pull are refused: try again
//!   once the AR is in data exchange (IO-Base's `PNIO_AR_REASON_PULLPLUG`).
//!
//! Every subscriber learns of it by a
//! [`Notification::StationPlug`](crate::Notification::StationPlug). A refusal is
//! [`ControlError::Refused`] with a [`Refusal::StationPlug`](crate::Refusal::StationPlug),
//! whose [`PlugRefusal`](crate::PlugRefusal) says why (no such position, taken, empty,
//! the AR starting up).

use crate::client::Client;
use crate::error::ControlError;
use procimg_control::DeviceRequest;

impl Client {
    /// Plugs a submodule with these ident numbers at the configured position
    /// `api`/`slot`/`subslot`.
    pub fn plug_submodule(
        &self,
        (api, slot, subslot): (u32, u16, u16),
        module_ident: u32,
        submodule_ident: u32,
    ) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationPlug {
            api,
            slot,
            subslot,
            module_ident,
            submodule_ident,
        })
    }

    /// Pulls the submodule at `api`/`slot`/`subslot`.
    pub fn pull_submodule(
        &self,
        (api, slot, subslot): (u32, u16, u16),
    ) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationPull { api, slot, subslot })
    }

    /// Tells the PLC that the submodule's data is valid again after it was BAD for a while
    /// (its provider came back): a Return of Submodule alarm. Refused without an AR in data
    /// exchange that holds the submodule.
    pub fn return_submodule(
        &self,
        (api, slot, subslot): (u32, u16, u16),
    ) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationReturnSubmodule { api, slot, subslot })
    }
}
