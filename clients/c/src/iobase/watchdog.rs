// SPDX-License-Identifier: MIT OR Apache-2.0
//! The CP application watchdog: `PNIO_CP_set_appl_watchdog`, `PNIO_CP_trigger_watchdog`
//! and `PNIO_CBF_APPL_WATCHDOG`, for controller and device programs alike.
//!
//! The rule (armed by the first trigger, expired once, refused until deregistered) is
//! [`AppWatchdogs`]'s, which a Rust program uses on its own; this file keeps its timer
//! thread and what an expiry does to the library's handles. The watchdog is the library's,
//! one per CPIndex in this process: procimgd has no
//! watchdog of its clients' programs, and a process that stops triggering is one whose
//! threads still run (a hung one keeps its timer thread too, but a crashed one loses its
//! claims with its registrations, which procimgd notices). A timer thread of the library
//! watches every armed registration. Monitoring starts at the first trigger; when a
//! trigger does not come within the timeout:
//!
//! * every controller and device of this process open on the instance the CPIndex names is
//!   stopped: the outputs (a device's I data) it holds go out once more with IOPS BAD, and
//!   an isochronous one's later cycles are ended by the library with them BAD (its STARTOP
//!   callback is no longer called);
//! * the callback is called once, on the timer thread, with the CPIndex;
//! * from then on every call with such a handle answers `PNIO_ERR_NO_FW_COMMUNICATION`
//!   (the CP no longer talks to the program), except `PNIO_controller_close` and
//!   `PNIO_device_close`; a handle opened afterwards works.
//!
//! Programs of other processes on the same procimgd are not affected (on a real CP they
//! are). The 20 ms between registrations that the manual asks for is not needed here and
//! not checked.
#![allow(non_snake_case)]

use super::callbacks::{in_callback, invoke_device};
use super::controller::{self, instance_for};
use super::device::state as device;
use super::errors::*;
use super::stopped;
use super::sync::lock;
use super::types::*;
use crate::ffi::guard;
use procimg_client::iobase::{AppWatchdogs, WatchdogError};
use std::sync::{Condvar, Mutex};
use std::time::{Duration, Instant};

/// The longest the timer thread sleeps with nothing armed (a deregistration ends it no
/// later than this; the first trigger of a registration wakes it at once).
const IDLE: Duration = Duration::from_millis(100);

struct State {
    /// By CPIndex, with the program's callback.
    dogs: AppWatchdogs<PNIO_CBF_APPL_WATCHDOG>,
    /// Whether the timer thread runs.
    timer: bool,
}

/// Wakes the timer thread when a watchdog is armed (its first trigger).
static ARMED: Condvar = Condvar::new();

static STATE: Mutex<State> = Mutex::new(State {
    dogs: AppWatchdogs::new(),
    timer: false,
});

/// `PNIO_CP_set_appl_watchdog` after the caller check.
fn set(cp: u32, ms: u32, cbf: PNIO_CBF_APPL_WATCHDOG) -> u32 {
    const F: &str = "PNIO_CP_set_appl_watchdog";
    if let Err(code) = super::controller::check_cp_index(F, cp) {
        return code;
    }
    let mut st = lock(&STATE);
    match (ms, cbf) {
        (0, None) => {
            st.dogs.deregister(cp);
            return PNIO_OK;
        }
        (0, Some(_)) => {
            return fail(
                F,
                PNIO_ERR_PRM_TIMEOUT,
                "wdTimeOutInMs is 0 with a callback: give a timeout, or 0 and NULL to \
                 deregister",
            );
        }
        (_, None) => {
            return fail(
                F,
                PNIO_ERR_PRM_CALLBACK,
                "pnio_appl_wd_cbf is NULL with a timeout: give a callback, or 0 and NULL to \
                 deregister",
            );
        }
        _ => {}
    }
    let timeout = Duration::from_millis(u64::from(ms));
    if st.dogs.register(cp, timeout, cbf).is_err() {
        // Registered already: the arguments were checked above.
        return fail(
            F,
            PNIO_ERR_ALLREADY_DONE,
            format_args!(
                "a watchdog is registered for CPIndex {cp} already: deregister it (0, NULL) \
                 first"
            ),
        );
    }
    if !st.timer {
        let spawned = std::thread::Builder::new()
            .name("pnio-watchdog".into())
            .spawn(timer);
        if let Err(e) = spawned {
            st.dogs.deregister(cp);
            return fail(
                F,
                PNIO_ERR_CREATE_INSTANCE,
                format_args!("cannot start the watchdog's thread: {e}"),
            );
        }
        st.timer = true;
    }
    PNIO_OK
}

