// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFINET IO, sans-IO: wire formats as checked views over byte buffers plus `Repr`s that
//! parse and emit them. No socket, no clock: bytes in, bytes out; the cycle thread and the
//! acyclic side drive it, tests drive it directly from real captures.

// The protocol crate's modules, where the runtime's code has always found them.
pub use procimg_profinet::{controller, dcp_client, device_sim, iocr_layout, rta, wire};
