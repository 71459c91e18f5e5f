// SPDX-License-Identifier: MIT OR Apache-2.0
//! Cycle statistics: counters readable at any time, and latency histograms that the cycle
//! thread fills and hands over whole to the acyclic side.
//!
//! The cycle thread records into a batch of fixed-size histograms. Every
//! [`HANDOFF_CYCLES`] cycles it swaps the batch for an empty one through two bounded
//! lock-free queues; the acyclic side folds full batches into the totals and returns them
//! empty. Nothing allocates after start-up and no lock is shared with the cycle thread.

use crossbeam_queue::ArrayQueue;
use hdrhistogram::{Counter, Histogram};
use procimg_control::{Bucket, HistogramsReport, Percentiles};
use procimg_shm_layout::MAX_CLIENTS;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};

/// Cycles between two hand-overs of a histogram batch.
pub const HANDOFF_CYCLES: u64 = 128;
/// Largest value a histogram holds (10 s in ns); larger values are clamped.
pub const HIGHEST_NS: u64 = 10_000_000_000;

/// A latency histogram in ns, 1 ns … 10 s, 3 significant digits: a fixed ~200 KiB. The
/// latency tools' histogram (`procimg-cyclictest`, `procimg-handshake`, the baselines).
pub fn latency_histogram() -> Histogram<u64> {
    Histogram::new_with_bounds(1, HIGHEST_NS, 3).expect("valid histogram bounds")
}

/// Significant digits of procimgd's own histograms: 2, each value within 0.8 % (exact below
/// 256 ns). At 3 digits the twenty histograms procimgd keeps (four sets in circulation
/// between the threads, and the totals) were 2.4 MiB of locked memory; at 2, 0.4 MiB. The
/// histograms answered through the control service were cut to 2 digits before already: at
/// 3 a long run fills thousands of buckets per histogram, hundreds of KiB the service must
/// grow (and `mlockall` lock) memory for, which took seconds on a loaded machine.
pub const SERVER_DIGITS: u8 = 2;

/// One of procimgd's histograms, with counts of type `C`: 3 584 of them, whatever is
/// recorded.
fn histogram<C: Counter>() -> Histogram<C> {
    Histogram::new_with_bounds(1, HIGHEST_NS, SERVER_DIGITS).expect("valid histogram bounds")
}

/// Batches in circulation: one being filled, the rest in the queues.
const BATCHES: usize = 4;

/// One set of latency histograms, in ns, with counts of type `C`: `u32` in the batches the
/// cycle thread fills (a batch holds some hundred cycles, or as many as the acyclic side
/// lets pile up: a count saturates after 4·10⁹ values, an hour of 64 clients at 31.25 µs),
/// which halves the memory locked for the five sets in circulation; `u64` in the totals.
pub struct StatsBatch<C: Counter = u32> {
    /// Actual minus planned cycle start.
    pub wakeup: Histogram<C>,
    /// STARTOP → OPDONE of each synchronous client.
    pub handshake: Histogram<C>,
    /// A client's OPDONE sent → received here (one way).
    pub opdone: Histogram<C>,
    /// Cycle start until the outputs were handed to the IO system.
    pub work: Histogram<C>,
}

impl<C: Counter> StatsBatch<C> {
    fn new() -> StatsBatch<C> {
        let h = histogram::<C>;
        StatsBatch {
            wakeup: h(),
            handshake: h(),
            opdone: h(),
            work: h(),
        }
    }

    fn reset(&mut self) {
        self.wakeup.reset();
        self.handshake.reset();
        self.opdone.reset();
        self.work.reset();
    }

    fn is_empty(&self) -> bool {
        self.wakeup.is_empty()
            && self.handshake.is_empty()
            && self.opdone.is_empty()
            && self.work.is_empty()
    }
}

/// Counters shared between the cycle thread (writer) and everyone else (readers).
#[derive(Debug)]
pub struct Counters {
    /// Cycles run.
    pub cycles: AtomicU64,
    /// Cycles that overran their period.
    pub overruns: AtomicU64,
    /// OPFAULTs given.
    pub opfaults: AtomicU64,
    /// Output samples dropped because the sender did not hold the claim.
    pub rejected_writes: AtomicU64,
    /// OPDONE samples of busy clients taken where they wrote them (no iceoryx2 send).
    pub outputs_in_place: AtomicU64,
    /// Failed receives of client output samples (iceoryx2 could not update a connection,
    /// e.g. while a dead client's resources are being removed).
    pub receive_errors: AtomicU64,
    /// Cycles whose input image could not be published (no free image slot), or reached
    /// the clients that read by their mark but not iceoryx2's readers (its send failed).
    pub unpublished_images: AtomicU64,
    /// The mode the cycle runs in (shm-layout MODE_* value).
    pub mode: AtomicU32,
    /// The cycle thread runs SCHED_FIFO.
    pub realtime: AtomicBool,
    /// OPFAULTs per client slot.
    pub client_opfaults: [AtomicU64; MAX_CLIENTS],
    /// Per client slot: the cycle of its last OPFAULT (0: none).
    pub client_last_opfault: [AtomicU64; MAX_CLIENTS],
}

