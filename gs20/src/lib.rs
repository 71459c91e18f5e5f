// SPDX-License-Identifier: MIT OR Apache-2.0
//! The GS20-PN host protocol, sans-IO.
//!
//! placeholder
#![forbid(unsafe_code)]

pub mod frame;
pub mod messages;
pub mod stream;
