// SPDX-License-Identifier: MIT OR Apache-2.0
//! The simulated device's input handling: frames on its link, datagrams to its address, time
//! and alarms (see `procimg_fuzz::world::device_ops`), seeded with what the controller sent
//! it during a bring-up. It must never panic, and everything it sends must parse.
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_fuzz::world::DeviceBench;

fuzz_target!(|data: &[u8]| {
    DeviceBench::new().run(data);
});
