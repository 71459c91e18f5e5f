// SPDX-License-Identifier: MIT OR Apache-2.0
//! IO-Base style access by logical address (`PNIO_data_read`, `PNIO_data_write`,
//! `PNIO_output_data_read` and the buffered calls). Inside an open STARTOP window the
//! unbuffered calls act on the window (this cycle's inputs, this cycle's output sample)
//! without taking a newer image; outside, on the newest image and a sample of their own.

use super::args::{bytes, bytes_mut, ioxs, ioxs_byte, required, store, store_opt};
use super::error::{Outcome, call, procimg_error_t};
use super::handle::{Handle, Window, handle};
use procimg_client::access::resolve_read;
use procimg_client::{IoError, Ioxs, OutputReadResult, Space};

/// Reads inputs at logical address `address` (IO-Base `PNIO_data_read`): copies
/// `min(len, *data_len)` bytes into `buf`, where `*data_len` is the number of bytes from the
/// address to the end of its submodule (with slice access; the whole submodule without).
/// `local` is the local status (IOCS) to send for these inputs, `PROCIMG_IOXS_GOOD` or
/// `PROCIMG_IOXS_BAD`; `*remote` (when not NULL) gets the device's IOPS.
///
/// Inside a window it reads this cycle's inputs; outside, the newest image.
/// `PROCIMG_ERR_UNKNOWN_ADDRESS` when no submodule has the address.
///
/// # Safety
/// `client` is NULL or a live handle; `buf` is NULL (only with `len` 0) or `len` writable
/// bytes; `data_len` is NULL or writable; `remote` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_data_read(
    client: *mut Handle,
    address: u32,
    buf: *mut u8,
    len: usize,
    data_len: *mut usize,
    local: u8,
    remote: *mut u8,
) -> procimg_error_t {
    const F: &str = "procimg_data_read";
    call(|| -> Outcome {
        // SAFETY: NULL or `len` writable bytes by the caller's contract.
        let buf = unsafe { bytes_mut(buf, len, F, "buf") }?;
        required(data_len, F, "data_len")?;
        let local = ioxs(local, F, "local")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        let mut state = h.enter(F)?;
        let r = match state.in_window(|c| c.read(address, buf, local)) {
            Window::Open(r) => r?,
            _ => state.client.data_read(address, buf, local)?,
        };
        // SAFETY: `data_len` checked not NULL, `remote` NULL or writable, by the caller's
        // contract.
        unsafe {
            store(data_len, r.len);
            store_opt(remote, ioxs_byte(r.remote));
        }
        Ok(())
    })
}

/// Reads back outputs at logical address `address` as they were last sent (IO-Base
/// `PNIO_output_data_read`), with the `*data_len` rule of `procimg_data_read`. `*local` gets
/// the local status (IOPS) they were sent with, `*remote` the device's IOCS; either may be
/// NULL. Inside a window it reads what this cycle's image reports as sent.
///
/// # Safety
/// As `procimg_data_read`; `local` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_output_data_read(
    client: *mut Handle,
    address: u32,
    buf: *mut u8,
    len: usize,
    data_len: *mut usize,
    local: *mut u8,
    remote: *mut u8,
) -> procimg_error_t {
    const F: &str = "procimg_output_data_read";
    call(|| -> Outcome {
        // SAFETY: NULL or `len` writable bytes by the caller's contract.
        let buf = unsafe { bytes_mut(buf, len, F, "buf") }?;
        required(data_len, F, "data_len")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        let mut state = h.enter(F)?;
        let slice_access = state.client.options().slice_access;
        let in_window = state.in_window(|c| -> Result<OutputReadResult, IoError> {
            let r = resolve_read(
                &h.layout.submodules,
                Space::Output,
                address,
                buf.len(),
                slice_access,
            )?;
            if let Some(sent) = c.outputs_sent(r.submodule) {
                let src = sent.get(r.offset..r.offset + r.len).unwrap_or(&[]);
                buf[..src.len()].copy_from_slice(src);
            }
            let st = c.status(r.submodule);
            Ok(OutputReadResult {
                len: r.data_len,
                local: st.map_or(Ioxs::Bad, |s| s.output_local),
                remote: st.map_or(Ioxs::Bad, |s| s.output_remote),
            })
        });
        let r = match in_window {
            Window::Open(r) => r?,
            _ => state.client.output_data_read(address, buf)?,
        };
        // SAFETY: `data_len` checked not NULL; `local` and `remote` NULL or writable, by the
        // caller's contract.
        unsafe {
            store(data_len, r.len);
            store_opt(local, ioxs_byte(r.local));
            store_opt(remote, ioxs_byte(r.remote));
        }
        Ok(())
    })
}

