// SPDX-License-Identifier: MIT OR Apache-2.0
//! The application's hold on the ApplicationReady (GOAL's END_OF_PARAM answered later,
//! IO-Base's `PNIO_set_appl_state_ready` after `PNIO_CBF_PRM_END_IND`): after the PLC's
//! PrmEnd the device waits with its ApplicationReady until the application has taken over
//! its parameters and releases it, at most [`APP_READY_HOLD_TIMEOUT_NS`] and never past the
//! AR's CMI activity timeout, after which the ApplicationReady goes out all the same.

use super::diagnosis::SubslotAddr;
use super::{APP_READY_DELAY_NS, Application, ArState, Device};

/// The longest the application may hold the ApplicationReady.
pub const APP_READY_HOLD_TIMEOUT_NS: u64 = 10_000_000_000;
/// How long before the AR's CMI activity timeout a held ApplicationReady goes out anyway,
/// so that the controller still takes it.
const CMI_MARGIN_NS: u64 = 1_000_000_000;

impl<A: Application> Device<A> {
    /// Whether the ApplicationReady waits after each PrmEnd until
    /// [`release_application_ready`](Self::release_application_ready) (or the hold's
    /// timeout). Off from the start.
    pub fn hold_application_ready(&mut self, hold: bool) {
        self.ar.hold_app_ready = hold;
    }

    /// Lets a held ApplicationReady go out, and the held PlugApplicationReady of plugged
    /// submodules; `false` when none is held (no AR, the PLC's
    /// PrmEnd has not come, or it went out already).
    pub fn release_application_ready(&mut self, now_ns: u64) -> bool {
        let Some(ar) = self.ar.current.as_mut() else {
            return false;
        };
        // A plugged submodule's PlugApplicationReady that waits (with the hold timeout as
        // its due time) goes now.
        let mut released = false;
        for r in ar.plug_ready.iter_mut().filter(|r| r.2 > now_ns) {
            r.2 = now_ns;
            released = true;
        }
        if ar.app_ready_held.is_none() {
            return released;
        }
        ar.app_ready_held = None;
        ar.app_ready_due = Some(now_ns);
        true
    }

    /// Marks submodules the application is not ready for (IO-Base's list of
    /// `PNIO_set_appl_state_ready`): the ApplicationReady that goes next, and the AR's
    /// ModuleDiffBlock after it, give them ARInfo "application ready pending" until the
    /// application announces each one with a Return of Submodule alarm
    /// ([`return_submodule`](Self::return_submodule)). Each PrmEnd starts a new list.
    pub fn application_ready_pending(&mut self, at: impl IntoIterator<Item = SubslotAddr>) {
        let Some(ar) = self.ar.current.as_mut() else {
            return;
        };
        for a in at {
            if !ar.app_ready_pending.contains(&a) {
                ar.app_ready_pending.push(a);
            }
        }
    }

    /// At PrmEnd: when the ApplicationReady of the AR goes out, or that it is held.
    pub(super) fn schedule_app_ready(&mut self, now_ns: u64) {
        let hold = self.ar.hold_app_ready;
        let Some(ar) = self.ar.current.as_mut() else {
            return;
        };
        ar.app_ready_pending.clear();
        if hold {
            let mut until = now_ns.saturating_add(APP_READY_HOLD_TIMEOUT_NS);
            if let Some(cmi) = ar.cmi_deadline {
                until = until.min(cmi.saturating_sub(CMI_MARGIN_NS)).max(now_ns);
            }
            ar.app_ready_held = Some(until);
        } else {
            ar.app_ready_due = Some(now_ns.saturating_add(APP_READY_DELAY_NS));
        }
    }

    /// Sends a held ApplicationReady whose time is up.
    pub(super) fn expire_app_ready_hold(&mut self, now_ns: u64) {
        let Some(ar) = self.ar.current.as_mut() else {
            return;
        };
        if ar.state == ArState::Parameterized && ar.app_ready_held.is_some_and(|d| now_ns >= d) {
            ar.app_ready_held = None;
            ar.app_ready_due = Some(now_ns);
            self.ar.app_ready_hold_timeouts += 1;
        }
    }
}
