// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device's user records: which ones it accepts and which go to its application
//! ([`super::params`]), and the calls that wait for the application's answers
//! ([`super::delegated_records`]). [`Device::records`](super::Device::records) gives the
//! read-only view.

use super::delegated_records::Waiting;
use super::params::ParameterRecords;

/// Which user records the device takes, and the calls waiting for its application.
#[derive(Default)]
pub struct Records {
    /// Which user records are accepted, and which the application answers.
    pub(super) params: ParameterRecords,
    /// Calls waiting for the application's record answers.
    pub(super) waiting: Waiting,
}

impl Records {
    /// Record jobs the application did not answer in time, so far.
    pub fn timeouts(&self) -> u64 {
        self.waiting.timeouts
    }
}