/// `PNIO_CP_trigger_watchdog` after the caller check.
fn trigger(cp: u32) -> u32 {
    const F: &str = "PNIO_CP_trigger_watchdog";
    if let Err(code) = super::controller::check_cp_index(F, cp) {
        return code;
    }
    let triggered = lock(&STATE).dogs.trigger(cp, Instant::now());
    match triggered {
        Ok(armed) => {
            if armed {
                // Monitoring starts: the timer thread is to sleep until this deadline at most.
                ARMED.notify_all();
            }
            PNIO_OK
        }
        Err(WatchdogError::NotRegistered { .. }) => fail(
            F,
            PNIO_ERR_SEQUENCE,
            format_args!("no watchdog is registered for CPIndex {cp} (PNIO_CP_set_appl_watchdog)"),
        ),
        Err(_) => fail(
            F,
            PNIO_ERR_NO_FW_COMMUNICATION,
            format_args!(
                "the watchdog of CPIndex {cp} expired: close the controllers and devices, \
                 deregister it (0, NULL) and register again"
            ),
        ),
    }
}

/// The timer thread: runs while a registration exists, asleep until the nearest deadline
/// of an armed watchdog (a trigger only moves a deadline later).
fn timer() {
    let mut st = lock(&STATE);
    loop {
        if st.dogs.is_empty() {
            st.timer = false;
            return;
        }
        let now = Instant::now();
        let fired = st.dogs.expire(now);
        if !fired.is_empty() {
            drop(st);
            for (cp, cbf) in fired {
                expire(cp, cbf);
            }
            st = lock(&STATE);
            continue;
        }
        let next = st
            .dogs
            .next_deadline()
            .map_or(now + IDLE, |d| d.min(now + IDLE));
        // Past the deadline by a little: expired only once the timeout is exceeded.
        let wait = next.saturating_duration_since(now) + Duration::from_micros(100);
        st = match ARMED.wait_timeout(st, wait) {
            Ok((guard, _)) => guard,
            Err(poisoned) => poisoned.into_inner().0,
        };
    }
}

/// Stops the handles on the instance `cp` names, then calls the program back.
fn expire(cp: u32, cbf: PNIO_CBF_APPL_WATCHDOG) {
    let instance = instance_for(cp);
    let controllers = controller::on_instance(&instance);
    let devices = device::on_instance(&instance);
    stopped::stop(controllers.iter().map(|c| c.handle));
    stopped::stop(devices.iter().map(|d| d.handle));
    // Outside the watchdog's lock: the handles' threads ask it while they hold their own.
    for c in &controllers {
        c.outputs_bad();
    }
    for d in &devices {
        d.outputs_bad();
    }
    if let Some(f) = cbf {
        // SAFETY: the PNIO_CBF_APPL_WATCHDOG the program registered for this CPIndex, called
        // with the CPIndex as its prototype says.
        invoke_device(|| unsafe { f(cp) });
    }
}

/// Registers the CP application watchdog of `CPIndex` (`wdTimeOutInMs` 0 and `cbf` NULL:
/// deregisters it). Monitoring starts at the first `PNIO_CP_trigger_watchdog`.
///
/// # Safety
/// `pnio_appl_wd_cbf` is NULL or a function of the `PNIO_CBF_APPL_WATCHDOG` type that stays
/// callable until it is deregistered.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_CP_set_appl_watchdog(
    CPIndex: PNIO_UINT32,
    wdTimeOutInMs: PNIO_UINT32,
    pnio_appl_wd_cbf: PNIO_CBF_APPL_WATCHDOG,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_CP_set_appl_watchdog";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        set(CPIndex, wdTimeOutInMs, pnio_appl_wd_cbf)
    })
}

/// Retriggers the CP application watchdog of `CPIndex`.
///
/// # Safety
/// None beyond the C ABI; every value is checked.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_CP_trigger_watchdog(CPIndex: PNIO_UINT32) -> PNIO_UINT32 {
    // Allowed inside callbacks: an isochronous program triggers in its STARTOP callback.
    guard(PNIO_ERR_INTERNAL, || trigger(CPIndex))
}
