// SPDX-License-Identifier: MIT OR Apache-2.0
//! A word on a cache line of its own, for the handshake block's words.

/// One cache line, so that words written by different sides never share a line.
#[repr(C, align(64))]
#[derive(Debug, Default)]
pub struct Line<T>(pub T);
