// SPDX-License-Identifier: MIT OR Apache-2.0
//! The clients' allocations in their measured cycles. The program runs on procimg's
//! real-time allocator ([`procimg_client::rt_alloc::RtAllocator`], as a client program that
//! cares installs it), and the client's thread is marked real-time: what it counts as heap
//! allocations on that thread is what reaches `malloc`. [`counting`] adds up that count
//! around the measured cycles only (after the warm-up), so the figure is the steady-state
//! allocations of a client's cycle: the goal is 0.

use procimg_client::rt_alloc::rt_heap_allocations;
use std::sync::atomic::{AtomicU64, Ordering};

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

/// Runs `f`, adding the heap allocations of real-time threads during it when `on`.
pub fn counting<R>(on: bool, f: impl FnOnce() -> R) -> R {
    let before = rt_heap_allocations();
    let r = f();
    if on {
        ALLOCATIONS.fetch_add(rt_heap_allocations() - before, Ordering::Relaxed);
    }
    r
}

/// Allocations counted so far.
pub fn allocations() -> u64 {
    ALLOCATIONS.load(Ordering::Relaxed)
}