/// Writes `len` bytes of outputs at logical address `address` (IO-Base `PNIO_data_write`)
/// with local status `local` (IOPS, `PROCIMG_IOXS_GOOD` or `PROCIMG_IOXS_BAD`); `*remote`
/// (when not NULL) gets the device's IOCS, which refers to the previous cycle's outputs.
///
/// Inside a window the bytes go into this cycle's output sample, sent with
/// `procimg_set_opdone`; outside, they are sent at once in a sample of their own, applied
/// whole in one cycle. `PROCIMG_ERR_LENGTH` when `len` does not fit the submodule (without
/// slice access it must be the whole submodule), `PROCIMG_ERR_NOT_CLAIMED` without the claim.
///
/// # Safety
/// `client` is NULL or a live handle; `buf` is NULL (only with `len` 0) or `len` readable
/// bytes; `remote` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_data_write(
    client: *mut Handle,
    address: u32,
    buf: *const u8,
    len: usize,
    local: u8,
    remote: *mut u8,
) -> procimg_error_t {
    const F: &str = "procimg_data_write";
    call(|| -> Outcome {
        // SAFETY: NULL or `len` readable bytes by the caller's contract.
        let data = unsafe { bytes(buf, len, F, "buf") }?;
        let local = ioxs(local, F, "local")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        let mut state = h.enter(F)?;
        let r = match state.in_window(|c| c.write(address, data, local)) {
            Window::Open(r) => r?,
            _ => state.client.data_write(address, data, local)?,
        };
        // SAFETY: NULL or writable by the caller's contract.
        unsafe { store_opt(remote, ioxs_byte(r)) };
        Ok(())
    })
}

/// Copies the newest input image into the read cache (IO-Base
/// `PNIO_data_read_cache_refresh`), for `procimg_read_cache`. Takes a newer image.
///
/// # Safety
/// `client` is NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_read_cache_refresh(client: *mut Handle) -> procimg_error_t {
    const F: &str = "procimg_read_cache_refresh";
    call(|| -> Outcome {
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        h.enter(F)?.client.data_read_cache_refresh()?;
        Ok(())
    })
}

/// Reads inputs from the read cache (IO-Base `PNIO_data_read_cache`), as
/// `procimg_data_read`; `local` goes out with the next `procimg_write_cache_flush`.
/// `PROCIMG_ERR_NO_IMAGE` before the first `procimg_read_cache_refresh`.
///
/// # Safety
/// As `procimg_data_read`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_read_cache(
    client: *mut Handle,
    address: u32,
    buf: *mut u8,
    len: usize,
    data_len: *mut usize,
    local: u8,
    remote: *mut u8,
) -> procimg_error_t {
    const F: &str = "procimg_read_cache";
    call(|| -> Outcome {
        // SAFETY: NULL or `len` writable bytes by the caller's contract.
        let buf = unsafe { bytes_mut(buf, len, F, "buf") }?;
        required(data_len, F, "data_len")?;
        let local = ioxs(local, F, "local")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        let r = h.enter(F)?.client.data_read_cache(address, buf, local)?;
        // SAFETY: `data_len` checked not NULL, `remote` NULL or writable, by the caller's
        // contract.
        unsafe {
            store(data_len, r.len);
            store_opt(remote, ioxs_byte(r.remote));
        }
        Ok(())
    })
}

/// Writes outputs into the write cache (IO-Base `PNIO_data_write_cache`), as
/// `procimg_data_write`; they go out with the next `procimg_write_cache_flush`. `*remote`
/// comes from the read cache (BAD before the first refresh). It may take a newer image: a
/// submodule's first cached write starts from its outputs as last sent.
///
/// # Safety
/// As `procimg_data_write`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_write_cache(
    client: *mut Handle,
    address: u32,
    buf: *const u8,
    len: usize,
    local: u8,
    remote: *mut u8,
) -> procimg_error_t {
    const F: &str = "procimg_write_cache";
    call(|| -> Outcome {
        // SAFETY: NULL or `len` readable bytes by the caller's contract.
        let data = unsafe { bytes(buf, len, F, "buf") }?;
        let local = ioxs(local, F, "local")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        let r = h.enter(F)?.client.data_write_cache(address, data, local)?;
        // SAFETY: NULL or writable by the caller's contract.
        unsafe { store_opt(remote, ioxs_byte(r)) };
        Ok(())
    })
}

/// Sends everything in the write cache in one sample, applied by the server in one cycle
/// (IO-Base `PNIO_data_write_cache_flush`). Nothing to send is no error.
///
/// # Safety
/// `client` is NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_write_cache_flush(client: *mut Handle) -> procimg_error_t {
    const F: &str = "procimg_write_cache_flush";
    call(|| -> Outcome {
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        h.enter(F)?.client.data_write_cache_flush()?;
        Ok(())
    })
}
