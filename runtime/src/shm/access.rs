// SPDX-License-Identifier: MIT OR Apache-2.0
//! `[access] group`: the clients of one group attach, other users do not (see
//! `procimg_shm_layout::share` for how, with iceoryx2 0.10 creating its files owner-only).

use super::dir::directory;
use procimg_config::AccessConfig;
use procimg_shm_layout::share;
use procimg_shm_layout::share::IOX2_PREFIX;
use std::time::{Duration, Instant};

/// How soon a file procimgd created is given to the group: a client that finds it owner-only
/// meanwhile retries its attach.
pub const SHARE_PERIOD: Duration = Duration::from_millis(50);

/// Why group access cannot be set up.
#[derive(Debug, thiserror::Error)]
pub enum AccessError {
    /// Modes procimg does not offer.
    #[error(
        "[access] mode = \"{mode:04o}\"{group}: procimg offers owner-only (\"0600\", the default) \
         or the owner's access for one group (group = \"NAME\", mode \"0660\"), never access for \
         every user"
    )]
    Mode {
        /// The mode asked for.
        mode: u32,
        /// The group, as text.
        group: String,
    },
    /// No such group.
    #[error(
        "[access] group = \"{0}\": no such group in /etc/group; create it (groupadd) or name another"
    )]
    UnknownGroup(String),
    /// The directory could not be given to the group.
    #[error(
        "[access] group = \"{group}\": cannot make {dir} a directory of the group ({error}); \
         procimgd's user must own it and be a member of the group (or procimgd runs as root)"
    )]
    Directory {
        /// The group.
        group: String,
        /// iceoryx2's directory.
        dir: String,
        /// Why.
        error: std::io::Error,
    },
}

/// Gives the group of iceoryx2's directory (when it has one: `[access] group`) what this
/// process created, now: for a file a client opens right after procimgd answered it.
pub fn share_now() {
    share::share_with_group_now(&directory());
}

/// The access group, while procimgd runs.
pub struct GroupAccess {
    gid: u32,
    last: Option<Instant>,
}

impl GroupAccess {
    /// Checks `[access]` and, with a group, prepares iceoryx2's directory for it. `None`: files
    /// stay owner-only.
    pub fn set_up(access: &AccessConfig) -> Result<Option<GroupAccess>, AccessError> {
        let group_text = access
            .group
            .as_ref()
            .map(|g| format!(", group = \"{g}\""))
            .unwrap_or_default();
        let mode_error = || AccessError::Mode {
            mode: access.mode,
            group: group_text.clone(),
        };
        let Some(group) = &access.group else {
            return match access.mode {
                0o600 => Ok(None),
                _ => Err(mode_error()),
            };
        };
        if access.mode != 0o660 {
            return Err(mode_error());
        }
        let gid = share::group_id(group).ok_or_else(|| AccessError::UnknownGroup(group.clone()))?;
        let root = directory();
        share::prepare_root(&root, gid).map_err(|error| AccessError::Directory {
            group: group.clone(),
            dir: root.display().to_string(),
            error,
        })?;
        Ok(Some(GroupAccess { gid, last: None }))
    }

    /// Gives the group what procimgd created since the last call (at most every
    /// [`SHARE_PERIOD`]).
    pub fn share(&mut self) {
        if self.last.is_some_and(|t| t.elapsed() < SHARE_PERIOD) {
            return;
        }
        self.last = Some(Instant::now());
        share::share_own_files(&directory(), IOX2_PREFIX, self.gid);
    }
}
