// SPDX-License-Identifier: MIT OR Apache-2.0
//! The C library of procimg (`libprocimg.so`, `libprocimg.a`).
//!
//! Two C interfaces over the Rust client:
//! - [`native`]: the thin native API of `include/procimg.h` (generated from this crate by
//!   cbindgen): attach, the STARTOP/OPDONE handshake with pointers into shared memory,
//!   IO-Base style access by logical address, mode and events, error codes.
//! - [`iobase`]: the IO-Base compatible controller API (`PNIO_*` of `pniousrx.h`,
//!   `pniobase.h`, `pnioerrx.h`) with the manual's names, types and numeric values, so an
//!   IO-Base program builds and runs against procimg unchanged.
//!
//! Nothing panics or unwinds across the C boundary: every exported function runs inside
//! [`ffi::guard`], checks every pointer it is given and reports failures as error codes.

// The whole crate is the C ABI: exported functions take raw pointers from C.
#![allow(unsafe_code)]
pub mod ffi;
pub mod iobase;
pub mod native;

/// The library's Rust code allocates through procimg's real-time allocator: a thread that
/// waits for STARTOP (`procimg_wait_startop`, IO-Base's callback threads) takes iceoryx2's
/// per-sample allocations from a fixed pool instead of `malloc`; other threads are served by
/// the system allocator as before. The C program's own `malloc` is not affected.
#[global_allocator]
static ALLOCATOR: procimg_client::rt_alloc::RtAllocator = procimg_client::rt_alloc::RtAllocator;
