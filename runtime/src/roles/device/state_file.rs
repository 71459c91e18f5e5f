// SPDX-License-Identifier: MIT OR Apache-2.0
//! The station's state file (`[station] state_file`): what a PROFINET device keeps across a
//! restart — the name and address DCP set permanently (or the factory state after a reset to
//! factory), and I&M1 to I&M4 as the PLC or the engineering tool wrote them.
//!
//! A small TOML file, read once at start and written whenever one of these changes: into a
//! temporary file beside it, flushed to disk, then renamed over it, so that a crash or a
//! power cut leaves either the old file or the new one, never half of one.

use procimg_profinet::device::{ImRecords, KeptIdentity};
use procimg_profinet::wire::record::{Im1, Im2, Im3, Im4};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::net::Ipv4Addr;
use std::path::{Path, PathBuf};

/// What the file holds. Keys left out keep the configuration's values.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeptState {
    /// NameOfStation (empty: none, after a reset to factory).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// IP address (0.0.0.0: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ip: Option<Ipv4Addr>,
    /// Subnet mask.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub netmask: Option<Ipv4Addr>,
    /// Default gateway (0.0.0.0: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gateway: Option<Ipv4Addr>,
    /// The I&M1 to I&M4 records as written, blocks with their headers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub im: Option<KeptIm>,
}

/// I&M1 to I&M4, each its whole record block.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeptIm {
    /// I&M1 (tag function, tag location).
    pub im1: Vec<u8>,
    /// I&M2 (installation date).
    pub im2: Vec<u8>,
    /// I&M3 (descriptor).
    pub im3: Vec<u8>,
    /// I&M4 (signature).
    pub im4: Vec<u8>,
}

/// Why the state file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum StateFileError {
    /// Reading failed (other than the file not being there yet).
    #[error(
        "cannot read the station's state file {path}: {source}; check its permissions, or \
         remove it to start from the configuration's values"
    )]
    Read {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// The content is not what procimgd writes.
    #[error(
        "the station's state file {path} is damaged: {message}; remove it to start from the \
         configuration's values"
    )]
    Damaged {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// Writing failed.
    #[error(
        "cannot write the station's state file {path}: {source}; the station's name, address \
         and I&M data will not survive a restart until it can (check the directory's \
         permissions and free space)"
    )]
    Write {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
}

/// The state in `path`; empty when there is no such file yet.
pub fn load(path: &Path) -> Result<KeptState, StateFileError> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(KeptState::default()),
        Err(source) => {
            return Err(StateFileError::Read {
                path: path.to_path_buf(),
                source,
            });
        }
    };
    let state: KeptState = toml::from_str(&text).map_err(|e| StateFileError::Damaged {
        path: path.to_path_buf(),
        message: e.message().to_owned(),
    })?;
    // The station's address goes onto its interface with the netmask's prefix length.
    if let Some(mask) = state.netmask
        && crate::roles::address::prefix_len(mask).is_none()
    {
        return Err(StateFileError::Damaged {
            path: path.to_path_buf(),
            message: format!("netmask {mask} is not ones followed by zeros"),
        });
    }
    if let Some(im) = &state.im {
        im_records(im).map_err(|message| StateFileError::Damaged {
            path: path.to_path_buf(),
            message,
        })?;
    }
    Ok(state)
}

/// Writes `state` to `path` atomically.
pub fn save(path: &Path, state: &KeptState) -> Result<(), StateFileError> {
    let failed = |source| StateFileError::Write {
        path: path.to_path_buf(),
        source,
    };
    let text = format!(
        "# The PROFINET station's values that survive a restart, written by procimgd.\n\
         # Remove this file to start from the configuration's values.\n{}",
        toml::to_string(state).map_err(|e| failed(std::io::Error::other(e.to_string())))?
    );
    let mut tmp_name = path.file_name().unwrap_or_default().to_os_string();
    tmp_name.push(".tmp");
    let tmp = path.with_file_name(tmp_name);
    let mut file = std::fs::File::create(&tmp).map_err(failed)?;
    file.write_all(text.as_bytes()).map_err(failed)?;
    file.sync_all().map_err(failed)?;
    std::fs::rename(&tmp, path).map_err(failed)?;
    // The rename itself is durable once the directory is.
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
        && let Ok(d) = std::fs::File::open(dir)
    {
        let _ = d.sync_all();
    }
    Ok(())
}

/// The engine's I&M records from the file's blocks.
pub fn im_records(im: &KeptIm) -> Result<ImRecords, String> {
    let bad = |n: u8| format!("im.im{n} is not an I&M{n} block");
    Ok(ImRecords {
        im1: Im1::parse(&im.im1).map_err(|_| bad(1))?,
        im2: Im2::parse(&im.im2).map_err(|_| bad(2))?,
        im3: Im3::parse(&im.im3).map_err(|_| bad(3))?,
        im4: Im4::parse(&im.im4).map_err(|_| bad(4))?,
    })
}

/// The file's blocks of the engine's I&M records.
pub fn kept_im(records: &ImRecords) -> KeptIm {
    KeptIm {
        im1: records.im1.to_bytes().to_vec(),
        im2: records.im2.to_bytes().to_vec(),
        im3: records.im3.to_bytes().to_vec(),
        im4: records.im4.to_bytes().to_vec(),
    }
}

/// Takes what DCP set to be kept into `state`.
pub fn keep_identity(state: &mut KeptState, kept: &KeptIdentity) {
    if let Some(name) = &kept.name {
        state.name = Some(name.clone());
    }
    if let Some([ip, mask, gateway]) = kept.ip_suite {
        state.ip = Some(ip.into());
        state.netmask = Some(mask.into());
        state.gateway = Some(gateway.into());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_state_survives_the_round_trip_and_a_missing_file_is_empty() {
        let dir = std::env::temp_dir().join(format!("procimg-state-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("station.toml");
        assert_eq!(load(&path).unwrap(), KeptState::default());
        let mut state = KeptState::default();
        keep_identity(
            &mut state,
            &KeptIdentity {
                name: Some("pc-device".into()),
                ip_suite: Some([[10, 0, 0, 5], [255, 255, 255, 0], [0; 4]]),
                changes: 1,
            },
        );
        let mut records = ImRecords::default();
        records.im1.tag_function[..4].copy_from_slice(b"PUMP");
        state.im = Some(kept_im(&records));
        save(&path, &state).unwrap();
        let back = load(&path).unwrap();
        assert_eq!(back, state);
        assert_eq!(im_records(back.im.as_ref().unwrap()).unwrap(), records);
        assert!(!dir.join("station.toml.tmp").exists());

        std::fs::write(&path, "name = 7\n").unwrap();
        let e = load(&path).unwrap_err().to_string();
        assert!(e.contains("station.toml") && e.contains("remove it"), "{e}");
        std::fs::write(&path, "ip = \"10.0.0.5\"\nnetmask = \"255.0.255.0\"\n").unwrap();
        let e = load(&path).unwrap_err().to_string();
        assert!(e.contains("netmask 255.0.255.0"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
