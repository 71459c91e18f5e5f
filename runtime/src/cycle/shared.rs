// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the acyclic side and the cycle thread share: lock-free only.

use super::force::ForcePlan;
use crate::shm::outputs::OutputHandoff;
use crate::shm::reserve::InputReserve;
use crate::stats::Counters;
use crossbeam_queue::ArrayQueue;
use procimg_control::doorbell::Doorbell;
use procimg_shm_layout::Mode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

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
    /// Asks the network side to release every connection (procimgd is stopping), while the
    /// cycle still runs: a device then sees the Release before its cyclic data ends, instead
    /// of a watchdog expiry.
    pub release_all: AtomicBool,
    /// The mode last asked for (confirmed when `counters.mode` reaches it).
    pub target_mode: std::sync::atomic::AtomicU32,
    /// New force plans for the cycle thread, which takes the newest at a cycle start.
    pub force_plans: ArrayQueue<Box<ForcePlan>>,
    /// Plans the cycle thread replaced, for the acyclic side to free: the cycle never frees.
    pub spent_force_plans: ArrayQueue<Box<ForcePlan>>,
    /// The clients' output ports, connected by the control thread for the cycle thread and
    /// handed back by it to be dropped.
    pub outputs: OutputHandoff,
    /// What of the input samples is faulted in: loans noted by the cycle thread, more
    /// faulted in by the control thread when it asks.
    pub input_reserve: Arc<InputReserve>,
    /// The control thread sleeps on it between rounds; the role's thread rings it after it
    /// queues an event, clients after a request (none in tests that run no control thread).
    doorbell: Option<Doorbell>,
}

/// Force plans waiting for the cycle thread, which takes them every cycle: more waiting
/// means the cycle is stalled, and the force is refused.
const FORCE_PLANS: usize = 2;

impl Shared {
    /// Shared state for `submodules` submodules.
    pub fn new(submodules: usize) -> Shared {
        Shared {
            counters: Counters::default(),
            claims: (0..submodules).map(|_| AtomicU64::new(0)).collect(),
            commands: ArrayQueue::new(COMMANDS),
            stop: AtomicBool::new(false),
            release_all: AtomicBool::new(false),
            target_mode: std::sync::atomic::AtomicU32::new(procimg_shm_layout::MODE_OFFLINE),
            force_plans: ArrayQueue::new(FORCE_PLANS),
            // Room for every plan that can be on its way, and the one in use.
            spent_force_plans: ArrayQueue::new(FORCE_PLANS + 1),
            outputs: OutputHandoff::default(),
            input_reserve: Arc::default(),
            doorbell: None,
        }
    }

    /// The same, with the control thread's doorbell.
    pub fn with_doorbell(mut self, doorbell: Doorbell) -> Shared {
        self.doorbell = Some(doorbell);
        self
    }

    /// Wakes the control thread: there is work for it.
    pub fn ring_control(&self) {
        if let Some(d) = &self.doorbell {
            d.ring();
        }
    }

    /// How often the control thread's doorbell has rung (0 without one): read before a
    /// round of work, handed to [`Shared::wait_for_control_work`] after it.
    pub fn control_rung(&self) -> u32 {
        self.doorbell.as_ref().map_or(0, Doorbell::rung)
    }

    /// Sleeps until the control thread's doorbell rings after `seen`, at most for `timeout`.
    /// Returns `false` at once without a doorbell: the caller waits its own way.
    pub fn wait_for_control_work(&self, seen: u32, timeout: Duration) -> bool {
        match &self.doorbell {
            Some(d) => {
                d.wait(seen, timeout);
                true
            }
            None => false,
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

    /// Hands a new force plan to the cycle thread, after freeing the plans it gave back.
    /// Gives the plan back when the cycle has not taken the previous ones (it is stalled).
    pub fn send_force_plan(&self, plan: Box<ForcePlan>) -> Result<(), Box<ForcePlan>> {
        while self.spent_force_plans.pop().is_some() {}
        self.force_plans.push(plan)
    }

    /// The newest force plan for the cycle thread, if one came; the plans it replaces go back.
    /// Neither allocates nor frees.
    pub fn take_force_plan(&self, current: &mut Box<ForcePlan>) -> bool {
        let mut taken = false;
        while let Some(plan) = self.force_plans.pop() {
            let old = std::mem::replace(current, plan);
            if let Err(old) = self.spent_force_plans.push(old) {
                // Cannot happen (room for all), but freeing here would call the allocator
                // from the cycle: the plan is leaked instead.
                std::mem::forget(old);
            }
            taken = true;
        }
        taken
    }

    /// The mode the cycle currently runs in.
    pub fn mode(&self) -> Mode {
        Mode::from_u32(self.counters.mode.load(Ordering::Acquire)).unwrap_or(Mode::Offline)
    }
}
