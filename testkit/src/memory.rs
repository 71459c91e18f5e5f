// SPDX-License-Identifier: MIT OR Apache-2.0
//! What of this process's memory is resident and locked, as a test of faulting in ahead or of
//! locking checks it.

use procimg_shm_layout::maps::{kib, smaps_entries};

/// The resident bytes of this process's mapping that starts at `start`, from
/// `/proc/self/smaps`. Panics when there is no such mapping.
pub fn resident_bytes(start: usize) -> usize {
    smaps_kib(start, "Rss") * 1024
}

/// The locked bytes of this process's mapping that starts at `start`: its share of the
/// resident pages the kernel keeps in memory for `mlock` (a page mapped by two processes
/// counts half in each). Panics when there is no such mapping.
pub fn locked_bytes(start: usize) -> usize {
    smaps_kib(start, "Locked") * 1024
}

/// The kernel's flags of the mapping that starts at `start` (`VmFlags`: `lo` locked, `ex`
/// executable, …). Panics when there is no such mapping.
pub fn vm_flags(start: usize) -> Vec<String> {
    smaps_field(start, "VmFlags")
        .split_whitespace()
        .map(str::to_owned)
        .collect()
}

/// A `NAME: N kB` field of the mapping that starts at `start`.
fn smaps_kib(start: usize, name: &str) -> usize {
    let kib = kib(&smaps_field(start, name)).unwrap_or_else(|| panic!("{name} in kB"));
    kib as usize
}

/// The text after `NAME:` in the mapping that starts at `start`, from `/proc/self/smaps`.
fn smaps_field(start: usize, name: &str) -> String {
    let smaps = std::fs::read_to_string("/proc/self/smaps").expect("read /proc/self/smaps");
    let entries = smaps_entries(&smaps);
    let entry = entries
        .iter()
        .find(|e| e.mapping.start == start)
        .unwrap_or_else(|| panic!("no mapping at {start:#x} in smaps"));
    entry
        .field(name)
        .unwrap_or_else(|| panic!("the mapping at {start:#x} has no {name} line"))
        .to_owned()
}
