// SPDX-License-Identifier: MIT OR Apache-2.0
//! The file behind the handshake block: `/dev/shm/procimg_<instance>_<generation>.handshake`,
//! created by procimgd for each server generation, mapped read-write by every client.

extern crate std;

use crate::handshake::{HANDSHAKE_BLOCK_SIZE, HandshakeBlock};
use std::fs::{self, File, OpenOptions};
use std::io;
use std::os::unix::fs::OpenOptionsExt as _;
use std::path::PathBuf;
use std::string::String;

const SUFFIX: &str = ".handshake";

/// `instance` as it appears in a file name of `/dev/shm`.
pub fn instance_part(instance: &str) -> String {
    instance
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}

/// Where the block of `instance`'s server `generation` lives.
pub fn handshake_path(instance: &str, generation: u64) -> PathBuf {
    PathBuf::from(std::format!(
        "{}/{}{}_{generation:016x}{SUFFIX}",
        crate::share::SHM_DIR,
        crate::share::IOX2_PREFIX,
        instance_part(instance)
    ))
}

/// Removes the blocks earlier servers of `instance` left (killed before they could): the
/// server calls it once it knows no other server of the instance runs. Returns how many.
pub fn remove_stale_blocks(instance: &str) -> usize {
    let prefix = std::format!("{}{}_", crate::share::IOX2_PREFIX, instance_part(instance));
    let Ok(entries) = fs::read_dir(crate::share::SHM_DIR) else {
        return 0;
    };
    entries
        .flatten()
        .filter(|e| {
            let name = e.file_name();
            let name = name.to_string_lossy();
            name.strip_prefix(&prefix)
                .and_then(|rest| rest.strip_suffix(SUFFIX))
                .is_some_and(|g| g.len() == 16 && g.bytes().all(|b| b.is_ascii_hexdigit()))
        })
        .filter(|e| fs::remove_file(e.path()).is_ok())
        .count()
}

/// A mapped handshake block.
pub struct HandshakeMap {
    map: memmap2::MmapRaw,
    /// Set for the server's block: the file goes when the server does.
    owned: Option<PathBuf>,
}

impl HandshakeMap {
    /// Creates the block of `instance`'s server `generation` (owner-only, like iceoryx2's
    /// files; `[access] group` shares it with the rest), initialised.
    pub fn create(instance: &str, generation: u64) -> io::Result<HandshakeMap> {
        let path = handshake_path(instance, generation);
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(true)
            .mode(0o600)
            .open(&path)?;
        file.set_len(HANDSHAKE_BLOCK_SIZE as u64)?;
        let map = HandshakeMap {
            map: map(&file)?,
            owned: Some(path),
        };
        map.block().initialise(generation);
        Ok(map)
    }

    /// Opens the block of `instance`'s server `generation`. `NotFound` when it does not
    /// exist (or is not initialised yet), `PermissionDenied` when this user may not use it.
    pub fn open(instance: &str, generation: u64) -> io::Result<HandshakeMap> {
        let path = handshake_path(instance, generation);
        let file = OpenOptions::new().read(true).write(true).open(&path)?;
        if file.metadata()?.len() < HANDSHAKE_BLOCK_SIZE as u64 {
            return Err(io::Error::new(
                io::ErrorKind::NotFound,
                std::format!("{} is not a handshake block", path.display()),
            ));
        }
        let map = HandshakeMap {
            map: map(&file)?,
            owned: None,
        };
        if !map.block().belongs_to(generation) {
            return Err(io::Error::new(
                io::ErrorKind::NotFound,
                std::format!("{} is not initialised", path.display()),
            ));
        }
        Ok(map)
    }

    /// The block.
    pub fn block(&self) -> &HandshakeBlock {
        // SAFETY: the mapping is page-aligned, HANDSHAKE_BLOCK_SIZE long (checked: at least
        // the block's size) and lives as long as `self`. The block consists of atomics only,
        // for which every bit pattern is valid, and every access to it — from this process or
        // another one mapping the same file — goes through those atomics.
        unsafe { &*(self.map.as_ptr() as *const HandshakeBlock) }
    }
}

fn map(file: &File) -> io::Result<memmap2::MmapRaw> {
    memmap2::MmapOptions::new()
        .len(HANDSHAKE_BLOCK_SIZE)
        .map_raw(file)
}

impl Drop for HandshakeMap {
    fn drop(&mut self) {
        if let Some(path) = &self.owned {
            let _ = fs::remove_file(path);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::handshake::Futex;
    use core::sync::atomic::AtomicU32;

    /// No sleeping and no waking: the test looks at the words, which the mapping shares.
    struct NoFutex;

    impl Futex for NoFutex {
        fn wait_until(&self, _: &AtomicU32, _: u32, _: u64) {}
        fn wake(&self, _: &AtomicU32, _: u32) {}
        fn now_ns(&self) -> u64 {
            0
        }
    }

    #[test]
    fn a_client_maps_the_servers_block_and_the_file_goes_with_the_server() {
        let instance = "handshake-map-test";
        let generation = 0x5eed_0000_0000_0000 | u64::from(std::process::id());
        let server = HandshakeMap::create(instance, generation).unwrap();
        let client = HandshakeMap::open(instance, generation).unwrap();
        let seen = client.block().events_seen();
        server.block().announce(&NoFutex, false);
        assert_ne!(client.block().events_seen(), seen);
        assert_eq!(
            HandshakeMap::open(instance, generation + 1)
                .err()
                .map(|e| e.kind()),
            Some(io::ErrorKind::NotFound)
        );
        drop(server);
        assert!(!handshake_path(instance, generation).exists());
    }
}
