// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the cycle engine exchanges with its clients, and its clock, behind one trait: the
//! iceoryx2 ports in procimgd ([`CyclePorts`]), an in-memory link in the engine's tests
//! ([`MemoryLink`]), so that the cycle's rules are tested without a process, a sleep or a
//! real clock.

use crate::shm::CyclePorts;
use crate::shm::aside::Loan;
use crate::shm::outputs::OutputHandoff;
use crate::sys::clock::now_ns;
use core::ptr::NonNull;
use iceoryx2::port::update_connections::UpdateConnections;
use iceoryx2::prelude::EventId;
use procimg_control::futex::LinuxFutex;
use procimg_shm_layout::cycle_record::Recorded;
use procimg_shm_layout::events::EVENT_STARTOP;
use procimg_shm_layout::segment::SamplePlace;
use procimg_shm_layout::{ImageHeader, OutputHeader};
use std::collections::VecDeque;

/// The clients' side of the cycle, and the clock the cycle runs on.
pub trait ClientLink {
    /// Now, in ns on the cycle's clock (`CLOCK_MONOTONIC` in procimgd).
    fn now_ns(&self) -> u64;
    /// Loans the sample this cycle's input image is built in, of `len` bytes, and returns
    /// where its payload starts; `None` when no sample can be had (the cycle then publishes
    /// nothing). The payload is valid for reads and writes by the caller alone until
    /// [`ClientLink::publish`], and after a publication readable and unchanged until the next
    /// sample has been published. Loaned for the first time it holds garbage; loaned again, it
    /// holds what the caller left in it (iceoryx2's readers map its samples read-only:
    /// `tests/input_samples.rs` checks iceoryx2 for it).
    fn loan_image(&mut self, len: usize) -> Option<NonNull<u8>>;
    /// Loans, ahead of time, the sample the next [`ClientLink::loan_image`] returns (when
    /// it asks for as many bytes): at the end of a cycle, so that iceoryx2's loan (some µs)
    /// does not lie between STARTOP and the clients' answers. Nothing when one is loaned
    /// ahead already.
    fn loan_ahead(&mut self, len: usize);
    /// Publishes the loaned sample, every byte of which the caller wrote, with `header`. The
    /// header is stamped last ([`procimg_shm_layout::CycleInfo::stamp`]), once the rest of
    /// it is in the sample: its clock says when the image was complete. The stamp goes into
    /// `header` too. `false` if nothing was loaned or it could not be published. With
    /// `send_later`, a sample the busy path can name is only named now (clients that read by
    /// their mark find it at once) and goes to iceoryx2's readers at
    /// [`ClientLink::send_named`].
    fn publish(&mut self, header: &mut ImageHeader, send_later: bool) -> bool;
    /// Sends the sample [`ClientLink::publish`] named and kept back, if there is one.
    /// `false` if it could not be sent.
    fn send_named(&mut self) -> bool;
    /// Whether every client of `slots` (bit per slot) reads the images by its mark and none
    /// waits for STARTOP on iceoryx2's descriptor: nobody the cycle waits for then needs
    /// iceoryx2's copy of the image before the outputs are out.
    fn read_by_mark(&self, slots: u64) -> bool;
    /// Hands the oldest client output sample waiting to `take`, with the time it was taken
    /// (read only when there is one).
    fn take_output(&mut self, take: &mut dyn FnMut(&OutputHeader, &[u8], u64)) -> Taken;
    /// Signals event `id` (STARTOP, OPFAULT of a slot, ...) to the clients.
    fn notify(&mut self, id: usize);
    /// A mark of the OPDONE signals so far: taken before looking for output samples, then
    /// handed to [`ClientLink::wait_outputs`], so that an OPDONE in between is not slept
    /// through.
    fn opdone_mark(&self) -> u32;
    /// Waits until a client signalled OPDONE after `mark` was taken, or `deadline_ns` passed:
    /// polling until `spin_until_ns`, sleeping after it.
    fn wait_outputs(&mut self, mark: u32, deadline_ns: u64, spin_until_ns: u64);
    /// Forgets what the client of `slot` left in the link (it joined anew, left or died): its
    /// wake-up state, and its output port, which goes back through `handoff`.
    fn forget_client(&mut self, slot: u32, handoff: &OutputHandoff);
    /// Takes the clients' output ports that arrived through `handoff`: those of the
    /// registrations `current(slot, token)` accepts, the others back at once.
    fn adopt_outputs(&mut self, handoff: &OutputHandoff, current: &dyn Fn(u32, u64) -> bool);
    /// Brings the connections to clients that came or went up to date.
    fn maintain(&mut self);
}

pub use crate::shm::outputs::Taken;

/// A call into iceoryx2's ports. When a client came or went since the last call, iceoryx2
/// sets up or tears down its connection inside such a call, and that allocates: those
/// allocations are counted as connection set-up, apart from the cycle's own. In steady
/// state (no client coming or going) neither count moves: `tests/alloc.rs` proves both.
fn iceoryx2_call<R>(f: impl FnOnce() -> R) -> R {
    crate::sys::rt_alloc::as_connection_setup(f)
}

