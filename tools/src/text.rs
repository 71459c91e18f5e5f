// SPDX-License-Identifier: MIT OR Apache-2.0
//! Bytes as the commands print them.

/// `01 ff 10`: bytes in hex, a space between them.
pub(crate) fn hex(b: &[u8]) -> String {
    b.iter()
        .map(|x| format!("{x:02x}"))
        .collect::<Vec<_>>()
        .join(" ")
}
