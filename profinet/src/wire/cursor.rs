// SPDX-License-Identifier: MIT OR Apache-2.0
//! Bounds-checked reading and writing of big-endian fields, shared by the block codecs:
//! reads past the end give [`Error`], writes past it [`EmitError`], never a panic.

use super::{BlockType, EmitError, EmitResult, Error, MacAddress, Result, Uuid, be16, be32};

/// Reads fields from the front of a byte slice.
pub(crate) struct Reader<'a> {
    b: &'a [u8],
}

impl<'a> Reader<'a> {
    pub(crate) const fn new(b: &'a [u8]) -> Reader<'a> {
        Reader { b }
    }

    pub(crate) fn take(&mut self, n: usize) -> Result<&'a [u8]> {
        let (head, rest) = self.b.split_at_checked(n).ok_or(Error)?;
        self.b = rest;
        Ok(head)
    }

    pub(crate) fn array<const N: usize>(&mut self) -> Result<[u8; N]> {
        self.take(N)?.try_into().map_err(|_| Error)
    }

    pub(crate) fn u8(&mut self) -> Result<u8> {
        self.array::<1>().map(|[b]| b)
    }

    pub(crate) fn u16(&mut self) -> Result<u16> {
        self.take(2).map(be16)
    }

    pub(crate) fn u32(&mut self) -> Result<u32> {
        self.take(4).map(be32)
    }

    /// A UUID in block (big-endian) order.
    pub(crate) fn uuid(&mut self) -> Result<Uuid> {
        self.array().map(Uuid)
    }

    pub(crate) fn mac(&mut self) -> Result<MacAddress> {
        self.take(6).map(MacAddress::from_slice)
    }

    /// A u16 length followed by that many bytes of UTF-8.
    pub(crate) fn string(&mut self) -> Result<String> {
        let n = self.u16()?;
        let s = self.take(usize::from(n))?;
        core::str::from_utf8(s)
            .map(str::to_owned)
            .map_err(|_| Error)
    }

    /// A u16 count followed by that many items.
    pub(crate) fn list<T>(
        &mut self,
        mut item: impl FnMut(&mut Reader<'a>) -> Result<T>,
    ) -> Result<Vec<T>> {
        let n = self.u16()?;
        let mut v = Vec::new();
        for _ in 0..n {
            v.push(item(self)?);
        }
        Ok(v)
    }

    pub(crate) const fn is_empty(&self) -> bool {
        self.b.is_empty()
    }

    /// `Ok` when everything was read.
    pub(crate) fn end(&self) -> Result<()> {
        if self.b.is_empty() {
            Ok(())
        } else {
            Err(Error)
        }
    }

    pub(crate) const fn rest(&self) -> &'a [u8] {
        self.b
    }
}

/// Writes fields into a byte slice from its front.
pub(crate) struct Writer<'a> {
    /// What is being written, for the errors.
    what: &'static str,
    buf: &'a mut [u8],
    pos: usize,
}

impl<'a> Writer<'a> {
    /// A writer of `what` (named in its errors) into `buf`.
    pub(crate) const fn new(what: &'static str, buf: &'a mut [u8]) -> Writer<'a> {
        Writer { what, buf, pos: 0 }
    }

    /// Bytes written so far.
    pub(crate) const fn position(&self) -> usize {
        self.pos
    }

    /// The next `n` bytes, to be filled by the caller.
    pub(crate) fn reserve(&mut self, n: usize) -> EmitResult<&mut [u8]> {
        let len = self.buf.len();
        let short = EmitError::BufferTooShort {
            what: self.what,
            needed: self.pos.saturating_add(n),
            len,
        };
        let end = self.pos.checked_add(n).ok_or(short)?;
        let b = self.buf.get_mut(self.pos..end).ok_or(short)?;
        self.pos = end;
        Ok(b)
    }

    pub(crate) fn put(&mut self, bytes: &[u8]) -> EmitResult<()> {
        self.reserve(bytes.len())?.copy_from_slice(bytes);
        Ok(())
    }

    pub(crate) fn zeros(&mut self, n: usize) -> EmitResult<()> {
        self.reserve(n)?.fill(0);
        Ok(())
    }

    pub(crate) fn u8(&mut self, v: u8) -> EmitResult<()> {
        self.put(&[v])
    }

    pub(crate) fn u16(&mut self, v: u16) -> EmitResult<()> {
        self.put(&v.to_be_bytes())
    }

    pub(crate) fn u32(&mut self, v: u32) -> EmitResult<()> {
        self.put(&v.to_be_bytes())
    }

    /// The 16-bit count `field` of `n` items.
    pub(crate) fn count(&mut self, field: &'static str, n: usize) -> EmitResult<()> {
        self.u16(u16::try_from(n).map_err(|_| EmitError::too_long_u16(field, n))?)
    }

    /// The u16 length `field` and the string's bytes.
    pub(crate) fn string(&mut self, field: &'static str, s: &str) -> EmitResult<()> {
        self.count(field, s.len())?;
        self.put(s.as_bytes())
    }

    /// A v1.0 block header for a body of `body_len` bytes.
    pub(crate) fn block_header(
        &mut self,
        block_type: BlockType,
        body_len: usize,
    ) -> EmitResult<()> {
        let h = super::BlockHeader::v1(block_type, body_len)?;
        self.put(&h.to_bytes())
    }

    /// `Ok` when the buffer was filled exactly.
    pub(crate) fn finish(self) -> EmitResult<()> {
        if self.pos == self.buf.len() {
            Ok(())
        } else {
            Err(EmitError::LengthMismatch {
                what: self.what,
                computed: self.buf.len(),
                written: self.pos,
            })
        }
    }
}
