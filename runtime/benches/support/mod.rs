// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the cycle benchmarks share: configurations of a given shape, a null IO system, a
//! network interface that plays the devices' side of the cyclic exchange, the rig that puts
//! an engine together with clients, and the check that nothing is left in shared memory.
// Each bench target uses a different part of this module.
#![allow(dead_code)]

pub mod cases;
pub mod leftovers;
pub mod loop_nic;
pub mod null_io;
pub mod rig;
pub mod shape;
