// SPDX-License-Identifier: MIT OR Apache-2.0
//! `CLOCK_MONOTONIC` in nanoseconds (shared with the clients), and the absolute-time sleep
//! the cycle thread waits with.

pub use procimg_shm_layout::os::monotonic_ns as now_ns;

/// Sleeps until `CLOCK_MONOTONIC` reaches `deadline_ns` (absolute), resuming after signals.
/// Absolute sleeps do not accumulate drift: cycle k wakes at epoch + k·T however long cycle
/// k-1 took.
pub fn sleep_until_ns(deadline_ns: u64) {
    let ts = libc::timespec {
        tv_sec: (deadline_ns / 1_000_000_000) as libc::time_t,
        tv_nsec: (deadline_ns % 1_000_000_000) as libc::c_long,
    };
    loop {
        // SAFETY: `ts` is a valid timespec; the remaining-time pointer may be null with
        // TIMER_ABSTIME.
        let rc = unsafe {
            libc::clock_nanosleep(
                libc::CLOCK_MONOTONIC,
                libc::TIMER_ABSTIME,
                &ts,
                std::ptr::null_mut(),
            )
        };
        if rc != libc::EINTR {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sleeps_until_the_deadline() {
        let start = now_ns();
        sleep_until_ns(start + 2_000_000);
        // Not before it; how much later is the scheduler's figure (procimg-cyclictest).
        assert!(now_ns() >= start + 2_000_000);
    }

    #[test]
    fn a_past_deadline_returns_at_once() {
        let start = now_ns();
        sleep_until_ns(start.saturating_sub(1_000_000));
        // Returning at all is the point: an absolute sleep towards a past deadline must not
        // wait for the clock to wrap. The bound only guards against that.
        assert!(now_ns() - start < 10_000_000_000);
    }
}