impl CyclePorts {
    /// Loans a sample no busy client holds, and where it lies in the input segment; `None`
    /// when none can be had.
    fn loan_unheld(&mut self, len: usize) -> Option<(Loan, Option<u32>)> {
        let pins = &self.handshake.block().pins;
        loop {
            let loan = Loan::new(iceoryx2_call(|| self.inputs.loan_slice_uninit(len)).ok()?);
            let at = loan.at;
            let offset = self.aside.offset(at);
            // A sample a busy client still reads, though a newer image replaced it: never
            // written while it holds it (see `shm::aside`). A sample loaned ahead cannot
            // come to be held before it is used: a client marks only the newest image.
            if offset.is_some_and(|off| pins.held(off)) {
                // Without room it goes back unwritten, and this cycle publishes nothing.
                if !self.aside.keep(loan) {
                    return None;
                }
                continue;
            }
            self.reserve.note_loan(at, len);
            return Some((loan, offset));
        }
    }
}

impl ClientLink for CyclePorts {
    fn now_ns(&self) -> u64 {
        now_ns()
    }

    fn loan_image(&mut self, len: usize) -> Option<NonNull<u8>> {
        // A sample still loaned (a cycle that did not get to publish it) goes back first,
        // and so do the samples kept aside that no busy client holds any more.
        self.loaned = None;
        self.aside.release(&self.handshake.block().pins);
        let (loan, offset) = match self.ahead.take() {
            Some(ahead) if ahead.0.len == len => ahead,
            _ => self.loan_unheld(len)?,
        };
        self.loaned_offset = offset;
        self.loaned = Some(loan.sample);
        NonNull::new(loan.at as *mut u8)
    }

    fn loan_ahead(&mut self, len: usize) {
        if self.ahead.is_none() {
            self.aside.release(&self.handshake.block().pins);
            self.ahead = self.loan_unheld(len);
        }
    }

    fn publish(&mut self, header: &mut ImageHeader, send_later: bool) -> bool {
        // The engine sends an image it kept back at the end of its cycle; one left over
        // still goes to iceoryx2's readers before a newer one.
        let _ = self.send_named();
        let Some(sample) = self.loaned.take() else {
            return false;
        };
        // SAFETY: the engine wrote every byte of the payload before publishing
        // (`Image::carry_over_inputs` and `Image::publish_into`).
        #[allow(unsafe_code)]
        let mut sample = unsafe { sample.assume_init() };
        // The header's lines are written before the clock is read: the stamp is the
        // image's last write, as close to the word that names it as it can be.
        let in_sample = sample.user_header_mut();
        *in_sample = *header;
        header.cycle.stamp(now_ns());
        in_sample.cycle = header.cycle;
        if let Some(offset) = self.loaned_offset.take() {
            // Complete, so named at once: a busy client holds it by its mark and need not
            // wait for iceoryx2 to deliver it (the next loans skip it while it is held, also
            // should the send below fail).
            let pins = &self.handshake.block().pins;
            // The cycle and the mode on the word's line first: a busy client that sees the
            // word has them without the header's lines.
            pins.record(&Recorded {
                cycle: header.cycle,
                mode: header.mode,
                mode_changes: header.mode_changes,
            });
            pins.publish(SamplePlace {
                cycle: header.cycle.cycle_number as u32,
                offset,
            });
            if send_later {
                // iceoryx2's send (some microseconds, growing with its readers) then runs
                // after the outputs are out, not between the image and the clients' answers.
                self.unsent = Some(sample);
                return true;
            }
        }
        iceoryx2_call(|| sample.send().is_ok())
    }

    fn send_named(&mut self) -> bool {
        match self.unsent.take() {
            Some(sample) => iceoryx2_call(|| sample.send().is_ok()),
            None => true,
        }
    }

    fn read_by_mark(&self, slots: u64) -> bool {
        let block = self.handshake.block();
        !block.has_fd_waiters() && block.pins.joined() & slots == slots
    }

    fn take_output(&mut self, take: &mut dyn FnMut(&OutputHeader, &[u8], u64)) -> Taken {
        let posts = &self.handshake.block().posts;
        self.outputs.take(posts, take)
    }

    fn notify(&mut self, id: usize) {
        let block = self.handshake.block();
        if id == EVENT_STARTOP {
            // Clients sleep on the block's futex word: one wake-up for all of them. The
            // event service carries STARTOP only for clients that wait on its descriptor.
            block.announce(&LinuxFutex, false);
            if !block.has_fd_waiters() {
                return;
            }
        }
        let _ = iceoryx2_call(|| self.events.notify_with_custom_event_id(EventId::new(id)));
        if id != EVENT_STARTOP {
            // After the event is on the service: a client woken by the word finds it there.
            block.announce(&LinuxFutex, true);
        }
    }

    fn opdone_mark(&self) -> u32 {
        self.handshake.block().opdone_seen()
    }

