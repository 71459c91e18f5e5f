// SPDX-License-Identifier: MIT OR Apache-2.0
//! An attached client: registration, claims, events, the cycle handshake and re-attachment
//! after a server restart.

use crate::arrivals::Arrivals;
use crate::connection::{Connection, Ipc, Registration, iox2_config};
use crate::control::ControlHandle;
use crate::error::{AttachError, ControlError, IoError, WaitError};
use crate::input_view::{InputView, SegmentKnowledge, learn_segment};
use crate::layout::Layout;
use crate::output_sample::OutputSample;
use crate::status::Ioxs;
use crate::wake_ahead::poll_window;
use iceoryx2::node::{Node, NodeState, NodeView};
use iceoryx2::prelude::CallbackProgression;
use procimg_control::futex::LinuxFutex;
use procimg_control::{ClientRole, CoreRequest, Response, server_node_name};
use procimg_shm_layout::events::{EVENT_MODE, EVENT_NEWCYCLE, EVENT_SHUTDOWN, opfault_event};
use procimg_shm_layout::handshake::Woken;
use procimg_shm_layout::handshake_map::HandshakeMap;
use procimg_shm_layout::maps::mapping_of;
use procimg_shm_layout::segment::SamplePlace;
use procimg_shm_layout::{
    CycleInfo, IMAGE_MAGIC, ImageHeader, MAX_CLIENTS, MODE_HISTORY, Mode, OUTPUT_SYNCHRONOUS,
    OutputHeader,
};
use std::collections::{BTreeSet, VecDeque};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How a client attaches.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AttachOptions {
    /// A name shown in `procimg status`.
    pub name: String,
    /// Synchronous (takes part in STARTOP/OPDONE) or asynchronous.
    pub role: ClientRole,
    /// IO-Base slice access (`PNIO_CEP_SLICE_ACCESS`): read and write parts of submodules.
    pub slice_access: bool,
    /// Refuse to attach unless the server's layout hash is this one.
    pub expected_layout_hash: Option<u64>,
    /// Deliver [`Event::NewCycle`] (IO-Base's NEWCYCLE is delivered only when registered).
    pub newcycle: bool,
    /// How long attaching may take (10 s by default: the server's control side runs at
    /// normal priority and answers late on a loaded machine, without being wrong).
    pub timeout: Duration,
    /// [`Client::wait_startop`] polls for the image instead of sleeping on the STARTOP event.
    pub busy_poll: bool,
    /// How long before the next STARTOP is due a sleeping [`Client::wait_startop`] wakes and
    /// polls for it ([`WAKE_AHEAD`] by default; zero: it sleeps until STARTOP wakes it).
    pub wake_ahead: Duration,
}

/// How often [`Client::refresh`] tries to hold the newest image by its mark before it takes
/// the one iceoryx2 delivered instead: each failed try means procimgd named a newer image
/// while this thread was not running.
const PIN_TRIES: usize = 4;

/// How long before the next STARTOP is due a sleeping client wakes by default. A thread
/// that sleeps until STARTOP wakes it starts on a CPU that has gone idle, which on a VM
/// costs several microseconds at the median and tens at p99 (docs/PERFORMANCE.md, *Waking
/// ahead*); one that wakes on its own timer this much earlier and polls is running when
/// STARTOP comes. The lead covers the timer's own wake-up latency (some 20–30 µs on a VM)
/// with room to spare. It costs at most this long of CPU time per cycle (less that
/// latency), and up to three times as long when procimgd is late.
pub const WAKE_AHEAD: Duration = Duration::from_micros(50);

/// How long attaching may take by default.
pub const ATTACH_TIMEOUT: Duration = Duration::from_secs(10);

impl AttachOptions {
    /// A synchronous client: the server waits for its OPDONE every cycle.
    pub fn synchronous(name: &str) -> AttachOptions {
        AttachOptions {
            name: name.to_string(),
            role: ClientRole::Synchronous,
            slice_access: true,
            expected_layout_hash: None,
            newcycle: false,
            timeout: ATTACH_TIMEOUT,
            busy_poll: false,
            wake_ahead: WAKE_AHEAD,
        }
    }

    /// An asynchronous client: reads and writes whenever it likes.
    pub fn asynchronous(name: &str) -> AttachOptions {
        AttachOptions {
            role: ClientRole::Asynchronous,
            ..AttachOptions::synchronous(name)
        }
    }

    /// Sets slice access.
    pub fn slice_access(mut self, on: bool) -> AttachOptions {
        self.slice_access = on;
        self
    }

    /// Asks for NEWCYCLE events.
    pub fn newcycle(mut self, on: bool) -> AttachOptions {
        self.newcycle = on;
        self
    }

    /// Makes [`Client::wait_startop`] poll for the next image without sleeping: the client
    /// finds each image through the handshake block as soon as procimgd has completed it,
    /// and reads it in place, held by its mark, without an iceoryx2 receive (below a
    /// microsecond on a 2-vCPU VM, docs/PERFORMANCE.md); it keeps its CPU busy all the time
    /// it waits. For a client thread with a CPU of its own (isolated, SCHED_FIFO); pair it
    /// with `opdone_wait = "busy-poll"` on the server for the shortest round trip.
    pub fn busy_poll(mut self, on: bool) -> AttachOptions {
        self.busy_poll = on;
        self
    }

