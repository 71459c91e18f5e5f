// SPDX-License-Identifier: MIT OR Apache-2.0
//! The program's callbacks: the table a controller keeps of them, and the one place that
//! calls them.
//!
//! IO-Base allows only the IO-data functions inside a callback. The library knows it is
//! inside one by a thread-local depth that [`CallbackTable::invoke`] and [`invoke_cp`] raise
//! around the call; the other functions then answer `PNIO_ERR_SEQUENCE`. The call is also
//! wrapped in `catch_unwind`, as defence in depth: a callback is an `extern "C"` function, and
//! Rust aborts the process when a panic tries to leave one (a C++ exception leaving a
//! callback is undefined behaviour, as in IO-Base), so nothing should ever arrive there.

use super::types::{
    PNIO_CBE_PRM, PNIO_CBE_TYPE, PNIO_CBF, PNIO_CP_CBE_PRM, PNIO_CP_CBE_TYPE, PNIO_CP_CBF,
};
use std::cell::Cell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Mutex;

/// Event types of `PNIO_CBE_TYPE` the table has room for (1..=14 are defined).
const CBE_TYPES: usize = 16;
/// Event types of `PNIO_CP_CBE_TYPE` (1..=3 are defined).
const CP_CBE_TYPES: usize = 4;

thread_local! {
    /// How many callbacks this thread is inside (a callback may call `PNIO_CP_set_opdone`,
    /// which never calls another, but depth is cheaper to get right than a flag).
    static IN_CALLBACK: Cell<u32> = const { Cell::new(0) };
}

/// Whether the calling thread is inside a callback of the program.
pub(crate) fn in_callback() -> bool {
    IN_CALLBACK.with(Cell::get) > 0
}

/// Raises the in-callback depth for as long as it lives (lowered on unwind too).
struct InCallback;

impl InCallback {
    fn enter() -> InCallback {
        IN_CALLBACK.with(|d| d.set(d.get() + 1));
        InCallback
    }
}

impl Drop for InCallback {
    fn drop(&mut self) {
        IN_CALLBACK.with(|d| d.set(d.get().saturating_sub(1)));
    }
}

/// The callbacks registered for one controller, read at delivery time.
pub(crate) struct CallbackTable {
    cbf: Mutex<[PNIO_CBF; CBE_TYPES]>,
    cp: Mutex<[PNIO_CP_CBF; CP_CBE_TYPES]>,
}

impl Default for CallbackTable {
    fn default() -> CallbackTable {
        CallbackTable::new()
    }
}

impl CallbackTable {
    /// An empty table.
    pub(crate) fn new() -> CallbackTable {
        CallbackTable {
            cbf: Mutex::new([None; CBE_TYPES]),
            cp: Mutex::new([None; CP_CBE_TYPES]),
        }
    }

    /// The callback currently registered for `t` (`None` when none is, or after close).
    pub(crate) fn get(&self, t: PNIO_CBE_TYPE) -> PNIO_CBF {
        let table = self.cbf.lock().unwrap_or_else(|e| e.into_inner());
        table.get(t as usize).copied().flatten()
    }

    /// Registers `cbf` for `t` unless one is registered already; whether it was stored.
    pub(crate) fn set_once(&self, t: PNIO_CBE_TYPE, cbf: PNIO_CBF) -> bool {
        let mut table = self.cbf.lock().unwrap_or_else(|e| e.into_inner());
        match table.get_mut(t as usize) {
            Some(slot) if slot.is_none() => {
                *slot = cbf;
                true
            }
            _ => false,
        }
    }

    /// The isochronous callback registered for `t`.
    pub(crate) fn get_cp(&self, t: PNIO_CP_CBE_TYPE) -> PNIO_CP_CBF {
        let table = self.cp.lock().unwrap_or_else(|e| e.into_inner());
        table.get(t as usize).copied().flatten()
    }

    /// Registers an isochronous callback unless one is registered already.
    pub(crate) fn set_cp_once(&self, t: PNIO_CP_CBE_TYPE, cbf: PNIO_CP_CBF) -> bool {
        let mut table = self.cp.lock().unwrap_or_else(|e| e.into_inner());
        match table.get_mut(t as usize) {
            Some(slot) if slot.is_none() => {
                *slot = cbf;
                true
            }
            _ => false,
        }
    }

    /// Forgets the isochronous callback for `t` (a registration that could not take effect).
    pub(crate) fn unset_cp(&self, t: PNIO_CP_CBE_TYPE) {
        if let Some(slot) = self
            .cp
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get_mut(t as usize)
        {
            *slot = None;
        }
    }

    /// Forgets every callback: after close nothing is delivered any more.
    pub(crate) fn clear(&self) {
        *self.cbf.lock().unwrap_or_else(|e| e.into_inner()) = [None; CBE_TYPES];
        *self.cp.lock().unwrap_or_else(|e| e.into_inner()) = [None; CP_CBE_TYPES];
    }