    fn wait_outputs(&mut self, mark: u32, deadline_ns: u64, spin_until_ns: u64) {
        self.handshake
            .block()
            .wait_opdone(&LinuxFutex, mark, deadline_ns, spin_until_ns);
    }

    fn forget_client(&mut self, slot: u32, handoff: &OutputHandoff) {
        self.handshake.block().forget_slot(slot);
        self.outputs.retire(slot, handoff);
    }

    fn adopt_outputs(&mut self, handoff: &OutputHandoff, current: &dyn Fn(u32, u64) -> bool) {
        self.outputs.adopt(handoff, current);
    }

    fn maintain(&mut self) {
        iceoryx2_call(|| {
            // The output ports are connected by the control thread; a publisher that went
            // away is let go of by the port's next receive.
            let _ = self.inputs.update_connections();
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
    /// Clients whose samples come out torn (as a busy client's written during the copy).
    pub torn_slots: Vec<u32>,
    /// Every image published: its header and payload.
    pub published: Vec<(ImageHeader, Vec<u8>)>,
    /// Every event signalled, in order.
    pub events: Vec<usize>,
    /// No sample can be loaned (all are held by readers).
    pub refuse_loans: bool,
    /// Every client reads by its mark ([`ClientLink::read_by_mark`]).
    pub all_read_by_mark: bool,
    /// For each image of [`MemoryLink::published`] kept back: where in
    /// [`MemoryLink::events`] it was sent.
    pub sent_at: Vec<Option<usize>>,
    /// A publication kept back for [`ClientLink::send_named`].
    kept_back: bool,
    /// Payload ranges every publication writes whole (the status bytes, the padding): filled
    /// with [`UNWRITTEN`] at every loan, so that a byte of them left unwritten shows in every
    /// image, not only in a sample's first.
    pub scribble: Vec<(usize, usize)>,
    /// The samples images are built in, in turn: the last one published stays untouched
    /// while the next is written, and each comes back as it was published.
    samples: [Vec<u8>; 3],
    /// Which of them is loaned (or was published last).
    loaned: usize,
}

/// What a sample holds when it is loaned for the first time, before the engine writes it: a
/// value no test image has everywhere, so that a byte left unwritten shows.
pub const UNWRITTEN: u8 = 0xEE;

impl ClientLink for MemoryLink {
    fn now_ns(&self) -> u64 {
        self.now
    }

    fn loan_image(&mut self, len: usize) -> Option<NonNull<u8>> {
        if self.refuse_loans {
            return None;
        }
        // Three samples in turn, as a publisher with a history of one and a reader that
        // holds one image has: the last one published stays untouched while the next is
        // written. A sample loaned for the first time holds garbage, as an uninitialised
        // one does; after that, what it held when it was published (iceoryx2's readers map
        // the samples read-only).
        self.loaned = (self.loaned + 1) % self.samples.len();
        let sample = &mut self.samples[self.loaned];
        if sample.len() != len {
            sample.clear();
            sample.resize(len, UNWRITTEN);
        }
        for &(start, end) in &self.scribble {
            if let Some(bytes) = sample.get_mut(start..end) {
                bytes.fill(UNWRITTEN);
            }
        }
        NonNull::new(sample.as_mut_ptr())
    }

    fn loan_ahead(&mut self, _len: usize) {
        // The samples go round in a fixed order: a loan ahead would change nothing.
    }

    fn publish(&mut self, header: &mut ImageHeader, send_later: bool) -> bool {
        self.send_named();
        if self.refuse_loans {
            return false;
        }
        let copy = self.samples[self.loaned].clone();
        header.cycle.stamp(self.now);
        self.published.push((*header, copy));
        self.sent_at.push(None);
        self.kept_back = send_later;
        true
    }

    fn send_named(&mut self) -> bool {
        if std::mem::take(&mut self.kept_back)
            && let Some(last) = self.sent_at.last_mut()
        {
            *last = Some(self.events.len());
        }
        true
    }

    fn read_by_mark(&self, _slots: u64) -> bool {
        self.all_read_by_mark
    }

    fn take_output(&mut self, take: &mut dyn FnMut(&OutputHeader, &[u8], u64)) -> Taken {
        match self.outputs.pop_front() {
            Some((h, payload)) => {
                take(&h, &payload, self.now);
                if self.torn_slots.contains(&h.client_slot) {
                    Taken::Torn(h.client_slot)
                } else {
                    Taken::Sample
                }
            }
            None => Taken::Nothing,
        }
    }

    fn notify(&mut self, id: usize) {
        self.events.push(id);
    }

    fn opdone_mark(&self) -> u32 {
        0
    }

    fn wait_outputs(&mut self, _mark: u32, deadline_ns: u64, _spin_until_ns: u64) {
        match self.answers.pop_front() {
            Some(answer) => self.outputs.push_back(answer),
            None => self.now = self.now.max(deadline_ns),
        }
    }

    fn forget_client(&mut self, _slot: u32, _handoff: &OutputHandoff) {}

    fn adopt_outputs(&mut self, _handoff: &OutputHandoff, _current: &dyn Fn(u32, u64) -> bool) {}

    fn maintain(&mut self) {}
}