    /// Sets how long before the next STARTOP is due a sleeping client wakes and polls for it
    /// ([`WAKE_AHEAD`] by default; at most an eighth of the cycle is used). Zero: the client
    /// sleeps until procimgd wakes it, and spends no CPU time polling.
    pub fn wake_ahead(mut self, lead: Duration) -> AttachOptions {
        self.wake_ahead = lead;
        self
    }

    /// Insists on a layout hash.
    pub fn expect_layout_hash(mut self, hash: u64) -> AttachOptions {
        self.expected_layout_hash = Some(hash);
        self
    }
}

/// Something that happened, as IO-Base reports through its callbacks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Event {
    /// The mode changed (`PNIO_CBE_MODE_IND`); one event per step.
    Mode(Mode),
    /// This client's OPDONE for `cycle` came too late (`PNIO_CP_CBE_OPFAULT_IND`).
    OpFault {
        /// The cycle it missed.
        cycle: u64,
    },
    /// A bus cycle's outputs went out (`PNIO_CP_CBE_NEWCYCLE_IND`).
    NewCycle,
    /// The server announced it is stopping.
    ServerShutdown,
    /// The client re-attached to a restarted server.
    Reattached {
        /// The new server generation.
        generation: u64,
    },
    /// A claim held before a server restart could not be taken again.
    ClaimLost {
        /// Submodule index.
        submodule: usize,
    },
    /// The server came back with another layout (a changed configuration, or a station its
    /// program defined anew), and the client follows it: [`Client::layout`] is the new one,
    /// submodule indexes and addresses are the new layout's, and the claims of submodules
    /// still there (same device, API, slot, subslot and ident numbers) were taken again
    /// under their new indexes. Comes right after [`Event::Reattached`]. A client attached
    /// with [`AttachOptions::expect_layout_hash`] does not follow: its wait ends with
    /// [`WaitError::LayoutChanged`] instead.
    LayoutChanged {
        /// The layout hash before.
        was: u64,
        /// The layout hash now.
        now: u64,
    },
}

/// How often a client without STARTOP checks whether the server is still alive.
pub(crate) const LIVENESS_PERIOD: Duration = Duration::from_millis(100);
/// How often a client whose server is gone tries to re-attach.
pub(crate) const REATTACH_PERIOD: Duration = Duration::from_millis(50);
/// How long one step of re-attaching (registration, layout) may take.
const REATTACH_STEP: Duration = Duration::from_millis(300);
/// How long without a new image before an asynchronous access checks the server is alive.
const STALE_IMAGE: Duration = Duration::from_millis(100);

/// Whether the cycle node of `instance`'s server with process id `pid` (any process when 0)
/// is alive; `None` when the node list failed part-way, which proves nothing.
///
/// By name and process: a server SIGKILLed and started again between two checks has a live
/// node of the same name, but not the services its predecessor's clients hold.
pub(crate) fn server_listed(instance: &str, pid: u32) -> Option<bool> {
    let wanted = format!("{}/cycle", server_node_name(instance));
    let mut alive = false;
    let listed = Node::<Ipc>::list(iox2_config(), |state| {
        if let NodeState::Alive(v) = &state
            && v.details().as_ref().is_some_and(|d| {
                d.name().as_str() == wanted && (pid == 0 || d.process_id().value() as u32 == pid)
            })
        {
            alive = true;
            return CallbackProgression::Stop;
        }
        CallbackProgression::Continue
    });
    listed.is_ok().then_some(alive)
}

/// Events a client keeps for [`Client::events`]; older ones are dropped when a program does
/// not collect them.
pub const EVENT_QUEUE: usize = 256;

/// A client attached to a procimgd instance.
pub struct Client {
    pub(crate) opts: AttachOptions,
    pub(crate) slot: u32,
    pub(crate) token: u64,
    pub(crate) generation: u64,
    /// The process id of the server attached to (0: it did not say).
    server_pid: u32,
    pub(crate) layout: Layout,
    pub(crate) claims: BTreeSet<usize>,
    /// The newest input image taken (the client's read view).
    pub(crate) latest: Option<InputView>,
    /// Busy-polling: where this connection's input segment lies, learnt from a received
    /// image; from then on images are found through the handshake block (see `input_view`).
    segment: SegmentKnowledge,
    /// Last cycle handed out by `wait_startop`.
    last_startop: u64,
    /// Last OPFAULT cycle seen for this client's slot.
    last_opfault: u64,
    /// `ImageHeader::mode_changes` of the last mode change reported.
    mode_changes_seen: Option<u32>,
    /// The handshake block's other-events word when the event service was last drained.
    other_events_seen: u32,
    /// A caller waits on [`Client::event_fd`]: the server then signals STARTOP on the event
    /// service too, and every look drains it.
    fd_waiter: AtomicBool,
    /// Images taken (to notice a server that stopped publishing).
    arrivals: Arrivals,
    events: VecDeque<Event>,
    last_liveness: Instant,
    last_reattach: Instant,
    /// Per submodule: the local input status the client wants sent (IOCS).
    pub(crate) local_input_iocs: Vec<Ioxs>,
    pub(crate) read_cache: Option<crate::cache::ReadCache>,
    pub(crate) write_cache: crate::cache::WriteCache,
    /// An output sample loaned ahead, right after an OPDONE, so that the next cycle's window
    /// does not pay for the loan (dropped before the ports it came from).
    spare_output: Option<OutputSample>,
    /// Busy-polling: the spare is last cycle's OPDONE sample, named in the handshake block
    /// (`procimg_shm_layout::posts`): withdrawn before it is written again.
    spare_posted: bool,
    /// Busy-polling: where this connection's output segment starts, looked up once, at the
    /// first OPDONE (`/proc/self/maps`): `Some(None)` when it could not be found, and the
    /// outputs then go as samples, without a look per cycle.
    output_start: Option<Option<usize>>,
    // Data ports, then the control handle (and its node) last: ports drop before the node.
    pub(crate) conn: Option<Connection>,
    pub(crate) control: ControlHandle,
}

