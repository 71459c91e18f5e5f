// SPDX-License-Identifier: MIT OR Apache-2.0
//! Real-time set-up of the cycle thread: memory locking, SCHED_FIFO, CPU pinning, stack
//! pre-faulting. Each step that lacks the privilege is reported, and the thread goes on at
//! normal priority, so the server runs (with worse timing) without root.

use thread_priority::{
    RealtimeThreadSchedulePolicy, ScheduleParams, ThreadPriority, ThreadSchedulePolicy,
};

/// What the set-up achieved.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RtSetup {
    /// The thread runs under SCHED_FIFO at the configured priority.
    pub realtime: bool,
    /// The CPU the thread is pinned to.
    pub pinned_cpu: Option<usize>,
    /// All present and future pages of the process are locked in memory.
    pub memory_locked: bool,
    /// One line per step that could not be done, saying what is missing.
    pub warnings: Vec<String>,
}

/// Stack size of the cycle thread. Memory locking populates and locks every thread's whole
/// stack (see [`super::populate::populate_all`]), and std's 2 MiB per thread were a fifth of procimgd's locked memory.
/// The cycle thread's deepest use is [`prefault_stack`]'s 256 KiB; measured as the stack's
/// resident pages with memory left unlocked, it touched 268 KiB in a release build and
/// 652 KiB in a debug build (whose frames are larger).
pub const CYCLE_THREAD_STACK: usize = 1024 * 1024;
/// Stack size of procimgd's other threads (the acyclic thread, the simulated plant and PLC).
/// Measured as above, the deepest touched 68 KiB (a debug build's acyclic thread in the
/// device role, answering the PLC's Connect and records).
pub const HELPER_THREAD_STACK: usize = 512 * 1024;

/// Locks all current and future pages of the process (`mlockall`), so the cycle never waits
/// for a page fault. Returns a warning on failure.
///
/// Pages mapped from now on are locked as they are faulted in (`MCL_ONFAULT`), and what the
/// cycle will touch is faulted in ahead of it, a chunk at a time, by
/// [`super::populate`]: a mapping populated whole inside `mmap` holds the process's
/// memory-map lock for milliseconds, and the cycle thread waits for it whenever it maps
/// something itself. Unless `prefault_all`, the pages mapped now are locked on fault too,
/// and [`super::populate::populate_all`] leaves the code and read-only data of the program
/// and its libraries, and the stacks of the other threads, to be locked as they are used:
/// the cycle runs a small part of a program that also holds configuration, OPC UA, SNMP and
/// the device role, and a helper thread uses a tenth of its stack. A kernel without
/// `MADV_POPULATE_READ` (before 5.14) gets `MCL_CURRENT` and `MCL_FUTURE` alone, which
/// populate at mapping time.
///
/// Call it before threads are started: it first keeps every thread on glibc's main heap. Each
/// further malloc arena reserves 64 MiB of address space, which `MCL_FUTURE` counts as
/// locked (`VmLck`, and against `RLIMIT_MEMLOCK`) though it never becomes memory; the cycle
/// thread does not use the heap in its cycles (see `rt_alloc`), so it loses nothing by
/// sharing one.
pub fn lock_memory(prefault_all: bool) -> Result<(), String> {
    // SAFETY: mallopt takes two integers and only changes the allocator's tuning; no arena
    // exists yet besides the main one when this runs before the first thread.
    unsafe { libc::mallopt(libc::M_ARENA_MAX, 1) };
    let on_fault = super::populate::supported();
    let (current, future) = match (on_fault, prefault_all) {
        (false, _) => (libc::MCL_CURRENT, libc::MCL_FUTURE),
        (true, true) => (libc::MCL_CURRENT, libc::MCL_FUTURE | libc::MCL_ONFAULT),
        (true, false) => (
            libc::MCL_CURRENT | libc::MCL_ONFAULT,
            libc::MCL_FUTURE | libc::MCL_ONFAULT,
        ),
    };
    // SAFETY: mlockall takes only flags and has no memory-safety preconditions. The first
    // call locks what is mapped now (populating it unless on fault); the second, without
    // MCL_CURRENT, leaves that as it is and only says how later mappings are locked.
    let rc = unsafe {
        match libc::mlockall(current) {
            0 => libc::mlockall(future),
            failed => failed,
        }
    };
    if rc == 0 {
        super::populate::set_locked_as_used(on_fault && !prefault_all);
        Ok(())
    } else {
        let err = std::io::Error::last_os_error();
        Err(format!(
            "cannot lock memory ({err}): page faults may delay cycles; \
             grant CAP_IPC_LOCK or raise RLIMIT_MEMLOCK (ulimit -l unlimited)"
        ))
    }
}

