// SPDX-License-Identifier: MIT OR Apache-2.0
//! The STARTOP / OPDONE handshake of a synchronous client, with the inputs and outputs in
//! place in shared memory, and the newest image for any client outside a window.

use super::args::{ioxs, ioxs_byte, required, store, store_opt};
use super::error::{
    Fail, Outcome, PROCIMG_ERR_NOT_IN_CYCLE, PROCIMG_ERR_WRONG_ROLE, call, procimg_error_t,
};
use super::handle::{Handle, State, Window, handle};
use crate::ffi::millis;
use procimg_client::{IoError, SubmoduleIoxs};
use procimg_shm_layout::CycleInfo;

/// The four status bytes of a submodule, each `PROCIMG_IOXS_GOOD` or `PROCIMG_IOXS_BAD`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct procimg_submodule_ioxs_t {
    /// Remote status of the inputs: the device's IOPS.
    pub input_remote: u8,
    /// Local status of the inputs as sent to the device: this side's IOCS.
    pub input_local: u8,
    /// Local status of the outputs as sent to the device: this side's IOPS.
    pub output_local: u8,
    /// Remote status of the outputs: the device's IOCS for the previous cycle's outputs.
    pub output_remote: u8,
}

impl From<SubmoduleIoxs> for procimg_submodule_ioxs_t {
    fn from(s: SubmoduleIoxs) -> procimg_submodule_ioxs_t {
        procimg_submodule_ioxs_t {
            input_remote: ioxs_byte(s.input_remote),
            input_local: ioxs_byte(s.input_local),
            output_local: ioxs_byte(s.output_local),
            output_remote: ioxs_byte(s.output_remote),
        }
    }
}

/// Refuses the handshake to an asynchronous client.
pub(crate) fn synchronous_only(h: &Handle, function: &str) -> Result<(), Fail> {
    if h.synchronous {
        return Ok(());
    }
    Err(Fail::new(
        PROCIMG_ERR_WRONG_ROLE,
        format!(
            "{function}: the client of instance \"{}\" is asynchronous and takes no part in the \
             STARTOP/OPDONE handshake; attach with PROCIMG_ROLE_SYNCHRONOUS, or use \
             procimg_data_read/procimg_data_write",
            h.instance
        ),
    ))
}

/// The error for a window that is over or was never opened.
pub(crate) fn not_in_cycle<R>(h: &Handle, window: Window<R>, function: &str) -> Fail {
    let text = match window {
        Window::Over(n) => format!(
            "{function}: the STARTOP window of cycle {n} on instance \"{}\" is over (a newer \
             image was taken meanwhile, or the server went away); its outputs are not sent. \
             Call procimg_wait_startop for the next cycle",
            h.instance
        ),
        _ => format!(
            "{function}: no STARTOP window is open on instance \"{}\"; call \
             procimg_wait_startop first (procimg_set_opdone closes the window)",
            h.instance
        ),
    };
    Fail::new(PROCIMG_ERR_NOT_IN_CYCLE, text)
}

/// Runs `action` on the open window; NOT_IN_CYCLE without one.
fn on_window<R>(
    h: &Handle,
    state: &mut State,
    function: &str,
    action: impl FnOnce(&mut procimg_client::Cycle<'_>) -> Result<R, IoError>,
) -> Result<R, Fail> {
    match state.in_window(action) {
        Window::Open(r) => Ok(r?),
        other => Err(not_in_cycle(h, other, function)),
    }
}

/// The body of a function that hands out a slice in place: `data` and `len`, checked not NULL
/// before anything else, get the pointer and length `view` finds through the handle.
///
/// # Safety
/// `client` is NULL or a live handle; `data` and `len` are NULL or writable.
unsafe fn slice_out<P>(
    client: *mut Handle,
    function: &str,
    data: *mut P,
    len: *mut usize,
    view: impl FnOnce(&Handle) -> Result<(P, usize), Fail>,
) -> procimg_error_t {
    call(|| -> Outcome {
        required(data, function, "data")?;
        required(len, function, "len")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, function) }?;
        let (p, n) = view(h)?;
        // SAFETY: both checked not NULL; writable by the caller's contract.
        unsafe {
            store(data, p);
            store(len, n);
        }
        Ok(())
    })
}

