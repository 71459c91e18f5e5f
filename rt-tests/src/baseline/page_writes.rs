// SPDX-License-Identifier: MIT OR Apache-2.0
//! What a write costs to a page that has lain unwritten for a while: one thread, asleep
//! between writes as procimgd's cycle thread is, writes one byte each period, rotating over
//! N pages, so that each page is written again only every N periods. The pages are
//! resident and written once before the clock runs.
//!
//! On bare metal every write takes the same few nanoseconds. A virtual machine's host may
//! make a guest page's first write after some time fault in the host (dirty-page tracking,
//! reclaim), invisible to the guest's own tracing: then the cost grows with N, and a cycle
//! that writes pages it wrote long ago meets it that much more often.

use hdrhistogram::Histogram;
use procimg_rt_tests::report::{HIGHEST_NS, new_histogram};
use procimg_runtime::sys::clock::{now_ns, sleep_until_ns};
use std::hint::black_box;

const PAGE: usize = 4096;

/// The measurement's name for `pages` (as the report names it).
pub fn name(pages: usize) -> String {
    format!("page write, {pages} pages")
}

/// Times `loops` writes, one every `period_ns`, rotating over `pages` pages.
pub fn measure(pages: usize, loops: u64, period_ns: u64) -> Histogram<u64> {
    let pages = pages.max(1);
    let mut memory = vec![0u8; (pages + 1) * PAGE];
    // Page-aligned start, so that each write lands on a page of its own.
    let start = memory.as_ptr().align_offset(PAGE);
    let area = &mut memory[start..start + pages * PAGE];
    // Resident and written once: what follows measures rewrites, not first faults.
    area.iter_mut().step_by(PAGE).for_each(|b| *b = 1);
    let mut h = new_histogram();
    let mut tick = now_ns();
    for i in 0..loops {
        tick += period_ns;
        sleep_until_ns(tick);
        let page = (i % pages as u64) as usize;
        // A different line of the page each round: a line never stays hot in the caches.
        let line = ((i / pages as u64) % (PAGE as u64 / 64)) as usize;
        let t0 = now_ns();
        area[page * PAGE + line * 64] = black_box(i as u8);
        let took = now_ns().saturating_sub(t0);
        h.saturating_record(took.clamp(1, HIGHEST_NS));
    }
    black_box(&memory);
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_write_is_timed() {
        let h = measure(4, 20, 10_000);
        assert_eq!(h.len(), 20);
        assert_eq!(name(256), "page write, 256 pages");
    }
}
