// SPDX-License-Identifier: MIT OR Apache-2.0
//! The handles the CP application watchdog's expiry stopped (see `watchdog`), until they
//! are closed: every call with one but close is refused.

use super::errors::*;
use super::sync::lock;
use std::collections::BTreeSet;
use std::sync::Mutex;

static STOPPED: Mutex<BTreeSet<u32>> = Mutex::new(BTreeSet::new());

/// Marks `handles` stopped.
pub(crate) fn stop(handles: impl IntoIterator<Item = u32>) {
    lock(&STOPPED).extend(handles);
}

/// Whether the watchdog's expiry stopped `handle`.
pub(crate) fn expired(handle: u32) -> bool {
    lock(&STOPPED).contains(&handle)
}

/// Forgets `handle` (closed).
pub(crate) fn forget(handle: u32) {
    lock(&STOPPED).remove(&handle);
}

/// The answer of every call with a handle the watchdog's expiry stopped.
pub(crate) fn refused(function: &str, handle: u32) -> u32 {
    fail(
        function,
        PNIO_ERR_NO_FW_COMMUNICATION,
        format_args!(
            "the CP application watchdog expired (PNIO_CP_trigger_watchdog did not come in \
             time): handle {handle} is stopped; close it (PNIO_controller_close or \
             PNIO_device_close) and open again"
        ),
    )
}