/// Waits up to `timeout_ms` (0: only looks) for the next STARTOP and opens this cycle's
/// window: the inputs of the cycle are published, the outputs may be written until
/// `procimg_set_opdone`. A window still open from before is dropped, its outputs unsent (the
/// server counts an OPFAULT for that cycle). `*info` (when not NULL) gets the cycle's timing
/// as the server stamped it.
///
/// `PROCIMG_ERR_TIMEOUT` when no STARTOP came, `PROCIMG_ERR_SERVER_GONE` when the server is
/// gone (the client re-attaches by itself while waiting), `PROCIMG_ERR_WRONG_ROLE` for an
/// asynchronous client. Other events that arrive meanwhile wait for `procimg_next_event`.
///
/// # Safety
/// `client` is NULL or a live handle; `info` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_wait_startop(
    client: *mut Handle,
    timeout_ms: u32,
    info: *mut CycleInfo,
) -> procimg_error_t {
    const F: &str = "procimg_wait_startop";
    call(|| -> Outcome {
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        synchronous_only(h, F)?;
        let mut state = h.enter(F)?;
        // As a dropped Rust `Cycle`: the old window's outputs are not sent.
        state.window = None;
        let cycle = state.client.wait_startop(millis(timeout_ms))?;
        let cycle_info = cycle.info();
        let window = cycle.detach();
        state.window = Some(window);
        // SAFETY: NULL or writable by the caller's contract.
        unsafe { store_opt(info, cycle_info) };
        Ok(())
    })
}

/// The whole input data (the I area) in place in shared memory, without a copy: `*data`
/// points to `*len` bytes, read-only. Inside a STARTOP window they are this cycle's inputs,
/// valid until the next `procimg_wait_startop` or `procimg_detach` (see the pointer rules at
/// the top of this header for the calls that take a newer image); outside a window they are
/// the newest image's, taken now.
///
/// # Safety
/// `client` is NULL or a live handle; `data` and `len` are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_inputs(
    client: *mut Handle,
    data: *mut *const u8,
    len: *mut usize,
) -> procimg_error_t {
    const F: &str = "procimg_inputs";
    // SAFETY: `client`, `data` and `len` as the caller's contract says.
    unsafe {
        slice_out(client, F, data, len, |h| {
            let mut state = h.enter(F)?;
            let (p, n) = match state.in_window(|c| {
                let i = c.inputs();
                (i.as_ptr(), i.len())
            }) {
                Window::Open(v) => v,
                _ => {
                    let i = state.client.newest_inputs()?;
                    (i.as_ptr(), i.len())
                }
            };
            Ok((p, n))
        })
    }
}

/// The inputs of submodule `submodule` in place, as `procimg_inputs` (same validity).
/// `*len` is the submodule's input length (0 for a submodule without inputs).
///
/// # Safety
/// `client` is NULL or a live handle; `data` and `len` are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_input(
    client: *mut Handle,
    submodule: usize,
    data: *mut *const u8,
    len: *mut usize,
) -> procimg_error_t {
    const F: &str = "procimg_input";
    // SAFETY: `client`, `data` and `len` as the caller's contract says.
    unsafe {
        slice_out(client, F, data, len, |h| {
            let s = h.submodule(submodule, F)?;
            let mut state = h.enter(F)?;
            let view = match state.in_window(|c| c.input(s).map(|i| (i.as_ptr(), i.len()))) {
                Window::Open(v) => v,
                _ => state.client.newest_input(s)?.map(|i| (i.as_ptr(), i.len())),
            };
            // The index was checked against the same layout: a view is always there.
            let (p, n) = view.ok_or_else(|| Fail::invalid(F, "submodule not in the image"))?;
            Ok((p, n))
        })
    }
}

/// The whole output data of this cycle (the Q area of the output sample this client sends
/// with its OPDONE), writable in place: `*data` points to `*len` bytes that start as the
/// outputs last sent. Every submodule this client has claimed is marked written with local
/// status GOOD; bytes of submodules it has not claimed are ignored by the server. Valid until
/// `procimg_set_opdone`, the next `procimg_wait_startop` or `procimg_detach`.
///
/// `PROCIMG_ERR_NOT_IN_CYCLE` outside a window, `PROCIMG_ERR_WRONG_ROLE` for an asynchronous
/// client, `PROCIMG_ERR_NOT_DELIVERED` when no output sample is free.
///
/// # Safety
/// `client` is NULL or a live handle; `data` and `len` are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_outputs(
    client: *mut Handle,
    data: *mut *mut u8,
    len: *mut usize,
) -> procimg_error_t {
    const F: &str = "procimg_outputs";
    // SAFETY: `client`, `data` and `len` as the caller's contract says.
    unsafe {
        slice_out(client, F, data, len, |h| {
            synchronous_only(h, F)?;
            let mut state = h.enter(F)?;
            let (p, n) = on_window(h, &mut state, F, |c| {
                let o = c.outputs_mut()?;
                Ok((o.as_mut_ptr(), o.len()))
            })?;
            Ok((p, n))
        })
    }
}

