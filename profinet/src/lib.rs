// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFINET IO, sans-IO: wire formats as checked views over byte buffers plus `Repr`s that
//! parse and emit them, the layout of an IO CR's frame, the acyclic RTA channel, the DCP
//! client and the IO controller's state machines. No socket, no clock, no random source
//! (randomness comes in as a seed): bytes and timestamps in, bytes and actions out. procimgd's cycle thread and acyclic side drive it; tests drive it directly, from
//! real captures (`tests/fixtures/captures`).
#![forbid(unsafe_code)]

pub mod controller;
pub mod dcp_client;
pub mod device_sim;
pub mod iocr_layout;
pub mod rta;
#[cfg(test)]
pub(crate) mod test_fixtures;
pub mod wire;
