// SPDX-License-Identifier: MIT OR Apache-2.0
//! The newest image's cycle info and mode, beside the newest image's word on its cache line
//! (`crate::pins::Pins`), under a sequence count.
//!
//! A busy client that sees the word move has that cache line already. With the record on it,
//! the client learns the cycle and the mode without bringing over the image's header: the
//! header's lines are ones the server has just written, and each costs a line crossing
//! between the CPUs between STARTOP and the client's answer. The client copies the whole
//! header only when an event asks for what only the header has (the OPFAULT record, the mode
//! history), or when the record was being rewritten while it read.
//!
//! The record is written before its image is named, and a reader checks that the cycle it
//! read is the one the word names: a record for the next image, written while the reader
//! read, shows as a count that moved or as another cycle.

use core::sync::atomic::{AtomicU32, AtomicU64, Ordering, fence};

use crate::CycleInfo;

/// What the record holds: the cycle info, the mode and the mode changes of one image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Recorded {
    /// The image's cycle info (`since_cycle_start_ns` is `clock_ns - cycle_start_ns`).
    pub cycle: CycleInfo,
    /// `ImageHeader::mode`.
    pub mode: u32,
    /// `ImageHeader::mode_changes`.
    pub mode_changes: u32,
}

/// The record (`#[repr(C)]`, 40 bytes, in the newest image's line of the handshake block).
#[repr(C)]
#[derive(Debug, Default)]
pub struct CycleRecord {
    /// Odd while the server writes the record.
    sequence: AtomicU32,
    cycle_count: AtomicU32,
    cycle_number: AtomicU64,
    cycle_start_ns: AtomicU64,
    clock_ns: AtomicU64,
    mode: AtomicU32,
    mode_changes: AtomicU32,
}

impl CycleRecord {
    /// Writes the record of the image about to be named (the server, one writer).
    pub fn write(&self, r: &Recorded) {
        let s = self.sequence.load(Ordering::Relaxed);
        self.sequence
            .store(s.wrapping_add(1) | 1, Ordering::Relaxed);
        // The odd count before any field: a reader that sees a new field sees it odd.
        fence(Ordering::Release);
        self.cycle_count
            .store(r.cycle.cycle_count, Ordering::Relaxed);
        self.cycle_number
            .store(r.cycle.cycle_number, Ordering::Relaxed);
        self.cycle_start_ns
            .store(r.cycle.cycle_start_ns, Ordering::Relaxed);
        self.clock_ns.store(r.cycle.clock_ns, Ordering::Relaxed);
        self.mode.store(r.mode, Ordering::Relaxed);
        self.mode_changes.store(r.mode_changes, Ordering::Relaxed);
        self.sequence
            .store((s | 1).wrapping_add(1), Ordering::Release);
    }

    /// The record, if it was whole while read and is that of `cycle` (the low 32 bits of the
    /// cycle number, as the newest word gives them).
    pub fn read(&self, cycle: u32) -> Option<Recorded> {
        let before = self.sequence.load(Ordering::Acquire);
        let (cycle_start_ns, clock_ns) = (
            self.cycle_start_ns.load(Ordering::Relaxed),
            self.clock_ns.load(Ordering::Relaxed),
        );
        let r = Recorded {
            cycle: CycleInfo {
                cycle_number: self.cycle_number.load(Ordering::Relaxed),
                cycle_start_ns,
                clock_ns,
                since_cycle_start_ns: clock_ns.saturating_sub(cycle_start_ns),
                cycle_count: self.cycle_count.load(Ordering::Relaxed),
                reserved: 0,
            },
            mode: self.mode.load(Ordering::Relaxed),
            mode_changes: self.mode_changes.load(Ordering::Relaxed),
        };
        // The fields before the second look at the count.
        fence(Ordering::Acquire);
        let after = self.sequence.load(Ordering::Relaxed);
        let whole = before == after && before & 1 == 0 && before != 0;
        (whole && r.cycle.cycle_number as u32 == cycle).then_some(r)
    }

    /// Marks the record as being written, for a test: reads fail until the next write.
    #[cfg(test)]
    fn begin_write(&self) {
        let s = self.sequence.load(Ordering::Relaxed);
        self.sequence.store(s | 1, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::sync::Arc;
    use std::sync::atomic::AtomicBool;

    fn recorded(k: u64) -> Recorded {
        Recorded {
            cycle: CycleInfo {
                cycle_number: k,
                cycle_start_ns: k * 1_000_000,
                clock_ns: k * 1_000_000 + 3_000,
                since_cycle_start_ns: 3_000,
                cycle_count: (k * 32) as u32 & 0xffff,
                reserved: 0,
            },
            mode: (k % 3) as u32,
            mode_changes: (k / 10) as u32,
        }
    }

    #[test]
    fn a_record_reads_back_for_its_cycle_only_and_not_while_written() {
        let rec = CycleRecord::default();
        assert_eq!(rec.read(0), None, "never written");
        rec.write(&recorded(7));
        assert_eq!(rec.read(7), Some(recorded(7)));
        assert_eq!(rec.read(8), None, "another image's word");
        let big = (1u64 << 32) + 5;
        rec.write(&recorded(big));
        assert_eq!(
            rec.read(5),
            Some(recorded(big)),
            "the word holds 32 bits of the cycle"
        );
        rec.begin_write();
        assert_eq!(rec.read(5), None, "being written");
        rec.write(&recorded(9));
        assert_eq!(rec.read(9), Some(recorded(9)));
    }

    /// A writer rewrites the record as fast as it can; a reader accepts only whole records,
    /// whose fields all follow from one cycle number.
    #[test]
    fn a_reader_never_accepts_a_record_mixed_from_two_writes() {
        let rec = Arc::new(CycleRecord::default());
        let done = Arc::new(AtomicBool::new(false));
        let reader = {
            let (rec, done) = (rec.clone(), done.clone());
            std::thread::spawn(move || {
                let (mut whole, mut refused) = (0u64, 0u64);
                while !done.load(Ordering::Relaxed) {
                    let k = rec.cycle_number.load(Ordering::Relaxed);
                    match rec.read(k as u32) {
                        Some(r) => {
                            assert_eq!(r, recorded(r.cycle.cycle_number), "a mixed record");
                            whole += 1;
                        }
                        None => refused += 1,
                    }
                }
                (whole, refused)
            })
        };
        for k in 1..=200_000u64 {
            rec.write(&recorded(k));
        }
        done.store(true, Ordering::Relaxed);
        let (whole, refused) = reader.join().expect("the reader");
        assert!(whole + refused > 0);
    }
}
