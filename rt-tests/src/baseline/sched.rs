// SPDX-License-Identifier: MIT OR Apache-2.0
//! Scheduling of the two measuring processes: SCHED_FIFO and CPU pinning. Both are
//! best-effort: without the privilege the tool still measures, and says how it was run.

/// Why a process could not be set up as asked.
#[derive(Debug, thiserror::Error)]
pub enum SchedError {
    /// sched_setscheduler refused.
    #[error(
        "cannot run SCHED_FIFO at priority {priority} ({source}): measuring at normal \
         priority; run as root or grant CAP_SYS_NICE"
    )]
    Fifo {
        /// Priority asked for.
        priority: u8,
        /// The OS error.
        source: std::io::Error,
    },
    /// sched_setaffinity refused.
    #[error(
        "cannot pin process {who} to CPU {cpu} ({source}): it may migrate; check that CPU \
         {cpu} is online and in this process's cpuset"
    )]
    Pin {
        /// "A" or "B".
        who: &'static str,
        /// CPU asked for.
        cpu: usize,
        /// The OS error.
        source: std::io::Error,
    },
}

/// Makes the calling process SCHED_FIFO at `priority` (1..=99). A child forked afterwards
/// inherits the policy, so calling this once before `fork` sets up both sides.
pub fn set_fifo(priority: u8) -> Result<(), SchedError> {
    let param = libc::sched_param {
        sched_priority: libc::c_int::from(priority),
    };
    // SAFETY: `param` is a valid sched_param that lives across the call; pid 0 is the caller.
    let rc = unsafe { libc::sched_setscheduler(0, libc::SCHED_FIFO, &param) };
    if rc == 0 {
        Ok(())
    } else {
        Err(SchedError::Fifo {
            priority,
            source: std::io::Error::last_os_error(),
        })
    }
}

/// Pins the calling process to `cpu`.
pub fn pin(who: &'static str, cpu: usize) -> Result<(), SchedError> {
    let too_large = || SchedError::Pin {
        who,
        cpu,
        source: std::io::Error::from_raw_os_error(libc::EINVAL),
    };
    if cpu >= libc::CPU_SETSIZE as usize {
        return Err(too_large());
    }
    // SAFETY: cpu_set_t is a plain bit array, for which all-zero is the empty set.
    let mut set: libc::cpu_set_t = unsafe { std::mem::zeroed() };
    // SAFETY: cpu < CPU_SETSIZE was checked above, so the bit is inside `set`.
    unsafe { libc::CPU_SET(cpu, &mut set) };
    // SAFETY: `set` is a valid cpu_set_t of the size passed; pid 0 is the caller.
    let rc = unsafe { libc::sched_setaffinity(0, size_of::<libc::cpu_set_t>(), &set) };
    if rc == 0 {
        Ok(())
    } else {
        Err(SchedError::Pin {
            who,
            cpu,
            source: std::io::Error::last_os_error(),
        })
    }
}

/// The CPUs this process may run on, in rising order (its affinity mask, which a cpuset or
/// `taskset` may have narrowed; so not simply 0..n).
pub fn allowed_cpus() -> Vec<usize> {
    // SAFETY: cpu_set_t is a plain bit array, for which all-zero is the empty set.
    let mut set: libc::cpu_set_t = unsafe { std::mem::zeroed() };
    // SAFETY: `set` is a writable cpu_set_t of the size passed; pid 0 is the caller.
    let rc = unsafe { libc::sched_getaffinity(0, size_of::<libc::cpu_set_t>(), &mut set) };
    if rc != 0 {
        // Unknown mask: assume the usual numbering.
        return (0..std::thread::available_parallelism().map_or(1, |n| n.get())).collect();
    }
    (0..libc::CPU_SETSIZE as usize)
        // SAFETY: cpu < CPU_SETSIZE, so the bit is inside `set`.
        .filter(|&cpu| unsafe { libc::CPU_ISSET(cpu, &set) })
        .collect()
}
