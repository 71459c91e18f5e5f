// SPDX-License-Identifier: MIT OR Apache-2.0
//! The runtime's transport beside the network interfaces of `procimg-nic`: UDP for the
//! PROFINET connection services, which only the acyclic side and the simulated plant use.

pub mod datagram;
