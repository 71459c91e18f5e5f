// SPDX-License-Identifier: MIT OR Apache-2.0
//! A global allocator that keeps real-time threads off the heap: procimgd's cycle thread and a
//! client's cycle loop.
//!
//! iceoryx2 0.10 boxes a reference count for every sample it loans (48 bytes in the server's
//! single-threaded service variant, 104 with the mutex of the clients' thread-safe one); a cycle
//! publishes one input sample (the server) or sends one output sample (a client), so either
//! would call `malloc` once per cycle. On
//! threads marked real-time ([`mark_current_thread_realtime`]) this allocator serves small
//! allocations from a fixed pool in static memory, with a lock-free bitmap, so the cycle
//! never enters the system allocator (its locks, its page faults). Anything the pool cannot
//! serve goes to the system allocator and is counted: [`rt_heap_allocations`] is what the
//! allocation test and `procimg status` report, and it stays 0 in steady state.
//!
//! Install it in a binary with `#[global_allocator] static A: RtAllocator = RtAllocator;`.
//! A client program that does gets a cycle loop without `malloc` once its thread is marked,
//! which `procimg_client::realtime::make_current_thread_realtime` does.
//!
//! A crate of its own because both sides of the shared memory install it: procimgd and the
//! client library (and through it the C library).
// A global allocator hands out raw memory: unsafe by nature, each block says why it holds.
#![allow(unsafe_code)]

use core::alloc::{GlobalAlloc, Layout};
use core::cell::Cell;
use core::sync::atomic::{AtomicU64, Ordering};
use std::alloc::System;

/// Bytes of one pool block (and its alignment): the largest of iceoryx2's per-loan boxes fits.
const BLOCK: usize = 128;
/// Words of the free bitmap; the pool holds 64 blocks per word.
const WORDS: usize = 4;
const BLOCKS: usize = WORDS * 64;

#[repr(C, align(128))]
struct Pool([u8; BLOCK * BLOCKS]);

struct PoolCell(core::cell::UnsafeCell<Pool>);
// SAFETY: blocks are handed out to one owner at a time through the atomic bitmap below; the
// pool's bytes are never accessed through the cell except via those exclusive blocks.
unsafe impl Sync for PoolCell {}

static POOL: PoolCell = PoolCell(core::cell::UnsafeCell::new(Pool([0; BLOCK * BLOCKS])));
/// Bit set = block in use.
static USED: [AtomicU64; WORDS] = [const { AtomicU64::new(0) }; WORDS];
static RT_HEAP_ALLOCATIONS: AtomicU64 = AtomicU64::new(0);
static RT_SETUP_ALLOCATIONS: AtomicU64 = AtomicU64::new(0);
static POOL_ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

std::thread_local! {
    static REALTIME: Cell<bool> = const { Cell::new(false) };
    static SETTING_UP: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f` on a real-time thread as a call that may set up connections (iceoryx2's port
/// calls do, when clients come or go): its heap allocations are counted apart
/// ([`rt_setup_allocations`]), since setting up a client's shared-memory connection
/// allocates by nature. In steady state such calls do not allocate either.
pub fn as_connection_setup<R>(f: impl FnOnce() -> R) -> R {
    SETTING_UP.with(|s| s.set(true));
    let r = f();
    SETTING_UP.with(|s| s.set(false));
    r
}

/// Marks the calling thread as real-time: from now on its small allocations come from the
/// pool, and its heap allocations are counted.
pub fn mark_current_thread_realtime() {
    REALTIME.with(|r| r.set(true));
}

/// Ends the real-time marking of the calling thread.
pub fn clear_current_thread_realtime() {
    REALTIME.with(|r| r.set(false));
}

/// Heap (system allocator) allocations made by real-time threads since start, outside
/// connection set-up: the figure that must stay 0.
pub fn rt_heap_allocations() -> u64 {
    RT_HEAP_ALLOCATIONS.load(Ordering::Relaxed)
}

/// Heap allocations made by real-time threads inside [`as_connection_setup`].
pub fn rt_setup_allocations() -> u64 {
    RT_SETUP_ALLOCATIONS.load(Ordering::Relaxed)
}

/// Allocations served from the pool since start.
pub fn pool_allocations() -> u64 {
    POOL_ALLOCATIONS.load(Ordering::Relaxed)
}

fn pool_base() -> usize {
    POOL.0.get() as usize
}

fn in_pool(ptr: *mut u8) -> Option<usize> {
    let p = ptr as usize;
    let base = pool_base();
    (p >= base && p < base + BLOCK * BLOCKS).then(|| (p - base) / BLOCK)
}

fn take_block() -> Option<usize> {
    for (w, word) in USED.iter().enumerate() {
        let mut cur = word.load(Ordering::Relaxed);
        while cur != u64::MAX {
            let bit = (!cur).trailing_zeros() as usize;
            match word.compare_exchange_weak(
                cur,
                cur | (1 << bit),
                Ordering::Acquire,
                Ordering::Relaxed,
            ) {
                Ok(_) => return Some(w * 64 + bit),
                Err(now) => cur = now,
            }
        }
    }
    None
}

fn is_realtime() -> bool {
    // `try_with` so that allocations during thread teardown do not panic.
    REALTIME.try_with(|r| r.get()).unwrap_or(false)
}

/// The allocator. See the module documentation.
pub struct RtAllocator;

// SAFETY: every pointer returned is either from `System` (with the caller's layout) or a
// distinct BLOCK-byte, BLOCK-aligned pool block owned exclusively until `dealloc` clears its bit;
// `dealloc` routes each pointer back to where it came from by its address.
unsafe impl GlobalAlloc for RtAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if is_realtime() {
            if layout.size() <= BLOCK
                && layout.align() <= BLOCK
                && let Some(i) = take_block()
            {
                POOL_ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
                return (pool_base() + i * BLOCK) as *mut u8;
            }
            if SETTING_UP.try_with(|s| s.get()).unwrap_or(false) {
                RT_SETUP_ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
            } else {
                RT_HEAP_ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
            }
        }
        // SAFETY: forwarded with the caller's valid layout.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        if let Some(i) = in_pool(ptr) {
            USED[i / 64].fetch_and(!(1u64 << (i % 64)), Ordering::Release);
            return;
        }
        // SAFETY: not a pool block, so it came from `System.alloc` with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if in_pool(ptr).is_none() && !is_realtime() {
            // SAFETY: a system allocation, resized by the system allocator.
            return unsafe { System.realloc(ptr, layout, new_size) };
        }
        // SAFETY: the new layout has the old alignment and a non-zero size per the
        // GlobalAlloc contract; we copy the smaller of the two sizes and free the old block.
        unsafe {
            let new_layout = Layout::from_size_align_unchecked(new_size, layout.align());
            let new = self.alloc(new_layout);
            if !new.is_null() {
                core::ptr::copy_nonoverlapping(ptr, new, layout.size().min(new_size));
                self.dealloc(ptr, layout);
            }
            new
        }
    }
}
