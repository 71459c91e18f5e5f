// SPDX-License-Identifier: MIT OR Apache-2.0
//! SearchRanges (RFC 2741 §5.2): where a Get, GetNext or GetBulk looks.
//!
//! ```text
//! start (OID, its include byte the flag)  end (OID, include 0)
//! ```
//!
//! A SearchRangeList is SearchRanges up to the end of the payload.

use super::codec::{Reader, Writer};
use super::{EmitError, Oid, ParseError};

/// The range a request searches: from `start` (itself included when `include` is set) up
/// to, but not including, `end`; a null `end` is unbounded.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct SearchRange {
    /// The first OID of the range.
    pub start: Oid,
    /// Whether `start` itself is in the range.
    pub include: bool,
    /// The first OID after the range; null for no end.
    pub end: Oid,
}

impl SearchRange {
    /// Whether `oid` lies in the range.
    pub fn contains(&self, oid: &Oid) -> bool {
        let after_start = if self.include {
            *oid >= self.start
        } else {
            *oid > self.start
        };
        after_start && (self.end.is_null() || *oid < self.end)
    }

    pub(crate) fn wire_len(&self) -> usize {
        self.start.wire_len() + self.end.wire_len()
    }

    pub(crate) fn read(r: &mut Reader<'_>) -> Result<SearchRange, ParseError> {
        let (start, include) = Oid::read(r)?;
        let (end, _) = Oid::read(r)?;
        Ok(SearchRange {
            start,
            include,
            end,
        })
    }

    pub(crate) fn write(&self, w: &mut Writer<'_>) -> Result<(), EmitError> {
        self.start.write(self.include, w)?;
        self.end.write(false, w)
    }

    pub(crate) fn read_list(r: &mut Reader<'_>) -> Result<Vec<SearchRange>, ParseError> {
        let mut list = Vec::new();
        while !r.is_empty() {
            list.push(SearchRange::read(r)?);
        }
        Ok(list)
    }

    pub(crate) fn list_len(list: &[SearchRange]) -> usize {
        list.iter().map(SearchRange::wire_len).sum()
    }

    pub(crate) fn write_list(list: &[SearchRange], w: &mut Writer<'_>) -> Result<(), EmitError> {
        list.iter().try_for_each(|s| s.write(w))
    }
}
