// SPDX-License-Identifier: MIT OR Apache-2.0
//! The two-process ping-pong: process A (this one) sends sequence number n, process B (a
//! forked child) waits for it and sends n back, A waits for it and records the round trip.
//! Two processes, not two threads, because procimgd and its clients are processes: the
//! figures then include whatever crossing address spaces costs (futex keys, page tables).

use super::mechanism::{Channel, Dir, MechanismError};
use super::sched::{self, SchedError};
use hdrhistogram::Histogram;
use procimg_rt_tests::report::{HIGHEST_NS, new_histogram};
use procimg_runtime::sys::clock::{now_ns, sleep_until_ns};
use std::os::unix::process::ExitStatusExt;
use std::process::ExitStatus;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Round trips done before measuring: page faults, cache misses and the first wake-ups of
/// a fresh process would otherwise land in the histogram.
pub const WARMUP: u64 = 1000;

/// How to run a ping-pong.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Measured round trips.
    pub loops: u64,
    /// CPUs of A and B.
    pub cpus: Option<(usize, usize)>,
    /// SCHED_FIFO priority of both; 0: normal scheduling.
    pub priority: u8,
    /// A starts each round trip at the next tick of this period (an absolute sleep, as a
    /// cycle thread's), so that both sides sleep between round trips as a cyclic
    /// handshake's do; 0: back to back.
    pub period_ns: u64,
}

/// What a ping-pong measured.
pub struct Outcome {
    /// Round trips, ns.
    pub round_trips: Histogram<u64>,
    /// Both processes ran SCHED_FIFO.
    pub realtime: bool,
    /// Set-up steps that failed (the run went on without them).
    pub warnings: Vec<SchedError>,
}

