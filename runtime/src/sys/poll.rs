// SPDX-License-Identifier: MIT OR Apache-2.0
//! Waiting for a file descriptor with nanosecond timeouts (shared with the clients).

pub use procimg_shm_layout::os::{wait_any_readable, wait_readable};
