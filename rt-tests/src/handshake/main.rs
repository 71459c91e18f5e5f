// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimg-handshake (being written).

fn main() {}
