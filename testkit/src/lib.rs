// SPDX-License-Identifier: MIT OR Apache-2.0
//! What procimg's tests, benches and interop tests share, once: the real `procimgd` as a
//! child process that is stopped even when a test fails ([`Procimgd`]), unique instance
//! names, the workspace's binaries built up to date, two network namespaces joined by a veth
//! pair ([`netns::TestNet`]), data both ways between procimg's two roles ([`exchange`]),
//! Wireshark's verdict on frames ([`tshark::dissect_clean`]), C and C++ programs built
//! against `libprocimg` ([`c`]), hex fixtures, and the deterministic in-memory PROFINET
//! network of a controller and simulated devices ([`world`]).
//!
//! Dev-only (`publish = false`): no production crate depends on it.

pub mod build;
pub mod c;
pub mod exchange;
pub mod files;
pub mod fixtures;
pub mod memory;
/// Network namespaces with a veth pair (the `procimg-netns` crate, which the soak shares).
pub use procimg_netns::netns;
pub mod pattern;
mod procimgd;
pub mod pypi;
/// Signals to child processes (the `procimg-netns` crate).
pub use procimg_netns::signal;
pub mod snmpd;
pub mod tshark;
pub mod udp;
pub mod veth_station;
pub mod world;

pub use build::{procimg_in_netns, procimgd_bin, profile_dir, workspace_bin, workspace_dir};
pub use pattern::{pattern, pattern_value};
pub use procimgd::{Launch, Procimgd, unique_instance};
