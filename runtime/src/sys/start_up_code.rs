// SPDX-License-Identifier: MIT OR Apache-2.0
//! Letting go of the program's start-up code once start-up is over.
//!
//! procimgd locks its code as it is used (`sys::rt::lock_memory` with `MCL_ONFAULT`). Start-up
//! runs code from all over the program: reading the configuration, building the station's
//! tables, creating the iceoryx2 services, the OPC UA certificate. The kernel keeps the
//! program file in large folios and maps a whole folio at each fault, so by the first cycle
//! some 90 % of the program's code was locked, most of it never to run again. Here the
//! program's code and read-only data are unmapped once (`MADV_DONTNEED`, which for a file
//! mapping drops only the page-table entries: the file in the page cache stays as it is) and
//! locked again as used, so that what stays locked is what the running server executes.

use super::populate::{Mapping, is_code_or_read_only_data, locked_as_used};
use procimg_shm_layout::maps::{kib, smaps_entries};

/// Unmaps the program's code and read-only data that is mapped and locked now, to be faulted
/// back in and locked as it is used, when the process locks its code as used. A mapping that
/// holds a private copy of any page (a debugger's breakpoint, an uprobe, relocated
/// read-only data) is left alone: dropping the copy would lose what was written into it.
/// Returns what was let go, with a warning for each mapping that, once unlocked, could not
/// be locked again (the others are still done).
pub fn release_start_up_code() -> Released {
    let mut released = Released::default();
    if !locked_as_used() {
        return released;
    }
    let Some(program) = program_path() else {
        return released;
    };
    let Ok(smaps) = std::fs::read_to_string("/proc/self/smaps") else {
        return released;
    };
    for (m, anonymous_kib) in mappings_with_private_pages(&smaps) {
        if m.path == program && is_code_or_read_only_data(&m) && anonymous_kib == 0 {
            match release(&m) {
                Ok(n) => released.bytes += n,
                Err(w) => released.warnings.push(w),
            }
        }
    }
    released
}

/// What [`release_start_up_code`] let go.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Released {
    /// Bytes of the mappings let go.
    pub bytes: usize,
    /// One per mapping that could not be locked again: it names the mapping and what to do.
    pub warnings: Vec<String>,
}

/// The program's path as `/proc/self/maps` names its mappings (with " (deleted)" when the
/// file was replaced since, as the link says too).
fn program_path() -> Option<String> {
    std::fs::read_link("/proc/self/exe")
        .ok()
        .map(|p| p.to_string_lossy().into_owned())
}

/// Each mapping of `/proc/self/smaps` text with its `Anonymous` and `Swap` kB: the pages it
/// holds a private copy of rather than the file's, in memory or swapped out (a file's own
/// pages never are).
fn mappings_with_private_pages(smaps: &str) -> Vec<(Mapping, u64)> {
    smaps_entries(smaps)
        .into_iter()
        .map(|e| {
            let private = ["Anonymous", "Swap"]
                .iter()
                .filter_map(|name| e.field(name))
                // Unreadable: taken as holding private pages, and so left alone.
                .map(|v| kib(v).unwrap_or(u64::MAX))
                .fold(0u64, u64::saturating_add);
            (e.mapping, private)
        })
        .collect()
}

/// Unlocks `m`, drops its pages from the process and locks it again as used. Returns its
/// length, or 0 when the kernel refused to unlock it or to drop its pages (it is locked
/// again all the same); an error, the warning to give, when it cannot be locked again.
fn release(m: &Mapping) -> Result<usize, String> {
    let at = m.start as *mut libc::c_void;
    // SAFETY: munlock takes an address range of this process's own mapping and changes no
    // memory contents.
    if unsafe { libc::munlock(at, m.len) } != 0 {
        return Ok(0);
    }
    // SAFETY: as munlock. The mapping is a private file mapping without a private page
    // (checked by the caller), so MADV_DONTNEED only drops page-table entries: the next
    // access reads the same bytes from the file again. A thread running this code meanwhile
    // only faults it back in.
    let dropped = unsafe { libc::madvise(at, m.len, libc::MADV_DONTNEED) } == 0;
    // SAFETY: as munlock; MLOCK_ONFAULT locks the pages present and those faulted in later.
    if unsafe { libc::mlock2(at, m.len, libc::MLOCK_ONFAULT) } != 0 {
        return Err(format!(
            "cannot lock {} again after letting start-up's code go ({}): the cycle may wait              for its code to be read from disk; set [cycle_thread] prefault_all = true to keep              it populated and locked",
            m.path,
            std::io::Error::last_os_error()
        ));
    }
    Ok(if dropped { m.len } else { 0 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smaps_mappings_come_with_their_private_pages() {
        let smaps = "\
55d0a0000000-55d0a0100000 r-xp 00001000 fd:01 42 /usr/bin/procimgd
Size:               1024 kB
Anonymous:             0 kB
VmFlags: rd ex mr mw me lf
55d0a0200000-55d0a0210000 r--p 00200000 fd:01 42 /usr/bin/procimgd
Size:                 64 kB
Anonymous:            60 kB
Swap:                  4 kB
VmFlags: rd mr mw me lf
7ffd00000000-7ffd00021000 rw-p 00000000 00:00 0 [stack]
Size:                132 kB
Anonymous:            12 kB
";
        let got = mappings_with_private_pages(smaps);
        let summary: Vec<(usize, usize, &str, u64)> = got
            .iter()
            .map(|(m, a)| (m.start, m.len, m.path.as_str(), *a))
            .collect();
        assert_eq!(
            summary,
            [
                (0x55d0a0000000, 0x100000, "/usr/bin/procimgd", 0),
                (0x55d0a0200000, 0x10000, "/usr/bin/procimgd", 64),
                (0x7ffd00000000, 0x21000, "[stack]", 12),
            ]
        );
    }

    #[test]
    fn nothing_is_let_go_by_a_process_that_does_not_lock_as_used() {
        // Tests do not lock their memory: their code stays mapped as it is.
        assert_eq!(release_start_up_code(), Released::default());
    }
}