/// Why a ping-pong failed.
#[derive(Debug, thiserror::Error)]
pub enum PingPongError {
    /// fork failed.
    #[error("cannot start the second process ({0}); check the process limit (ulimit -u)")]
    Fork(std::io::Error),
    /// A's side of the mechanism failed.
    #[error("process A: {0}")]
    Mechanism(#[from] MechanismError),
    /// B ended early or badly.
    #[error("process B ended with {0} (its error is printed above)")]
    Partner(ExitStatus),
}

/// Runs the ping-pong over `channel`. Must be called while this process has one thread:
/// `fork` copies only the calling thread.
pub fn run<C: Channel>(channel: &C, plan: &Plan) -> Result<Outcome, PingPongError> {
    let mut warnings = Vec::new();
    // Before fork, so that B inherits the policy.
    let realtime = plan.priority > 0
        && match sched::set_fifo(plan.priority) {
            Ok(()) => true,
            Err(w) => {
                warnings.push(w);
                false
            }
        };
    let total = WARMUP + plan.loops;
    // SAFETY: getpid has no preconditions.
    let parent = unsafe { libc::getpid() };
    // SAFETY: this process is single-threaded (the caller's contract), so the child is a
    // complete copy; it only touches memory it inherited and ends with _exit.
    let pid = unsafe { libc::fork() };
    if pid < 0 {
        return Err(PingPongError::Fork(std::io::Error::last_os_error()));
    }
    if pid == 0 {
        partner(channel, plan, parent, total);
    }
    if let Some((a, _)) = plan.cpus
        && let Err(w) = sched::pin("A", a)
    {
        warnings.push(w);
    }

    // B can only die of a bug or a signal; A would then wait for ever. The watchdog reaps
    // B and ends this process if B failed while A still needs it.
    let abandoned = Arc::new(AtomicBool::new(false));
    let watchdog = {
        let abandoned = abandoned.clone();
        std::thread::spawn(move || {
            let status = wait_for(pid);
            if !status.success() && !abandoned.load(Ordering::Acquire) {
                eprintln!(
                    "procimg-baseline: process B ended with {status} during the measurement \
                     (its error is printed above)"
                );
                std::process::exit(1);
            }
            status
        })
    };

    let mut round_trips = new_histogram();
    let measured = (|| -> Result<(), MechanismError> {
        let mut tick = now_ns();
        for n in 1..=total {
            if plan.period_ns > 0 {
                tick = next_tick(tick, now_ns(), plan.period_ns);
                sleep_until_ns(tick);
            }
            let start = now_ns();
            channel.send(Dir::ToB, n)?;
            channel.wait(Dir::ToA, n)?;
            let end = now_ns();
            if n > WARMUP {
                round_trips.saturating_record(end.saturating_sub(start).clamp(1, HIGHEST_NS));
            }
        }
        Ok(())
    })();
    if measured.is_err() {
        abandoned.store(true, Ordering::Release);
        // SAFETY: kill takes a pid and a signal; pid is our own child, not yet reaped (the
        // watchdog reaps it only after it has ended).
        unsafe {
            libc::kill(pid, libc::SIGKILL);
        }
    }
    let status = watchdog
        .join()
        .unwrap_or_else(|_| ExitStatus::from_raw(libc::SIGKILL));
    measured?;
    if !status.success() {
        return Err(PingPongError::Partner(status));
    }
    Ok(Outcome {
        round_trips,
        realtime,
        warnings,
    })
}

/// The first tick after `last` (a multiple of `period` later) that is not yet past at
/// `now`: ticks a stall overran are skipped, as a cycle thread skips its overrun cycles,
/// rather than run back to back with both sides awake.
fn next_tick(last: u64, now: u64, period: u64) -> u64 {
    let next = last + period;
    if next > now {
        next
    } else {
        next + (now - next) / period * period + period
    }
}

/// Process B: answers every number, then ends without running A's destructors or atexit
/// handlers (they belong to A).
fn partner<C: Channel>(channel: &C, plan: &Plan, parent: libc::pid_t, total: u64) -> ! {
    // SAFETY: prctl with PR_SET_PDEATHSIG takes a signal number; no memory is involved.
    unsafe {
        libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL);
    }
    // SAFETY: getppid has no preconditions.
    if unsafe { libc::getppid() } != parent {
        // A died before the death signal was armed.
        // SAFETY: _exit ends the process at once; nothing is left half-done.
        unsafe { libc::_exit(1) };
    }
    if let Some((_, b)) = plan.cpus
        && let Err(w) = sched::pin("B", b)
    {
        eprintln!("procimg-baseline: warning: {w}");
    }
    let answered = (|| -> Result<(), MechanismError> {
        for n in 1..=total {
            channel.wait(Dir::ToB, n)?;
            channel.send(Dir::ToA, n)?;
        }
        Ok(())
    })();
    let code = match answered {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("procimg-baseline: process B: {e}");
            1
        }
    };
    // SAFETY: _exit ends the process at once, as a forked child should.
    unsafe { libc::_exit(code) }
}

/// Waits for `pid` to end and returns how it ended.
fn wait_for(pid: libc::pid_t) -> ExitStatus {
    let mut status: libc::c_int = 0;
    loop {
        // SAFETY: `status` is a writable int; pid is our child.
        let rc = unsafe { libc::waitpid(pid, &mut status, 0) };
        if rc == pid {
            return ExitStatus::from_raw(status);
        }
        if rc < 0 && std::io::Error::last_os_error().raw_os_error() != Some(libc::EINTR) {
            // Already reaped or not ours: nothing to wait for, call it a failure.
            return ExitStatus::from_raw(libc::SIGKILL);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::next_tick;

    #[test]
    fn ticks_follow_the_period_and_skip_what_a_stall_overran() {
        assert_eq!(next_tick(1000, 1500, 1000), 2000);
        assert_eq!(next_tick(1000, 1999, 1000), 2000);
        // At or past the next tick: the one after the present.
        assert_eq!(next_tick(1000, 2000, 1000), 3000);
        assert_eq!(next_tick(1000, 5400, 1000), 6000);
    }
}
