// SPDX-License-Identifier: MIT OR Apache-2.0
//! The client-side caches of IO-Base's buffered access, and the shadow of the outputs this
//! client writes.
//!
//! The write cache keeps every output byte this client wrote, so that partial (slice) writes
//! accumulate: each sample sent carries whole submodules from it, never stale bytes. Flushing
//! sends every dirty submodule in one sample, which the server applies in one cycle.

use crate::layout::Layout;
use crate::status::Ioxs;

/// A copy of the input image taken by `data_read_cache_refresh`.
pub struct ReadCache {
    /// The whole input-image payload at refresh time.
    pub payload: Vec<u8>,
}

/// Outputs written by this client, and local statuses not yet sent.
pub struct WriteCache {
    /// Output data region (same offsets as an output sample).
    pub data: Vec<u8>,
    /// Per submodule: `data` holds this submodule's current outputs.
    pub valid: Vec<bool>,
    /// Per submodule: written since the last send.
    pub dirty: Vec<bool>,
    /// Per submodule: the output IOPS to send.
    pub output_iops: Vec<Ioxs>,
    /// Per submodule: a local input status (IOCS) to send.
    pub input_iocs: Vec<Option<Ioxs>>,
}

impl WriteCache {
    /// An empty cache for `layout`.
    pub fn new(layout: &Layout) -> WriteCache {
        let n = layout.submodules.len();
        WriteCache {
            data: vec![0; layout.header.output_size as usize],
            valid: vec![false; n],
            dirty: vec![false; n],
            output_iops: vec![Ioxs::Good; n],
            input_iocs: vec![None; n],
        }
    }

    /// Whether anything waits to be sent.
    pub fn pending(&self) -> bool {
        self.dirty.iter().any(|&d| d) || self.input_iocs.iter().any(Option::is_some)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_shm_layout::{LayoutHeader, SubmoduleEntry};

    #[test]
    fn a_new_cache_fits_the_layout_and_waits_for_nothing_until_written() {
        let layout = Layout {
            header: LayoutHeader {
                output_size: 6,
                ..LayoutHeader::default()
            },
            devices: Vec::new(),
            submodules: vec![SubmoduleEntry::EMPTY; 2],
        };
        let mut c = WriteCache::new(&layout);
        assert_eq!(c.data.len(), 6);
        assert_eq!(c.output_iops, vec![Ioxs::Good; 2]);
        assert!(!c.pending());
        c.dirty[1] = true;
        assert!(c.pending(), "a written submodule waits");
        c.dirty[1] = false;
        c.input_iocs[0] = Some(Ioxs::Bad);
        assert!(c.pending(), "a local input status waits too");
    }
}
