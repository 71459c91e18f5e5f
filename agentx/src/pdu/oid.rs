// SPDX-License-Identifier: MIT OR Apache-2.0
//! Object identifiers and their AgentX encoding (RFC 2741 §5.1).
//!
//! ```text
//! n_subid (1)  prefix (1)  include (1)  reserved (1)  subidentifier × n_subid (4 each)
//! ```
//!
//! An OID that starts `1.3.6.1.x` with `x` in 1..=255 is sent with `prefix = x` and only
//! the subidentifiers after it; prefix 0 sends them all. The null OID is `n_subid = 0,
//! prefix = 0`. `include` is the SearchRange flag (RFC 2741 §5.2) and 0 elsewhere.

use core::fmt;
use core::str::FromStr;

use super::EmitError;
use super::ParseError;
use super::codec::{Reader, Writer};

/// The internet prefix that the `prefix` byte stands for.
const INTERNET: [u32; 4] = [1, 3, 6, 1];

/// An object identifier: a sequence of 32-bit subidentifiers. Ordered as SNMP orders
/// OIDs (lexicographically, a prefix before its extensions), which is what GetNext walks.
/// The empty OID is AgentX's null OID.
#[derive(Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Oid(Vec<u32>);

impl Oid {
    /// The OID of these subidentifiers.
    pub fn new(subids: impl Into<Vec<u32>>) -> Oid {
        Oid(subids.into())
    }

    /// The null OID (no subidentifiers).
    pub const fn null() -> Oid {
        Oid(Vec::new())
    }

    /// The subidentifiers.
    pub fn as_slice(&self) -> &[u32] {
        &self.0
    }

    /// Whether this is the null OID.
    pub fn is_null(&self) -> bool {
        self.0.is_empty()
    }

    /// Whether `prefix`'s subidentifiers begin this OID (an OID starts with itself).
    pub fn starts_with(&self, prefix: &[u32]) -> bool {
        self.0.starts_with(prefix)
    }

    /// This OID with `suffix` appended.
    pub fn child(&self, suffix: &[u32]) -> Oid {
        let mut v = Vec::with_capacity(self.0.len() + suffix.len());
        v.extend_from_slice(&self.0);
        v.extend_from_slice(suffix);
        Oid(v)
    }

    /// The prefix byte and the subidentifiers sent after it.
    fn compressed(&self) -> (u8, &[u32]) {
        match self.0.split_at_checked(INTERNET.len() + 1) {
            Some((head, rest)) if head[..INTERNET.len()] == INTERNET => {
                match u8::try_from(head[INTERNET.len()]) {
                    Ok(prefix) if prefix != 0 => (prefix, rest),
                    _ => (0, &self.0),
                }
            }
            _ => (0, &self.0),
        }
    }

    /// The encoded length: 4 bytes and 4 per subidentifier sent.
    pub(crate) fn wire_len(&self) -> usize {
        4 + 4 * self.compressed().1.len()
    }

    /// Reads an encoded OID and its include flag.
    pub(crate) fn read(r: &mut Reader<'_>) -> Result<(Oid, bool), ParseError> {
        const FIELD: &str = "object identifier";
        let n_subid = r.u8(FIELD)?;
        let prefix = r.u8(FIELD)?;
        let include = r.u8(FIELD)? != 0;
        r.u8(FIELD)?;
        let mut subids = Vec::with_capacity(usize::from(n_subid) + 5);
        if prefix != 0 {
            subids.extend_from_slice(&INTERNET);
            subids.push(u32::from(prefix));
        }
        for _ in 0..n_subid {
            subids.push(r.u32(FIELD)?);
        }
        Ok((Oid(subids), include))
    }

    /// Writes the OID, compressed where it can be, with its include flag.
    pub(crate) fn write(&self, include: bool, w: &mut Writer<'_>) -> Result<(), EmitError> {
        let (prefix, rest) = self.compressed();
        let n_subid = u8::try_from(rest.len()).map_err(|_| EmitError::OidTooLong(self.0.len()))?;
        w.u8(n_subid)?;
        w.u8(prefix)?;
        w.u8(u8::from(include))?;
        w.u8(0)?;
        rest.iter().try_for_each(|s| w.u32(*s))
    }
}

impl From<&[u32]> for Oid {
    fn from(subids: &[u32]) -> Oid {
        Oid(subids.to_vec())
    }
}

impl<const N: usize> From<[u32; N]> for Oid {
    fn from(subids: [u32; N]) -> Oid {
        Oid(subids.to_vec())
    }
}

impl fmt::Display for Oid {
    /// Dotted decimal, `1.3.6.1.2.1.1.5.0`; the null OID as the empty text.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, s) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(".")?;
            }
            write!(f, "{s}")?;
        }
        Ok(())
    }
}

/// A text that is not a dotted-decimal OID.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{0:?} is not a dotted-decimal OID (like 1.3.6.1.2.1.1.5.0): write numbers 0 to 4294967295 between dots"
)]
pub struct OidParseError(pub String);

impl FromStr for Oid {
    type Err = OidParseError;

    /// Parses `1.3.6.1.2.1.1`, with or without a leading dot; the empty text is the null
    /// OID.
    fn from_str(s: &str) -> Result<Oid, OidParseError> {
        let digits = s.strip_prefix('.').unwrap_or(s);
        if digits.is_empty() {
            return Ok(Oid::null());
        }
        digits
            .split('.')
            .map(|part| part.parse::<u32>())
            .collect::<Result<Vec<_>, _>>()
            .map(Oid)
            .map_err(|_| OidParseError(s.to_owned()))
    }
}
