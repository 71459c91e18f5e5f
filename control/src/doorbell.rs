// SPDX-License-Identifier: MIT OR Apache-2.0
//! The control thread's doorbell: `/dev/shm/procimg_<instance>.doorbell`, one futex word.
//!
//! procimgd's control thread answers requests, hands the layout to new subscribers and turns
//! the role's events into notifications. It sleeps on this word between rounds of that work.
//! A client rings it after it sends a request or opens a port the server must connect; the
//! server's own threads ring it after they queue an event for it. So a request is answered
//! as soon as the control thread runs, not at its next round.
//!
//! The word is a counter: a ring adds one and wakes the sleepers. The file belongs to the
//! instance, not to one server generation, since a client rings before it learns the
//! generation (its first request is the registration). Nothing is lost when a ring goes
//! unheard (no server, an old server's file, no permission): the request is then answered at
//! the control thread's next round, as it would be without a doorbell.

use crate::futex::LinuxFutex;
use core::sync::atomic::{AtomicU32, Ordering};
use core::time::Duration;
use procimg_shm_layout::handshake::Futex as _;
use std::fs::{self, File, OpenOptions};
use std::io;
use std::os::unix::fs::{MetadataExt as _, OpenOptionsExt as _};
use std::path::PathBuf;

const SUFFIX: &str = ".doorbell";
/// One page: the mapping's unit.
const DOORBELL_FILE_SIZE: usize = 4096;

/// Where the doorbell of `instance` lives.
pub fn doorbell_path(instance: &str) -> PathBuf {
    PathBuf::from(std::format!(
        "{}/{}{}{SUFFIX}",
        procimg_shm_layout::share::SHM_DIR,
        procimg_shm_layout::share::IOX2_PREFIX,
        procimg_shm_layout::handshake_map::instance_part(instance)
    ))
}

/// A mapped doorbell.
pub struct Doorbell {
    map: memmap2::MmapRaw,
    /// The file's inode: a doorbell whose file was replaced is no longer the server's.
    inode: u64,
    /// Set for the server's doorbell: the file goes when the server does.
    owned: Option<PathBuf>,
}

impl Doorbell {
    /// Creates the doorbell of `instance` for its server (owner-only, like iceoryx2's files;
    /// `[access] group` shares it). A file a killed server left is taken over as it is: the
    /// word is a counter, and clients that mapped it keep ringing the right one.
    pub fn create(instance: &str) -> io::Result<Doorbell> {
        let path = doorbell_path(instance);
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .mode(0o600)
            .open(&path)?;
        if file.metadata()?.len() < DOORBELL_FILE_SIZE as u64 {
            file.set_len(DOORBELL_FILE_SIZE as u64)?;
        }
        Doorbell::map(&file, Some(path))
    }

    /// Opens the doorbell of `instance`'s server: `NotFound` when no server made one,
    /// `PermissionDenied` when this user may not use it.
    pub fn open(instance: &str) -> io::Result<Doorbell> {
        let path = doorbell_path(instance);
        let file = OpenOptions::new().read(true).write(true).open(&path)?;
        if file.metadata()?.len() < DOORBELL_FILE_SIZE as u64 {
            return Err(io::Error::new(
                io::ErrorKind::NotFound,
                std::format!("{} is not a doorbell", path.display()),
            ));
        }
        Doorbell::map(&file, None)
    }

    fn map(file: &File, owned: Option<PathBuf>) -> io::Result<Doorbell> {
        let map = memmap2::MmapOptions::new()
            .len(DOORBELL_FILE_SIZE)
            .map_raw(file)?;
        Ok(Doorbell {
            map,
            inode: file.metadata()?.ino(),
            owned,
        })
    }

    /// Whether this is still the instance's doorbell (its file was not removed or replaced
    /// since it was opened): a client reopens it after the server changed.
    pub fn is_current(&self, instance: &str) -> bool {
        fs::metadata(doorbell_path(instance)).is_ok_and(|m| m.ino() == self.inode)
    }

    fn word(&self) -> &AtomicU32 {
        // SAFETY: the mapping is page-aligned, at least 4 bytes long and lives as long as
        // `self`; an AtomicU32 is valid for every bit pattern, and every process that maps the
        // file accesses the word only through atomics.
        unsafe { &*(self.map.as_ptr() as *const AtomicU32) }
    }

    /// Rings: the control thread wakes (or, awake, does another round before it sleeps).
    pub fn ring(&self) {
        self.word().fetch_add(1, Ordering::Release);
        LinuxFutex.wake(self.word(), u32::MAX);
    }

    /// How often it has rung: read before a round of work, and handed to [`Doorbell::wait`]
    /// after it, so that a ring during the round is not slept through.
    pub fn rung(&self) -> u32 {
        self.word().load(Ordering::Acquire)
    }

    /// Sleeps until the doorbell rings again after `seen` (from [`Doorbell::rung`]), at most
    /// for `timeout`. Returns whether it rang.
    pub fn wait(&self, seen: u32, timeout: Duration) -> bool {
        let deadline = LinuxFutex
            .now_ns()
            .saturating_add(timeout.as_nanos().min(u64::MAX as u128) as u64);
        loop {
            if self.rung() != seen {
                return true;
            }
            if LinuxFutex.now_ns() >= deadline {
                return false;
            }
            LinuxFutex.wait_until(self.word(), seen, deadline);
        }
    }
}

impl Drop for Doorbell {
    fn drop(&mut self) {
        if let Some(path) = &self.owned {
            // Only the file this server made or took over: a later server's stays.
            if fs::metadata(path).is_ok_and(|m| m.ino() == self.inode) {
                let _ = fs::remove_file(path);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn instance(test: &str) -> std::string::String {
        std::format!("doorbell-{test}-{}", std::process::id())
    }

    #[test]
    fn a_ring_from_another_mapping_wakes_the_sleeper() {
        let name = instance("wake");
        let server = Arc::new(Doorbell::create(&name).unwrap());
        let client = Doorbell::open(&name).unwrap();
        let seen = server.rung();
        let sleeper = {
            let server = server.clone();
            // An hour: the ring, not the time, must end the wait.
            std::thread::spawn(move || server.wait(seen, Duration::from_secs(3600)))
        };
        client.ring();
        assert!(sleeper.join().unwrap());
        assert_eq!(server.rung(), seen.wrapping_add(1));
    }

    #[test]
    fn a_ring_before_the_wait_is_not_slept_through() {
        let name = instance("early");
        let server = Doorbell::create(&name).unwrap();
        let seen = server.rung();
        Doorbell::open(&name).unwrap().ring();
        assert!(server.wait(seen, Duration::from_secs(3600)));
    }

    #[test]
    fn an_unrung_wait_ends_at_its_timeout() {
        let name = instance("timeout");
        let server = Doorbell::create(&name).unwrap();
        assert!(!server.wait(server.rung(), Duration::from_millis(1)));
    }

    #[test]
    fn the_file_goes_with_the_server_and_a_client_sees_it_replaced() {
        let name = instance("replaced");
        let first = Doorbell::create(&name).unwrap();
        let client = Doorbell::open(&name).unwrap();
        assert!(client.is_current(&name));
        drop(first);
        assert!(!doorbell_path(&name).exists());
        assert!(!client.is_current(&name));
        let second = Doorbell::create(&name).unwrap();
        assert!(!client.is_current(&name));
        assert!(Doorbell::open(&name).unwrap().is_current(&name));
        drop(second);
        assert_eq!(
            Doorbell::open(&name).err().map(|e| e.kind()),
            Some(io::ErrorKind::NotFound)
        );
    }
}
