// SPDX-License-Identifier: MIT OR Apache-2.0
//! The clock and the wait that server and clients share: `CLOCK_MONOTONIC` (the clock of
//! `CycleInfo`) and a precise wait on an event socket; and why iceoryx2's directory may be
//! unusable for this process.
//!
//! iceoryx2's own `Listener::timed_wait` rounds short timeouts up to several milliseconds (it
//! uses `SO_RCVTIMEO`); `ppoll` on the listener's socket sleeps on a high-resolution timer.

extern crate std;

use std::borrow::ToOwned;
use std::ffi::CString;
use std::format;
use std::os::fd::RawFd;
use std::os::unix::ffi::OsStrExt as _;
use std::os::unix::fs::MetadataExt as _;
use std::path::Path;
use std::string::String;

/// Now on `CLOCK_MONOTONIC`, in ns.
pub fn monotonic_ns() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; CLOCK_MONOTONIC always exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut ts) };
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

/// Waits until `fd` is readable or `timeout_ns` passed. Returns whether it is readable.
pub fn wait_readable(fd: RawFd, timeout_ns: u64) -> bool {
    let [readable] = wait_any_readable([fd], timeout_ns);
    readable
}

/// Waits until one of `fds` is readable (or has an error) or `timeout_ns` passed. Returns
/// which are.
pub fn wait_any_readable<const N: usize>(fds: [RawFd; N], timeout_ns: u64) -> [bool; N] {
    let mut polled = fds.map(|fd| libc::pollfd {
        fd,
        events: libc::POLLIN,
        revents: 0,
    });
    let ts = libc::timespec {
        tv_sec: (timeout_ns / 1_000_000_000) as libc::time_t,
        tv_nsec: (timeout_ns % 1_000_000_000) as libc::c_long,
    };
    // SAFETY: `polled` is an array of N valid pollfds, `ts` a valid timespec, and a null
    // sigmask keeps the current signal mask.
    let rc = unsafe {
        libc::ppoll(
            polled.as_mut_ptr(),
            N as libc::nfds_t,
            &ts,
            core::ptr::null(),
        )
    };
    polled.map(|p| rc > 0 && p.revents & (libc::POLLIN | libc::POLLERR) != 0)
}

/// Whether this process may create and remove entries in directory `dir` (write and search
/// permission, for the effective user and groups). `false` also when `dir` cannot be
/// looked at.
pub fn may_create_in(dir: &Path) -> bool {
    let Ok(path) = CString::new(dir.as_os_str().as_bytes()) else {
        return false;
    };
    // SAFETY: `path` is a valid NUL-terminated string that outlives the call; faccessat(2)
    // only reads it, and AT_FDCWD with an absolute or relative path is always valid.
    let rc = unsafe {
        libc::faccessat(
            libc::AT_FDCWD,
            path.as_ptr(),
            libc::W_OK | libc::X_OK,
            libc::AT_EACCESS,
        )
    };
    rc == 0
}

/// The effective user id of this process.
pub fn effective_uid() -> u32 {
    // SAFETY: geteuid(2) takes no arguments and cannot fail.
    unsafe { libc::geteuid() }
}

/// The effective group id of this process.
pub fn effective_gid() -> u32 {
    // SAFETY: getegid(2) takes no arguments and cannot fail.
    unsafe { libc::getegid() }
}

/// The name of user `uid` from `/etc/passwd`, or `uid N` when it has none there.
pub fn user_name(uid: u32) -> String {
    if uid == 0 {
        return "root".to_owned();
    }
    std::fs::read_to_string("/etc/passwd")
        .ok()
        .and_then(|passwd| {
            passwd.lines().find_map(|line| {
                let mut fields = line.split(':');
                let name = fields.next()?;
                let id = fields.nth(1)?.parse::<u32>().ok()?;
                (id == uid).then(|| name.to_owned())
            })
        })
        .unwrap_or_else(|| format!("uid {uid}"))
}

/// Why this process cannot create an iceoryx2 node, when the reason is that iceoryx2's
/// directory `root` (`/dev/shm/procimg-iceoryx2` by default), or its `nodes/` or `services/`, exists, belongs to
/// another user and is not writable for this one; `None` when that is not the reason.
///
/// iceoryx2 creates the directory with the first process's user and mode 0750, and reports
/// only an internal error to everyone else: after a procimgd or client ran as root, a
/// non-root run fails there. The text says whose directory it is and how to go on.
/// `prefix` is the one procimg's files carry in `/dev/shm`.
pub fn foreign_iox2_directory(root: &Path, prefix: &str) -> Option<String> {
    let me = effective_uid();
    let (dir, meta) = [
        root.to_path_buf(),
        root.join("nodes"),
        root.join("services"),
    ]
    .into_iter()
    .find_map(|dir| {
        let meta = std::fs::metadata(&dir).ok()?;
        (meta.is_dir() && meta.uid() != me && !may_create_in(&dir)).then_some((dir, meta))
    })?;
    let owner = user_name(meta.uid());
    // POSIX shared memory lives in /dev/shm on Linux, where iceoryx2 names procimg's files
    // with the prefix.
    Some(format!(
        "the shared-memory directory {} belongs to {owner} (mode {:04o}), left by a procimgd \
         or client run as {owner}: run as {owner} too, or, with no procimgd running, remove it \
         (`sudo rm -rf {} /dev/shm/{prefix}*`)",
        dir.display(),
        meta.mode() & 0o7777,
        root.display(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn temporary_directory_is_usable_and_a_missing_one_is_not() {
        assert!(may_create_in(&std::env::temp_dir()));
        assert!(!may_create_in(Path::new("/nonexistent/procimg-test")));
        assert_eq!(user_name(0), "root");
        assert!(!user_name(effective_uid()).is_empty());
    }
}
