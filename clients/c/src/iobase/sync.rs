// SPDX-License-Identifier: MIT OR Apache-2.0
//! Locking as the library does it everywhere.

use std::sync::{Mutex, MutexGuard};

/// Locks a mutex; a panic elsewhere (caught at the boundary) does not make every later
/// call fail.
pub(crate) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}