impl Client {
    /// Attaches to `instance`.
    pub fn attach(instance: &str, opts: AttachOptions) -> Result<Client, AttachError> {
        let control = ControlHandle::open(instance, &opts.name)?;
        let (slot, token, generation, server_pid) = register(&control, &opts)?;
        let conn = match Connection::open(
            control.node(),
            instance,
            registration(generation, token, &opts),
            opts.timeout,
            &|| control.ring_server(),
            &|| connect_outputs(&control, slot, token, opts.timeout),
        ) {
            Ok(c) => c,
            Err(e) => {
                let _ = control.request_done(CoreRequest::Unregister { slot, token });
                return Err(e);
            }
        };
        control.own_ports(&conn.port_ids);
        let layout = conn.layout.clone();
        if let Some(expected) = opts.expected_layout_hash
            && expected != layout.hash()
        {
            let _ = control.request_done(CoreRequest::Unregister { slot, token });
            return Err(AttachError::LayoutHash {
                instance: instance.to_string(),
                expected,
                found: layout.hash(),
            });
        }
        let n = layout.submodules.len();
        let mut client = Client {
            opts,
            slot,
            token,
            generation,
            server_pid,
            write_cache: crate::cache::WriteCache::new(&layout),
            layout,
            claims: BTreeSet::new(),
            latest: None,
            segment: SegmentKnowledge::Unknown,
            last_startop: 0,
            last_opfault: 0,
            mode_changes_seen: None,
            other_events_seen: 0,
            fd_waiter: AtomicBool::new(false),
            arrivals: Arrivals::new(),
            events: VecDeque::with_capacity(EVENT_QUEUE),
            last_liveness: Instant::now(),
            last_reattach: Instant::now(),
            local_input_iocs: vec![Ioxs::Good; n],
            read_cache: None,
            spare_output: None,
            spare_posted: false,
            output_start: None,
            conn: Some(conn),
            control,
        };
        client.refresh();
        if let Some(opfault) = client
            .header()
            .map(|h| h.opfault_cycle[slot as usize % MAX_CLIENTS])
        {
            client.last_opfault = opfault;
        }
        Ok(client)
    }

    /// The instance name.
    pub fn instance(&self) -> &str {
        self.control.instance()
    }

    /// The server's layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// This client's slot on the server.
    pub fn slot(&self) -> u32 {
        self.slot
    }

    /// The server generation this client is attached to.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The control service (status, mode).
    pub fn control(&self) -> &ControlHandle {
        &self.control
    }

    /// Claims the outputs of these submodules (all or none). A claim held by another client is
    /// refused with an error naming the holder.
    pub fn claim(&mut self, submodules: &[usize]) -> Result<(), ControlError> {
        self.control.request_done(CoreRequest::Claim {
            slot: self.slot,
            token: self.token,
            submodules: submodules.iter().map(|&s| s as u32).collect(),
        })?;
        self.claims.extend(submodules.iter().copied());
        for &s in submodules {
            if let Some(v) = self.write_cache.valid.get_mut(s) {
                *v = false;
            }
        }
        Ok(())
    }

    /// Claims every output submodule of the device named `device`.
    pub fn claim_device(&mut self, device: &str) -> Result<Vec<usize>, ControlError> {
        let subs: Vec<usize> = match self.layout.device(device) {
            Some(d) => self
                .layout
                .submodules_of(d)
                .filter(|&s| self.layout.submodules[s].output_length > 0)
                .collect(),
            None => {
                return Err(ControlError::Refused(
                    procimg_control::Refusal::BadRequest {
                        message: format!("no device named \"{device}\" in the layout"),
                    },
                ));
            }
        };
        self.claim(&subs)?;
        Ok(subs)
    }

    /// Releases claims.
    pub fn release(&mut self, submodules: &[usize]) -> Result<(), ControlError> {
        self.control.request_done(CoreRequest::Release {
            slot: self.slot,
            token: self.token,
            submodules: submodules.iter().map(|&s| s as u32).collect(),
        })?;
        for &s in submodules {
            self.claims.remove(&s);
            if let Some(v) = self.write_cache.valid.get_mut(s) {
                *v = false;
            }
        }
        Ok(())
    }

    /// Whether this client holds the claim on submodule `s`.
    pub fn holds(&self, s: usize) -> bool {
        self.claims.contains(&s)
    }

    /// Asks for a mode change; confirmed by [`Event::Mode`].
    pub fn set_mode(&self, mode: Mode) -> Result<(), ControlError> {
        self.control.set_mode(mode)
    }

    /// The mode of the newest image.
    pub fn mode(&self) -> Option<Mode> {
        self.header().and_then(|h| Mode::from_u32(h.mode))
    }

