// SPDX-License-Identifier: MIT OR Apache-2.0
//! What of this process's memory is resident, as a test of faulting in ahead checks it.

/// The resident bytes of this process's mapping that starts at `start`, from
/// `/proc/self/smaps`. Panics when there is no such mapping.
pub fn resident_bytes(start: usize) -> usize {
    let smaps = std::fs::read_to_string("/proc/self/smaps").expect("read /proc/self/smaps");
    let header = format!("{start:x}-");
    let mut lines = smaps.lines().skip_while(|l| !l.starts_with(&header));
    assert!(lines.next().is_some(), "no mapping at {start:#x} in smaps");
    let rss = lines
        .find(|l| l.starts_with("Rss:"))
        .expect("the mapping's Rss line");
    let kib: usize = rss
        .split_whitespace()
        .nth(1)
        .and_then(|v| v.parse().ok())
        .expect("Rss in kB");
    kib * 1024
}