    /// Calls `cbf` with `prm` as a callback: inside it only the IO-data functions are
    /// allowed, and a panic stops here. Nothing happens for `None`.
    pub(crate) fn invoke(cbf: PNIO_CBF, prm: &mut PNIO_CBE_PRM) {
        let Some(f) = cbf else {
            return;
        };
        let _inside = InCallback::enter();
        let prm: *mut PNIO_CBE_PRM = prm;
        // SAFETY: `f` is a callback the program registered for this event type, called with
        // a pointer to a live, initialised PNIO_CBE_PRM for the duration of the call, as
        // the IO-Base contract of PNIO_CBF says.
        let _ = catch_unwind(AssertUnwindSafe(|| unsafe { f(prm) }));
    }
}

/// Calls an isochronous callback (`PNIO_CP_CBF`) like [`CallbackTable::invoke`].
pub(crate) fn invoke_cp(cbf: PNIO_CP_CBF, prm: &mut PNIO_CP_CBE_PRM) {
    let Some(f) = cbf else {
        return;
    };
    let _inside = InCallback::enter();
    let prm: *mut PNIO_CP_CBE_PRM = prm;
    // SAFETY: as in `CallbackTable::invoke`: a registered PNIO_CP_CBF called with a pointer
    // to a live PNIO_CP_CBE_PRM for the duration of the call.
    let _ = catch_unwind(AssertUnwindSafe(|| unsafe { f(prm) }));
}

/// Runs `call` (one call of a device callback, `pniousrd.h`'s typed ones) as a callback:
/// inside it only the IO-data functions are allowed, and a panic stops here.
pub(crate) fn invoke_device(call: impl FnOnce()) {
    invoke_call(call);
}

/// Runs `call`, one call of any callback of the program whose type the tables above do not
/// hold (PN Driver's trace callbacks), as a callback.
pub(crate) fn invoke_call(call: impl FnOnce()) {
    let _inside = InCallback::enter();
    let _ = catch_unwind(AssertUnwindSafe(call));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::iobase::types::{PNIO_CBE_MODE_IND, PNIO_CP_CBE_STARTOP_IND, PNIO_CYCLE_INFO};
    use std::sync::atomic::{AtomicBool, Ordering};

    static INSIDE: AtomicBool = AtomicBool::new(false);

    unsafe extern "C" fn records_inside(_: *mut PNIO_CBE_PRM) {
        INSIDE.store(in_callback(), Ordering::SeqCst);
    }

    unsafe extern "C" fn other(_: *mut PNIO_CBE_PRM) {}

    unsafe extern "C" fn cp_noop(_: *mut PNIO_CP_CBE_PRM) {}

    #[test]
    fn each_type_is_registered_once_and_cleared_by_close() {
        let t = CallbackTable::new();
        assert!(t.get(PNIO_CBE_MODE_IND).is_none());
        assert!(t.set_once(PNIO_CBE_MODE_IND, Some(records_inside)));
        assert!(!t.set_once(PNIO_CBE_MODE_IND, Some(other)));
        assert!(
            t.get(PNIO_CBE_MODE_IND)
                .is_some_and(|f| std::ptr::fn_addr_eq(
                    f,
                    records_inside as unsafe extern "C" fn(*mut PNIO_CBE_PRM)
                ))
        );
        assert!(
            !t.set_once(9999, Some(other)),
            "out of range types are refused"
        );
        assert!(t.set_cp_once(PNIO_CP_CBE_STARTOP_IND, Some(cp_noop)));
        assert!(!t.set_cp_once(PNIO_CP_CBE_STARTOP_IND, Some(cp_noop)));
        t.unset_cp(PNIO_CP_CBE_STARTOP_IND);
        assert!(t.get_cp(PNIO_CP_CBE_STARTOP_IND).is_none());
        t.clear();
        assert!(t.get(PNIO_CBE_MODE_IND).is_none());
    }

    #[test]
    fn invoke_marks_the_thread_while_the_callback_runs() {
        let mut prm = PNIO_CBE_PRM::new(PNIO_CBE_MODE_IND, 1);
        assert!(!in_callback());
        CallbackTable::invoke(Some(records_inside), &mut prm);
        assert!(
            INSIDE.load(Ordering::SeqCst),
            "inside the callback the flag is set"
        );
        assert!(!in_callback(), "and cleared after it");
        CallbackTable::invoke(None, &mut prm);
        let mut cp =
            PNIO_CP_CBE_PRM::new(PNIO_CP_CBE_STARTOP_IND, 1, 1, PNIO_CYCLE_INFO::default());
        invoke_cp(Some(cp_noop), &mut cp);
    }
}