    /// The header of the newest image received.
    pub(crate) fn header(&self) -> Option<&ImageHeader> {
        self.latest.as_ref().map(|s| s.user_header())
    }

    /// The descriptor that becomes readable when the server signals this client (STARTOP,
    /// mode, OPFAULT, NEWCYCLE, shutdown), for a caller that waits in its own `poll` and then
    /// calls [`Client::wait_startop`] or [`Client::events`] with a zero timeout. `None` while
    /// the server is gone; it changes when the client re-attaches.
    ///
    /// A caller that only needs to sleep until the next signal does better with
    /// [`Client::event_wait`]: once a client's descriptor was asked for, the server signals
    /// STARTOP through the event service as well (a system call per such client and cycle).
    pub fn event_fd(&self) -> Option<std::os::fd::RawFd> {
        let conn = self.conn.as_ref()?;
        self.fd_waiter.store(true, Ordering::Relaxed);
        conn.handshake.block().set_fd_waiter(self.slot, true);
        Some(conn.events_fd)
    }

    /// A wait for the server's next signal to this client (STARTOP, mode, OPFAULT, NEWCYCLE,
    /// shutdown), held apart from the client: a thread takes it, looks at the client
    /// ([`Client::events`], [`Client::wait_startop`] with a zero timeout), lets go of it and
    /// then sleeps in [`EventWait::wait`] on the handshake block's futex. What the server
    /// signals after the wait was taken ends the sleep. `None` while the server is gone.
    pub fn event_wait(&self) -> Option<EventWait> {
        let conn = self.conn.as_ref()?;
        let block = conn.handshake.block();
        Some(EventWait {
            seen: (block.events_seen(), block.pins.newest_word()),
            poll: self.poll_window(),
            block: conn.handshake.clone(),
            slot: self.slot,
        })
    }

    /// When a sleeping synchronous client polls for the next STARTOP (see
    /// [`AttachOptions::wake_ahead`]): `None` for an asynchronous client, which STARTOP does
    /// not concern, and when there is no window to poll in now.
    pub(crate) fn poll_window(&self) -> Option<(u64, u64)> {
        if self.opts.role != ClientRole::Synchronous {
            return None;
        }
        let lead = self.opts.wake_ahead.as_nanos().min(u64::MAX as u128) as u64;
        let named = self.conn.as_ref()?.handshake.block().pins.newest();
        let now = procimg_shm_layout::os::monotonic_ns();
        let window = poll_window(self.header()?, named.map(|p| p.cycle), lead, now)?;
        Some((window.start, window.end))
    }

    /// Whether this client is connected to a live server (it re-attaches by itself).
    pub fn connected(&self) -> bool {
        self.conn.is_some()
    }

    /// The attach options this client was made with.
    pub fn options(&self) -> &AttachOptions {
        &self.opts
    }

    /// The cycle info of the newest image received.
    pub fn cycle_info(&self) -> Option<CycleInfo> {
        self.header().map(|h| h.cycle)
    }

    /// Takes the newest input image, if a newer one arrived. Returns whether it did. On the
    /// busy path only the image's cycle and mode are current in its header (see
    /// [`Client::refresh_whole`]).
    pub(crate) fn refresh(&mut self) -> bool {
        self.take_newest(false)
    }

    /// As [`Client::refresh`], with the whole header current: the OPFAULT record and the
    /// mode history too, which the busy path copies only when asked.
    pub(crate) fn refresh_whole(&mut self) -> bool {
        self.take_newest(true)
    }

    fn take_newest(&mut self, whole: bool) -> bool {
        let Some(conn) = &self.conn else {
            return false;
        };
        let mut newer = false;
        let pins = &conn.handshake.block().pins;
        let mut pinned = false;
        if let SegmentKnowledge::Known(segment) = &self.segment {
            // The busy path: the newest image, held by this client's mark, found without a
            // receive. Nothing can be borrowing the one held before (`&mut self`). A try
            // fails only when procimgd named a newer image meanwhile (this thread was
            // preempted): the next try takes that one.
            for _ in 0..PIN_TRIES {
                let current = self
                    .latest
                    .as_ref()
                    .map(|l| (l.user_header().cycle.cycle_number, l.whole()));
                let Some(newest) = pins.pin_newest(self.slot) else {
                    break;
                };
                let same = current.is_some_and(|(c, _)| c as u32 == newest.cycle);
                if same && (!whole || current.is_some_and(|(_, w)| w)) {
                    pinned = true;
                    break;
                }
                // The cycle and mode from the newest word's line, which this thread has
                // since it saw the word move; the header's lines only when asked for or
                // when the record was being rewritten.
                let followed = !whole
                    && self
                        .latest
                        .as_mut()
                        .is_some_and(|view| view.follow_record(segment, newest, pins));
                if !followed {
                    // The header copied from the held sample. When the mark moved to a new
                    // image, the one held before is no longer held, so it goes whether or
                    // not the new one is taken.
                    self.latest =
                        InputView::pinned(segment, newest, pins, self.slot).filter(|view| {
                            let h = view.user_header();
                            h.magic == IMAGE_MAGIC && h.layout_hash == self.layout.hash()
                        });
                }
                if same && self.latest.is_some() {
                    pinned = true;
                    break;
                }
                if self.latest.is_some() {
                    (pinned, newer) = (true, true);
                    break;
                }
            }
            if !pinned {
                // No image held by the mark (tries used up on a machine that kept this
                // thread from running, or none named yet): the one iceoryx2 delivered.
                pins.unpin(self.slot);
            }
        }
        if !pinned {
            // The service lets a reader hold one image (procimgd keeps only a few): the one
            // held goes before the next is taken. Nothing can be borrowing it here (`&mut
            // self`).
            while conn.inputs.has_samples().unwrap_or(false) {
                self.latest = None;
                let Ok(Some(sample)) = conn.inputs.receive() else {
                    break;
                };
                let h = sample.user_header();
                if h.magic != IMAGE_MAGIC || h.layout_hash != self.layout.hash() {
                    continue;
                }
                if (self.opts.busy_poll || self.opts.role == ClientRole::Synchronous)
                    && matches!(self.segment, SegmentKnowledge::Unknown)
                    && let Some(newest) = pins.newest()
                {
                    // Where the segment lies, from an image the block names too (decided
                    // once: an older image received after it must not undo it).
                    self.segment = learn_segment(&sample, newest);
                }
                self.latest = Some(InputView::Received(sample));
                newer = true;
            }
        }
        if newer {
            self.arrivals.note();
            // The first image after attaching sets where mode changes are counted from.
            if self.mode_changes_seen.is_none() {
                self.mode_changes_seen = self.header().map(|h| h.mode_changes);
            }
        }
        newer
    }

