// SPDX-License-Identifier: MIT OR Apache-2.0
//! What procimg's latency tools share: one JSON report format, histograms with the same
//! bounds everywhere, HdrHistogram log files, and a description of the machine.
//!
//! Every tool (`procimg-cyclictest`, `procimg-handshake`, `procimg-baseline`) measures into
//! [`report::new_histogram`] histograms and writes a [`report::Report`]; `procimg-compare`
//! reads them back, puts each figure beside its baseline and draws the plots.

pub mod cyclictest_json;
pub mod names;
pub mod report;
