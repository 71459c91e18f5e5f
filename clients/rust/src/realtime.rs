// SPDX-License-Identifier: MIT OR Apache-2.0
//! Real-time set-up for a client's cycle thread: a synchronous client that must answer
//! within the OPDONE deadline should run SCHED_FIFO with its memory locked, like the server.

/// Makes the calling thread SCHED_FIFO at `priority` (1..=99) and locks the process's memory.
/// Fails with the OS error when the process lacks CAP_SYS_NICE / CAP_IPC_LOCK (or the
/// rlimits); the thread then keeps its normal priority.
///
/// The thread is also marked real-time for [`crate::rt_alloc::RtAllocator`]: in a program
/// that installs it as its global allocator, the thread's cycle loop does not call `malloc`
/// (iceoryx2's per-sample reference count comes from a fixed pool).
pub fn make_current_thread_realtime(priority: u8) -> std::io::Result<()> {
    crate::rt_alloc::mark_current_thread_realtime();
    let param = libc::sched_param {
        sched_priority: priority as libc::c_int,
    };
    // SAFETY: `param` is a valid sched_param; pid 0 means the calling thread.
    if unsafe { libc::sched_setscheduler(0, libc::SCHED_FIFO, &param) } != 0 {
        return Err(std::io::Error::last_os_error());
    }
    // SAFETY: mlockall takes only flags.
    if unsafe { libc::mlockall(libc::MCL_CURRENT | libc::MCL_FUTURE) } != 0 {
        return Err(std::io::Error::last_os_error());
    }
    Ok(())
}
