// SPDX-License-Identifier: MIT OR Apache-2.0
//! The lock-free hand-over between the PROFINET controller on the acyclic side and the
//! cycle thread that owns the network interface.
//!
//! Frames travel in fixed buffers that are allocated once and only ever move between the
//! queues, so neither side allocates per frame and the cycle thread never frees memory; ARs
//! the cycle thread no longer needs go back to the acyclic side to be dropped there.

use crate::sys::doorbell::Doorbell;
use crossbeam_queue::ArrayQueue;
use procimg_nic::MAX_FRAME;
use procimg_profinet::cyclic::CyclicAr;
use std::sync::atomic::{AtomicBool, AtomicU8, AtomicU64, Ordering};

/// Frame buffers in circulation.
const BUFFERS: usize = 256;
/// Depth of each queue.
const DEPTH: usize = 256;

/// One frame.
pub struct FrameBuf {
    /// Bytes used.
    pub len: usize,
    /// The frame.
    pub data: [u8; MAX_FRAME],
}

impl FrameBuf {
    /// The frame's bytes.
    pub fn bytes(&self) -> &[u8] {
        &self.data[..self.len.min(MAX_FRAME)]
    }
}

/// What the acyclic side asks of the cycle thread.
pub enum ToCycle {
    /// Start (or replace) the cyclic exchange of a device.
    Start(Box<CyclicAr>),
    /// Stop the cyclic exchange of a device.
    Stop {
        /// Device index.
        device: usize,
    },
    /// Send this frame (DCP, alarms).
    Send(Box<FrameBuf>),
}

/// What the cycle thread reports to the acyclic side.
pub enum FromCycle {
    /// An acyclic PROFINET frame arrived (DCP, alarm).
    Received(Box<FrameBuf>),
    /// The first valid frame of an AR arrived.
    DataStarted {
        /// Device index.
        device: usize,
        /// AR epoch.
        epoch: u32,
    },
    /// No input frame within the watchdog time: the exchange was stopped.
    WatchdogExpired {
        /// Device index.
        device: usize,
        /// AR epoch.
        epoch: u32,
    },
    /// An exchange the cycle thread has let go of, to be dropped off the real-time thread.
    Retired(Box<CyclicAr>),
}

/// Counters of what arrived at the interface, written by the cycle thread.
#[derive(Default)]
pub struct NetCounters {
    /// Cyclic frames taken into the image.
    pub cyclic_frames: AtomicU64,
    /// Frames that were too short or malformed for what they claimed to be.
    pub malformed: AtomicU64,
    /// Cyclic frames with a FrameID no AR uses, or from a MAC that does not own it.
    pub unknown: AtomicU64,
    /// Cyclic frames whose CycleCounter was not newer than the last one.
    pub stale: AtomicU64,
    /// Frames dropped because a queue or the buffer pool was exhausted.
    pub dropped: AtomicU64,
    /// Cyclic frames sent from the image, where the outputs are (one server copy of each
    /// output byte).
    pub sent_in_place: AtomicU64,
    /// Cyclic frames written from the image first: a frame without outputs (consumer
    /// statuses only), or an AR's frame the image does not hold as its peer laid it out (two
    /// server copies of each output byte).
    pub sent_copied: AtomicU64,
    /// Sends the interface refused.
    pub send_errors: AtomicU64,
    /// Watchdog expiries.
    pub watchdog_expiries: AtomicU64,
}

impl NetCounters {
    /// Adds one to `c`.
    pub fn count(c: &AtomicU64) {
        c.fetch_add(1, Ordering::Relaxed);
    }
}

/// Both directions and the buffer pool.
pub struct Channel {
    /// Acyclic → cycle thread.
    pub to_cycle: ArrayQueue<ToCycle>,
    /// Cycle thread → acyclic.
    pub from_cycle: ArrayQueue<FromCycle>,
    /// Empty frame buffers.
    pub free: ArrayQueue<Box<FrameBuf>>,
    /// Interface counters.
    pub counters: NetCounters,
    /// In the device role: the station has a fault diagnosis pending, which the produced
    /// frames' DataStatus says (StationProblemIndicator); set by the acyclic side.
    pub station_problem: AtomicBool,
    /// The DataStatus of the last cyclic frame taken from a peer (in the device role, the
    /// PLC's: RUN or STOP, valid or not); set by the cycle thread.
    pub peer_data_status: AtomicU8,
    /// Rung by the cycle thread with every report it leaves in `from_cycle`, so that the
    /// acyclic thread takes it at once (`None`: no eventfd could be made; the acyclic thread
    /// then looks every few ms).
    pub doorbell: Option<Doorbell>,
}

impl Default for Channel {
    fn default() -> Self {
        Channel::new()
    }
}

impl Channel {
    /// A channel with its buffers allocated.
    pub fn new() -> Channel {
        let free = ArrayQueue::new(BUFFERS);
        for _ in 0..BUFFERS {
            let _ = free.push(Box::new(FrameBuf {
                len: 0,
                data: [0; MAX_FRAME],
            }));
        }
        Channel {
            to_cycle: ArrayQueue::new(DEPTH),
            from_cycle: ArrayQueue::new(DEPTH),
            doorbell: Doorbell::new().ok(),
            free,
            counters: NetCounters::default(),
            station_problem: AtomicBool::new(false),
            peer_data_status: AtomicU8::new(0),
        }
    }

    /// Queues `frame` for sending (acyclic side); `false` when no buffer or queue space is
    /// left, which means the cycle thread is not running.
    pub fn send(&self, frame: &[u8]) -> bool {
        let Some(mut buf) = self.free.pop() else {
            NetCounters::count(&self.counters.dropped);
            return false;
        };
        let n = frame.len().min(MAX_FRAME);
        buf.data[..n].copy_from_slice(&frame[..n]);
        buf.len = n;
        match self.to_cycle.push(ToCycle::Send(buf)) {
            Ok(()) => true,
            Err(ToCycle::Send(buf)) => {
                let _ = self.free.push(buf);
                NetCounters::count(&self.counters.dropped);
                false
            }
            Err(_) => false,
        }
    }

    /// Returns a buffer received from the cycle thread to the pool.
    pub fn recycle(&self, buf: Box<FrameBuf>) {
        let _ = self.free.push(buf);
    }
}
