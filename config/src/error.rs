// SPDX-License-Identifier: MIT OR Apache-2.0
//! Why a configuration was refused.

use core::fmt;
use std::path::PathBuf;

use super::gsdml::GsdmlError;

/// Why a configuration could not be loaded.
///
/// Every message says where (file, 1-based line, key path such as
/// `device[1].submodule[0].input_address`) and what to do about it.
#[derive(Debug)]
pub enum ConfigError {
    /// The file could not be read.
    Read {
        /// The path as given.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// The text is not TOML, or a value has the wrong type, a required key is missing or a key
    /// is unknown.
    Syntax {
        /// Name of the file (or other origin) the text came from.
        origin: String,
        /// 1-based line of the error, where known.
        line: Option<usize>,
        /// Key path of the error, where known.
        key: Option<String>,
        /// What is wrong and what to do.
        message: String,
    },
    /// A value is well-formed but not acceptable.
    Invalid {
        /// Name of the file (or other origin) the text came from.
        origin: String,
        /// 1-based line of the offending value.
        line: usize,
        /// Key path of the offending value.
        key: String,
        /// What is wrong and what to do.
        message: String,
    },
    /// A GSDML file the configuration names cannot be read or has something the import
    /// cannot use.
    Gsdml {
        /// Name of the configuration file (or other origin).
        origin: String,
        /// 1-based line of the key that led to the GSDML file (`gsdml`, `module`).
        line: usize,
        /// Key path of that key.
        key: String,
        /// What is wrong with the GSDML file, with its name and line (boxed: it is larger
        /// than the other variants).
        error: Box<GsdmlError>,
    },
    /// TIA Portal's PN Driver configuration (XML) has something the import cannot use.
    PnDriver {
        /// Name of the XML file (or other origin).
        origin: String,
        /// 1-based line of the XML element.
        line: usize,
        /// The element: its object and, where it is one, the record field.
        element: String,
        /// What is wrong and what to do.
        message: String,
    },
}

impl ConfigError {
    /// The 1-based line the error is on, if it refers to one.
    pub fn line(&self) -> Option<usize> {
        match self {
            ConfigError::Read { .. } => None,
            ConfigError::Syntax { line, .. } => *line,
            ConfigError::Invalid { line, .. }
            | ConfigError::Gsdml { line, .. }
            | ConfigError::PnDriver { line, .. } => Some(*line),
        }
    }

    /// The key path the error is about (`cycle_time`, `device[1].submodule[0].input_address`),
    /// if it refers to one.
    pub fn key(&self) -> Option<&str> {
        match self {
            ConfigError::Read { .. } => None,
            ConfigError::Syntax { key, .. } => key.as_deref(),
            ConfigError::Invalid { key, .. } | ConfigError::Gsdml { key, .. } => Some(key),
            ConfigError::PnDriver { element, .. } => Some(element),
        }
    }

    /// The file name (or other origin) the error is in.
    pub fn origin(&self) -> String {
        match self {
            ConfigError::Read { path, .. } => path.display().to_string(),
            ConfigError::Syntax { origin, .. }
            | ConfigError::Invalid { origin, .. }
            | ConfigError::Gsdml { origin, .. }
            | ConfigError::PnDriver { origin, .. } => origin.clone(),
        }
    }

    /// What is wrong and what to do, without file, line and key.
    pub fn message(&self) -> String {
        match self {
            ConfigError::Read { path, source } => format!(
                "cannot read the configuration: {source}; {}",
                read_hint(path, source)
            ),
            ConfigError::Syntax { message, .. }
            | ConfigError::Invalid { message, .. }
            | ConfigError::PnDriver { message, .. } => message.clone(),
            ConfigError::Gsdml { error, .. } => error.to_string(),
        }
    }
}

/// What to do when the configuration file at `path` cannot be read.
fn read_hint(path: &std::path::Path, source: &std::io::Error) -> String {
    match source.kind() {
        std::io::ErrorKind::NotFound => format!(
            "check the path, or start from the commented example: `procimgd \
             --print-demo-config > {}`",
            path.display()
        ),
        std::io::ErrorKind::PermissionDenied => {
            "check the file's permissions: procimgd must be able to read it".to_owned()
        }
        std::io::ErrorKind::IsADirectory => {
            "give the configuration file, not its directory".to_owned()
        }
        _ => "check the path and its permissions".to_owned(),
    }
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ConfigError::Read { path, source } => write!(
                f,
                "cannot read {}: {source}; {}",
                path.display(),
                read_hint(path, source)
            ),
            ConfigError::Syntax {
                origin,
                line,
                key,
                message,
            } => {
                f.write_str(origin)?;
                if let Some(line) = line {
                    write!(f, ":{line}")?;
                }
                if let Some(key) = key {
                    write!(f, ": {key}")?;
                }
                write!(f, ": {message}")
            }
            ConfigError::Invalid {
                origin,
                line,
                key,
                message,
            } => write!(f, "{origin}:{line}: {key}: {message}"),
            ConfigError::Gsdml {
                origin,
                line,
                key,
                error,
            } => write!(f, "{origin}:{line}: {key}: {error}"),
            ConfigError::PnDriver {
                origin,
                line,
                element,
                message,
            } => write!(f, "{origin}:{line}: {element}: {message}"),
        }
    }
}

// No `source`: every message already holds what the operating system or the GSDML file said,
// and error chains (anyhow's `{:#}`) would print it twice. The cause stays in the variants'
// fields.
impl core::error::Error for ConfigError {}
