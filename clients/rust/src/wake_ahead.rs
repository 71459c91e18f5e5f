// SPDX-License-Identifier: MIT OR Apache-2.0
//! When a sleeping client wakes ahead of STARTOP and polls for it.
//!
//! procimgd's cycle k+1 starts at `cycle_start(k) + cycle_ns`, and its STARTOP came, in
//! cycle k, `since_cycle_start(k)` after its start: the next one is expected as far after
//! the next start. The client sleeps until `lead` before that, then polls until `2·lead`
//! after it; a STARTOP later than that finds it asleep again, as without waking ahead.

use procimg_shm_layout::ImageHeader;

/// The part of the cycle in which a client polls for the next STARTOP, in
/// `CLOCK_MONOTONIC` ns: from `start`, until `end`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct PollWindow {
    pub start: u64,
    pub end: u64,
}

/// How many cycles past the image a client holds the block's newest word may name, for the
/// window to follow it; further apart, the word is not trusted (it is a hint).
const NAMED_AHEAD_MAX: u32 = 1024;

/// The window before and around the STARTOP that follows the image `held` (the newest the
/// client took), or, when the block already names a newer image (`named`: its cycle number
/// as the block's word holds it, modulo 2^32), the STARTOP after that one. `None` when there
/// is none to poll in: waking ahead is off (`lead_ns` zero), the header carries no cycle
/// time, or the window is over at `now_ns` (the server is late: the client sleeps until it
/// signals). The lead is at most an eighth of the cycle.
pub(crate) fn poll_window(
    held: &ImageHeader,
    named: Option<u32>,
    lead_ns: u64,
    now_ns: u64,
) -> Option<PollWindow> {
    let cycle_ns = held.cycle_ns;
    let lead = lead_ns.min(cycle_ns / 8);
    if lead == 0 {
        return None;
    }
    // A client that looks before it takes the image STARTOP announced (the IO-Base callback
    // thread does) would otherwise poll through that cycle's window once more.
    let ahead = named
        .map(|k| k.wrapping_sub(held.cycle.cycle_number as u32))
        .filter(|&d| d <= NAMED_AHEAD_MAX)
        .unwrap_or(0);
    let phase = held.cycle.since_cycle_start_ns.min(cycle_ns / 2);
    let expected = cycle_ns
        .checked_mul(u64::from(ahead) + 1)?
        .checked_add(held.cycle.cycle_start_ns)?
        .checked_add(phase)?;
    let window = PollWindow {
        start: expected.saturating_sub(lead),
        end: expected.checked_add(2 * lead)?,
    };
    (now_ns < window.end).then_some(window)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(cycle_start_ns: u64, since_start_ns: u64, cycle_ns: u64) -> ImageHeader {
        let mut h = ImageHeader::default();
        h.cycle.cycle_start_ns = cycle_start_ns;
        h.cycle.since_cycle_start_ns = since_start_ns;
        h.cycle_ns = cycle_ns;
        h
    }

    #[test]
    fn the_window_is_around_where_the_next_startop_is_expected() {
        // Cycle k started at 10 ms, STARTOP 15 µs later; 1 ms cycle, 30 µs lead.
        let h = header(10_000_000, 15_000, 1_000_000);
        let w = poll_window(&h, None, 30_000, 10_020_000).unwrap();
        assert_eq!(w.start, 11_015_000 - 30_000);
        assert_eq!(w.end, 11_015_000 + 60_000);
    }

    #[test]
    fn no_window_when_waking_ahead_is_off_or_over_or_the_cycle_unknown() {
        let h = header(10_000_000, 15_000, 1_000_000);
        assert_eq!(poll_window(&h, None, 0, 10_020_000), None);
        assert_eq!(poll_window(&h, None, 30_000, 11_075_000), None);
        assert_eq!(
            poll_window(&header(10_000_000, 15_000, 0), None, 30_000, 0),
            None
        );
    }

    #[test]
    fn the_lead_is_at_most_an_eighth_of_the_cycle() {
        let h = header(0, 0, 125_000);
        let w = poll_window(&h, None, 30_000, 0).unwrap();
        assert_eq!((w.start, w.end), (125_000 - 15_625, 125_000 + 31_250));
    }

    #[test]
    fn a_late_startop_does_not_push_the_window_past_half_a_cycle() {
        let h = header(0, 900_000, 1_000_000);
        let w = poll_window(&h, None, 30_000, 0).unwrap();
        assert_eq!(w.start, 1_500_000 - 30_000);
    }

    #[test]
    fn a_newer_image_named_already_moves_the_window_to_the_cycle_after_it() {
        let mut h = header(10_000_000, 15_000, 1_000_000);
        h.cycle.cycle_number = 10;
        let held = poll_window(&h, Some(10), 30_000, 0).unwrap();
        assert_eq!(held.start, 11_015_000 - 30_000);
        let next = poll_window(&h, Some(11), 30_000, 0).unwrap();
        assert_eq!(next.start, 12_015_000 - 30_000);
        // Across the word's wrap, and a word too far ahead (not trusted).
        h.cycle.cycle_number = u64::from(u32::MAX);
        let wrapped = poll_window(&h, Some(0), 30_000, 0).unwrap();
        assert_eq!(wrapped.start, 12_015_000 - 30_000);
        assert_eq!(poll_window(&h, Some(5000), 30_000, 0), Some(held));
    }

    #[test]
    fn clocks_near_the_end_of_time_give_no_window() {
        let h = header(u64::MAX - 10, 0, 1_000_000);
        assert_eq!(poll_window(&h, None, 30_000, 0), None);
    }
}
