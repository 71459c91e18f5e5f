// SPDX-License-Identifier: MIT OR Apache-2.0
//! Attaching to a procimgd instance and detaching: the options, their defaults and checks.

use super::args::{required, store, text};
use super::error::{Fail, Outcome, PROCIMG_ERR_BUSY, call, procimg_error_t};
use super::handle::{Handle, handle};
use crate::ffi::millis;
use procimg_client::{AttachOptions, Client};
use std::ffi::c_char;
use std::time::Duration;

/// Role of a client that takes part in the STARTOP/OPDONE handshake: the server waits for
/// its `procimg_set_opdone` every cycle (IO-Base's isochronous access).
pub const PROCIMG_ROLE_SYNCHRONOUS: u32 = 0;
/// Role of a client that reads the newest image and writes outputs whenever it likes (no
/// handshake; IO-Base's non-isochronous access).
pub const PROCIMG_ROLE_ASYNCHRONOUS: u32 = 1;

/// Attach flag: slice access (IO-Base `PNIO_CEP_SLICE_ACCESS`): read and write parts of a
/// submodule, from any address inside it. Without it, accesses by address cover whole
/// submodules from their first address.
pub const PROCIMG_ATTACH_SLICE_ACCESS: u32 = 1;
/// Attach flag: deliver `PROCIMG_EVENT_NEWCYCLE` events.
pub const PROCIMG_ATTACH_NEWCYCLE: u32 = 2;
/// Attach flag: `procimg_wait_startop` polls for the next image instead of sleeping (for a
/// thread with a CPU of its own).
pub const PROCIMG_ATTACH_BUSY_POLL: u32 = 4;
/// Attach flag: refuse to attach (`PROCIMG_ERR_LAYOUT`) unless the server's layout hash is
/// `layout_hash`.
pub const PROCIMG_ATTACH_EXPECT_LAYOUT_HASH: u32 = 8;
/// Attach flag: a sleeping `procimg_wait_startop` (and an IO-Base callback thread) sleeps
/// until procimgd signals STARTOP, instead of waking 50 µs before it is due and polling for
/// it (the default, which finds the CPU running when STARTOP comes, for some 30 µs of CPU
/// time a cycle).
pub const PROCIMG_ATTACH_SLEEP_ONLY: u32 = 16;

/// Every attach flag this version knows.
const KNOWN_FLAGS: u32 = PROCIMG_ATTACH_SLICE_ACCESS
    | PROCIMG_ATTACH_NEWCYCLE
    | PROCIMG_ATTACH_BUSY_POLL
    | PROCIMG_ATTACH_EXPECT_LAYOUT_HASH
    | PROCIMG_ATTACH_SLEEP_ONLY;

/// The default attach timeout in milliseconds.
pub const PROCIMG_DEFAULT_ATTACH_TIMEOUT_MS: u32 = 3000;

/// How `procimg_attach` attaches. Fill it with `procimg_attach_options_init` first, then
/// change what you need.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct procimg_attach_options_t {
    /// `sizeof(procimg_attach_options_t)` of the header the program was built with (set by
    /// `procimg_attach_options_init`); a smaller value is refused.
    pub struct_size: u32,
    /// `PROCIMG_ROLE_SYNCHRONOUS` or `PROCIMG_ROLE_ASYNCHRONOUS`.
    pub role: u32,
    /// `PROCIMG_ATTACH_*` flags, or-ed.
    pub flags: u32,
    /// How long attaching may take, in milliseconds.
    pub timeout_ms: u32,
    /// The layout hash required with `PROCIMG_ATTACH_EXPECT_LAYOUT_HASH`.
    pub layout_hash: u64,
}

impl procimg_attach_options_t {
    const DEFAULT: procimg_attach_options_t = procimg_attach_options_t {
        struct_size: size_of::<procimg_attach_options_t>() as u32,
        role: PROCIMG_ROLE_SYNCHRONOUS,
        flags: PROCIMG_ATTACH_SLICE_ACCESS,
        timeout_ms: PROCIMG_DEFAULT_ATTACH_TIMEOUT_MS,
        layout_hash: 0,
    };

    /// The Rust client's options for these, checked.
    fn to_rust(self, name: &str, function: &str) -> Result<AttachOptions, Fail> {
        let base = match self.role {
            PROCIMG_ROLE_SYNCHRONOUS => AttachOptions::synchronous(name),
            PROCIMG_ROLE_ASYNCHRONOUS => AttachOptions::asynchronous(name),
            other => {
                return Err(Fail::invalid(
                    function,
                    format!(
                        "role {other} is unknown; use PROCIMG_ROLE_SYNCHRONOUS or \
                         PROCIMG_ROLE_ASYNCHRONOUS"
                    ),
                ));
            }
        };
        let unknown = self.flags & !KNOWN_FLAGS;
        if unknown != 0 {
            return Err(Fail::invalid(
                function,
                format!(
                    "flags {unknown:#x} are unknown; use the PROCIMG_ATTACH_* flags of procimg.h"
                ),
            ));
        }
        let mut opts = base
            .slice_access(self.flags & PROCIMG_ATTACH_SLICE_ACCESS != 0)
            .newcycle(self.flags & PROCIMG_ATTACH_NEWCYCLE != 0)
            .busy_poll(self.flags & PROCIMG_ATTACH_BUSY_POLL != 0);
        if self.flags & PROCIMG_ATTACH_EXPECT_LAYOUT_HASH != 0 {
            opts = opts.expect_layout_hash(self.layout_hash);
        }
        if self.flags & PROCIMG_ATTACH_SLEEP_ONLY != 0 {
            opts = opts.wake_ahead(Duration::ZERO);
        }
        opts.timeout = millis(self.timeout_ms);
        Ok(opts)
    }
}

