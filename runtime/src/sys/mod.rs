// SPDX-License-Identifier: MIT OR Apache-2.0
//! The operating-system calls of the server: clocks, real-time scheduling, memory locking,
//! the device role's interface address and UDP socket.
//! The only place in the crate besides the shared-memory services where `unsafe` may appear.
pub mod clock;
pub mod doorbell;
pub mod netlink;
pub mod poll;
pub mod populate;
pub mod port_state;
pub mod random;
pub mod rt;
pub mod start_up_code;
/// The allocator of real-time threads, shared with the clients.
pub use procimg_rt_alloc as rt_alloc;
pub mod udp;
