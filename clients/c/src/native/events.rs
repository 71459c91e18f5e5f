// SPDX-License-Identifier: MIT OR Apache-2.0
//! The server's mode, and events as IO-Base reports them through callbacks, here taken one
//! by one from a queue in the handle (poll `procimg_event_fd` to wait for them).

use super::args::{required, store};
use super::error::{
    Fail, Outcome, PROCIMG_ERR_NO_EVENT, PROCIMG_ERR_SERVER_GONE, call, procimg_error_t,
};
use super::handle::{Handle, handle};
use procimg_client::Event;
use procimg_shm_layout::Mode;
use std::ffi::c_int;

/// Event kind: the mode changed to `mode` (IO-Base `PNIO_CBE_MODE_IND`); one event per step,
/// so OFFLINE → OPERATE reports CLEAR, then OPERATE. The same value as `procimg_shm.h`'s
/// event id of the same name, so both headers can be included together.
pub const PROCIMG_EVENT_MODE: u32 = 3;
/// Event kind: this client's OPDONE for cycle `cycle` came too late, its outputs of that
/// cycle were not used (IO-Base `PNIO_CP_CBE_OPFAULT_IND`).
pub const PROCIMG_EVENT_OPFAULT: u32 = 1;
/// Event kind: a bus cycle's outputs went out (IO-Base `PNIO_CP_CBE_NEWCYCLE_IND`); only
/// with `PROCIMG_ATTACH_NEWCYCLE`. The same value as `procimg_shm.h`'s event id of the same
/// name.
pub const PROCIMG_EVENT_NEWCYCLE: u32 = 2;
/// Event kind: the server announced that it is stopping. The client re-attaches by itself
/// when a server for the instance returns.
pub const PROCIMG_EVENT_SERVER_SHUTDOWN: u32 = 4;
/// Event kind: the client re-attached to a restarted server of generation `generation`;
/// `procimg_event_fd` has a new descriptor.
pub const PROCIMG_EVENT_REATTACHED: u32 = 5;
/// Event kind: after a server restart, the claim on submodule `submodule` could not be taken
/// again (another client holds it now).
pub const PROCIMG_EVENT_CLAIM_LOST: u32 = 6;
/// Event kind: the restarted server has another layout (a changed configuration, or a
/// station its program defined anew), hash `layout_hash`, and the client follows it:
/// submodule indexes and addresses are the new layout's, and claims of submodules still
/// there were taken again. Comes right after `PROCIMG_EVENT_REATTACHED`. A client attached
/// with `PROCIMG_ATTACH_EXPECT_LAYOUT_HASH` does not follow: its calls answer
/// `PROCIMG_ERR_LAYOUT` instead.
pub const PROCIMG_EVENT_LAYOUT_CHANGED: u32 = 7;

// procimg_shm.h defines event ids of the same names: identical values keep including both
// headers legal C (a macro may be defined again with the same value, not with another).
const _: () = assert!(PROCIMG_EVENT_MODE as usize == procimg_shm_layout::events::EVENT_MODE);
const _: () =
    assert!(PROCIMG_EVENT_NEWCYCLE as usize == procimg_shm_layout::events::EVENT_NEWCYCLE);

/// One event. Fields a kind does not use are 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct procimg_event_t {
    /// `PROCIMG_EVENT_*`.
    pub kind: u32,
    /// `PROCIMG_EVENT_MODE`: the new mode (`PROCIMG_MODE_OFFLINE`, `_CLEAR`, `_OPERATE`).
    pub mode: u32,
    /// `PROCIMG_EVENT_OPFAULT`: the cycle whose OPDONE came too late.
    pub cycle: u64,
    /// `PROCIMG_EVENT_REATTACHED`: the new server generation.
    pub generation: u64,
    /// `PROCIMG_EVENT_CLAIM_LOST`: the submodule index.
    pub submodule: u64,
    /// `PROCIMG_EVENT_LAYOUT_CHANGED`: the new layout hash.
    pub layout_hash: u64,
}

impl From<Event> for procimg_event_t {
    fn from(e: Event) -> procimg_event_t {
        let none = procimg_event_t::default();
        match e {
            Event::Mode(m) => procimg_event_t {
                kind: PROCIMG_EVENT_MODE,
                mode: m.as_u32(),
                ..none
            },
            Event::OpFault { cycle } => procimg_event_t {
                kind: PROCIMG_EVENT_OPFAULT,
                cycle,
                ..none
            },
            Event::NewCycle => procimg_event_t {
                kind: PROCIMG_EVENT_NEWCYCLE,
                ..none
            },
            Event::ServerShutdown => procimg_event_t {
                kind: PROCIMG_EVENT_SERVER_SHUTDOWN,
                ..none
            },
            Event::Reattached { generation } => procimg_event_t {
                kind: PROCIMG_EVENT_REATTACHED,
                generation,
                ..none
            },
            Event::ClaimLost { submodule } => procimg_event_t {
                kind: PROCIMG_EVENT_CLAIM_LOST,
                submodule: submodule as u64,
                ..none
            },
            Event::LayoutChanged { now, .. } => procimg_event_t {
                kind: PROCIMG_EVENT_LAYOUT_CHANGED,
                layout_hash: now,
                ..none
            },
        }
    }
}

