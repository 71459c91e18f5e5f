// SPDX-License-Identifier: MIT OR Apache-2.0
//! The clients' output ports: one iceoryx2 service per client, subscribed to off the cycle
//! thread.
//!
//! The control thread creates each client's output service
//! (`procimg_control::client_output_service`) and its subscriber when the client registers.
//! The client opens it, creates its publisher and asks the control thread to connect
//! (`CoreRequest::ConnectOutputs`). The control thread connects the subscriber there: iceoryx2
//! maps the client's output samples (about 4 MiB at a 360 KiB image), and faulting in and
//! locking every page of them costs a cycle or more. The port ready, it goes to the cycle
//! thread through [`OutputHandoff`]; the cycle thread hands the ports of clients that left
//! back the same way, so that the control thread unmaps them. The ports are of iceoryx2's
//! thread-safe variant, whose ports may move between threads; only one thread uses a port at
//! a time, so its mutex is never contended.
//!
//! A busy-polling client need not send its OPDONE sample: it names it in the handshake block
//! (`procimg_shm_layout::posts`), and the cycle thread copies the outputs straight from it.
//! The place of the client's segment in this process is learnt from the first sample it
//! sent while naming it, and that sample is kept borrowed for as long as the port lives:
//! iceoryx2 keeps a connection with a borrowed sample, so the segment stays mapped even after
//! the client is gone, and a place it named can never point at memory no longer mapped.

use super::node::{self, ShmError, server_node_of};
use crate::sys::clock::now_ns;
use crate::sys::populate::{self, Mapping};
use crate::sys::rt_alloc::as_connection_setup;
use crossbeam_queue::ArrayQueue;
use iceoryx2::node::Node;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::port::update_connections::UpdateConnections;
use iceoryx2::prelude::ServiceName;
use iceoryx2::sample::Sample;
use procimg_control::{OUTPUT_BORROWED, OUTPUT_BUFFER};
use procimg_shm_layout::posts::Posts;
use procimg_shm_layout::segment::{SamplePlace, Segment};
use procimg_shm_layout::{MAX_CLIENTS, OUTPUT_SYNCHRONOUS, OutputHeader};

/// iceoryx2's inter-process variant whose ports may move between threads.
pub type IpcThreadsafe = iceoryx2::service::ipc_threadsafe::Service;

/// The server's subscriber to one client's outputs.
pub type OutputPort = Subscriber<IpcThreadsafe, [u8], OutputHeader>;

/// A sample received from a client.
type OutputSample = Sample<IpcThreadsafe, [u8], OutputHeader>;

/// The shared-memory mappings that connecting a port added: where the client's output
/// samples may lie. Of fixed size, so that it goes to the cycle thread without the heap.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Bounds {
    /// First address and end of each mapping, the largest first; (0, 0) for none.
    ranges: [(usize, usize); 4],
}

impl Bounds {
    /// The largest of `mappings` (the client's output segment is the largest by far; the
    /// others are iceoryx2's small connection segments).
    pub fn of(mappings: &[Mapping]) -> Bounds {
        let mut by_size: Vec<&Mapping> = mappings.iter().collect();
        by_size.sort_by_key(|m| core::cmp::Reverse(m.len));
        let mut b = Bounds::default();
        for (r, m) in b.ranges.iter_mut().zip(by_size) {
            *r = (m.start, m.start + m.len);
        }
        b
    }

    /// The mapping `at` lies in.
    pub fn containing(&self, at: usize) -> Option<(usize, usize)> {
        self.ranges
            .iter()
            .copied()
            .find(|&(start, end)| start <= at && at < end)
    }
}

/// A connected output port on its way to the cycle thread.
pub struct Arrival {
    /// The client's slot.
    pub slot: u32,
    /// The token of the registration it belongs to.
    pub token: u64,
    /// The port.
    pub port: Box<OutputPort>,
    /// Where the client's samples lie in this process.
    pub bounds: Bounds,
}

/// Output ports between the control thread and the cycle thread, both ways.
pub struct OutputHandoff {
    arriving: ArrayQueue<Arrival>,
    spent: ArrayQueue<Box<OutputPort>>,
}