    /// Collects pending events without waiting.
    pub(crate) fn drain_events(&mut self) {
        let Some(conn) = &self.conn else {
            return;
        };
        // The event service holds something only when the block's other-events word moved
        // (or, for a descriptor waiter, STARTOP): otherwise looking costs a system call for
        // nothing.
        let other = conn.handshake.block().other_events_seen();
        if other == self.other_events_seen && !self.fd_waiter.load(Ordering::Relaxed) {
            return;
        }
        self.other_events_seen = other;
        let (mut mode, mut newcycle, mut shutdown, mut opfault) = (false, false, false, false);
        let mine = opfault_event(self.slot);
        let _ = conn.events.try_wait(|a| {
            let id = a.id.as_value();
            mode |= id == EVENT_MODE;
            newcycle |= id == EVENT_NEWCYCLE;
            shutdown |= id == EVENT_SHUTDOWN;
            opfault |= id == mine;
        });
        if mode || opfault {
            self.refresh_whole();
        }
        if mode {
            self.replay_mode_changes();
        }
        if opfault {
            // The image recording the OPFAULT is published only in the next cycle; until it
            // arrives, the cycle that faulted is the newest one this client was given.
            let recorded = self
                .header()
                .map_or(0, |h| h.opfault_cycle[self.slot as usize % MAX_CLIENTS]);
            let newest = self.header().map_or(0, |h| h.cycle.cycle_number);
            let cycle = if recorded > self.last_opfault {
                recorded
            } else {
                newest.max(self.last_startop)
            };
            if cycle > self.last_opfault {
                self.last_opfault = cycle;
                self.push_event(Event::OpFault { cycle });
            }
        }
        if newcycle && self.opts.newcycle {
            self.push_event(Event::NewCycle);
        }
        if shutdown {
            self.push_event(Event::ServerShutdown);
            self.disconnect();
        }
    }

    /// Queues one [`Event::Mode`] per mode change since the last one seen, from the image
    /// header's history: MODE notifications coalesce, the history does not.
    fn replay_mode_changes(&mut self) {
        let Some(h) = self.header() else {
            return;
        };
        let (changes, history) = (h.mode_changes, h.mode_history);
        let Some(seen) = self.mode_changes_seen else {
            self.mode_changes_seen = Some(changes);
            return;
        };
        let missed = changes.wrapping_sub(seen) as usize;
        let first = changes.wrapping_sub(missed.min(MODE_HISTORY) as u32) + 1;
        for n in 0..missed.min(MODE_HISTORY) as u32 {
            let at = first.wrapping_add(n) as usize % MODE_HISTORY;
            if let Some(m) = Mode::from_u32(history[at]) {
                if m == Mode::Offline {
                    // IO-Base: in OFFLINE the outputs written are lost.
                    self.write_cache.valid.iter_mut().for_each(|v| *v = false);
                }
                self.push_event(Event::Mode(m));
            }
        }
        self.mode_changes_seen = Some(changes);
    }

    /// Queues an event for [`Client::events`]. The queue is allocated once: a program that
    /// never asks for its events loses the oldest, and its cycle loop stays off the heap.
    fn push_event(&mut self, e: Event) {
        if self.events.len() == EVENT_QUEUE {
            self.events.pop_front();
        }
        self.events.push_back(e);
    }

    /// Returns the events that arrived since the last call, without waiting.
    pub fn events(&mut self) -> Vec<Event> {
        self.drain_events();
        self.events.drain(..).collect()
    }

    /// Takes the newest image; whether its cycle is one not handed out yet (then it is
    /// counted as handed out). Another call (an event, a data_read) may have taken the new
    /// image already: what counts is whether it is newer than the last cycle handed out.
    pub(crate) fn take_new_cycle(&mut self) -> bool {
        self.refresh();
        let cycle = self.header().map_or(0, |h| h.cycle.cycle_number);
        if cycle > self.last_startop {
            self.last_startop = cycle;
            return true;
        }
        false
    }

