// SPDX-License-Identifier: MIT OR Apache-2.0
//! What a run on a real network stack needs around procimg, for the tests (through
//! `procimg-testkit`, which re-exports it) and the soak run of `procimg-rt-tests` alike: two
//! network namespaces joined by a veth pair, removed when dropped ([`netns::TestNet`]), and
//! signals to child processes, with a stop that waits and then kills ([`signal`]).
//!
//! A normal dependency of `procimg-rt-tests` (the soak binary builds its network with it),
//! so it holds no test-only code: no process of procimg's, no fixture, no tshark.

pub mod netns;
// Signals, the effective user and setns(2) are system calls.
#[allow(unsafe_code)]
pub mod signal;
