// SPDX-License-Identifier: MIT OR Apache-2.0
//! Real-time set-up for a client's cycle thread: a synchronous client that must answer
//! within the OPDONE deadline should run SCHED_FIFO with its memory locked, like the server.

/// Makes the calling thread SCHED_FIFO at `priority` (1..=99) and locks the process's memory.
/// Call it before `Client::attach`: the shared memory mapped later is locked as it is used.
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
    // What is mapped now (the program, its heap and stacks) is faulted in and locked. Later
    // mappings are locked page by page as they are touched: procimgd's input segment holds
    // an image for every reader that may hold one, and only the few in use are ever touched
    // (procimgd locks it the same way). Called after `Client::attach`, the first call faults
    // that whole segment in as well.
    // SAFETY: mlockall takes only flags.
    if unsafe { libc::mlockall(libc::MCL_CURRENT) } != 0 {
        return Err(std::io::Error::last_os_error());
    }
    // SAFETY: as above. A kernel without MCL_ONFAULT (before 4.4) refuses it: plain
    // MCL_FUTURE then.
    let on_fault = unsafe { libc::mlockall(libc::MCL_FUTURE | libc::MCL_ONFAULT) };
    // SAFETY: as above.
    if on_fault != 0 && unsafe { libc::mlockall(libc::MCL_FUTURE) } != 0 {
        return Err(std::io::Error::last_os_error());
    }
    Ok(())
}
