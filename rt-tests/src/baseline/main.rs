// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimg-baseline (being written).

fn main() {}