impl Default for Counters {
    fn default() -> Self {
        Counters {
            cycles: AtomicU64::new(0),
            overruns: AtomicU64::new(0),
            opfaults: AtomicU64::new(0),
            rejected_writes: AtomicU64::new(0),
            receive_errors: AtomicU64::new(0),
            outputs_in_place: AtomicU64::new(0),
            unpublished_images: AtomicU64::new(0),
            mode: AtomicU32::new(0),
            realtime: AtomicBool::new(false),
            client_opfaults: std::array::from_fn(|_| AtomicU64::new(0)),
            client_last_opfault: std::array::from_fn(|_| AtomicU64::new(0)),
        }
    }
}

/// The cycle thread's end: records values and hands batches over.
pub struct StatsRecorder {
    current: Box<StatsBatch>,
    full: Arc<ArrayQueue<Box<StatsBatch>>>,
    empty: Arc<ArrayQueue<Box<StatsBatch>>>,
}

/// The acyclic side's end: collects batches into totals.
pub struct StatsCollector {
    totals: StatsBatch<u64>,
    full: Arc<ArrayQueue<Box<StatsBatch>>>,
    empty: Arc<ArrayQueue<Box<StatsBatch>>>,
}

/// A connected recorder/collector pair, with every batch allocated up front.
pub fn stats_channel() -> (StatsRecorder, StatsCollector) {
    let full = Arc::new(ArrayQueue::new(BATCHES));
    let empty = Arc::new(ArrayQueue::new(BATCHES));
    for _ in 1..BATCHES {
        // The queue has room for every batch, so this push cannot fail.
        let _ = empty.push(Box::new(StatsBatch::new()));
    }
    (
        StatsRecorder {
            current: Box::new(StatsBatch::new()),
            full: full.clone(),
            empty: empty.clone(),
        },
        StatsCollector {
            totals: StatsBatch::new(),
            full,
            empty,
        },
    )
}

impl StatsRecorder {
    /// Records a wake-up latency.
    #[inline]
    pub fn wakeup(&mut self, ns: u64) {
        self.current.wakeup.saturating_record(ns.max(1));
    }

    /// Records a STARTOP → OPDONE round trip.
    #[inline]
    pub fn handshake(&mut self, ns: u64) {
        self.current.handshake.saturating_record(ns.max(1));
    }

    /// Records an OPDONE one-way latency (client sent → cycle thread received).
    #[inline]
    pub fn opdone(&mut self, ns: u64) {
        self.current.opdone.saturating_record(ns.max(1));
    }

    /// Records the work time of a cycle.
    #[inline]
    pub fn work(&mut self, ns: u64) {
        self.current.work.saturating_record(ns.max(1));
    }

    /// Hands the current batch over if an empty one is available; otherwise keeps filling
    /// it. Moves boxes only: no allocation.
    pub fn hand_over(&mut self) {
        if self.current.is_empty() {
            return;
        }
        if let Some(next) = self.empty.pop() {
            let filled = std::mem::replace(&mut self.current, next);
            if let Err(filled) = self.full.push(filled) {
                // Cannot happen with BATCHES boxes in circulation; keep the data anyway.
                self.current = filled;
            }
        }
    }
}

impl StatsCollector {
    /// Folds every handed-over batch into the totals and returns the batches empty.
    pub fn collect(&mut self) {
        while let Some(mut batch) = self.full.pop() {
            add(&mut self.totals.wakeup, &batch.wakeup);
            add(&mut self.totals.handshake, &batch.handshake);
            add(&mut self.totals.opdone, &batch.opdone);
            add(&mut self.totals.work, &batch.work);
            batch.reset();
            let _ = self.empty.push(batch);
        }
    }

    /// Percentiles of the wake-up latency since start.
    pub fn wakeup(&self) -> Percentiles {
        percentiles(&self.totals.wakeup)
    }

