// SPDX-License-Identifier: MIT OR Apache-2.0
//! Writing frames to a pcap file that Wireshark and tshark open (link type Ethernet).

use pcap_file::pcap::{PcapPacket, PcapWriter};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Why a capture file could not be written.
#[derive(Debug, thiserror::Error)]
pub enum CaptureError {
    /// The file could not be created or written.
    #[error(
        "cannot write the capture file {path}: {detail}; check the directory exists and is writable"
    )]
    Write {
        /// The file.
        path: PathBuf,
        /// What failed.
        detail: String,
    },
}

/// A pcap file being written.
pub struct CaptureWriter {
    path: PathBuf,
    writer: PcapWriter<BufWriter<File>>,
}

impl CaptureWriter {
    /// Creates (or truncates) `path`.
    pub fn create(path: &Path) -> Result<CaptureWriter, CaptureError> {
        let err = |detail: String| CaptureError::Write {
            path: path.to_path_buf(),
            detail,
        };
        let file = File::create(path).map_err(|e| err(e.to_string()))?;
        let writer = PcapWriter::new(BufWriter::new(file)).map_err(|e| err(e.to_string()))?;
        Ok(CaptureWriter {
            path: path.to_path_buf(),
            writer,
        })
    }

    /// Appends one Ethernet frame (without FCS) seen at `timestamp` (since the Unix epoch).
    pub fn write(&mut self, timestamp: Duration, frame: &[u8]) -> Result<(), CaptureError> {
        let packet = PcapPacket::new(timestamp, frame.len() as u32, frame);
        self.writer
            .write_packet(&packet)
            .map(|_| ())
            .map_err(|e| CaptureError::Write {
                path: self.path.clone(),
                detail: e.to_string(),
            })
    }

    /// Flushes and closes the file.
    pub fn finish(self) -> Result<(), CaptureError> {
        let path = self.path;
        let mut inner = self.writer.into_writer();
        std::io::Write::flush(&mut inner).map_err(|e| CaptureError::Write {
            path,
            detail: e.to_string(),
        })
    }
}
