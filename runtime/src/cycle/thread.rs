// SPDX-License-Identifier: MIT OR Apache-2.0
//! The cycle thread: real-time set-up, its own iceoryx2 node and ports, and the loop of
//! absolute-time sleeps that runs the engine once per cycle.

use super::engine::{Engine, EngineSettings};
use super::shared::Shared;
use crate::image::Tables;
use crate::io::IoSystem;
use crate::shm::{CyclePorts, ShmError};
use crate::stats::StatsRecorder;
use crate::sys::clock::{now_ns, sleep_until_ns};
use crate::sys::rt::{RtSetup, setup_current_thread};
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::thread::JoinHandle;

/// Where and how the cycle thread runs.
#[derive(Clone, Debug)]
pub struct ThreadSettings {
    /// Instance name (for the service names).
    pub instance: String,
    /// CPU to pin to.
    pub cpu: Option<usize>,
    /// SCHED_FIFO priority.
    pub priority: u8,
}

/// Builds the IO system on the cycle thread itself.
pub type IoFactory = Box<dyn FnOnce() -> Box<dyn IoSystem> + Send>;

/// Starts the cycle thread. Returns once its ports exist and it is about to run its first
/// cycle, with what the real-time set-up achieved.
pub fn spawn(
    settings: EngineSettings,
    thread: ThreadSettings,
    tables: Tables,
    io: IoFactory,
    shared: Arc<Shared>,
    stats: StatsRecorder,
) -> Result<(JoinHandle<()>, RtSetup), ShmError> {
    let (ready_tx, ready_rx) = std::sync::mpsc::sync_channel(1);
    let handle = std::thread::Builder::new()
        .name("procimg-cycle".into())
        .stack_size(crate::sys::rt::CYCLE_THREAD_STACK)
        .spawn(move || {
            let rt = setup_current_thread(thread.cpu, thread.priority);
            shared
                .counters
                .realtime
                .store(rt.realtime, Ordering::Relaxed);
            let mut ports = match CyclePorts::create(&thread.instance, settings.generation, &tables)
            {
                Ok(p) => p,
                Err(e) => {
                    let _ = ready_tx.send(Err(e));
                    return;
                }
            };
            // The input samples the first cycles use, faulted in; the others as they come
            // into use, by the control thread (`shm::reserve`).
            let len = tables.layout.input_payload_size as usize;
            let samples = ports.set_up_reserve(shared.input_reserve.clone(), len);
            let cycle_ns = settings.cycle_ns;
            let mut engine = Engine::new(settings, &tables, ports, io(), shared.clone(), stats);
            // Every other page the cycle may touch (its IO system's buffers, the process's
            // heap and stacks), faulted in and locked before the first cycle: later mappings
            // are locked only as they are faulted in (`sys::rt::lock_memory`).
            crate::sys::populate::populate_all(samples);
            let _ = ready_tx.send(Ok(rt));
            // From here on the thread must stay off the heap; the allocator counts it if not.
            crate::sys::rt_alloc::mark_current_thread_realtime();
            run(&mut engine, &shared, cycle_ns);
        })
        .map_err(|e| ShmError::Create {
            instance: String::new(),
            what: "cycle thread".into(),
            detail: e.to_string(),
        })?;
    match ready_rx.recv() {
        Ok(Ok(rt)) => Ok((handle, rt)),
        Ok(Err(e)) => {
            let _ = handle.join();
            Err(e)
        }
        Err(_) => Err(ShmError::Create {
            instance: String::new(),
            what: "cycle thread".into(),
            detail: "the thread ended during set-up".into(),
        }),
    }
}

/// How long before a cycle starts the thread wakes to maintain connections: a tenth of the
/// cycle, at most 100 µs.
fn maintenance_lead(cycle_ns: u64) -> u64 {
    (cycle_ns / 10).min(100_000)
}

/// The cycle loop: cycle k starts at epoch + k·T. Shortly before, the thread wakes once to
/// maintain connections (see [`Engine::maintain_connections`]). A cycle whose work runs past
/// the start of the next counts an overrun, and the loop resumes at the next period still
/// ahead, so cycle numbers keep matching the clock (a jump in CycleCount shows the lost
/// cycles).
pub fn run(engine: &mut Engine, shared: &Shared, cycle_ns: u64) {
    let epoch = now_ns();
    let lead = maintenance_lead(cycle_ns);
    let mut k: u64 = 1;
    loop {
        let t0 = epoch + k * cycle_ns;
        sleep_until_ns(t0 - lead);
        engine.maintain_connections();
        sleep_until_ns(t0);
        if shared.stop.load(Ordering::Acquire) {
            engine.announce_shutdown();
            return;
        }
        engine.run_cycle(k, t0);
        let now = now_ns();
        if now >= epoch + (k + 1) * cycle_ns {
            engine.count_overrun();
            k = (now - epoch) / cycle_ns + 1;
        } else {
            k += 1;
        }
    }
}
