// SPDX-License-Identifier: MIT OR Apache-2.0
//! Writing a GSDML file to disk so that whoever reads it (an engineering tool importing it,
//! procimgd loading its station's file) finds the old file or the whole new one, never a
//! part: what every program that writes one (`procimg gsdml`, `procimg-gs20 gsdml`) does.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::StationGsdml;

/// Why a GSDML file was not written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The path names no file (`.`, `..`, `/`).
    #[error("{}: give a file name, not a directory", path.display())]
    NotAFile {
        /// The path given.
        path: PathBuf,
    },
    /// Creating, writing or renaming the file failed.
    #[error(
        "cannot write {}: {error}; check that the directory {} exists and is writable",
        path.display(),
        dir.display()
    )]
    Io {
        /// The path given.
        path: PathBuf,
        /// Its directory.
        dir: PathBuf,
        /// What the system said. Not the error's source: the message already shows it.
        error: std::io::Error,
    },
    /// Writing to standard output failed.
    #[error("cannot write the file to standard output: {0}")]
    Stdout(std::io::Error),
}

/// Where a program puts the file it made: a file (`-o FILE`), a directory under the file's
/// standard name (`-d DIR`), or standard output (neither).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Destination {
    /// This file.
    File(PathBuf),
    /// This directory, under the file's standard name.
    Dir(PathBuf),
    /// Standard output.
    Stdout,
}

impl Destination {
    /// The destination of the options `-o FILE` and `-d DIR` (the file if both).
    pub fn of(file: Option<PathBuf>, dir: Option<PathBuf>) -> Destination {
        match (file, dir) {
            (Some(file), _) => Destination::File(file),
            (None, Some(dir)) => Destination::Dir(dir),
            (None, None) => Destination::Stdout,
        }
    }
}

impl StationGsdml {
    /// Puts the file's text at `to` (a file as [`write`](Self::write) does); the path
    /// written, or `None` for standard output.
    pub fn deliver(&self, to: Destination) -> Result<Option<PathBuf>, WriteError> {
        let path = match to {
            Destination::File(file) => file,
            Destination::Dir(dir) => dir.join(&self.file_name),
            Destination::Stdout => {
                let mut out = std::io::stdout().lock();
                out.write_all(self.xml.as_bytes())
                    .and_then(|()| out.flush())
                    .map_err(WriteError::Stdout)?;
                return Ok(None);
            }
        };
        self.write(&path)?;
        Ok(Some(path))
    }

    /// Writes the file's text to `path`, replacing the file there: to a temporary file
    /// beside it first (same directory, so the rename cannot cross file systems), then
    /// renamed over it. A temporary file left by a failure is removed.
    pub fn write(&self, path: &Path) -> Result<(), WriteError> {
        let Some(name) = path.file_name() else {
            return Err(WriteError::NotAFile {
                path: path.to_path_buf(),
            });
        };
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        let mut temporary = name.to_os_string();
        temporary.push(format!(".{}.tmp", std::process::id()));
        let temporary = dir.join(temporary);
        let written = (|| {
            let mut file = std::fs::File::create(&temporary)?;
            file.write_all(self.xml.as_bytes())?;
            file.sync_all()?;
            std::fs::rename(&temporary, path)
        })();
        written.map_err(|error| {
            let _ = std::fs::remove_file(&temporary);
            WriteError::Io {
                path: path.to_path_buf(),
                dir: dir.to_path_buf(),
                error,
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(xml: &str) -> StationGsdml {
        StationGsdml {
            file_name: "GSDML-V2.4-procimg-test-20250131.xml".to_owned(),
            xml: xml.to_owned(),
        }
    }

    #[test]
    fn replaces_the_file_and_leaves_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.xml");
        std::fs::write(&path, "old").unwrap();
        file("<new/>").write(&path).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "<new/>");
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["out.xml"]);
    }

    #[test]
    fn says_what_to_do_when_it_cannot() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("no-such-dir").join("out.xml");
        let e = file("<x/>").write(&missing).unwrap_err();
        let shown = e.to_string();
        assert!(
            shown.contains("exists and is writable") && shown.contains("no-such-dir"),
            "{shown}"
        );
        let e = file("<x/>").write(Path::new("..")).unwrap_err();
        assert!(
            e.to_string().contains("give a file name, not a directory"),
            "{e}"
        );
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
