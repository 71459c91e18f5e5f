// SPDX-License-Identifier: MIT OR Apache-2.0
//! Output claims: each output submodule is written by at most one client at a time.

use super::args::{array, text};
use super::error::{Fail, Outcome, call, procimg_error_t};
use super::handle::{Handle, handle};
use std::ffi::c_char;

/// Checks every index of `subs` against the layout.
fn check_indices(h: &Handle, subs: &[usize], function: &str) -> Result<(), Fail> {
    subs.iter()
        .try_for_each(|&s| h.submodule(s, function).map(|_| ()))
}

/// Claims the outputs of `count` submodules (indices into the submodule table), all or
/// none. `PROCIMG_ERR_REFUSED` when another client holds one of them: `procimg_last_error()`
/// names the holder (name, pid). `submodules` may be NULL when `count` is 0. Claims die with
/// the client.
///
/// # Safety
/// `client` is NULL or a live handle; `submodules` is NULL or points to `count` indices.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_claim(
    client: *mut Handle,
    submodules: *const usize,
    count: usize,
) -> procimg_error_t {
    const F: &str = "procimg_claim";
    call(|| -> Outcome {
        // SAFETY: NULL or `count` indices by the caller's contract.
        let subs = unsafe { array(submodules, count, F, "submodules") }?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        check_indices(h, subs, F)?;
        h.enter(F)?.client.claim(subs)?;
        Ok(())
    })
}

/// Releases the claims on `count` submodules. `submodules` may be NULL when `count` is 0.
///
/// # Safety
/// `client` is NULL or a live handle; `submodules` is NULL or points to `count` indices.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_release(
    client: *mut Handle,
    submodules: *const usize,
    count: usize,
) -> procimg_error_t {
    const F: &str = "procimg_release";
    call(|| -> Outcome {
        // SAFETY: NULL or `count` indices by the caller's contract.
        let subs = unsafe { array(submodules, count, F, "submodules") }?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        check_indices(h, subs, F)?;
        h.enter(F)?.client.release(subs)?;
        Ok(())
    })
}

/// Claims the outputs of every submodule of device `device` (its station name) that has
/// outputs. `PROCIMG_ERR_INVALID_ARGUMENT` when the layout has no such device,
/// `PROCIMG_ERR_REFUSED` (holder named) when another client holds one of them.
///
/// # Safety
/// `client` is NULL or a live handle; `device` is NULL or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_claim_device(
    client: *mut Handle,
    device: *const c_char,
) -> procimg_error_t {
    const F: &str = "procimg_claim_device";
    call(|| -> Outcome {
        super::args::required(device, F, "device")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        // SAFETY: a NUL-terminated string by the caller's contract.
        let device = unsafe { text(device, F, "device") }?;
        if h.layout.device(device).is_none() {
            return Err(Fail::invalid(
                F,
                format!(
                    "instance \"{}\" has no device named \"{device}\"; `procimg status \
                     --instance {}` lists them",
                    h.instance, h.instance
                ),
            ));
        }
        h.enter(F)?.client.claim_device(device)?;
        Ok(())
    })
}