/// Asks the server for mode `mode` (`PROCIMG_MODE_OFFLINE`, `_CLEAR`, `_OPERATE`; IO-Base
/// `PNIO_set_mode`). Returns at once; the change is confirmed by `PROCIMG_EVENT_MODE` events,
/// one per step. `PROCIMG_ERR_REFUSED` while the previous change is not confirmed yet.
///
/// # Safety
/// `client` is NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_set_mode(client: *mut Handle, mode: u32) -> procimg_error_t {
    const F: &str = "procimg_set_mode";
    call(|| -> Outcome {
        let m = Mode::from_u32(mode).ok_or_else(|| {
            Fail::invalid(
                F,
                format!(
                    "mode {mode} is unknown; use PROCIMG_MODE_OFFLINE, PROCIMG_MODE_CLEAR or \
                     PROCIMG_MODE_OPERATE"
                ),
            )
        })?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        h.enter(F)?.client.set_mode(m)?;
        Ok(())
    })
}

/// The server's mode: in this cycle's image inside a window, in the newest image outside.
///
/// # Safety
/// `client` is NULL or a live handle; `mode` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_mode(client: *mut Handle, mode: *mut u32) -> procimg_error_t {
    const F: &str = "procimg_mode";
    call(|| -> Outcome {
        required(mode, F, "mode")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        let mut state = h.enter(F)?;
        if state.window.is_none() {
            state.client.newest_inputs()?;
        }
        let m = state.client.mode().ok_or_else(|| {
            Fail::new(
                super::error::PROCIMG_ERR_NO_IMAGE,
                format!(
                    "{F}: no process image received yet from instance \"{}\"; wait for a cycle",
                    h.instance
                ),
            )
        })?;
        // SAFETY: checked not NULL; writable by the caller's contract.
        unsafe { store(mode, m.as_u32()) };
        Ok(())
    })
}

/// Takes the next event: `PROCIMG_OK` with `*event` filled, or `PROCIMG_ERR_NO_EVENT` (not a
/// failure; the last error text is left alone) when none is pending. Never waits: poll
/// `procimg_event_fd` to sleep until the server signals. Inside a STARTOP window it hands out
/// only events already collected (asking the server could take a newer image, which would end
/// the window); the rest follow after `procimg_set_opdone`.
///
/// # Safety
/// `client` is NULL or a live handle; `event` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_next_event(
    client: *mut Handle,
    event: *mut procimg_event_t,
) -> procimg_error_t {
    const F: &str = "procimg_next_event";
    call(|| -> Outcome {
        required(event, F, "event")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        let mut state = h.enter(F)?;
        if state.events.is_empty() && state.window.is_none() {
            let new = state.client.events();
            state.events.extend(new);
        }
        let next = state.events.pop_front().ok_or(Fail {
            code: PROCIMG_ERR_NO_EVENT,
            text: None,
        })?;
        // SAFETY: checked not NULL; writable by the caller's contract.
        unsafe { store(event, next.into()) };
        Ok(())
    })
}

/// A descriptor that becomes readable when the server signals this client (STARTOP, mode,
/// OPFAULT, NEWCYCLE, shutdown): `poll` it, then call `procimg_next_event` or
/// `procimg_wait_startop` with timeout 0. Do not read from or close it. It changes when the
/// client re-attaches (`PROCIMG_EVENT_REATTACHED`); `PROCIMG_ERR_SERVER_GONE` while the server
/// is gone.
///
/// # Safety
/// `client` is NULL or a live handle; `fd` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn procimg_event_fd(client: *mut Handle, fd: *mut c_int) -> procimg_error_t {
    const F: &str = "procimg_event_fd";
    call(|| -> Outcome {
        required(fd, F, "fd")?;
        // SAFETY: NULL or a live handle by the caller's contract.
        let h = unsafe { handle(client, F) }?;
        let descriptor = h.enter(F)?.client.event_fd().ok_or_else(|| {
            Fail::new(
                PROCIMG_ERR_SERVER_GONE,
                format!(
                    "{F}: the server of instance \"{}\" is gone, so there is no descriptor; \
                     procimg_wait_startop or procimg_data_read re-attach when it returns",
                    h.instance
                ),
            )
        })?;
        // SAFETY: checked not NULL; writable by the caller's contract.
        unsafe { store(fd, descriptor) };
        Ok(())
    })
}
