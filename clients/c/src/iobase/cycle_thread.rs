// SPDX-License-Identifier: MIT OR Apache-2.0
//! The isochronous event thread, one loop for a controller and a device.
//!
//! The thread sleeps on the client's [`EventWait`] (or [`POLL`] while there is none: no
//! server, or the client was replaced), then looks at the client once, with it locked: a
//! synchronous client's STARTOP opens the cycle's [`Window`] (after the CP watchdog's
//! expiry the thread ends that cycle itself with the outputs BAD, and the program gets no
//! STARTOP_IND), and the events since the last look are taken. Then, with the client
//! unlocked (the callbacks call the data functions and `PNIO_CP_set_opdone`), it calls
//! OPFAULT_IND and NEWCYCLE_IND in the order they happened, and STARTOP_IND last. The
//! callbacks come one at a time, from this thread only.
//!
//! What differs between the roles is a [`CycleSide`]: how the client and the window are
//! locked, the controller's other events (its mode, a restarted server), and whether a
//! handle the watchdog stopped still hears of events.

use super::callbacks::CallbackTable;
use super::isochronous::{Window, cycle_info, report};
use super::stopped;
use super::types::*;
use procimg_client::{Client, CycleInfo, Event, EventWait, Mode, now_ns};
use std::time::Duration;

/// The longest the thread sleeps before it looks at its stop flag and the server.
const POLL: Duration = Duration::from_millis(20);

/// A controller or a device as its isochronous event thread sees it. The thread owns the
/// value, so what it keeps from one look to the next lives in it.
pub(crate) trait CycleSide {
    /// Whether a handle the CP watchdog's expiry stopped still gets the callbacks of its
    /// events (every one but STARTOP_IND, which it never gets again).
    const EVENTS_WHEN_STOPPED: bool;

    /// Whether the thread is to end.
    fn stopping(&self) -> bool;
    /// The PNIO handle: the callbacks' `Handle`, and what the watchdog's expiry stops.
    fn handle(&self) -> u32;
    /// The CpIndex, for the callbacks.
    fn cp_index(&self) -> u32;
    /// The program's callbacks (the `PNIO_CP_CBE_*` ones are called here).
    fn callbacks(&self) -> &CallbackTable;
    /// Whether STARTOP is registered: the client is synchronous, each cycle a window.
    /// Asked with the client locked, where a re-attach changes both together.
    fn synchronous(&self) -> bool;
    /// Runs `f` with the client and the window locked; `None` while there is no client.
    fn with_io<R>(&self, f: impl FnOnce(&mut Client, &mut Window) -> R) -> Option<R>;
    /// What a look does with an asynchronous client (it has no window to take), before
    /// its events are taken.
    fn look_asynchronous(&self, _client: &mut Client) {}
    /// An event other than OPFAULT and NEWCYCLE, in its place among them.
    fn event(&mut self, _e: Event) {}
    /// After the events of a look, before its STARTOP_IND; `mode` is the server's mode in
    /// the newest image.
    fn after_events(&mut self, _mode: Option<Mode>) {}
}

/// What one look at the client took.
struct Look {
    events: Vec<Event>,
    /// The STARTOP of a window opened for the program.
    startop: Option<CycleInfo>,
    /// The newest image's cycle, for the events' cycle info.
    newest: Option<CycleInfo>,
    mode: Option<Mode>,
}

/// The thread's loop, until `side` says stop.
pub(crate) fn run<S: CycleSide>(mut side: S) {
    // Taken before each look at the client: what the server signals after it ends the
    // next sleep at once. A re-attach meanwhile costs one short sleep.
    let mut wait: Option<EventWait> = None;
    while !side.stopping() {
        match wait.take() {
            Some(w) => {
                let _ = w.wait(POLL);
            }
            None => std::thread::sleep(POLL),
        }
        if side.stopping() {
            break;
        }
        wait = side.with_io(|client, _| client.event_wait()).flatten();
        let expired = stopped::expired(side.handle());
        let Some(look) = look(&side, expired) else {
            continue;
        };
        if expired && !S::EVENTS_WHEN_STOPPED {
            continue;
        }
        deliver(&mut side, look);
    }
}

fn look(side: &impl CycleSide, expired: bool) -> Option<Look> {
    side.with_io(|client, window| {
        let mut startop = None;
        if side.synchronous() {
            startop = window.take_startop(client);
            if startop.is_some() && expired {
                // After the watchdog's expiry the program gets no cycle: the library ends
                // it with the outputs BAD.
                window.finish_bad(client);
                startop = None;
            }
        } else {
            side.look_asynchronous(client);
        }
        Look {
            events: client.events(),
            startop,
            newest: client.cycle_info(),
            mode: client.mode(),
        }
    })
}

/// Calls the program's callbacks for one look, in the order things happened.
fn deliver(side: &mut impl CycleSide, look: Look) {
    let info_now = || cycle_info(&look.newest.unwrap_or_default(), now_ns());
    for e in look.events {
        let t = match e {
            Event::OpFault { .. } => PNIO_CP_CBE_OPFAULT_IND,
            Event::NewCycle => PNIO_CP_CBE_NEWCYCLE_IND,
            other => {
                side.event(other);
                continue;
            }
        };
        report(
            side.callbacks(),
            t,
            side.cp_index(),
            side.handle(),
            info_now(),
        );
    }
    side.after_events(look.mode);
    if let Some(info) = look.startop {
        report(
            side.callbacks(),
            PNIO_CP_CBE_STARTOP_IND,
            side.cp_index(),
            side.handle(),
            cycle_info(&info, now_ns()),
        );
    }
}
