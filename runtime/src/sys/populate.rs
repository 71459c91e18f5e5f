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
use std::sync::atomic::{AtomicBool, Ordering};

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
/// done now, a chunk at a time. When the process locks as used
/// ([`set_locked_as_used`]), code and read-only data of files are only read ahead
/// into the page cache, and threads' stacks are left alone: both are locked when first
/// used (the cycle thread's stack is faulted in by `sys::rt::prefault_stack`). Returns the
/// bytes populated.
pub fn populate_all(except: Option<usize>) -> usize {
    let as_used = locked_as_used();
    let maps = mappings().unwrap_or_default();
    let mut below: Option<&Mapping> = None;
    let mut done = 0;
    for m in &maps {
        let stack = below.is_some_and(|b| is_thread_stack(b, m));
        below = Some(m);
        if Some(m.start) == except || (as_used && stack) {
            continue;
        }
        if as_used && is_code_or_read_only_data(m) {
            read_ahead(m);
        } else {
            done += populate(m);
        }
    }
    done
}

/// Whether the process locks code and threads' stacks as they are used: set by
/// `sys::rt::lock_memory`, a property of the whole process, as the locking is.
static AS_USED: AtomicBool = AtomicBool::new(false);

/// Says whether the process locks the code and read-only data of files, and threads'
/// stacks, as they are used (`mlockall` with `MCL_ONFAULT` for what is mapped now), so
/// that [`populate_all`] leaves them alone.
pub fn set_locked_as_used(as_used: bool) {
    AS_USED.store(as_used, Ordering::Relaxed);
}

/// Whether the process locks code and threads' stacks as they are used.
pub(crate) fn locked_as_used() -> bool {
    AS_USED.load(Ordering::Relaxed)
}

/// A read-only mapping of a file that is not shared memory: a program's or library's code
/// or read-only data. (A subscriber's view of another process's shared memory is read-only
/// too, and is populated.)
pub(crate) fn is_code_or_read_only_data(m: &Mapping) -> bool {
    !m.writable && m.path.starts_with('/') && !m.is_shared_memory()
}

/// Whether `m` is a thread's stack, `below` the mapping just under it: anonymous memory
/// right above an inaccessible guard, as glibc maps a thread's stack. (Its heap keeps no
/// guard below memory; the main thread's stack is `[stack]`.) Anonymous memory that the
/// kernel merged into a stack mapping would be taken for stack and locked only as used;
/// since Linux 6.7 a `MAP_STACK` mapping carries `VM_NOHUGEPAGE`, which ordinary anonymous
/// memory lacks, so the kernel keeps the two apart.
fn is_thread_stack(below: &Mapping, m: &Mapping) -> bool {
    let anonymous = |m: &Mapping| m.path.is_empty();
    below.start + below.len == m.start
        && anonymous(below)
        && !below.readable
        && !below.writable
        && anonymous(m)
        && m.readable
        && m.writable
}

/// Makes every later page fault on the code and read-only data of the program and its
/// libraries map that one page, not the 16 around it that the kernel maps by default
/// (`MADV_RANDOM` turns its fault-around off): with the code locked as used
/// (`sys::rt::lock_memory`), the pages around would be locked too. Call it first thing
/// in `main`. (A kernel that keeps the file in large folios still maps a whole folio per
/// fault.)
pub fn fault_code_page_by_page() {
    for m in mappings()
        .unwrap_or_default()
        .iter()
        .filter(|m| is_code_or_read_only_data(m))
    {
        // SAFETY: MADV_RANDOM only changes how the kernel reads ahead and faults around in
        // the mapping; it changes no contents and no mapping.
        unsafe { libc::madvise(m.start as *mut libc::c_void, m.len, libc::MADV_RANDOM) };
    }
}

/// Asks the kernel to read `m`'s file into the page cache, without mapping or locking it.
fn read_ahead(m: &Mapping) {
    // SAFETY: MADV_WILLNEED on a file mapping only starts readahead into the page cache; it
    // changes no contents and no mapping, and fails harmlessly on an address unmapped meanwhile.
    unsafe { libc::madvise(m.start as *mut libc::c_void, m.len, libc::MADV_WILLNEED) };
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
    fn code_and_read_only_data_of_files_are_told_from_what_the_cycle_writes_or_shares() {
        let kind = |line: &str| is_code_or_read_only_data(&Mapping::parse(line).unwrap());
        let code = "5581e2a00000-5581e3200000 r-xp 00200000 fd:01 1234 /usr/bin/procimgd";
        let rodata = "7f1c2a000000-7f1c2a100000 r--p 00000000 fd:01 99 /usr/lib/libc.so.6";
        let data = "5581e3400000-5581e3410000 rw-p 00a00000 fd:01 1234 /usr/bin/procimgd";
        let heap = "5581e4000000-5581e4200000 rw-p 00000000 00:00 0 [heap]";
        let stack = "7f1c28000000-7f1c28100000 rw-p 00000000 00:00 0 ";
        let seen = "7f1c26000000-7f1c26400000 r--s 00000000 00:19 77 /dev/shm/procimg_x";
        assert!(kind(code) && kind(rodata));
        assert!(!kind(data) && !kind(heap) && !kind(stack) && !kind(seen));
    }

    #[test]
    fn a_thread_stack_is_anonymous_memory_right_above_a_guard() {
        let m = |line: &str| Mapping::parse(line).unwrap();
        let guard = m("7f4f5c77c000-7f4f5c77d000 ---p 00000000 00:00 0 ");
        let stack = m("7f4f5c77d000-7f4f5c87d000 rw-p 00000000 00:00 0 ");
        let apart = m("7f4f5c77e000-7f4f5c87d000 rw-p 00000000 00:00 0 ");
        let heap = m("7f4f5c77d000-7f4f5c87d000 rw-p 00000000 00:00 0 [heap]");
        let code = m("7f4f5c770000-7f4f5c77d000 r-xp 00000000 fd:01 9 /usr/bin/procimgd");
        assert!(is_thread_stack(&guard, &stack));
        assert!(!is_thread_stack(&guard, &apart));
        assert!(!is_thread_stack(&guard, &heap));
        assert!(!is_thread_stack(&code, &stack));
    }

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