impl Default for OutputHandoff {
    fn default() -> Self {
        OutputHandoff {
            arriving: ArrayQueue::new(MAX_CLIENTS),
            // Every client's port, and as many arrivals refused (a client gone meanwhile).
            spent: ArrayQueue::new(2 * MAX_CLIENTS),
        }
    }
}

impl OutputHandoff {
    /// Sends a connected port to the cycle thread; gives it back when MAX_CLIENTS are already
    /// on their way (the cycle thread is not taking them).
    pub fn send(&self, arrival: Arrival) -> Result<(), Arrival> {
        self.arriving.push(arrival)
    }

    /// The next port that arrived (cycle thread).
    pub fn receive(&self) -> Option<Arrival> {
        self.arriving.pop()
    }

    /// Hands a port back to be dropped off the cycle thread (cycle thread). Without room the
    /// port is dropped here, at the cost of an unmapping in the cycle.
    pub fn retire(&self, port: Box<OutputPort>) {
        let _ = self.spent.push(port);
    }

    /// Drops the ports handed back (control thread): their mappings go here.
    pub fn drop_retired(&self) -> usize {
        let mut n = 0;
        while self.spent.pop().is_some() {
            n += 1;
        }
        n
    }
}

/// Creates a node for the server's output ports.
pub fn output_node(instance: &str) -> Result<Node<IpcThreadsafe>, ShmError> {
    server_node_of(instance, "outputs")
}

/// Creates the output service of the client registered with `token`, and the server's
/// subscriber to it. procimgd creates it, not the client: its files are then procimgd's, which
/// removes them when its port goes, also when the client is another user and left first.
pub fn create(
    node: &Node<IpcThreadsafe>,
    instance: &str,
    generation: u64,
    token: u64,
) -> Result<OutputPort, ShmError> {
    let service = procimg_control::client_output_service(instance, generation, token);
    let err =
        |what: &str, e: &dyn core::fmt::Debug| node::err(instance, format!("{what} {service}"), e);
    let name = ServiceName::new(&service).map_err(|e| err("the service name", &e))?;
    node.service_builder(&name)
        .publish_subscribe::<[u8]>()
        .user_header::<OutputHeader>()
        // The client publishes, the cycle thread alone subscribes: its buffer holds what is
        // sent between two of its cycles, it borrows one sample at a time and lets go of it
        // at once, and a full buffer makes the client's send fail rather than drop a sample
        // the server has not seen.
        .max_nodes(2)
        .max_publishers(1)
        .max_subscribers(1)
        .subscriber_max_buffer_size(OUTPUT_BUFFER)
        // One at a time, and a busy client's sample kept for its segment's place.
        .subscriber_max_borrowed_samples(OUTPUT_BORROWED)
        .history_size(0)
        .enable_safe_overflow(false)
        .create()
        .map_err(|e| err("a client's output service", &e))?
        .subscriber_builder()
        .buffer_size(OUTPUT_BUFFER)
        .create()
        .map_err(|e| err("a subscriber to", &e))
}

/// Connects `port` to the client's publisher, which maps the client's output samples, and
/// faults them in a chunk at a time (`sys::populate`): the cycle reads them without a fault,
/// and the memory-map lock is never held for the whole segment. Returns where they lie.
pub fn connect(port: &OutputPort, instance: &str) -> Result<Bounds, ShmError> {
    let before = populate::shared_memory_starts();
    port.update_connections()
        .map_err(|e| node::err(instance, "the connection to a client's output publisher", e))?;
    let added = populate::shared_memory_since(&before);
    added.iter().for_each(|m| {
        populate::populate(m);
    });
    Ok(Bounds::of(&added))
}

/// What a look for a client's output sample found (`cycle::link::ClientLink::take_output`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Taken {
    /// A sample was handed over.
    Sample,
    /// A busy client's sample was handed over from where the client wrote it.
    InPlace,
    /// No sample waits.
    Nothing,
    /// The link could not receive (a dead client's connection being removed).
    Failed,
    /// A busy client's sample was handed over, but the client wrote it again while it was
    /// being read (outside its cycle window): what was handed over may mix two writes.
    Torn(u32),
}

