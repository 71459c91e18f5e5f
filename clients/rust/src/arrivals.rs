// SPDX-License-Identifier: MIT OR Apache-2.0
//! How long since the client last took a new image: to notice a server that stopped
//! publishing. Taking an image only counts it; the clock is read when someone asks, so that
//! the busy path (an image taken every cycle, between STARTOP and the program's first read)
//! reads no clock of its own.

use std::time::{Duration, Instant};

/// Images taken, and when a look first found their count where it is.
#[derive(Debug)]
pub(crate) struct Arrivals {
    count: u64,
    seen_count: u64,
    seen_at: Instant,
}

impl Arrivals {
    /// None taken yet: the time runs from now.
    pub(crate) fn new() -> Arrivals {
        Arrivals {
            count: 0,
            seen_count: 0,
            seen_at: Instant::now(),
        }
    }

    /// Counts a new image taken.
    pub(crate) fn note(&mut self) {
        self.count = self.count.wrapping_add(1);
    }

    /// The time since an image was last taken, as far as the looks tell: zero at the first look
    /// after one, then the time since that look. Late by at most the time between two looks,
    /// which is what a check that runs every so often needs.
    pub(crate) fn since_last(&mut self) -> Duration {
        if self.count != self.seen_count {
            self.seen_count = self.count;
            self.seen_at = Instant::now();
            return Duration::ZERO;
        }
        self.seen_at.elapsed()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_image_taken_sets_the_time_back_to_zero_and_without_one_it_only_grows() {
        let mut a = Arrivals::new();
        let first = a.since_last();
        let later = a.since_last();
        assert!(later >= first);
        a.note();
        assert_eq!(a.since_last(), Duration::ZERO);
        let after = a.since_last();
        assert!(a.since_last() >= after);
        a.note();
        a.note();
        assert_eq!(a.since_last(), Duration::ZERO);
    }
}
