// SPDX-License-Identifier: MIT OR Apache-2.0
//! The byte format of the targets that take a sequence of operations (`controller`,
//! `device`, `rta_channel`): an operation is one opcode byte followed by its arguments,
//! big-endian integers and byte strings with a u16 length. A truncated argument ends the
//! sequence, so every input means something and libFuzzer's mutations stay meaningful.
//!
//! [`Writer`] builds the same format; `seed_corpus` uses it to write seeds that libFuzzer can
//! then mutate (e.g. turn one step into a dropped or corrupted frame).

/// Reads operations' arguments from the front of the input.
pub struct Reader<'a> {
    b: &'a [u8],
}

impl<'a> Reader<'a> {
    /// A reader over the whole input.
    pub const fn new(b: &'a [u8]) -> Reader<'a> {
        Reader { b }
    }

    /// Whether everything was read.
    pub const fn is_empty(&self) -> bool {
        self.b.is_empty()
    }

    /// One byte.
    pub fn u8(&mut self) -> Option<u8> {
        let (&v, rest) = self.b.split_first()?;
        self.b = rest;
        Some(v)
    }

    /// A big-endian u16.
    pub fn u16(&mut self) -> Option<u16> {
        Some(u16::from_be_bytes([self.u8()?, self.u8()?]))
    }

    /// A big-endian u32.
    pub fn u32(&mut self) -> Option<u32> {
        Some(u32::from_be_bytes([
            self.u8()?,
            self.u8()?,
            self.u8()?,
            self.u8()?,
        ]))
    }

    /// A byte string: a u16 length, then that many bytes, or fewer if the input ends first
    /// (a mutation that cuts a frame still delivers the cut frame).
    pub fn bytes(&mut self) -> Option<&'a [u8]> {
        let n = usize::from(self.u16()?);
        let (head, rest) = self.b.split_at(n.min(self.b.len()));
        self.b = rest;
        Some(head)
    }
}

/// Writes operations in the format [`Reader`] reads.
#[derive(Default)]
pub struct Writer {
    out: Vec<u8>,
}

impl Writer {
    /// An empty sequence.
    pub fn new() -> Writer {
        Writer::default()
    }

    /// One byte (an opcode or a byte argument).
    pub fn u8(&mut self, v: u8) -> &mut Writer {
        self.out.push(v);
        self
    }

    /// A big-endian u16.
    pub fn u16(&mut self, v: u16) -> &mut Writer {
        self.out.extend_from_slice(&v.to_be_bytes());
        self
    }

    /// A big-endian u32.
    pub fn u32(&mut self, v: u32) -> &mut Writer {
        self.out.extend_from_slice(&v.to_be_bytes());
        self
    }

    /// A byte string with its u16 length (cut to 65535 bytes).
    pub fn bytes(&mut self, b: &[u8]) -> &mut Writer {
        let b = &b[..b.len().min(usize::from(u16::MAX))];
        self.u16(b.len() as u16);
        self.out.extend_from_slice(b);
        self
    }

    /// The sequence so far.
    pub fn finish(&self) -> Vec<u8> {
        self.out.clone()
    }

    /// Bytes written so far.
    pub fn len(&self) -> usize {
        self.out.len()
    }

    /// Whether nothing was written.
    pub fn is_empty(&self) -> bool {
        self.out.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writer_and_reader_agree() {
        let mut w = Writer::new();
        w.u8(7).u16(0x1234).u32(0xdead_beef).bytes(b"abc");
        let b = w.finish();
        let mut r = Reader::new(&b);
        assert_eq!(r.u8(), Some(7));
        assert_eq!(r.u16(), Some(0x1234));
        assert_eq!(r.u32(), Some(0xdead_beef));
        assert_eq!(r.bytes(), Some(&b"abc"[..]));
        assert!(r.is_empty());
        assert_eq!(r.u8(), None);
    }

    #[test]
    fn a_cut_byte_string_is_delivered_cut() {
        let mut r = Reader::new(&[0, 9, 1, 2]);
        assert_eq!(r.bytes(), Some(&[1u8, 2][..]));
        assert_eq!(r.bytes(), None);
    }
}
