// SPDX-License-Identifier: MIT OR Apache-2.0
//! The process's memory mappings, as `/proc/self/maps` lists them: for procimgd, which faults
//! its mappings in ahead of the cycle, and for a client, which checks that a place the
//! handshake block names lies in the input segment it maps.

extern crate std;

use alloc::string::{String, ToString};
use alloc::vec::Vec;

/// One line of `/proc/self/maps`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mapping {
    /// First address.
    pub start: usize,
    /// Length in bytes.
    pub len: usize,
    /// Mapped readable.
    pub readable: bool,
    /// Mapped writable.
    pub writable: bool,
    /// The file mapped, or the kernel's name (`[stack]`), or empty.
    pub path: String,
}

impl Mapping {
    /// Parses one line of `/proc/self/maps`; `None` for a line of another shape.
    pub fn parse(line: &str) -> Option<Mapping> {
        let mut rest = line;
        let (start, end) = field(&mut rest).split_once('-')?;
        let start = usize::from_str_radix(start, 16).ok()?;
        let end = usize::from_str_radix(end, 16).ok()?;
        let perms = field(&mut rest).as_bytes();
        // offset, device, inode, then the path (which may hold spaces).
        for _ in 0..3 {
            field(&mut rest);
        }
        Some(Mapping {
            start,
            len: end.checked_sub(start)?,
            readable: perms.first() == Some(&b'r'),
            writable: perms.get(1) == Some(&b'w'),
            path: rest.trim().to_string(),
        })
    }

    /// Whether this is a shared-memory segment (iceoryx2's, a handshake block).
    pub fn is_shared_memory(&self) -> bool {
        self.path.starts_with("/dev/shm/")
    }
}

/// The next whitespace-separated field of `rest`, which moves past it.
fn field<'a>(rest: &mut &'a str) -> &'a str {
    let s = rest.trim_start();
    let end = s.find(char::is_whitespace).unwrap_or(s.len());
    let (f, r) = s.split_at(end);
    *rest = r;
    f
}

/// The process's mappings now.
pub fn mappings() -> std::io::Result<Vec<Mapping>> {
    let text = std::fs::read_to_string("/proc/self/maps")?;
    Ok(text.lines().filter_map(Mapping::parse).collect())
}

/// The mapping that holds address `at`.
pub fn mapping_of(at: usize) -> Option<Mapping> {
    mappings()
        .ok()?
        .into_iter()
        .find(|m| m.start <= at && at < m.start + m.len)
}

/// One mapping of a `/proc/<pid>/smaps` text: its first line, parsed, and the lines about it
/// (`Rss:`, `Locked:`, `VmFlags:`, …).
#[derive(Clone, Debug)]
pub struct SmapsEntry<'a> {
    /// The mapping, from its first line.
    pub mapping: Mapping,
    lines: Vec<&'a str>,
}

impl<'a> SmapsEntry<'a> {
    /// The text after `name:` in the mapping's lines, trimmed; `None` when it has no such line.
    pub fn field(&self, name: &str) -> Option<&'a str> {
        self.lines
            .iter()
            .find_map(|l| l.strip_prefix(name)?.strip_prefix(':'))
            .map(str::trim)
    }
}

/// The mappings of an smaps text, each with its lines. A mapping's first line is the one that
/// parses as a [`Mapping`]; the lines about it start with a field name, which does not.
pub fn smaps_entries(text: &str) -> Vec<SmapsEntry<'_>> {
    let mut out: Vec<SmapsEntry<'_>> = Vec::new();
    for line in text.lines() {
        match Mapping::parse(line) {
            Some(mapping) => out.push(SmapsEntry {
                mapping,
                lines: Vec::new(),
            }),
            None => {
                if let Some(e) = out.last_mut() {
                    e.lines.push(line);
                }
            }
        }
    }
    out
}

/// The kB of a field's text as smaps and `/proc/<pid>/status` write it (`  1024 kB`).
pub fn kib(value: &str) -> Option<u64> {
    value.trim().strip_suffix("kB")?.trim().parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_maps_lines() {
        let m = Mapping::parse(
            "7f3e9defc000-7f3e9e2da000 r--s 00000000 00:1a 1234   /dev/shm/iox2_abc.publisher_data",
        )
        .expect("a mapping");
        assert_eq!(m.start, 0x7f3e9defc000);
        assert_eq!(m.len, 0x7f3e9e2da000 - 0x7f3e9defc000);
        assert!(m.readable && !m.writable && m.is_shared_memory());
        let anon = Mapping::parse("7ffd1000-7ffd2000 rw-p 00000000 00:00 0 ").expect("anon");
        assert_eq!(anon.path, "");
        assert!(anon.writable);
        let spaced = Mapping::parse("1000-2000 r--p 00000000 08:01 7 /tmp/a b (deleted)")
            .expect("a path with spaces");
        assert_eq!(spaced.path, "/tmp/a b (deleted)");
        assert_eq!(Mapping::parse("garbage"), None);
        assert_eq!(Mapping::parse("2000-1000 r--p 0 0 0"), None);
    }

    #[test]
    fn smaps_fields_belong_to_the_mapping_above_them() {
        let text = "1000-2000 r-xp 00000000 08:01 7 /bin/x\nRss:   8 kB\nVmFlags: rd ex lo\n\
                    3000-4000 rw-p 00000000 00:00 0 \nRss:   4 kB\n";
        let e = smaps_entries(text);
        assert_eq!(e.len(), 2);
        assert_eq!(e[0].field("Rss").and_then(kib), Some(8));
        assert_eq!(e[0].field("VmFlags"), Some("rd ex lo"));
        assert_eq!(e[1].mapping.start, 0x3000);
        assert_eq!(e[1].field("Rss").and_then(kib), Some(4));
        assert_eq!(e[1].field("VmFlags"), None);
        assert_eq!(kib("12 kB"), Some(12));
        assert_eq!(kib("twelve kB"), None);
    }
}
