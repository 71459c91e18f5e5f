// SPDX-License-Identifier: MIT OR Apache-2.0
//! The whole controller: a `Controller` with the cycle thread's IO system and two simulated
//! devices on a simulated network, driven by a sequence of operations (see
//! `procimg_fuzz::world::ops`): time, arbitrary frames and datagrams handed to the
//! controller, arbitrary frames on the wire, corrupted, cut, dropped or repeated device
//! messages, and what clients do. It must never panic, and everything the controller and the
//! devices send must parse.
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_fuzz::world::World;

fuzz_target!(|data: &[u8]| {
    World::new().run(data);
});
