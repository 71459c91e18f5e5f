// SPDX-License-Identifier: MIT OR Apache-2.0
//! Faulting memory in ahead of the cycle, a little at a time.
//!
//! procimgd locks its memory with `mlockall(MCL_FUTURE | MCL_ONFAULT)` (see
//! [`super::rt::lock_memory`]): a new mapping's pages are locked as they are faulted in, not
//! when it is mapped. Without `MCL_ONFAULT` the kernel populates a whole new mapping inside
//! `mmap`, holding the process's memory-map lock all along: a client's output segment (4 MiB
//! at a 360 KiB image) held it for 2 to 5 ms, and the cycle thread, which maps a few hundred
//! bytes for each client that attaches, waited that long inside its cycle. Here the pages are
//! faulted in with `madvise(MADV_POPULATE_*)` in chunks of [`CHUNK`] bytes, so the lock is
//! held for one chunk at a time, off the cycle thread, before the cycle touches them.

pub use procimg_shm_layout::maps::{Mapping, mapping_of, mappings};
use std::collections::HashSet;

/// Whether the kernel lets `m` be populated: readable, and not the kernel's own pages.
fn populatable(m: &Mapping) -> bool {
    m.readable && !matches!(m.path.as_str(), "[vvar]" | "[vvar_vclock]" | "[vsyscall]")
}

/// Bytes populated per `madvise` call: 16 pages, some tens of microseconds of the lock.
pub const CHUNK: usize = 64 * 1024;

/// The page size `madvise` works in (procimg's targets: x86-64 and 64-bit ARM with 4 KiB
/// pages; a larger page only makes a range round to more than needed).
pub const PAGE: usize = 4096;

/// The first addresses of the process's shared-memory segments, to tell the ones mapped after.
pub fn shared_memory_starts() -> HashSet<usize> {
    mappings()
        .unwrap_or_default()
        .into_iter()
        .filter(Mapping::is_shared_memory)
        .map(|m| m.start)
        .collect()
}

/// Faults in and (the process being locked) locks the pages of `m`, [`CHUNK`] bytes per
/// call. A mapping that goes away meanwhile ends it early, without harm: `madvise` on an
/// address no longer mapped fails, where touching it would crash. Returns the bytes done.
pub fn populate(m: &Mapping) -> usize {
    if !populatable(m) {
        return 0;
    }
    let advice = if m.writable {
        libc::MADV_POPULATE_WRITE
    } else {
        libc::MADV_POPULATE_READ
    };
    let mut done = 0;
    while done < m.len {
        let len = CHUNK.min(m.len - done);
        // SAFETY: MADV_POPULATE_* changes no contents and no mapping: it faults pages in as
        // a read (or write) would. On an address no longer mapped it fails with ENOMEM
        // instead of faulting, so a racing munmap elsewhere is harmless.
        let rc = unsafe { libc::madvise((m.start + done) as *mut libc::c_void, len, advice) };
        if rc != 0 {
            break;
        }
        done += len;
    }
    done
}

/// Populates every mapping of the process but the one at `except` (its first address), if
/// any: what `mlockall(MCL_FUTURE)` without `MCL_ONFAULT` would have done at mapping time,
/// done now, a chunk at a time. Returns the bytes done.
pub fn populate_all(except: Option<usize>) -> usize {
    mappings()
        .unwrap_or_default()
        .iter()
        .filter(|m| Some(m.start) != except)
        .map(populate)
        .sum()
}

/// The shared-memory segments mapped since `before` was taken ([`shared_memory_starts`]).
pub fn shared_memory_since(before: &HashSet<usize>) -> Vec<Mapping> {
    mappings()
        .unwrap_or_default()
        .into_iter()
        .filter(|m| m.is_shared_memory() && !before.contains(&m.start))
        .collect()
}

/// Whether the kernel has `MADV_POPULATE_READ` (Linux 5.14 and later).
pub fn supported() -> bool {
    let page = [0u8; 1];
    let at = (page.as_ptr() as usize) & !4095;
    // SAFETY: populating the page of a live stack variable changes no contents or mapping.
    let rc = unsafe { libc::madvise(at as *mut libc::c_void, 1, libc::MADV_POPULATE_READ) };
    rc == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn populates_a_new_shared_segment_and_nothing_breaks_on_this_process() {
        if !supported() {
            return;
        }
        let before = shared_memory_starts();
        let path = format!("/dev/shm/procimg_populate_test_{}", std::process::id());
        let file = std::fs::File::options()
            .read(true)
            .write(true)
            .create(true)
            .truncate(true)
            .open(&path)
            .expect("a file in /dev/shm");
        let _ = std::fs::remove_file(&path);
        file.set_len(256 * 1024).expect("sized");
        // SAFETY: a fresh shared mapping of a file this test owns, unmapped below.
        let map = unsafe { memmap2::Mmap::map(&file) }.expect("mapped");
        let added = shared_memory_since(&before);
        let done: usize = added.iter().map(populate).sum();
        assert!(done >= map.len(), "populated {done} of {} bytes", map.len());
        assert!(populate_all(None) > 0);
        drop(map);
    }
}