    /// Percentiles of the handshake round trip since start.
    pub fn handshake(&self) -> Percentiles {
        percentiles(&self.totals.handshake)
    }

    /// Percentiles of the OPDONE one-way latency since start.
    pub fn opdone(&self) -> Percentiles {
        percentiles(&self.totals.opdone)
    }

    /// Percentiles of the cycle work time since start.
    pub fn work(&self) -> Percentiles {
        percentiles(&self.totals.work)
    }

    /// Every histogram since start, bucket by bucket, for `cycles` cycles run.
    pub fn histograms(&self, cycles: u64) -> HistogramsReport {
        HistogramsReport {
            cycles,
            wakeup: buckets(&self.totals.wakeup),
            handshake: buckets(&self.totals.handshake),
            opdone: buckets(&self.totals.opdone),
            work: buckets(&self.totals.work),
        }
    }
}

/// Adds the counts of `batch` to `total`, bucket by bucket: the same bounds on both sides, so
/// each value lands in the bucket it came from, and nothing is clamped or resized.
fn add(total: &mut Histogram<u64>, batch: &Histogram<u32>) {
    for v in batch.iter_recorded() {
        let _ = total.record_n(v.value_iterated_to(), u64::from(v.count_at_value()));
    }
}

/// The buckets of `h` that hold values, in rising order, each with its highest value.
pub fn buckets(h: &Histogram<u64>) -> Vec<Bucket> {
    h.iter_recorded()
        .map(|v| Bucket {
            ns: h.highest_equivalent(v.value_iterated_to()),
            count: v.count_at_value(),
        })
        .collect()
}

fn percentiles(h: &Histogram<u64>) -> Percentiles {
    if h.is_empty() {
        return Percentiles::default();
    }
    Percentiles {
        count: h.len(),
        min_ns: h.min(),
        p50_ns: h.value_at_quantile(0.50),
        p99_ns: h.value_at_quantile(0.99),
        p999_ns: h.value_at_quantile(0.999),
        max_ns: h.max(),
        mean_ns: h.mean() as u64,
    }
}

/// Loads a counter.
pub fn load(c: &AtomicU64) -> u64 {
    c.load(Ordering::Relaxed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batches_reach_the_collector_and_come_back() {
        let (mut rec, mut col) = stats_channel();
        for round in 0..10u64 {
            for i in 0..100 {
                rec.wakeup(1000 + i);
                rec.handshake(50_000);
            }
            rec.hand_over();
            col.collect();
            assert_eq!(col.wakeup().count, (round + 1) * 100);
        }
        assert_eq!(col.handshake().p50_ns / 1000, 50);
        assert!(col.wakeup().max_ns >= 1099);
    }

    #[test]
    fn totals_hold_what_the_batches_held_bucket_for_bucket() {
        let (mut rec, mut col) = stats_channel();
        let mut direct = histogram::<u64>();
        let mut v = 7u64;
        for round in 0..2000u64 {
            // Values over the whole range, some recorded many times.
            v = v
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let value = if round % 3 == 0 {
                12_345
            } else {
                (v % HIGHEST_NS).max(1)
            };
            rec.opdone(value);
            direct.saturating_record(value);
            if round % 128 == 127 {
                rec.hand_over();
                col.collect();
            }
        }
        rec.hand_over();
        col.collect();
        assert_eq!(buckets(&col.totals.opdone), buckets(&direct));
    }

    #[test]
    fn out_of_range_values_are_clamped_not_lost() {
        let (mut rec, mut col) = stats_channel();
        rec.work(u64::MAX);
        rec.hand_over();
        col.collect();
        assert_eq!(col.work().count, 1);
    }

    #[test]
    fn the_histogram_answer_stays_small_and_loses_no_value() {
        let (mut rec, mut col) = stats_channel();
        // A wake-up at every µs from 1 µs to 20 ms: 20 000 distinct 3-digit buckets.
        for us in 1..=20_000u64 {
            rec.wakeup(us * 1000);
            if us % 100 == 0 {
                rec.hand_over();
                col.collect();
            }
        }
        rec.hand_over();
        col.collect();
        let answer = col.histograms(20_000);
        let count: u64 = answer.wakeup.iter().map(|b| b.count).sum();
        assert_eq!(count, 20_000);
        assert!(
            answer.wakeup.len() < 2_000,
            "{} buckets",
            answer.wakeup.len()
        );
        // Every bucket's value within 1 % of what it holds.
        let max = answer.wakeup.last().unwrap().ns;
        assert!((20_000_000..=20_200_000).contains(&max), "{max}");
    }
}
