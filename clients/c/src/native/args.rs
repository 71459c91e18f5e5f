// SPDX-License-Identifier: MIT OR Apache-2.0
//! Checking what C passes in: NULL pointers, buffers, strings and status bytes, each refused
//! with an error that names the function and the argument.

use super::error::Fail;
use procimg_client::Ioxs;
use procimg_shm_layout::{IOXS_BAD, IOXS_GOOD};
use std::ffi::c_char;

/// Checks that a required pointer argument is not NULL.
pub(crate) fn required<T>(p: *const T, function: &str, argument: &str) -> Result<(), Fail> {
    if p.is_null() {
        Err(Fail::null(function, argument))
    } else {
        Ok(())
    }
}

/// Stores `value` through an out pointer that may be NULL (then nothing is stored).
///
/// # Safety
/// `p` is NULL or valid for writing one aligned `T`.
pub(crate) unsafe fn store_opt<T>(p: *mut T, value: T) {
    if !p.is_null() {
        // SAFETY: not NULL, and valid for writes by the caller's contract.
        unsafe { p.write(value) };
    }
}

/// Stores `value` through an out pointer checked with [`required`] before.
///
/// # Safety
/// `p` is not NULL and valid for writing one aligned `T`.
pub(crate) unsafe fn store<T>(p: *mut T, value: T) {
    // SAFETY: the caller checked `p` and vouches for it.
    unsafe { p.write(value) };
}

/// A C string argument as UTF-8.
///
/// # Safety
/// `p` is NULL or a NUL-terminated string valid during the call.
pub(crate) unsafe fn text<'a>(
    p: *const c_char,
    function: &str,
    argument: &str,
) -> Result<&'a str, Fail> {
    required(p, function, argument)?;
    // SAFETY: not NULL; NUL-terminated and valid by the caller's contract.
    unsafe { crate::ffi::c_str(p) }
        .ok_or_else(|| Fail::invalid(function, format!("`{argument}` is not UTF-8 text")))
}

/// A C input buffer: NULL only when `len` is 0.
///
/// # Safety
/// `p` is NULL or valid for reading `len` bytes during the call.
pub(crate) unsafe fn bytes<'a>(
    p: *const u8,
    len: usize,
    function: &str,
    argument: &str,
) -> Result<&'a [u8], Fail> {
    if len == 0 {
        return Ok(&[]);
    }
    required(p, function, argument)?;
    // SAFETY: not NULL, `len` readable bytes by the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(p, len) })
}

/// A C output buffer: NULL only when `len` is 0.
///
/// # Safety
/// `p` is NULL or valid for writing `len` bytes during the call, and no other reference to
/// them is used meanwhile.
pub(crate) unsafe fn bytes_mut<'a>(
    p: *mut u8,
    len: usize,
    function: &str,
    argument: &str,
) -> Result<&'a mut [u8], Fail> {
    if len == 0 {
        return Ok(&mut []);
    }
    required(p, function, argument)?;
    // SAFETY: not NULL, `len` writable bytes that nothing else uses, by the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, len) })
}

/// A C array argument: NULL only when `count` is 0.
///
/// # Safety
/// `p` is NULL or valid for reading `count` aligned `T` during the call.
pub(crate) unsafe fn array<'a, T>(
    p: *const T,
    count: usize,
    function: &str,
    argument: &str,
) -> Result<&'a [T], Fail> {
    if count == 0 {
        return Ok(&[]);
    }
    required(p, function, argument)?;
    // SAFETY: not NULL, `count` readable elements by the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(p, count) })
}

/// A status byte from C: `PROCIMG_IOXS_GOOD` or `PROCIMG_IOXS_BAD`, nothing else.
pub(crate) fn ioxs(byte: u8, function: &str, argument: &str) -> Result<Ioxs, Fail> {
    match byte {
        IOXS_GOOD => Ok(Ioxs::Good),
        IOXS_BAD => Ok(Ioxs::Bad),
        other => Err(Fail::invalid(
            function,
            format!(
                "`{argument}` is {other:#04x}; pass PROCIMG_IOXS_GOOD ({IOXS_GOOD:#04x}) or \
                 PROCIMG_IOXS_BAD ({IOXS_BAD:#04x})"
            ),
        )),
    }
}

/// A status as the byte C sees: `PROCIMG_IOXS_GOOD` or `PROCIMG_IOXS_BAD`.
pub(crate) fn ioxs_byte(status: Ioxs) -> u8 {
    match status {
        Ioxs::Good => IOXS_GOOD,
        Ioxs::Bad => IOXS_BAD,
    }
}
