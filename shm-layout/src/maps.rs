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
}
