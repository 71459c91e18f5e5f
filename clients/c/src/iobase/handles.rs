// SPDX-License-Identifier: MIT OR Apache-2.0
//! The one counter that numbers controller and device handles: the functions both take
//! (`PNIO_CP_register_cbf`, `PNIO_CP_set_opdone`) find a handle's kind by which table holds
//! it, so the two never share a number. Handles are never reused.

use std::sync::atomic::{AtomicU32, Ordering};

static NEXT: AtomicU32 = AtomicU32::new(1);

/// A handle no controller or device of this process had before.
pub(crate) fn next() -> u32 {
    NEXT.fetch_add(1, Ordering::Relaxed)
}