/// Fills `opts` with the defaults: `struct_size` = its size, synchronous role, slice access,
/// a timeout of 3000 ms, no expected layout hash. Does nothing when `opts` is NULL.
///
/// # Safety
/// `opts` is NULL or valid for writing a `procimg_attach_options_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_attach_options_init(opts: *mut procimg_attach_options_t) {
    crate::ffi::guard((), || {
        // SAFETY: NULL or writable by the caller's contract.
        unsafe { super::args::store_opt(opts, procimg_attach_options_t::DEFAULT) }
    })
}

/// Attaches to the procimgd serving `instance` as a client named `name` (shown by
/// `procimg status`; it names the holder when another client's claim is refused). `opts`
/// NULL means the defaults of `procimg_attach_options_init`. On success `*out` is the handle
/// (free it with `procimg_detach`); on failure it is NULL.
///
/// Fails with `PROCIMG_ERR_NO_SERVER` when no server serves the instance,
/// `PROCIMG_ERR_REFUSED` when it refuses the client (too many clients, no access),
/// `PROCIMG_ERR_LAYOUT` on a layout version or hash mismatch, `PROCIMG_ERR_TIMEOUT` when it
/// does not answer within `timeout_ms`, `PROCIMG_ERR_INVALID_ARGUMENT` on a bad option.
///
/// # Safety
/// `instance` and `name` are NULL or NUL-terminated strings; `opts` is NULL or points to a
/// `procimg_attach_options_t` of at least its `struct_size` bytes; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_attach(
    instance: *const c_char,
    name: *const c_char,
    opts: *const procimg_attach_options_t,
    out: *mut *mut Handle,
) -> procimg_error_t {
    const F: &str = "procimg_attach";
    call(|| -> Outcome {
        required(out, F, "out")?;
        // SAFETY: checked not NULL; writable by the caller's contract.
        unsafe { store(out, std::ptr::null_mut()) };
        // SAFETY: strings by the caller's contract.
        let instance = unsafe { text(instance, F, "instance") }?;
        // SAFETY: as above.
        let name = unsafe { text(name, F, "name") }?;
        let options = if opts.is_null() {
            procimg_attach_options_t::DEFAULT
        } else {
            // Read the size first: a program built against an older, smaller struct must not
            // have more read than it wrote.
            // SAFETY: not NULL; every version of the struct begins with `struct_size`.
            let size = unsafe { std::ptr::addr_of!((*opts).struct_size).read() };
            let need = size_of::<procimg_attach_options_t>();
            if (size as usize) < need {
                return Err(Fail::invalid(
                    F,
                    format!(
                        "opts->struct_size is {size}, this library needs {need}: fill the \
                         options with procimg_attach_options_init"
                    ),
                ));
            }
            // SAFETY: at least `need` readable bytes, as its struct_size says.
            unsafe { opts.read() }
        };
        let rust = options.to_rust(name, F)?;
        let client = Client::attach(instance, rust)?;
        let handle = Box::into_raw(Box::new(Handle::new(client)));
        // SAFETY: checked not NULL above.
        unsafe { store(out, handle) };
        Ok(())
    })
}

/// Detaches the client and frees the handle: its claims are released, an open STARTOP
/// window is dropped with its outputs unsent, and every pointer obtained through the handle
/// becomes invalid. `PROCIMG_ERR_BUSY` (and nothing freed) when another thread is inside a
/// call on it.
///
/// # Safety
/// `client` is NULL or a handle from `procimg_attach` not yet detached; it is not used
/// afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_detach(client: *mut Handle) -> procimg_error_t {
    const F: &str = "procimg_detach";
    call(|| -> Outcome {
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        if h.busy() {
            return Err(Fail::new(
                PROCIMG_ERR_BUSY,
                format!(
                    "{F}: another thread is inside a call on the handle of instance \"{}\"; \
                     detach after it returned",
                    h.instance
                ),
            ));
        }
        // SAFETY: made by Box::into_raw in procimg_attach and, by the caller's contract, not
        // freed before nor used after.
        let boxed = unsafe { Box::from_raw(client) };
        let mut state = boxed.into_state();
        // The window's unsent output sample goes before the client and its ports.
        state.window = None;
        drop(state);
        Ok(())
    })
}
