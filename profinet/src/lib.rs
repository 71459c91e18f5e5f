// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFINET IO, sans-IO: wire formats as checked views over byte buffers plus `Repr`s that
//! parse and emit them, the layout of an IO CR's frame, the acyclic RTA channel and the DCP
//! client. No socket, no clock, no random source: bytes and timestamps in, bytes and actions
//! out. procimgd's cycle thread and acyclic side drive it; tests drive it directly, from
//! real captures (`tests/fixtures/captures`).
#![forbid(unsafe_code)]

pub mod dcp_client;
pub mod iocr_layout;
pub mod rta;
#[cfg(test)]
pub(crate) mod test_fixtures;
pub mod wire;
