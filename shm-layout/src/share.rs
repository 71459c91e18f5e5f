// SPDX-License-Identifier: MIT OR Apache-2.0
//! Group access to procimg's shared memory.
//!
//! iceoryx2 0.10 creates every file owner-only (0600, static configuration 0400) and its
//! directories 0750, and has no setting for a group. With `[access] group` configured,
//! procimgd makes iceoryx2's directory a group directory (group set, mode 02770: what is
//! created in it carries the group), and every process of procimg — procimgd and each client
//! — gives the group the owner's permissions on the files it created itself, in that
//! directory and in `/dev/shm`, shortly after creating them. A user outside the group can
//! neither enter the directory nor open the shared memory (mode 0660, the access group), and
//! gets "access denied".

extern crate std;

use std::fs;
use std::io;
use std::os::unix::fs::{MetadataExt as _, PermissionsExt as _};
use std::path::Path;
use std::string::{String, ToString as _};

/// The environment variable that moves iceoryx2's directory (default [`DEFAULT_DIRECTORY`])
/// for procimgd and its clients alike: all of them must agree.
pub const DIRECTORY_VARIABLE: &str = "PROCIMG_SHM_DIR";

/// Where iceoryx2 keeps its node and service files for procimg unless
/// [`DIRECTORY_VARIABLE`] says otherwise: in memory (tmpfs), not iceoryx2's own default
/// `/tmp/iceoryx2`. iceoryx2 writes and `fsync`s a dozen small files for every process that
/// attaches; where `/tmp` is a disk, each `fsync` waits for the disk (0.5–1.5 ms measured on
/// a virtual disk, more on a PLC's flash, which it also wears).
pub const DEFAULT_DIRECTORY: &str = "/dev/shm/procimg-iceoryx2/";

/// iceoryx2's directory: [`DIRECTORY_VARIABLE`]'s when set to an absolute path, else
/// [`DEFAULT_DIRECTORY`]; with a trailing `/` as iceoryx2 wants it.
pub fn iceoryx2_directory() -> String {
    std::env::var(DIRECTORY_VARIABLE)
        .ok()
        .map(|dir| dir.trim_end_matches('/').to_string())
        .filter(|dir| dir.starts_with('/') && dir.len() > 1)
        .map_or_else(
            || DEFAULT_DIRECTORY.to_string(),
            |dir| std::format!("{dir}/"),
        )
}

/// Where POSIX shared memory lives on Linux.
pub const SHM_DIR: &str = "/dev/shm";

/// The iceoryx2 file prefix of every procimg service, so its files in `/dev/shm` and
/// iceoryx2's directory are recognisable (`procimg_…`) and apart from other iceoryx2 users.
pub const IOX2_PREFIX: &str = "procimg_";

/// Group read, write and search, and setgid: a directory of the access group.
const GROUP_DIR_BITS: u32 = 0o2070;

/// The access group of iceoryx2's directory `root`, when procimgd made it a group directory
/// (setgid, group read, write and search); `None` otherwise.
pub fn access_group(root: &Path) -> Option<u32> {
    let meta = fs::metadata(root).ok()?;
    let mode = meta.mode();
    (meta.is_dir() && mode & GROUP_DIR_BITS == GROUP_DIR_BITS).then_some(meta.gid())
}

/// Gives the group of `root` (when it is a directory of a group, [`access_group`]) the
/// procimg files in it that this process created, now: for a file another process opens
/// next.
pub fn share_with_group_now(root: &Path) {
    if let Some(gid) = access_group(root) {
        share_own_files(root, IOX2_PREFIX, gid);
    }
}

/// The id of group `name` (a name from `/etc/group`, or a number).
pub fn group_id(name: &str) -> Option<u32> {
    if let Ok(id) = name.parse() {
        return Some(id);
    }
    let groups = fs::read_to_string("/etc/group").ok()?;
    groups.lines().find_map(|line| {
        let mut fields = line.split(':');
        (fields.next()? == name).then_some(())?;
        fields.nth(1)?.parse().ok()
    })
}

/// Makes `root` and its `nodes/` and `services/` (created when missing) directories of group
/// `gid`, mode 02770. Fails when this process may not give them that group (it is neither
/// their owner and a member of the group, nor privileged).
pub fn prepare_root(root: &Path, gid: u32) -> io::Result<()> {
    for dir in [
        root.to_path_buf(),
        root.join("nodes"),
        root.join("services"),
    ] {
        match fs::create_dir(&dir) {
            Ok(()) => {}
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(e),
        }
        let meta = fs::metadata(&dir)?;
        if meta.gid() != gid {
            std::os::unix::fs::chown(&dir, None, Some(gid))?;
        }
        let mode = (meta.mode() & 0o7777 & !0o007) | 0o700 | GROUP_DIR_BITS;
        if meta.mode() & 0o7777 != mode {
            fs::set_permissions(&dir, fs::Permissions::from_mode(mode))?;
        }
    }
    Ok(())
}

