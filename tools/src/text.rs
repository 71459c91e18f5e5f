// SPDX-License-Identifier: MIT OR Apache-2.0
//! Bytes and image spaces as the commands print them.

use procimg_client::Space;

/// `01 ff 10`: bytes in hex, a space between them.
pub(crate) fn hex(b: &[u8]) -> String {
    b.iter()
        .map(|x| format!("{x:02x}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// What the bytes of `space` are, in words: in the device role (`device`) as the PLC sees
/// them, whose Q data is in the image's input space and whose I data in its output space.
pub(crate) fn space_words(device: bool, space: Space) -> &'static str {
    match (device, space) {
        (false, Space::Input) => "inputs",
        (false, Space::Output) => "outputs",
        (true, Space::Input) => "Q data from the PLC",
        (true, Space::Output) => "I data to the PLC",
    }
}