    /// For accesses outside the handshake: takes the newest image; when none came for a while,
    /// checks that the server lives; re-attaches to a restarted one. Errors when there is no
    /// server to read from.
    pub(crate) fn ensure_fresh(&mut self) -> Result<(), IoError> {
        if self.conn.is_none() {
            let _ = self.try_reattach();
        }
        if self.conn.is_some() && !self.refresh() && self.arrivals.since_last() > STALE_IMAGE {
            self.check_server();
        }
        if self.conn.is_none() {
            return Err(IoError::ServerGone {
                instance: self.instance().to_string(),
            });
        }
        Ok(())
    }

    /// Drops the data ports: the server is gone.
    fn disconnect(&mut self) {
        self.latest = None;
        self.segment = SegmentKnowledge::Unknown;
        self.forget_outputs();
        self.conn = None;
    }

    /// Looks (at most every [`LIVENESS_PERIOD`]) whether the server's cycle node is alive.
    pub(crate) fn check_server(&mut self) {
        // A server that published an image lately is alive: a wait that ends without an
        // event during a short stall does not list nodes (which allocates, inside what may
        // be a real-time cycle loop).
        if self.last_liveness.elapsed() < LIVENESS_PERIOD
            || self.arrivals.since_last() < STALE_IMAGE
        {
            return;
        }
        self.last_liveness = Instant::now();
        // A list that failed part-way proves nothing: keep the connection.
        if server_listed(self.instance(), self.server_pid) == Some(false) {
            self.disconnect();
        }
    }

    /// Registers again with a (re)started server and opens its data services.
    pub(crate) fn try_reattach(&mut self) -> Result<(), WaitError> {
        if self.last_reattach.elapsed() < REATTACH_PERIOD {
            return Ok(());
        }
        self.last_reattach = Instant::now();
        // Short timeouts: re-attaching runs inside calls that have timeouts of their own.
        let quick = AttachOptions {
            timeout: REATTACH_STEP,
            ..self.opts.clone()
        };
        let Ok((slot, token, generation, server_pid)) = register(&self.control, &quick) else {
            return Ok(());
        };
        let conn = match Connection::open(
            self.control.node(),
            self.instance(),
            registration(generation, token, &quick),
            REATTACH_STEP,
            &|| self.control.ring_server(),
            &|| connect_outputs(&self.control, slot, token, REATTACH_STEP),
        ) {
            Ok(c) => c,
            Err(_) => {
                let _ = self
                    .control
                    .request_done(CoreRequest::Unregister { slot, token });
                return Ok(());
            }
        };
        self.control.own_ports(&conn.port_ids);
        let was = self.layout.hash();
        let changed = conn.layout.hash() != was;
        if changed && self.opts.expected_layout_hash.is_some() {
            let _ = self
                .control
                .request_done(CoreRequest::Unregister { slot, token });
            return Err(WaitError::LayoutChanged {
                instance: self.instance().to_string(),
                was,
                found: conn.layout.hash(),
            });
        }
        // The claims, as indexes of the layout they will be taken in again.
        let mut lost = Vec::new();
        let claims: Vec<usize> = if changed {
            let (claims, gone) = claims_in(&self.layout, &conn.layout, &self.claims);
            lost = gone;
            self.layout = conn.layout.clone();
            self.write_cache = crate::cache::WriteCache::new(&self.layout);
            self.local_input_iocs = vec![Ioxs::Good; self.layout.submodules.len()];
            self.read_cache = None;
            self.latest = None;
            self.segment = SegmentKnowledge::Unknown;
            claims
        } else {
            self.claims.iter().copied().collect()
        };
        self.claims.clear();
        self.slot = slot;
        self.token = token;
        self.generation = generation;
        self.server_pid = server_pid;
        if self.fd_waiter.load(Ordering::Relaxed) {
            conn.handshake.block().set_fd_waiter(slot, true);
        }
        self.other_events_seen = 0;
        self.forget_outputs();
        self.conn = Some(conn);
        self.last_startop = 0;
        self.last_opfault = 0;
        self.mode_changes_seen = None;
        self.write_cache.valid.iter_mut().for_each(|v| *v = false);
        self.push_event(Event::Reattached { generation });
        if changed {
            self.push_event(Event::LayoutChanged {
                was,
                now: self.layout.hash(),
            });
        }
        for submodule in lost {
            self.push_event(Event::ClaimLost { submodule });
        }
        for s in claims {
            if self.claim(&[s]).is_err() {
                self.push_event(Event::ClaimLost { submodule: s });
            }
        }
        Ok(())
    }

    /// Loans an output sample whose status flags are clear. Its output bytes are left as the
    /// shared memory holds them (no pass over the output image): the server takes a
    /// submodule's bytes only where its flags say written, and [`crate::Cycle`] fills a
    /// submodule from the outputs last sent before it hands it out for changing.
    pub(crate) fn loan_output(&mut self) -> Result<OutputSample, IoError> {
        match self.spare_output.take() {
            Some(mut sample) => {
                if std::mem::take(&mut self.spare_posted) {
                    // Last cycle's OPDONE sample: withdrawn from the block before it is
                    // written again, and its flags cleared as a fresh loan's are.
                    if let Some(conn) = &self.conn {
                        conn.handshake.block().posts.withdraw(self.slot);
                    }
                    self.clear_flags(&mut sample);
                }
                *sample.header_mut() = self.output_header();
                Ok(sample)
            }
            None => self.fresh_output(),
        }
    }

