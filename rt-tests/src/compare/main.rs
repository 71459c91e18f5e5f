// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimg-compare (being written).

fn main() {}
