// SPDX-License-Identifier: MIT OR Apache-2.0
//! The users file: who may open a session with a user name and password, and with which role
//! (`reader`: read and subscribe; `writer`: also write outputs). Passwords are stored as
//! salted Argon2id hashes (PHC strings), never in clear; `procimg-opcua user add FILE NAME`
//! writes an entry, the password read from standard input.
//!
//! ```toml
//! [[user]]
//! name = "operator"
//! role = "writer"
//! hash = "$argon2id$v=19$m=19456,t=2,p=1$…"
//! ```

use argon2::Argon2;
use argon2::password_hash::rand_core::OsRng;
use argon2::password_hash::{PasswordHash, PasswordHasher, PasswordVerifier, SaltString};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// What a user may do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    /// Read, browse, subscribe.
    Reader,
    /// And write outputs.
    Writer,
}

/// One entry of the file.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct User {
    /// The user name a session gives.
    pub name: String,
    /// What the user may do.
    pub role: Role,
    /// The salted hash of the password (PHC string).
    pub hash: String,
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    #[serde(default)]
    user: Vec<User>,
}

/// The users of a server.
#[derive(Debug, Default)]
pub struct Users {
    users: Vec<User>,
}

/// Why the users file cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum UsersError {
    /// It cannot be read or written.
    #[error("{path}: {source}; check the path and its permissions")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// It is not a users file.
    #[error("{path}: not a users file ({why}); write it with `procimg-opcua user add FILE NAME`")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        why: String,
    },
    /// A user name that cannot be.
    #[error("user name {0:?}: give 1 to 64 characters, no control characters")]
    BadName(String),
    /// An empty password.
    #[error("the password is empty: give it on standard input")]
    EmptyPassword,
    /// Hashing failed.
    #[error("cannot hash the password: {0}")]
    Hash(String),
}

impl Users {
    /// Reads the file at `path`.
    pub fn load(path: &Path) -> Result<Users, UsersError> {
        let text = std::fs::read_to_string(path).map_err(|source| UsersError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let file: File = toml::from_str(&text).map_err(|e| UsersError::Format {
            path: path.to_path_buf(),
            why: e.message().to_owned(),
        })?;
        for u in &file.user {
            PasswordHash::new(&u.hash).map_err(|e| UsersError::Format {
                path: path.to_path_buf(),
                why: format!("user {:?}: the hash is no PHC string ({e})", u.name),
            })?;
        }
        Ok(Users { users: file.user })
    }

    /// The role of `name` if `password` is theirs.
    pub fn verify(&self, name: &str, password: &str) -> Option<Role> {
        let user = self.users.iter().find(|u| u.name == name)?;
        let hash = PasswordHash::new(&user.hash).ok()?;
        Argon2::default()
            .verify_password(password.as_bytes(), &hash)
            .ok()
            .map(|()| user.role)
    }

    /// The role of user `name`.
    pub fn role(&self, name: &str) -> Option<Role> {
        self.users.iter().find(|u| u.name == name).map(|u| u.role)
    }

    /// Whether there are users.
    pub fn is_empty(&self) -> bool {
        self.users.is_empty()
    }
}

/// Adds (or replaces) user `name` with `role` and `password` in the file at `path`, made if
/// it does not exist, readable by its owner only.
pub fn add(path: &Path, name: &str, role: Role, password: &str) -> Result<(), UsersError> {
    if name.is_empty() || name.chars().count() > 64 || name.chars().any(char::is_control) {
        return Err(UsersError::BadName(name.to_owned()));
    }
    if password.is_empty() {
        return Err(UsersError::EmptyPassword);
    }
    let mut file = if path.exists() {
        let text = std::fs::read_to_string(path).map_err(|source| UsersError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        toml::from_str::<File>(&text).map_err(|e| UsersError::Format {
            path: path.to_path_buf(),
            why: e.message().to_owned(),
        })?
    } else {
        File::default()
    };
    let salt = SaltString::generate(&mut OsRng);
    let hash = Argon2::default()
        .hash_password(password.as_bytes(), &salt)
        .map_err(|e| UsersError::Hash(e.to_string()))?
        .to_string();
    file.user.retain(|u| u.name != name);
    file.user.push(User {
        name: name.to_owned(),
        role,
        hash,
    });
    let text = toml::to_string(&file).map_err(|e| UsersError::Hash(e.to_string()))?;
    let io = |source| UsersError::Io {
        path: path.to_path_buf(),
        source,
    };
    {
        use std::io::Write;
        use std::os::unix::fs::OpenOptionsExt;
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .mode(0o600)
            .open(path)
            .map_err(io)?;
        f.write_all(b"# procimg-opcua users: procimg-opcua user add FILE NAME [--role writer]\n")
            .map_err(io)?;
        f.write_all(text.as_bytes()).map_err(io)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_user_added_is_verified_by_password_and_stored_salted() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("users.toml");
        add(&path, "operator", Role::Writer, "s3cret").unwrap();
        add(&path, "viewer", Role::Reader, "look").unwrap();
        add(&path, "viewer", Role::Reader, "look2").unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            !text.contains("s3cret") && text.contains("$argon2id$"),
            "{text}"
        );
        let users = Users::load(&path).unwrap();
        assert_eq!(users.verify("operator", "s3cret"), Some(Role::Writer));
        assert_eq!(users.verify("operator", "wrong"), None);
        assert_eq!(users.verify("viewer", "look"), None, "replaced");
        assert_eq!(users.verify("viewer", "look2"), Some(Role::Reader));
        assert_eq!(users.verify("nobody", "s3cret"), None);
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(&path).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o600);
        assert!(matches!(
            add(&path, "", Role::Reader, "x"),
            Err(UsersError::BadName(_))
        ));
        assert!(matches!(
            add(&path, "x", Role::Reader, ""),
            Err(UsersError::EmptyPassword)
        ));
        std::fs::write(
            &path,
            "[[user]]\nname = \"a\"\nrole = \"writer\"\nhash = \"plain\"\n",
        )
        .unwrap();
        assert!(matches!(Users::load(&path), Err(UsersError::Format { .. })));
    }
}
