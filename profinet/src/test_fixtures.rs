// SPDX-License-Identifier: MIT OR Apache-2.0
//! Test data for the PROFINET unit tests: hex strings and the captured frames in
//! `tests/fixtures/captures` (test data of the `pnio` crate 0.1.0, MIT OR Apache-2.0).

/// Bytes from hex digits; whitespace between them is ignored.
pub(crate) fn hex(s: &str) -> Vec<u8> {
    let digits: String = s.split_whitespace().collect();
    hex::decode(&digits).unwrap_or_else(|e| panic!("hex fixture {s:?}: {e}"))
}

/// The frame of a capture file, e.g. `capture("cm/ident_ok_pnet")`: `#` lines are comments.
pub(crate) fn capture(name: &str) -> Vec<u8> {
    let path = format!(
        "{}/tests/fixtures/captures/{name}.hex",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let digits: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    hex(&digits.join(" "))
}
