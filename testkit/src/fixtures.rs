// SPDX-License-Identifier: MIT OR Apache-2.0
//! Hex test data: byte strings written as hex digits, and captured frames kept as `.hex`
//! files whose `#` lines are comments.

use std::path::Path;

/// Bytes from hex digits; whitespace between them is ignored. Panics, naming the text, on
/// anything else: fixtures are written by hand.
pub fn hex(s: &str) -> Vec<u8> {
    let digits: String = s.split_whitespace().collect();
    hex::decode(&digits).unwrap_or_else(|e| panic!("hex fixture {s:?}: {e}"))
}

/// The frame in capture file `dir/NAME.hex`, e.g. `capture(dir, "cm/ident_ok_pnet")`.
pub fn capture(dir: &Path, name: &str) -> Vec<u8> {
    let path = dir.join(format!("{name}.hex"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let digits: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    hex(&digits.join(" "))
}

/// The capture fixtures of the protocol crate (`profinet/tests/fixtures/captures`; test data
/// of the `pnio` crate 0.1.0, MIT OR Apache-2.0).
pub fn profinet_capture(name: &str) -> Vec<u8> {
    capture(
        &crate::build::workspace_dir().join("profinet/tests/fixtures/captures"),
        name,
    )
}
