// SPDX-License-Identifier: MIT OR Apache-2.0
//! Files tests write: pcap captures of frames, and scratch directories of their own.

use pcap_file::TsResolution;
use pcap_file::pcap::{PcapHeader, PcapPacket, PcapWriter};
use std::time::Duration;
pub use tempfile::TempDir;

/// A pcap file (nanosecond timestamps) of `frames`, each `(timestamp in ns, frame)`.
pub fn pcap(frames: &[(u64, Vec<u8>)]) -> Vec<u8> {
    let header = PcapHeader {
        ts_resolution: TsResolution::NanoSecond,
        ..PcapHeader::default()
    };
    let mut w = PcapWriter::with_header(Vec::new(), header).expect("a pcap header fits a Vec");
    for (ts, f) in frames {
        // A test's frames are Ethernet frames: far below 4 GiB.
        let len = f.len() as u32;
        w.write_packet(&PcapPacket::new(Duration::from_nanos(*ts), len, f))
            .expect("a frame fits a Vec");
    }
    w.into_writer()
}

/// A fresh, empty directory for the files of test `name`, removed with all it holds when
/// the returned guard drops, whether the test passed or failed.
pub fn temp_dir(name: &str) -> TempDir {
    tempfile::Builder::new()
        .prefix(&format!("procimg-{name}-"))
        .tempdir()
        .unwrap_or_else(|e| panic!("cannot create a directory for test {name}: {e}"))
}
