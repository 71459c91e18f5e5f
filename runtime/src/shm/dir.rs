// SPDX-License-Identifier: MIT OR Apache-2.0
//! When iceoryx2's directory belongs to another user: see
//! [`procimg_shm_layout::os::foreign_iox2_directory`].

use super::iox2_config;
use std::path::PathBuf;

/// The directory iceoryx2 keeps its node and service files in
/// ([`procimg_shm_layout::share::DEFAULT_DIRECTORY`] unless moved).
pub fn directory() -> PathBuf {
    let root = iox2_config().global.root_path().to_string();
    PathBuf::from(root.trim_end_matches('/'))
}

/// Why this process cannot create a node, when iceoryx2's directory belongs to another user
/// and is not writable for this one.
pub fn foreign_directory() -> Option<String> {
    procimg_shm_layout::os::foreign_iox2_directory(
        &directory(),
        procimg_shm_layout::share::IOX2_PREFIX,
    )
}
