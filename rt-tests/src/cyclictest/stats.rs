// SPDX-License-Identifier: MIT OR Apache-2.0
//! What one thread's run measured, in the units cyclictest prints (µs), whether a measuring
//! thread of this tool recorded it or it was taken from procimgd's histograms.

use hdrhistogram::Histogram;
use procimg_rt_tests::report::{buckets, new_histogram};

/// One thread's results.
#[derive(Clone, Debug)]
pub struct ThreadStats {
    /// Thread number (`T:`).
    pub index: usize,
    /// Kernel thread id.
    pub tid: u32,
    /// Priority printed as `P:`.
    pub priority: u8,
    /// Period in µs (`I:`).
    pub interval_us: u64,
    /// Wake-ups (`C:`).
    pub cycles: u64,
    /// Smallest latency, µs.
    pub min_us: u64,
    /// Latest latency, µs (`Act:`).
    pub act_us: u64,
    /// Largest latency, µs.
    pub max_us: u64,
    /// Sum of all latencies in µs, each truncated to whole µs (for `Avg:`).
    pub sum_us: u64,
    /// All latencies in ns.
    pub ns: Histogram<u64>,
    /// With -h/-H: counts of latencies of 0, 1, … µs (`len()` = the histogram size).
    pub us_buckets: Vec<u64>,
    /// With -h/-H: latencies that did not fit in `us_buckets`.
    pub overflows: u64,
    /// The cycle numbers (from 0) of the first overflows, at most `us_buckets.len()` of them;
    /// the rest are only counted.
    pub overflow_cycles: Vec<u64>,
    /// Cycles that ran past the start of the next (procimgd's overrun rule).
    pub overruns: u64,
    /// CPU the thread last ran on.
    pub cpu: Option<usize>,
}

impl ThreadStats {
    /// Empty results for a thread that keeps a µs histogram of `hist_us` buckets (0: none).
    /// Everything is allocated here so that recording never allocates.
    pub fn new(index: usize, priority: u8, interval_us: u64, hist_us: usize) -> ThreadStats {
        ThreadStats {
            index,
            tid: 0,
            priority,
            interval_us,
            cycles: 0,
            min_us: 0,
            act_us: 0,
            max_us: 0,
            sum_us: 0,
            ns: new_histogram(),
            us_buckets: vec![0; hist_us],
            overflows: 0,
            overflow_cycles: Vec::with_capacity(hist_us),
            overruns: 0,
            cpu: None,
        }
    }

    /// Records one latency. Never allocates: the histograms have fixed bounds and the
    /// overflow list stops at the capacity it was given.
    #[inline]
    pub fn record(&mut self, latency_ns: u64) {
        let us = latency_ns / 1000;
        self.ns.saturating_record(latency_ns.max(1));
        if self.cycles == 0 || us < self.min_us {
            self.min_us = us;
        }
        if us > self.max_us {
            self.max_us = us;
        }
        self.act_us = us;
        self.sum_us = self.sum_us.saturating_add(us);
        if !self.us_buckets.is_empty() {
            match self.us_buckets.get_mut(us as usize) {
                Some(count) => *count += 1,
                None => {
                    self.overflows += 1;
                    if self.overflow_cycles.len() < self.overflow_cycles.capacity() {
                        self.overflow_cycles.push(self.cycles);
                    }
                }
            }
        }
        self.cycles += 1;
    }

    /// The mean in µs (as cyclictest: the sum of whole µs over the cycles).
    pub fn avg_us(&self) -> f64 {
        if self.cycles == 0 {
            0.0
        } else {
            self.sum_us as f64 / self.cycles as f64
        }
    }

    /// Fills cycles, min, max, sum and the µs buckets from an ns histogram (procimgd's): each
    /// of its buckets counts at the whole µs of the bucket's highest value. Cycle numbers of
    /// overflows are not known then; they are all "others".
    pub fn fill_from_histogram(&mut self, h: &Histogram<u64>, hist_us: usize) {
        self.cycles = h.len();
        self.us_buckets = vec![0; hist_us];
        self.overflows = 0;
        self.overflow_cycles = Vec::new();
        self.sum_us = 0;
        for b in buckets(h) {
            let us = b.ns / 1000;
            self.sum_us = self.sum_us.saturating_add(us.saturating_mul(b.count));
            if hist_us > 0 {
                match self.us_buckets.get_mut(us as usize) {
                    Some(count) => *count += b.count,
                    None => self.overflows += b.count,
                }
            }
        }
        if h.is_empty() {
            self.min_us = 0;
            self.max_us = 0;
        } else {
            self.min_us = h.min() / 1000;
            self.max_us = h.max() / 1000;
        }
        self.ns = h.clone();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_like_cyclictest_counts() {
        let mut s = ThreadStats::new(0, 80, 1000, 10);
        for ns in [12_500, 3_999, 25_000, 9_999, 10_000] {
            s.record(ns);
        }
        assert_eq!((s.cycles, s.min_us, s.max_us, s.act_us), (5, 3, 25, 10));
        assert_eq!(s.sum_us, 12 + 3 + 25 + 9 + 10);
        assert_eq!(s.us_buckets[3], 1);
        assert_eq!(s.us_buckets[9], 1);
        assert_eq!(s.overflows, 3);
        assert_eq!(s.overflow_cycles, vec![0, 2, 4]);
    }

    #[test]
    fn the_overflow_list_stops_at_the_histogram_size() {
        let mut s = ThreadStats::new(0, 80, 1000, 2);
        for _ in 0..5 {
            s.record(50_000);
        }
        assert_eq!(s.overflows, 5);
        assert_eq!(s.overflow_cycles, vec![0, 1]);
        assert_eq!(s.overflow_cycles.capacity(), 2);
    }

    #[test]
    fn a_histogram_fills_the_same_fields() {
        let mut h = new_histogram();
        for ns in [1_500, 2_500, 2_600, 40_000] {
            h.record(ns).unwrap();
        }
        let mut s = ThreadStats::new(0, 80, 1000, 0);
        s.fill_from_histogram(&h, 10);
        assert_eq!((s.cycles, s.min_us, s.max_us), (4, 1, 40));
        assert_eq!(s.us_buckets[1], 1);
        assert_eq!(s.us_buckets[2], 2);
        assert_eq!(s.overflows, 1);
    }
}
