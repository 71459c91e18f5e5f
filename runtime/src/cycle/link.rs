// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the cycle engine exchanges with its clients, and its clock, behind one trait: the
//! iceoryx2 ports in procimgd ([`CyclePorts`]), an in-memory link in the engine's tests
//! ([`MemoryLink`]), so that the cycle's rules are tested without a process, a sleep or a
//! real clock.

use crate::shm::CyclePorts;
use crate::sys::clock::now_ns;
use crate::sys::poll::wait_readable;
use iceoryx2::port::update_connections::UpdateConnections;
use iceoryx2::prelude::{EventId, FileDescriptorBased};
use procimg_shm_layout::{ImageHeader, OutputHeader};
use std::collections::VecDeque;

/// The clients' side of the cycle, and the clock the cycle runs on.
pub trait ClientLink {
    /// Now, in ns on the cycle's clock (`CLOCK_MONOTONIC` in procimgd).
    fn now_ns(&self) -> u64;
    /// Publishes `payload` as this cycle's input image; `header` is called after the copy
    /// with the time then, to stamp when the image was complete. `false` if it could not be
    /// published.
    fn publish(&mut self, payload: &[u8], header: &mut dyn FnMut(u64) -> ImageHeader) -> bool;
    /// Hands the oldest client output sample waiting to `take`, with the time it was taken
    /// (read only when there is one).
    fn take_output(&mut self, take: &mut dyn FnMut(&OutputHeader, &[u8], u64)) -> Taken;
    /// Signals event `id` (STARTOP, OPFAULT of a slot, ...) to the clients.
    fn notify(&mut self, id: usize);
    /// Waits until an output sample may have arrived or `deadline_ns` passed; `busy` polls
    /// instead of sleeping.
    fn wait_outputs(&mut self, deadline_ns: u64, busy: bool);
    /// Drops the OPDONE wake-ups that arrived (their samples are what counts).
    fn clear_wakeups(&mut self);
    /// Brings the connections to clients that came or went up to date.
    fn maintain(&mut self);
}

/// What [`ClientLink::take_output`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Taken {
    /// A sample was handed over.
    Sample,
    /// No sample waits.
    Nothing,
    /// The link could not receive (a dead client's connection being removed).
    Failed,
}

/// A call into iceoryx2's ports. When a client came or went since the last call, iceoryx2
/// sets up or tears down its connection inside such a call, and that allocates: those
/// allocations are counted as connection set-up, apart from the cycle's own. In steady
/// state (no client coming or going) neither count moves: `tests/alloc.rs` proves both.
fn iceoryx2_call<R>(f: impl FnOnce() -> R) -> R {
    crate::sys::rt_alloc::as_connection_setup(f)
}

impl ClientLink for CyclePorts {
    fn now_ns(&self) -> u64 {
        now_ns()
    }

    fn publish(&mut self, payload: &[u8], header: &mut dyn FnMut(u64) -> ImageHeader) -> bool {
        match iceoryx2_call(|| self.inputs.loan_slice_uninit(payload.len())) {
            Ok(sample) => {
                let mut sample = sample.write_from_slice(payload);
                *sample.user_header_mut() = header(now_ns());
                iceoryx2_call(|| sample.send().is_ok())
            }
            Err(_) => false,
        }
    }

    fn take_output(&mut self, take: &mut dyn FnMut(&OutputHeader, &[u8], u64)) -> Taken {
        match iceoryx2_call(|| self.outputs.receive()) {
            Ok(Some(sample)) => {
                take(sample.user_header(), sample.payload(), now_ns());
                Taken::Sample
            }
            Ok(None) => Taken::Nothing,
            Err(_) => Taken::Failed,
        }
    }

    fn notify(&mut self, id: usize) {
        let _ = iceoryx2_call(|| self.events.notify_with_custom_event_id(EventId::new(id)));
    }

    fn wait_outputs(&mut self, deadline_ns: u64, busy: bool) {
        if busy {
            // The sample is there before its OPDONE event: looking for samples is enough.
            while !self.outputs.has_samples().unwrap_or(true) && now_ns() < deadline_ns {
                std::hint::spin_loop();
            }
            return;
        }
        // SAFETY: the descriptor belongs to the listener in `self`, which outlives this call.
        #[allow(unsafe_code)]
        let fd = unsafe { self.opdone.file_descriptor().native_handle() };
        if wait_readable(fd, deadline_ns.saturating_sub(now_ns())) {
            self.clear_wakeups();
        }
    }

    fn clear_wakeups(&mut self) {
        let _ = self.opdone.try_wait(|_| {});
    }

    fn maintain(&mut self) {
        iceoryx2_call(|| {
            let _ = self.inputs.update_connections();
            let _ = self.outputs.update_connections();
            let _ = self.events.update_connections();
        });
    }
}

/// An in-memory link with a clock the test sets: output samples are queued by the test,
/// images and events are recorded. Waiting for outputs that are not there moves the clock
/// to the deadline, as time passing would.
#[derive(Debug, Default)]
pub struct MemoryLink {
    /// Now, in ns.
    pub now: u64,
    /// Client output samples waiting, oldest first.
    pub outputs: VecDeque<(OutputHeader, Vec<u8>)>,
    /// Output samples that arrive only while the engine waits for OPDONE (as a client's
    /// answer to this cycle's STARTOP does), oldest first.
    pub answers: VecDeque<(OutputHeader, Vec<u8>)>,
    /// Every image published: its header and payload.
    pub published: Vec<(ImageHeader, Vec<u8>)>,
    /// Every event signalled, in order.
    pub events: Vec<usize>,
}

impl ClientLink for MemoryLink {
    fn now_ns(&self) -> u64 {
        self.now
    }

    fn publish(&mut self, payload: &[u8], header: &mut dyn FnMut(u64) -> ImageHeader) -> bool {
        let copy = payload.to_vec();
        self.published.push((header(self.now), copy));
        true
    }

    fn take_output(&mut self, take: &mut dyn FnMut(&OutputHeader, &[u8], u64)) -> Taken {
        match self.outputs.pop_front() {
            Some((h, payload)) => {
                take(&h, &payload, self.now);
                Taken::Sample
            }
            None => Taken::Nothing,
        }
    }

    fn notify(&mut self, id: usize) {
        self.events.push(id);
    }

    fn wait_outputs(&mut self, deadline_ns: u64, _busy: bool) {
        match self.answers.pop_front() {
            Some(answer) => self.outputs.push_back(answer),
            None => self.now = self.now.max(deadline_ns),
        }
    }

    fn clear_wakeups(&mut self) {}

    fn maintain(&mut self) {}
}