/// Gives group `gid` the owner's access to every entry this user owns in iceoryx2's directory
/// `root` (directories: group read, write, search and setgid; files carrying `prefix`) and to
/// its files carrying `prefix` in `/dev/shm`. Returns how many entries were changed; entries
/// that vanish meanwhile or cannot be changed are left alone (the next call tries again).
pub fn share_own_files(root: &Path, prefix: &str, gid: u32) -> usize {
    let me = crate::os::effective_uid();
    let mut changed = 0;
    share_dir(root, prefix, gid, me, 0, &mut changed);
    if let Ok(entries) = fs::read_dir(SHM_DIR) {
        for entry in entries.flatten() {
            if entry
                .file_name()
                .as_encoded_bytes()
                .starts_with(prefix.as_bytes())
            {
                share_entry(&entry.path(), gid, me, false, &mut changed);
            }
        }
    }
    changed
}

/// Removes this user's connection files in `/dev/shm` (`prefix…_<sender>_<receiver>.connection`)
/// of the ports `ids`, which are gone. iceoryx2 leaves a connection to the other side's port
/// to remove, and with an access group that side is another user, whom `/dev/shm`'s sticky
/// bit does not let remove it. Returns how many were removed.
pub fn remove_own_connections(prefix: &str, ids: &[u128]) -> usize {
    if ids.is_empty() {
        return 0;
    }
    let me = crate::os::effective_uid();
    let Ok(entries) = fs::read_dir(SHM_DIR) else {
        return 0;
    };
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let Some(stem) = name
            .strip_prefix(prefix)
            .and_then(|n| n.strip_suffix(".connection"))
        else {
            continue;
        };
        let mine = stem
            .rsplit('_')
            .take(2)
            .filter_map(|n| n.parse::<u128>().ok())
            .any(|id| ids.contains(&id));
        if mine
            && entry.metadata().is_ok_and(|m| m.uid() == me)
            && fs::remove_file(entry.path()).is_ok()
        {
            removed += 1;
        }
    }
    removed
}

/// iceoryx2's directory is at most three levels deep (`nodes/<id>/<file>`).
const MAX_DEPTH: u32 = 3;

fn share_dir(dir: &Path, prefix: &str, gid: u32, me: u32, depth: u32, changed: &mut usize) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let Ok(kind) = entry.file_type() else {
            continue;
        };
        let path = entry.path();
        if kind.is_dir() {
            share_entry(&path, gid, me, true, changed);
            if depth + 1 < MAX_DEPTH {
                share_dir(&path, prefix, gid, me, depth + 1, changed);
            }
        } else if !kind.is_symlink()
            && entry
                .file_name()
                .as_encoded_bytes()
                .starts_with(prefix.as_bytes())
        {
            share_entry(&path, gid, me, false, changed);
        }
    }
}

fn share_entry(path: &Path, gid: u32, me: u32, dir: bool, changed: &mut usize) {
    let Ok(meta) = fs::symlink_metadata(path) else {
        return;
    };
    if meta.uid() != me {
        return;
    }
    let mode = meta.mode() & 0o7777;
    let wanted = if dir {
        mode | GROUP_DIR_BITS
    } else {
        // The group gets what the owner has.
        mode | ((mode & 0o700) >> 3)
    };
    let mut touched = false;
    if meta.gid() != gid && std::os::unix::fs::lchown(path, None, Some(gid)).is_ok() {
        touched = true;
    }
    if wanted != mode && fs::set_permissions(path, fs::Permissions::from_mode(wanted)).is_ok() {
        touched = true;
    }
    if touched {
        *changed += 1;
    }
}

/// Why this process cannot use iceoryx2's directory `root` of access group `gid`, for an
/// "access denied" message: the user is not in the group.
pub fn denied_text(root: &Path, gid: u32) -> String {
    std::format!(
        "{} belongs to access group {gid}, and this user is not in it: ask for membership of \
         the group procimgd's [access] names",
        root.display()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_group_is_found_by_name_or_number() {
        assert_eq!(group_id("root"), Some(0));
        assert_eq!(group_id("4200"), Some(4200));
        assert_eq!(group_id("no-such-group-procimg"), None);
    }

    #[test]
    fn own_files_get_the_group_and_the_owners_permissions() {
        let dir = std::env::temp_dir().join(std::format!("procimg-share-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        let gid = crate::os::effective_gid();
        prepare_root(&dir, gid).unwrap();
        assert_eq!(access_group(&dir), Some(gid));
        let node = dir.join("nodes").join("1234");
        fs::create_dir(&node).unwrap();
        fs::set_permissions(&node, fs::Permissions::from_mode(0o750)).unwrap();
        let file = node.join("procimg_node.details");
        fs::write(&file, b"x").unwrap();
        fs::set_permissions(&file, fs::Permissions::from_mode(0o600)).unwrap();
        let other = node.join("foreign.details");
        fs::write(&other, b"x").unwrap();
        fs::set_permissions(&other, fs::Permissions::from_mode(0o600)).unwrap();
        assert!(share_own_files(&dir, "procimg_", gid) >= 2);
        let mode = |p: &Path| fs::metadata(p).unwrap().mode() & 0o7777;
        assert_eq!(mode(&node), 0o2770);
        assert_eq!(mode(&file), 0o660);
        // Files of other prefixes are not procimg's.
        assert_eq!(mode(&other), 0o600);
        fs::remove_dir_all(&dir).unwrap();
    }
}