/// The outputs of submodule `submodule` for this cycle, writable in place (as
/// `procimg_outputs`, same validity): `*len` is its output length. Marks them written with
/// local status GOOD. `PROCIMG_ERR_NOT_CLAIMED` when this client has not claimed them.
///
/// # Safety
/// `client` is NULL or a live handle; `data` and `len` are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_output(
    client: *mut Handle,
    submodule: usize,
    data: *mut *mut u8,
    len: *mut usize,
) -> procimg_error_t {
    const F: &str = "procimg_output";
    // SAFETY: `client`, `data` and `len` as the caller's contract says.
    unsafe {
        slice_out(client, F, data, len, |h| {
            let s = h.submodule(submodule, F)?;
            synchronous_only(h, F)?;
            let mut state = h.enter(F)?;
            let (p, n) = on_window(h, &mut state, F, |c| {
                let o = c.output_mut(s)?;
                Ok((o.as_mut_ptr(), o.len()))
            })?;
            Ok((p, n))
        })
    }
}

/// The status bytes of submodule `submodule`: this cycle's inside a window, the newest
/// image's outside.
///
/// # Safety
/// `client` is NULL or a live handle; `status` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_submodule_status(
    client: *mut Handle,
    submodule: usize,
    status: *mut procimg_submodule_ioxs_t,
) -> procimg_error_t {
    const F: &str = "procimg_submodule_status";
    call(|| -> Outcome {
        required(status, F, "status")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        let s = h.submodule(submodule, F)?;
        let mut state = h.enter(F)?;
        let st = match state.in_window(|c| c.status(s)) {
            Window::Open(v) => v,
            _ => state.client.newest_status(s)?,
        };
        let st = st.ok_or_else(|| Fail::invalid(F, "submodule not in the image"))?;
        // SAFETY: checked not NULL; writable by the caller's contract.
        unsafe { store(status, st.into()) };
        Ok(())
    })
}

/// Sets the local status (IOPS) sent with submodule `submodule`'s outputs in this cycle
/// (`PROCIMG_IOXS_GOOD` or `PROCIMG_IOXS_BAD`); marks them written. Needs a window and the
/// claim.
///
/// # Safety
/// `client` is NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_set_output_status(
    client: *mut Handle,
    submodule: usize,
    local: u8,
) -> procimg_error_t {
    const F: &str = "procimg_set_output_status";
    call(|| -> Outcome {
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        let s = h.submodule(submodule, F)?;
        let local = ioxs(local, F, "local")?;
        synchronous_only(h, F)?;
        let mut state = h.enter(F)?;
        on_window(h, &mut state, F, |c| c.set_output_status(s, local))
    })
}

/// Sends this cycle's outputs and signals OPDONE (IO-Base `PNIO_CP_set_opdone`), closing
/// the window. `*info` (when not NULL) gets the cycle info at OPDONE time: its
/// `since_cycle_start_ns` minus the one from `procimg_wait_startop` is the time this cycle
/// took. Output pointers of the window are invalid afterwards.
///
/// `PROCIMG_ERR_NOT_IN_CYCLE` without a window or when the window is over (outputs not
/// sent), `PROCIMG_ERR_WRONG_ROLE` for an asynchronous client.
///
/// # Safety
/// `client` is NULL or a live handle; `info` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_set_opdone(
    client: *mut Handle,
    info: *mut CycleInfo,
) -> procimg_error_t {
    const F: &str = "procimg_set_opdone";
    call(|| -> Outcome {
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        synchronous_only(h, F)?;
        let mut state = h.enter(F)?;
        let state = &mut *state;
        let Some(window) = state.window.take() else {
            return Err(not_in_cycle(h, Window::<()>::Closed, F));
        };
        let number = window.number();
        let Some(cycle) = window.resume(&mut state.client) else {
            return Err(not_in_cycle(h, Window::<()>::Over(number), F));
        };
        let done = cycle.set_opdone()?;
        // SAFETY: NULL or writable by the caller's contract.
        unsafe { store_opt(info, done) };
        Ok(())
    })
}
