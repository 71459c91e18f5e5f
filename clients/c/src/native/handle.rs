// SPDX-License-Identifier: MIT OR Apache-2.0
//! The opaque handle behind `procimg_client_t *`: the attached client, its STARTOP window and
//! its event queue behind a lock that is only ever tried, and the layout, which never changes
//! and needs no lock.

use super::error::{Fail, PROCIMG_ERR_BUSY};
use procimg_client::{Client, Cycle, DetachedCycle, Event, Layout};
use std::collections::VecDeque;
use std::ffi::CString;
use std::sync::{Mutex, MutexGuard, TryLockError};

/// An attached client as C holds it (`procimg_client_t`). Made by `procimg_attach`, freed by
/// `procimg_detach`.
pub struct Handle {
    /// The instance name, for error texts that need no lock.
    pub(crate) instance: String,
    /// The server's layout as it was at attach (a re-attached client keeps it: a server that
    /// comes back with another layout is refused). C gets pointers into it.
    pub(crate) layout: Layout,
    /// Station names, NUL-terminated, by device index.
    pub(crate) device_names: Vec<CString>,
    /// Whether the client takes part in the handshake.
    pub(crate) synchronous: bool,
    state: Mutex<State>,
}

/// What calls change, one call at a time.
pub(crate) struct State {
    pub(crate) client: Client,
    /// The STARTOP window opened by `procimg_wait_startop`, until `procimg_set_opdone` or the
    /// next `procimg_wait_startop`. It stays here even when the client has moved on to a newer
    /// image, so that the output pointers handed out stay valid until then.
    pub(crate) window: Option<DetachedCycle>,
    /// Events taken from the client, handed out one by one by `procimg_next_event`.
    pub(crate) events: VecDeque<Event>,
}

/// How an action on the window went.
pub(crate) enum Window<R> {
    /// The window is open and current: here is what the action returned.
    Open(R),
    /// A window of this cycle is held, but the client has taken a newer image since (or lost
    /// its server): the window is over.
    Over(u64),
    /// No window is open.
    Closed,
}

impl Handle {
    /// A handle for a freshly attached client.
    pub(crate) fn new(client: Client) -> Handle {
        let layout = client.layout().clone();
        let device_names = (0..layout.devices.len())
            .map(|d| CString::new(layout.device_name(d)).unwrap_or_default())
            .collect();
        Handle {
            instance: client.instance().to_string(),
            synchronous: client.options().role == procimg_client::ClientRole::Synchronous,
            layout,
            device_names,
            state: Mutex::new(State {
                client,
                window: None,
                events: VecDeque::new(),
            }),
        }
    }

    /// Enters a call that changes the client. Never waits: a second thread inside a call on
    /// the same handle gets `PROCIMG_ERR_BUSY` (blocking would let a real-time thread wait
    /// behind a slow control request of another).
    pub(crate) fn enter(&self, function: &str) -> Result<MutexGuard<'_, State>, Fail> {
        match self.state.try_lock() {
            Ok(guard) => Ok(guard),
            // A panic in an earlier call was caught and reported; the client itself stays
            // consistent (it is safe Rust), so the handle remains usable.
            Err(TryLockError::Poisoned(p)) => Ok(p.into_inner()),
            Err(TryLockError::WouldBlock) => Err(Fail::new(
                PROCIMG_ERR_BUSY,
                format!(
                    "{function}: another thread is inside a call on the handle of instance \
                     \"{}\"; calls on one handle must not overlap (serialise them, or attach \
                     one client per thread)",
                    self.instance
                ),
            )),
        }
    }

    /// Takes the handle apart for `procimg_detach` (which checked [`Handle::busy`] first).
    pub(crate) fn into_state(self: Box<Handle>) -> State {
        let Handle { state, .. } = *self;
        state.into_inner().unwrap_or_else(|p| p.into_inner())
    }

    /// Whether another thread is inside a call on this handle right now.
    pub(crate) fn busy(&self) -> bool {
        matches!(self.state.try_lock(), Err(TryLockError::WouldBlock))
    }

    /// Checks that submodule index `s` is in the layout.
    pub(crate) fn submodule(&self, s: usize, function: &str) -> Result<usize, Fail> {
        if s < self.layout.submodules.len() {
            Ok(s)
        } else {
            Err(Fail::invalid(
                function,
                format!(
                    "submodule index {s} is out of range: instance \"{}\" has {} submodules \
                     (procimg_submodules lists them)",
                    self.instance,
                    self.layout.submodules.len()
                ),
            ))
        }
    }
}

impl State {
    /// Runs `action` on the open window without taking a newer image.
    pub(crate) fn in_window<R>(&mut self, action: impl FnOnce(&mut Cycle<'_>) -> R) -> Window<R> {
        let Some(window) = self.window.take() else {
            return Window::Closed;
        };
        let number = window.number();
        let current = self.client.cycle_info().map(|i| i.cycle_number);
        if current != Some(number) {
            // Keep it: its output sample backs pointers C may still hold.
            self.window = Some(window);
            return Window::Over(number);
        }
        match window.resume(&mut self.client) {
            Some(mut cycle) => {
                let r = action(&mut cycle);
                self.window = Some(cycle.detach());
                Window::Open(r)
            }
            // Not reached: resume fails only for a window that is not current, checked above.
            None => Window::Over(number),
        }
    }
}

/// The handle behind a `const procimg_client_t *`.
///
/// # Safety
/// `p` is NULL or a handle from `procimg_attach` not yet detached.
pub(crate) unsafe fn handle<'a>(p: *const Handle, function: &str) -> Result<&'a Handle, Fail> {
    // SAFETY: NULL or a live handle by the caller's contract; only shared access is made.
    unsafe { p.as_ref() }.ok_or_else(|| Fail::null(function, "client"))
}
