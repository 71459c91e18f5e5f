// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device's log book (LogBookData, record 0xF830): what happened to its ARs, newest
//! last, the oldest forgotten beyond [`LOG_BOOK_ENTRIES`]. Each entry carries the AR, a
//! PNIOStatus and an EntryDetail saying what happened ([`detail`]); the time stamps are
//! the device's clock, in ns.

use crate::wire::record::{LogBookData, LogEntry};
use crate::wire::{PnioStatus, Uuid};
use std::collections::VecDeque;

/// Entries kept.
pub const LOG_BOOK_ENTRIES: usize = 64;

/// EntryDetail values: what happened (manufacturer-specific, the standard leaves it to the
/// device).
pub mod detail {
    /// An IO AR was established (status OK).
    pub const AR_ESTABLISHED: u32 = 1;
    /// An IO AR was released by its controller (status OK).
    pub const AR_RELEASED: u32 = 2;
    /// An AR was aborted: the status is the ERR-RTA's (`CF 81 FD <reason>`).
    pub const AR_ABORTED: u32 = 3;
    /// A Connect was refused: the status is the refusal.
    pub const CONNECT_REFUSED: u32 = 4;
    /// A device access AR was established (status OK).
    pub const ACCESS_AR_ESTABLISHED: u32 = 5;
    /// A device access AR ended: released (status OK) or timed out (`CF 81 FD 0x0A`).
    pub const ACCESS_AR_ENDED: u32 = 6;
}

/// The log book.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LogBook {
    entries: VecDeque<LogEntry>,
}

impl LogBook {
    /// Notes what happened at `now_ns` to AR `ar_uuid`.
    pub fn note(&mut self, now_ns: u64, ar_uuid: Uuid, status: PnioStatus, detail: u32) {
        if self.entries.len() == LOG_BOOK_ENTRIES {
            self.entries.pop_front();
        }
        self.entries.push_back(LogEntry {
            time_stamp: now_ns,
            ar_uuid,
            status,
            detail,
        });
    }

    /// The entries, oldest first.
    pub fn entries(&self) -> impl Iterator<Item = &LogEntry> {
        self.entries.iter()
    }

    /// The record at `now_ns`.
    pub fn record(&self, now_ns: u64) -> LogBookData {
        LogBookData {
            now: now_ns,
            entries: self.entries.iter().copied().collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_oldest_entries_go() {
        let mut l = LogBook::default();
        for i in 0..LOG_BOOK_ENTRIES as u64 + 3 {
            l.note(i, Uuid([0; 16]), PnioStatus::OK, detail::AR_ESTABLISHED);
        }
        let r = l.record(1_000);
        assert_eq!(r.entries.len(), LOG_BOOK_ENTRIES);
        assert_eq!(r.entries[0].time_stamp, 3);
        assert_eq!(r.now, 1_000);
    }
}