    /// Drops the output samples of a connection that ends.
    fn forget_outputs(&mut self) {
        self.spare_output = None;
        self.spare_posted = false;
        self.output_start = None;
    }

    fn clear_flags(&self, sample: &mut OutputSample) {
        let at = self.layout.image().client_status_offset as usize;
        let statuses = 4 * self.layout.submodules.len();
        if let Some(flags) = sample.payload_mut().get_mut(at..at + statuses) {
            flags.fill(0);
        }
    }

    fn output_header(&self) -> OutputHeader {
        OutputHeader {
            magic: IMAGE_MAGIC,
            layout_hash: self.layout.hash(),
            cycle_number: self.header().map_or(0, |h| h.cycle.cycle_number),
            client_token: self.token,
            client_slot: self.slot,
            flags: 0,
            sent_ns: 0,
        }
    }

    fn fresh_output(&self) -> Result<OutputSample, IoError> {
        let conn = self.conn.as_ref().ok_or_else(|| IoError::ServerGone {
            instance: self.instance().to_string(),
        })?;
        let image = self.layout.image();
        let len = image.output_payload_size as usize;
        let sample = conn
            .outputs
            .loan_slice_uninit(len)
            .map_err(|_| IoError::NotDelivered(procimg_control::output_buffer(self.opts.role)))?;
        // SAFETY: the payload lies in iceoryx2's data segment, a shared-memory mapping: the
        // kernel zero-fills it when it is created and it is only ever written as bytes since,
        // so every byte holds an initialised u8 (iceoryx2 types a loan as uninitialised for
        // payload types where that would not hold).
        #[allow(unsafe_code)]
        let mut sample = OutputSample::new(unsafe { sample.assume_init() });
        self.clear_flags(&mut sample);
        *sample.header_mut() = self.output_header();
        Ok(sample)
    }

    /// Fills `dst` with submodule `s`'s outputs as they went out last (the newest image's
    /// mirror); zeros before the first image.
    pub(crate) fn copy_last_sent(&self, s: usize, dst: &mut [u8]) {
        match self.outputs_last_sent(s) {
            Some(last) if last.len() == dst.len() => dst.copy_from_slice(last),
            _ => dst.fill(0),
        }
    }

    /// Submodule `s`'s outputs as they went out last (the newest image's mirror), if there is
    /// an image.
    fn outputs_last_sent(&self, s: usize) -> Option<&[u8]> {
        let e = self.layout.submodules.get(s)?;
        let at = e.output_mirror_offset as usize;
        self.latest
            .as_ref()?
            .payload()
            .get(at..at + e.output_length as usize)
    }

    /// Sends an output sample; as OPDONE when `synchronous`.
    pub(crate) fn send_output(
        &mut self,
        mut sample: OutputSample,
        opdone_cycle: Option<u64>,
    ) -> Result<(), IoError> {
        // A synchronous client's OPDONE sample is named in the handshake block.
        let place = match opdone_cycle {
            Some(cycle) => self.place_of(&sample, cycle),
            _ => None,
        };
        let conn = self.conn.as_ref().ok_or_else(|| IoError::ServerGone {
            instance: self.instance().to_string(),
        })?;
        if let Some(cycle) = opdone_cycle {
            let h = sample.header_mut();
            h.cycle_number = cycle;
            h.flags |= OUTPUT_SYNCHRONOUS;
        }
        sample.header_mut().sent_ns = procimg_shm_layout::os::monotonic_ns();
        if let Some(place) = place {
            let posts = &conn.handshake.block().posts;
            posts.post(self.slot, place);
            if posts.learnt(self.slot) == self.token {
                // The server copies the outputs from where they are: nothing is sent, and
                // the sample stays this client's for the next window.
                conn.handshake.block().signal_opdone(&LinuxFutex);
                self.spare_output = Some(sample);
                self.spare_posted = true;
                return Ok(());
            }
            // Sent as well, named: the server learns from it where the segment lies.
        }
        match sample.send() {
            Ok(0) | Err(_) => {
                return Err(IoError::NotDelivered(procimg_control::output_buffer(
                    self.opts.role,
                )));
            }
            Ok(_) => conn.handshake.block().posts.count_sent(self.slot),
        }
        if opdone_cycle.is_some() {
            // The sample is there before the word moves: a server woken by it finds it.
            conn.handshake.block().signal_opdone(&LinuxFutex);
            // The next window's sample, loaned now that this one is answered.
            if self.spare_output.is_none() {
                self.spare_output = self.fresh_output().ok();
            }
        }
        Ok(())
    }
}

impl Client {
    /// Where `sample` lies in this connection's output segment, named for `cycle`.
    fn place_of(&mut self, sample: &OutputSample, cycle: u64) -> Option<SamplePlace> {
        let payload = sample.payload().as_ptr() as usize;
        let start = *self
            .output_start
            .get_or_insert_with(|| mapping_of(payload).map(|m| m.start));
        let offset = u32::try_from(payload.checked_sub(start?)?).ok()?;
        Some(SamplePlace {
            cycle: cycle as u32,
            offset,
        })
    }
}

