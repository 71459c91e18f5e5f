// SPDX-License-Identifier: MIT OR Apache-2.0
//! When iceoryx2's directory belongs to another user.
//!
//! iceoryx2 keeps its nodes and services in one directory (`/tmp/iceoryx2`, with `nodes/` and
//! `services/`), created by the first process that needs it, with that process's user and
//! mode 0750. After a procimgd or client ran as root, another user's node cannot be created
//! there, and iceoryx2 only reports an `InternalError`. [`foreign_directory`] says what
//! happened and what to do.

use super::iox2_config;
use crate::sys::access::{effective_uid, may_create_in, user_name};
use std::os::unix::fs::MetadataExt as _;
use std::path::PathBuf;

/// The directory iceoryx2 keeps its node and service files in (`/tmp/iceoryx2`).
pub fn directory() -> PathBuf {
    let root = iox2_config().global.root_path().to_string();
    PathBuf::from(root.trim_end_matches('/'))
}

/// Why this process cannot create a node, when the reason is that iceoryx2's directory (or
/// one of its `nodes/` and `services/`) exists, belongs to another user and is not writable
/// for this one. `None` when that is not the reason.
///
/// The text says whose directory it is, that a run as that user left it, and how to go on:
/// `the shared-memory directory /tmp/iceoryx2 belongs to root (mode 0750), left by a procimgd
/// or client run as root: run as root too, or, with no procimgd running, remove it (sudo rm
/// -rf /tmp/iceoryx2 /dev/shm/procimg_*)`.
pub fn foreign_directory() -> Option<String> {
    let root = directory();
    let me = effective_uid();
    let blocked = [root.clone(), root.join("nodes"), root.join("services")]
        .into_iter()
        .find_map(|dir| {
            let meta = std::fs::metadata(&dir).ok()?;
            (meta.is_dir() && meta.uid() != me && !may_create_in(&dir)).then_some((dir, meta))
        })?;
    let (dir, meta) = blocked;
    let owner = user_name(meta.uid());
    // POSIX shared memory lives in /dev/shm on Linux; iceoryx2 names its files there with
    // procimg's prefix.
    let prefix = procimg_shm_layout::control::IOX2_PREFIX;
    Some(format!(
        "the shared-memory directory {} belongs to {owner} (mode {:04o}), left by a procimgd \
         or client run as {owner}: run as {owner} too, or, with no procimgd running, remove it \
         (`sudo rm -rf {} /dev/shm/{prefix}*`)",
        dir.display(),
        meta.mode() & 0o7777,
        root.display(),
    ))
}
