// SPDX-License-Identifier: MIT OR Apache-2.0
//! Bounds-checked reading and writing of fields in a PDU's byte order: reads past the end
//! give [`ParseError::Truncated`], writes past it [`EmitError::BufferTooShort`], never a
//! panic. The OID, octet string and VarBind codecs are built on these.

use super::{ByteOrder, EmitError, ParseError};

/// Reads fields from the front of a byte slice.
pub(crate) struct Reader<'a> {
    bytes: &'a [u8],
    order: ByteOrder,
}

impl<'a> Reader<'a> {
    pub(crate) const fn new(bytes: &'a [u8], order: ByteOrder) -> Reader<'a> {
        Reader { bytes, order }
    }

    /// The next `n` bytes; `field` names what they hold, for the error.
    pub(crate) fn take(&mut self, n: usize, field: &'static str) -> Result<&'a [u8], ParseError> {
        let (head, rest) = self
            .bytes
            .split_at_checked(n)
            .ok_or(ParseError::Truncated { field })?;
        self.bytes = rest;
        Ok(head)
    }

    fn array<const N: usize>(&mut self, field: &'static str) -> Result<[u8; N], ParseError> {
        let bytes = self.take(N, field)?;
        bytes
            .try_into()
            .map_err(|_| ParseError::Truncated { field })
    }

    pub(crate) fn u8(&mut self, field: &'static str) -> Result<u8, ParseError> {
        self.array::<1>(field).map(|[b]| b)
    }

    pub(crate) fn u16(&mut self, field: &'static str) -> Result<u16, ParseError> {
        let b = self.array(field)?;
        Ok(match self.order {
            ByteOrder::Big => u16::from_be_bytes(b),
            ByteOrder::Little => u16::from_le_bytes(b),
        })
    }

    pub(crate) fn u32(&mut self, field: &'static str) -> Result<u32, ParseError> {
        let b = self.array(field)?;
        Ok(match self.order {
            ByteOrder::Big => u32::from_be_bytes(b),
            ByteOrder::Little => u32::from_le_bytes(b),
        })
    }

    pub(crate) fn u64(&mut self, field: &'static str) -> Result<u64, ParseError> {
        let b = self.array(field)?;
        Ok(match self.order {
            ByteOrder::Big => u64::from_be_bytes(b),
            ByteOrder::Little => u64::from_le_bytes(b),
        })
    }

    /// An octet string (RFC 2741 §5.3): a 32-bit length, the octets, and padding up to a
    /// multiple of 4 (whose values are ignored).
    pub(crate) fn octets(&mut self, field: &'static str) -> Result<&'a [u8], ParseError> {
        let len = self.u32(field)?;
        let len = usize::try_from(len).map_err(|_| ParseError::Truncated { field })?;
        let octets = self.take(len, field)?;
        self.take(padding(len), field)?;
        Ok(octets)
    }

    pub(crate) const fn is_empty(&self) -> bool {
        self.bytes.is_empty()
    }
}

/// Writes fields into a byte slice from its front.
pub(crate) struct Writer<'a> {
    bytes: &'a mut [u8],
    pos: usize,
    order: ByteOrder,
}

impl<'a> Writer<'a> {
    pub(crate) const fn new(bytes: &'a mut [u8], order: ByteOrder) -> Writer<'a> {
        Writer {
            bytes,
            pos: 0,
            order,
        }
    }

    /// How many bytes were written.
    pub(crate) const fn position(&self) -> usize {
        self.pos
    }

    pub(crate) fn put(&mut self, src: &[u8]) -> Result<(), EmitError> {
        let got = self.bytes.len();
        let end = self.pos.checked_add(src.len());
        let dst = end
            .and_then(|end| self.bytes.get_mut(self.pos..end))
            .ok_or(EmitError::BufferTooShort {
                needed: self.pos.saturating_add(src.len()),
                got,
            })?;
        dst.copy_from_slice(src);
        self.pos += src.len();
        Ok(())
    }

    pub(crate) fn u8(&mut self, v: u8) -> Result<(), EmitError> {
        self.put(&[v])
    }

    pub(crate) fn u16(&mut self, v: u16) -> Result<(), EmitError> {
        match self.order {
            ByteOrder::Big => self.put(&v.to_be_bytes()),
            ByteOrder::Little => self.put(&v.to_le_bytes()),
        }
    }

    pub(crate) fn u32(&mut self, v: u32) -> Result<(), EmitError> {
        match self.order {
            ByteOrder::Big => self.put(&v.to_be_bytes()),
            ByteOrder::Little => self.put(&v.to_le_bytes()),
        }
    }

    pub(crate) fn u64(&mut self, v: u64) -> Result<(), EmitError> {
        match self.order {
            ByteOrder::Big => self.put(&v.to_be_bytes()),
            ByteOrder::Little => self.put(&v.to_le_bytes()),
        }
    }

    /// An octet string: its 32-bit length, the octets, zero padding to a multiple of 4.
    pub(crate) fn octets(&mut self, octets: &[u8]) -> Result<(), EmitError> {
        let len =
            u32::try_from(octets.len()).map_err(|_| EmitError::OctetStringTooLong(octets.len()))?;
        self.u32(len)?;
        self.put(octets)?;
        self.put(&[0; 3][..padding(octets.len())])
    }
}

/// The padding after `len` octets up to a multiple of 4.
pub(crate) const fn padding(len: usize) -> usize {
    (4 - len % 4) % 4
}

/// The wire size of an octet string of `len` octets: length field, octets, padding.
pub(crate) const fn octets_len(len: usize) -> usize {
    4 + len + padding(len)
}
