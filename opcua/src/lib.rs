// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimg's process image over OPC UA: an ordinary asynchronous client of procimgd that
//! serves the image, states, alarms and records to the plant, off the real-time path.
//!
//! [`items`] names what is served the way the SIMATIC NET PROFINET IO OPC server names it
//! (`PNIO:[CTRL1]EB10`), so that a client written for that server finds its items.

pub mod items;
