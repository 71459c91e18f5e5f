// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the acyclic side and the cycle thread share: lock-free only.

use crate::stats::Counters;
use crossbeam_queue::ArrayQueue;
use procimg_shm_layout::Mode;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// Commands queued for the cycle thread, applied at the start of the next cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    /// A client registered.
    Join {
        /// Its slot.
        slot: u32,
        /// Its token.
        token: u64,
        /// It takes part in the STARTOP/OPDONE handshake.
        synchronous: bool,
        /// It wants NEWCYCLE events.
        newcycle: bool,
    },
    /// A client left (or died).
    Leave {
        /// Its slot.
        slot: u32,
    },
    /// Go to a mode (stepwise through CLEAR).
    SetMode(Mode),
}

/// Capacity of the command queue: enough for every client to join and leave in one cycle.
const COMMANDS: usize = 4 * procimg_shm_layout::MAX_CLIENTS;

/// State shared between the cycle thread and the acyclic side.
pub struct Shared {
    /// Counters, written by the cycle thread.
    pub counters: Counters,
    /// Per submodule: the token of the client owning its outputs, 0 when unclaimed.
    pub claims: Box<[AtomicU64]>,
    /// Commands for the cycle thread.
    pub commands: ArrayQueue<Command>,
    /// Asks the cycle thread to end after the current cycle.
    pub stop: AtomicBool,
    /// The mode last asked for (confirmed when `counters.mode` reaches it).
    pub target_mode: std::sync::atomic::AtomicU32,
}

impl Shared {
    /// Shared state for `submodules` submodules.
    pub fn new(submodules: usize) -> Shared {
        Shared {
            counters: Counters::default(),
            claims: (0..submodules).map(|_| AtomicU64::new(0)).collect(),
            commands: ArrayQueue::new(COMMANDS),
            stop: AtomicBool::new(false),
            target_mode: std::sync::atomic::AtomicU32::new(procimg_shm_layout::MODE_OFFLINE),
        }
    }

    /// The owner token of submodule `s`'s outputs (0: none).
    pub fn owner(&self, s: usize) -> u64 {
        self.claims.get(s).map_or(0, |c| c.load(Ordering::Acquire))
    }

    /// Queues a command; `false` if the queue is full (the cycle thread is stuck).
    pub fn command(&self, c: Command) -> bool {
        self.commands.push(c).is_ok()
    }

    /// The mode the cycle currently runs in.
    pub fn mode(&self) -> Mode {
        Mode::from_u32(self.counters.mode.load(Ordering::Acquire)).unwrap_or(Mode::Offline)
    }
}