/// A client's port as the cycle thread holds it.
struct Held {
    token: u64,
    port: Box<OutputPort>,
    bounds: Bounds,
    /// Once learnt: where the busy client's samples lie.
    posted: Option<Posted>,
}

/// What the cycle thread knows of a busy client's output segment.
struct Posted {
    /// The sample the segment's place was learnt from, kept borrowed: it keeps the segment
    /// mapped (dropped before the port).
    _keeps_mapped: OutputSample,
    segment: Segment,
    /// The sample last taken, not to be taken twice.
    taken: Option<SamplePlace>,
    /// The client's count of samples sent ([`Posts::sent`]) when its port was last looked at.
    sent_seen: u64,
}

impl Held {
    /// Learns where the client's samples lie from `sample`, just received, when the client
    /// names it in the block too; says so in the block. Whether the sample was kept.
    fn learn(&mut self, slot: u32, sample: OutputSample, posts: &Posts) -> Option<OutputSample> {
        let Some(place) = posts.posted(slot) else {
            return Some(sample);
        };
        let h = sample.user_header();
        let payload = sample.payload().as_ptr() as usize;
        let named = h.client_token == self.token
            && h.flags & OUTPUT_SYNCHRONOUS != 0
            && h.cycle_number as u32 == place.cycle;
        let header = h as *const OutputHeader as usize;
        let segment = self
            .bounds
            .containing(payload)
            .and_then(|b| Segment::learn(payload, header, sample.payload().len(), place.offset, b))
            .filter(|seg| {
                seg.place::<OutputHeader>(place.offset).map(|p| p.payload) == Some(payload)
            });
        match segment {
            Some(segment) if named && self.posted.is_none() => {
                self.posted = Some(Posted {
                    _keeps_mapped: sample,
                    segment,
                    taken: Some(place),
                    // Below any count the client has (it sent this sample): the port is
                    // looked at once more, for what it sent after this sample.
                    sent_seen: 0,
                });
                posts.set_learnt(slot, self.token);
                None
            }
            _ => Some(sample),
        }
    }

    /// Hands the sample the busy client names to `take`, if it was not taken yet.
    fn take_posted(
        &mut self,
        slot: u32,
        posts: &Posts,
        take: &mut dyn FnMut(&OutputHeader, &[u8], u64),
    ) -> Option<Taken> {
        let src = self.posted.as_mut()?;
        let place = posts.posted(slot)?;
        if src.taken == Some(place) {
            return None;
        }
        src.taken = Some(place);
        let p = src.segment.place::<OutputHeader>(place.offset)?;
        // SAFETY: `Segment::place` checked that the header (aligned) and the payload lie in
        // the client's output segment, which stays mapped while `_keeps_mapped` is borrowed
        // from it. The client writes that memory only outside its cycle window, after it
        // withdrew the place: a copy that overlapped such a write is found below and not
        // used. The header is copied out before anything reads it.
        #[allow(unsafe_code)]
        let (header, payload) = unsafe {
            (
                core::ptr::read_volatile(p.header as *const OutputHeader),
                core::slice::from_raw_parts(p.payload as *const u8, p.len),
            )
        };
        take(&header, payload, now_ns());
        Some(if posts.still_posted(slot, place) {
            Taken::InPlace
        } else {
            Taken::Torn(slot)
        })
    }
}

/// The output ports the cycle thread holds, by client slot.
pub struct OutputPorts {
    ports: Vec<Option<Held>>,
    /// Bit `slot`: that slot holds a port. The cycle thread looks only at these: a walk
    /// over every slot touches a cache line each, between STARTOP and the answers.
    held: u64,
    /// Bit `slot`: that client's samples are taken where it names them.
    posting: u64,
    /// Where the next look for a sample begins: the port that had the last one, so that a
    /// client's samples are taken in the order sent and the ports in turn.
    cursor: usize,
}

