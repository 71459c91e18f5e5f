// SPDX-License-Identifier: MIT OR Apache-2.0
//! The TOML configuration (`config::parse`, the validation behind it, and what is built from
//! a valid configuration: the image tables and the controller's device plans) and durations.
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_runtime::config::{self, format_duration, parse_duration};
use procimg_runtime::image::Tables;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    match config::parse(&text, "fuzz.toml") {
        Ok(c) => {
            let _ = c.submodule_count();
            if let Ok(t) = Tables::from_config(&c) {
                assert_eq!(t.submodules.len(), c.submodule_count());
            }
            let _ = procimg_runtime::roles::controller::plan_devices(&c);
            // What the configuration said, written back, reads the same.
            assert_eq!(parse_duration(&format_duration(c.cycle_ns)), Ok(c.cycle_ns));
        }
        Err(e) => {
            // Every error can be shown, with its place.
            let _ = (e.to_string(), e.line(), e.key(), e.origin(), e.message());
        }
    }
    // Durations: each line as one, and any u64 from the input formatted and read back.
    for line in text.lines().take(64) {
        if let Ok(ns) = parse_duration(line) {
            assert_eq!(parse_duration(&format_duration(ns)), Ok(ns));
        }
    }
    if let Some(b) = data.get(..8) {
        let ns = u64::from_be_bytes(b.try_into().expect("8 bytes"));
        assert_eq!(parse_duration(&format_duration(ns)), Ok(ns));
    }
});
