// SPDX-License-Identifier: MIT OR Apache-2.0
//! Whether this process may use a directory, as the kernel decides it for this process's
//! effective user: for messages that explain why a library failed inside such a directory.

use std::ffi::CString;
use std::os::unix::ffi::OsStrExt as _;
use std::path::Path;

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_directory_is_usable_and_a_missing_one_is_not() {
        assert!(may_create_in(&std::env::temp_dir()));
        assert!(!may_create_in(Path::new("/nonexistent/procimg-test")));
        assert_eq!(user_name(0), "root");
        assert!(!user_name(effective_uid()).is_empty());
    }
}