impl Default for OutputPorts {
    fn default() -> Self {
        OutputPorts {
            ports: (0..MAX_CLIENTS).map(|_| None).collect(),
            held: 0,
            posting: 0,
            cursor: 0,
        }
    }
}

impl OutputPorts {
    /// Takes the ports that arrived: those `current(slot, token)` accepts replace what their
    /// slot held; the others (their client left meanwhile) go back at once.
    pub fn adopt(&mut self, handoff: &OutputHandoff, current: &dyn Fn(u32, u64) -> bool) {
        while let Some(Arrival {
            slot,
            token,
            port,
            bounds,
        }) = handoff.receive()
        {
            if !current(slot, token) || slot as usize >= self.ports.len() {
                handoff.retire(port);
                continue;
            }
            self.retire(slot, handoff);
            self.ports[slot as usize] = Some(Held {
                token,
                port,
                bounds,
                posted: None,
            });
            self.held |= bit(slot);
        }
    }

    /// Hands back the port of `slot`, whose client left or registered anew.
    pub fn retire(&mut self, slot: u32, handoff: &OutputHandoff) {
        self.posting &= !bit(slot);
        self.held &= !bit(slot);
        if let Some(held) = self.ports.get_mut(slot as usize).and_then(Option::take) {
            // The kept sample goes first: it is the port's.
            drop(held.posted);
            handoff.retire(held.port);
        }
    }

    /// Hands the oldest output waiting to `take`: samples sent through iceoryx2 first (they
    /// were sent before any sample named now), then the samples busy clients name in
    /// `posts`.
    pub fn take(
        &mut self,
        posts: &Posts,
        take: &mut dyn FnMut(&OutputHeader, &[u8], u64),
    ) -> Taken {
        match self.receive(posts, take) {
            Taken::Nothing => self.take_posted(posts, take),
            taken => taken,
        }
    }

    /// Receives from the ports in turn, from the cursor on: the cursor stays on the port
    /// that had a sample, and moves past one whose receive failed, so that the next look
    /// begins with the others.
    fn receive(&mut self, posts: &Posts, take: &mut dyn FnMut(&OutputHeader, &[u8], u64)) -> Taken {
        let n = self.ports.len();
        // The slots holding a port, counted from the cursor on.
        let mut left = self.held.rotate_right(self.cursor as u32);
        while left != 0 {
            let at = (self.cursor + left.trailing_zeros() as usize) % n;
            left &= left - 1;
            let Some(held) = &mut self.ports[at] else {
                continue;
            };
            // A busy client that names its OPDONE samples sends only asynchronous writes:
            // its port is looked at only when it counted one. (The count is read before the
            // receive, so a sample that comes during it moves the count again.)
            if let Some(posted) = &mut held.posted {
                let sent = posts.sent(at as u32);
                if sent == posted.sent_seen {
                    continue;
                }
                posted.sent_seen = sent;
            }
            // When a client came or went, iceoryx2 sets up or tears down its connection
            // inside the receive, which allocates: counted as connection set-up.
            match as_connection_setup(|| held.port.receive()) {
                Ok(Some(sample)) => {
                    take(sample.user_header(), sample.payload(), now_ns());
                    if held.posted.is_none() && held.learn(at as u32, sample, posts).is_none() {
                        self.posting |= bit(at as u32);
                    }
                    self.cursor = at;
                    return Taken::Sample;
                }
                Ok(None) => {}
                Err(_) => {
                    self.cursor = (at + 1) % n;
                    return Taken::Failed;
                }
            }
        }
        Taken::Nothing
    }

    fn take_posted(
        &mut self,
        posts: &Posts,
        take: &mut dyn FnMut(&OutputHeader, &[u8], u64),
    ) -> Taken {
        let mut posting = self.posting;
        while posting != 0 {
            let slot = posting.trailing_zeros();
            posting &= posting - 1;
            if let Some(Some(held)) = self.ports.get_mut(slot as usize)
                && let Some(taken) = held.take_posted(slot, posts, take)
            {
                return taken;
            }
        }
        Taken::Nothing
    }
}

fn bit(slot: u32) -> u64 {
    1u64 << (slot as usize % MAX_CLIENTS)
}
