// SPDX-License-Identifier: MIT OR Apache-2.0
//! The server's layout as the client saw it at attach: the submodule table, device names,
//! the layout hash. It never changes for a handle, so these calls take no lock and never
//! return `PROCIMG_ERR_BUSY`.

use super::args::{required, store, text};
use super::error::{Fail, Outcome, call, procimg_error_t};
use super::handle::{Handle, handle};
use procimg_shm_layout::SubmoduleEntry;
use std::ffi::c_char;

/// The submodule table: `*table` points to `*count` entries in image order (an entry's index
/// is the `submodule` argument of the other calls). The table belongs to the handle and stays
/// valid, unchanged, until `procimg_detach`.
///
/// # Safety
/// `client` is NULL or a live handle; `table` and `count` are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_submodules(
    client: *const Handle,
    table: *mut *const SubmoduleEntry,
    count: *mut usize,
) -> procimg_error_t {
    const F: &str = "procimg_submodules";
    call(|| -> Outcome {
        required(table, F, "table")?;
        required(count, F, "count")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        let subs = &h.layout.submodules;
        // SAFETY: both checked not NULL; writable by the caller's contract.
        unsafe {
            store(table, subs.as_ptr());
            store(count, subs.len());
        }
        Ok(())
    })
}

/// The index of the submodule of device `device` (its station name) at `slot`/`subslot`.
/// `PROCIMG_ERR_INVALID_ARGUMENT` when the layout has no such submodule.
///
/// # Safety
/// `client` is NULL or a live handle; `device` is NULL or a NUL-terminated string; `index` is
/// NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_find_submodule(
    client: *const Handle,
    device: *const c_char,
    slot: u16,
    subslot: u16,
    index: *mut usize,
) -> procimg_error_t {
    const F: &str = "procimg_find_submodule";
    call(|| -> Outcome {
        required(device, F, "device")?;
        required(index, F, "index")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        // SAFETY: a NUL-terminated string by the caller's contract.
        let device = unsafe { text(device, F, "device") }?;
        let s = h.layout.find(device, slot, subslot).ok_or_else(|| {
            Fail::invalid(
                F,
                format!(
                    "instance \"{}\" has no submodule of device \"{device}\" at slot {slot} \
                     subslot {subslot}; `procimg status --instance {}` lists them",
                    h.instance, h.instance
                ),
            )
        })?;
        // SAFETY: checked not NULL; writable by the caller's contract.
        unsafe { store(index, s) };
        Ok(())
    })
}

/// The station name of device `device` (the `device` field of a submodule entry), as a
/// NUL-terminated string owned by the handle, valid until `procimg_detach`.
///
/// # Safety
/// `client` is NULL or a live handle; `name` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_device_name(
    client: *const Handle,
    device: u16,
    name: *mut *const c_char,
) -> procimg_error_t {
    const F: &str = "procimg_device_name";
    call(|| -> Outcome {
        required(name, F, "name")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        let n = h.device_names.get(usize::from(device)).ok_or_else(|| {
            Fail::invalid(
                F,
                format!(
                    "device index {device} is out of range: instance \"{}\" has {} devices",
                    h.instance,
                    h.device_names.len()
                ),
            )
        })?;
        // SAFETY: checked not NULL; writable by the caller's contract.
        unsafe { store(name, n.as_ptr()) };
        Ok(())
    })
}

/// The layout hash of the server's IO configuration (for `PROCIMG_ATTACH_EXPECT_LAYOUT_HASH`).
///
/// # Safety
/// `client` is NULL or a live handle; `hash` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_layout_hash(
    client: *const Handle,
    hash: *mut u64,
) -> procimg_error_t {
    const F: &str = "procimg_layout_hash";
    call(|| -> Outcome {
        required(hash, F, "hash")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        // SAFETY: checked not NULL; writable by the caller's contract.
        unsafe { store(hash, h.layout.hash()) };
        Ok(())
    })
}
