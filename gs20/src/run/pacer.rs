// SPDX-License-Identifier: MIT OR Apache-2.0
//! When Adapter Data (0x31) goes to the host: when the PLC's Q data changed since the last
//! one sent, and again after `--min-period-ms` without a change, so that a host that missed
//! a frame (a CRC error on its side) has the image again within that period — the
//! reference's "pushed when it changes and at a minimum period". Either way only on an idle
//! line: at 115200 bit/s a 384-byte image takes about 37 ms, longer than a PLC's cycle, so
//! the bridge never queues one image behind another; the next frame carries the newest Q
//! data whole.

use std::time::{Duration, Instant};

/// The Adapter Data pacing.
#[derive(Clone, Debug)]
pub struct Pacer {
    /// `None`: only on changes.
    period: Option<Duration>,
    last: Option<(Vec<u8>, Instant)>,
}

impl Pacer {
    /// Pushes on change and every `period` (`None`: on change only).
    pub fn new(period: Option<Duration>) -> Pacer {
        Pacer { period, last: None }
    }

    /// Forgets what was sent: the next image goes out (a new Run).
    pub fn reset(&mut self) {
        self.last = None;
    }

    /// Whether `q` is to be sent at `now` (the line being idle).
    pub fn due(&self, q: &[u8], now: Instant) -> bool {
        match &self.last {
            None => true,
            Some((sent, at)) => sent.as_slice() != q || self.period.is_some_and(|p| now >= *at + p),
        }
    }

    /// `q` was sent at `now`.
    pub fn sent(&mut self, q: Vec<u8>, now: Instant) {
        self.last = Some((q, now));
    }

    /// When the image is due again without a change.
    pub fn next_refresh(&self) -> Option<Instant> {
        let (_, at) = self.last.as_ref()?;
        Some(*at + self.period?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn on_change_and_after_the_period() {
        let t0 = Instant::now();
        let mut p = Pacer::new(Some(Duration::from_millis(100)));
        assert!(p.due(&[1], t0), "the first image");
        p.sent(vec![1], t0);
        assert!(!p.due(&[1], t0 + Duration::from_millis(99)));
        assert!(p.due(&[2], t0 + Duration::from_millis(1)), "a change");
        assert!(p.due(&[1], t0 + Duration::from_millis(100)), "the period");
        assert_eq!(p.next_refresh(), Some(t0 + Duration::from_millis(100)));
        let mut q = Pacer::new(None);
        q.sent(vec![1], t0);
        assert!(!q.due(&[1], t0 + Duration::from_secs(3600)));
        assert_eq!(q.next_refresh(), None);
        q.reset();
        assert!(q.due(&[1], t0));
    }
}