/// What the connection of a client registered with (`generation`, `token`) needs to know.
fn registration(generation: u64, token: u64, opts: &AttachOptions) -> Registration {
    Registration {
        generation,
        token,
        role: opts.role,
    }
}

/// A wait for the server's next signal, from [`Client::event_wait`].
pub struct EventWait {
    block: Arc<HandshakeMap>,
    slot: u32,
    /// The event word and the newest image's word when the wait was taken.
    seen: (u32, u64),
    /// When a synchronous client wakes ahead of STARTOP to poll for it.
    poll: Option<(u64, u64)>,
}

impl EventWait {
    /// Sleeps until the server signals something after the wait was taken, or `timeout`.
    /// Returns whether it did. A synchronous client wakes ahead of the next STARTOP and polls
    /// for it ([`AttachOptions::wake_ahead`]), and then returns as soon as procimgd names
    /// the cycle's image, or `false` when it did not come in the window.
    pub fn wait(&self, timeout: Duration) -> bool {
        let deadline = procimg_shm_layout::os::monotonic_ns()
            .saturating_add(timeout.as_nanos().min(u64::MAX as u128) as u64);
        self.block.block().wait_startop_ahead(
            &LinuxFutex,
            self.slot,
            self.seen,
            self.poll,
            deadline,
        ) == Woken::Moved
    }
}

impl Drop for Client {
    fn drop(&mut self) {
        if let Some(conn) = &self.conn {
            let unregistered = self.control.request(
                CoreRequest::Unregister {
                    slot: self.slot,
                    token: self.token,
                },
                Duration::from_millis(500),
            );
            if matches!(unregistered, Ok(Response::Done)) {
                conn.wait_outputs_released(OUTPUTS_RELEASE_WAIT);
            }
        }
    }
}

/// How long a detaching client waits for procimgd to let go of its outputs: a cycle and a
/// round of procimgd's control thread, with room for a loaded machine and slow cycles.
const OUTPUTS_RELEASE_WAIT: Duration = Duration::from_millis(250);

/// Registers with the server: slot, token, generation and the server's process id.
/// Asks the server to subscribe to this client's output service.
fn connect_outputs(
    control: &ControlHandle,
    slot: u32,
    token: u64,
    timeout: Duration,
) -> Result<(), AttachError> {
    let instance = control.instance();
    let what = "the connection of its outputs";
    match control.request(CoreRequest::ConnectOutputs { slot, token }, timeout) {
        Ok(Response::Done) => Ok(()),
        Ok(Response::Refused(refusal)) => Err(AttachError::Refused {
            instance: instance.to_string(),
            refusal,
        }),
        Ok(other) => Err(AttachError::Shm {
            instance: instance.to_string(),
            what,
            detail: format!("unexpected answer {other:?}"),
        }),
        Err(ControlError::NoServer { .. }) => Err(AttachError::NoServer {
            instance: instance.to_string(),
        }),
        Err(ControlError::NoAnswer { timeout, .. }) => Err(AttachError::Timeout {
            instance: instance.to_string(),
            what,
            timeout,
        }),
        Err(e) => Err(AttachError::Shm {
            instance: instance.to_string(),
            what,
            detail: e.to_string(),
        }),
    }
}

fn register(
    control: &ControlHandle,
    opts: &AttachOptions,
) -> Result<(u32, u64, u64, u32), AttachError> {
    let instance = control.instance().to_string();
    let node_id = control.node().id().to_string();
    let req = CoreRequest::Register {
        name: opts.name.clone(),
        pid: std::process::id(),
        role: opts.role,
        newcycle: opts.newcycle,
        node_id,
    };
    match control.request(req, opts.timeout) {
        Ok(Response::Registered {
            slot,
            token,
            generation,
            server_pid,
            ..
        }) => Ok((slot, token, generation, server_pid)),
        Ok(Response::Refused(refusal)) => Err(AttachError::Refused { instance, refusal }),
        Ok(other) => Err(AttachError::Shm {
            instance,
            what: "a registration",
            detail: format!("unexpected answer {other:?}"),
        }),
        Err(ControlError::NoServer { .. }) => Err(AttachError::NoServer { instance }),
        Err(ControlError::NoAnswer { timeout, .. }) => Err(AttachError::Timeout {
            instance,
            what: "the registration",
            timeout,
        }),
        Err(e) => Err(AttachError::Shm {
            instance,
            what: "a registration",
            detail: e.to_string(),
        }),
    }
}

/// The submodules of `claims` (indexes in `old`) as indexes in `new`: those with the same
/// device, API, slot, subslot and ident numbers there; and the indexes of `old` that have
/// no such submodule in `new`.
fn claims_in(old: &Layout, new: &Layout, claims: &BTreeSet<usize>) -> (Vec<usize>, Vec<usize>) {
    let key = |l: &Layout, e: &procimg_shm_layout::SubmoduleEntry| {
        (
            l.device_name(usize::from(e.device)).to_owned(),
            e.api,
            e.slot,
            e.subslot,
            e.module_ident,
            e.submodule_ident,
        )
    };
    let (mut kept, mut lost) = (Vec::new(), Vec::new());
    for &s in claims {
        let found = old.submodules.get(s).and_then(|e| {
            let k = key(old, e);
            new.submodules.iter().position(|n| key(new, n) == k)
        });
        match found {
            Some(i) => kept.push(i),
            None => lost.push(s),
        }
    }
    (kept, lost)
}