/// Asks the kernel to keep every CPU out of deep idle states (PM QoS `cpu_dma_latency` = 0
/// µs) for as long as the returned file stays open, as cyclictest does: waking a CPU from a
/// deep C-state adds tens of microseconds to every cycle's wake-up.
pub fn hold_cpu_dma_latency_zero() -> Result<std::fs::File, String> {
    use std::io::Write as _;
    let path = "/dev/cpu_dma_latency";
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .open(path)
        .map_err(|e| {
            format!(
                "cannot open {path} ({e}): idle CPUs may sleep deeply and wake late; run as \
                 root or grant write access to {path}"
            )
        })?;
    f.write_all(&0i32.to_ne_bytes())
        .map_err(|e| format!("cannot write {path} ({e}): idle CPUs may sleep deeply"))?;
    Ok(f)
}

/// Makes the calling thread SCHED_FIFO at `priority` (1..=99).
pub fn set_fifo(priority: u8) -> Result<(), String> {
    set_fifo_named("the cycle thread", priority)
}

/// Makes the calling thread, `what` in the message, SCHED_FIFO at `priority` (1..=99).
pub fn set_fifo_named(what: &str, priority: u8) -> Result<(), String> {
    let prio = ThreadPriority::from_posix(ScheduleParams {
        sched_priority: priority as libc::c_int,
    });
    thread_priority::set_thread_priority_and_policy(
        thread_priority::thread_native_id(),
        prio,
        ThreadSchedulePolicy::Realtime(RealtimeThreadSchedulePolicy::Fifo),
    )
    .map_err(|e| {
        format!(
            "cannot run {what} SCHED_FIFO at priority {priority} ({e}): it runs at normal \
             priority; grant CAP_SYS_NICE (or run as root), or raise RLIMIT_RTPRIO"
        )
    })
}

/// Pins the calling thread to `cpu`.
pub fn pin_to(cpu: usize) -> Result<(), String> {
    if core_affinity::set_for_current(core_affinity::CoreId { id: cpu }) {
        Ok(())
    } else {
        Err(format!(
            "cannot pin the cycle thread to CPU {cpu}: it may migrate between CPUs; check \
             that CPU {cpu} is online and in this process's cpuset"
        ))
    }
}

/// Touches `bytes` of stack so that the cycle never faults a stack page in.
#[inline(never)]
pub fn prefault_stack() {
    const BYTES: usize = 256 * 1024;
    let mut buf = [0u8; BYTES];
    for i in (0..BYTES).step_by(4096) {
        // black_box keeps the writes from being optimised away.
        buf[i] = std::hint::black_box(1);
    }
    std::hint::black_box(&buf);
}

/// Sets up the calling thread as the cycle thread: pinning, then SCHED_FIFO, then stack
/// pre-faulting. Memory locking is process-wide and done separately by [`lock_memory`].
pub fn setup_current_thread(cpu: Option<usize>, priority: u8) -> RtSetup {
    let mut setup = RtSetup::default();
    if let Some(cpu) = cpu {
        match pin_to(cpu) {
            Ok(()) => setup.pinned_cpu = Some(cpu),
            Err(w) => setup.warnings.push(w),
        }
    }
    match set_fifo(priority) {
        Ok(()) => setup.realtime = true,
        Err(w) => setup.warnings.push(w),
    }
    prefault_stack();
    setup
}
