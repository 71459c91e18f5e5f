// SPDX-License-Identifier: MIT OR Apache-2.0
//! The PNIO item names of the SIMATIC NET PROFINET IO OPC server, as string NodeIds: parsed,
//! written, and the bytes they name read as values and values written as bytes.
//!
//! The forms served (letters in any case):
//!
//! | item | what |
//! |---|---|
//! | `PNIO:[CTRL<n>]mode` | the controller's mode (0 OFFLINE, 1 CLEAR, 2 OPERATE) |
//! | `PNIO:[CTRL<n>]EB<addr>` | an input byte at logical address `addr` (`IB` in English) |
//! | `PNIO:[CTRL<n>]AB<addr>` | an output byte (`QB`) |
//! | `…EW`, `…ED`, `…EINT`, `…EDINT`, `…EREAL` | a word, double word, INT, DINT, REAL from `addr` |
//! | `…E<addr>.<bit>` (`EX<addr>.<bit>`) | one bit |
//! | `…EB<addr>,<count>` | `count` of them, an array |
//! | `PNIO:[CTRL<n>]EDS<addr>,DATA<index>,<len>` | record `index` of the submodule at `addr` (`ADS`: by an output address), `len` bytes |
//!
//! `n` is the CpIndex, as IO-Base names the instance (1 to 255). Multi-byte values are
//! big-endian, as in S7. `BYTE`, `WORD` and `DWORD` are accepted for `B`, `W` and `D`. The
//! forms are those of the examples in Siemens' migration guide "From PROFIBUS DP to PROFINET
//! IO" and of the S7 OPC server's item syntax the PNIO server shares; other forms of the
//! original (its STRING and CHAR formats, its status items) are not served.

use std::fmt;

/// The most bytes one item names (a record's length included): IO-Base's largest record.
pub const MAX_ITEM_BYTES: usize = 4096;

/// The controller index of an item name, 1 to 255 (IO-Base's CpIndex).
pub type Controller = u8;

/// One of the two logical address spaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Area {
    /// Inputs: `E` (German) or `I`.
    Input,
    /// Outputs: `A` (German) or `Q`.
    Output,
}

/// The letters an item was written with: the German `E`/`A` or the English `I`/`Q`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Letters {
    /// `E`, `A`.
    German,
    /// `I`, `Q`.
    English,
}

/// How an item's bytes read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// One bit (`X`, or none before `addr.bit`): Boolean.
    Bit,
    /// `B`: Byte (unsigned).
    Byte,
    /// `W`: UInt16.
    Word,
    /// `INT`: Int16.
    Int,
    /// `D`: UInt32.
    DWord,
    /// `DINT`: Int32.
    DInt,
    /// `REAL`: Float (IEEE 754 single).
    Real,
}

impl Format {
    /// Bytes of one value (a bit counts as a byte here; see [`ProcessItem::span`]).
    pub fn size(self) -> usize {
        match self {
            Format::Bit | Format::Byte => 1,
            Format::Word | Format::Int => 2,
            Format::DWord | Format::DInt | Format::Real => 4,
        }
    }

    /// Its token in a canonical name (none for a bit).
    fn token(self) -> &'static str {
        match self {
            Format::Bit => "",
            Format::Byte => "B",
            Format::Word => "W",
            Format::Int => "INT",
            Format::DWord => "D",
            Format::DInt => "DINT",
            Format::Real => "REAL",
        }
    }
}

/// Bytes (or bits) of the image by logical address.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ProcessItem {
    /// Inputs or outputs.
    pub area: Area,
    /// The letters it was written with.
    pub letters: Letters,
    /// How its bytes read.
    pub format: Format,
    /// The first byte's logical address.
    pub address: u32,
    /// The first bit (0 to 7) of a [`Format::Bit`] item; 0 otherwise.
    pub bit: u8,
    /// `,count`: an array of that many values; `None`: one value.
    pub count: Option<u16>,
}

impl ProcessItem {
    /// How many values it names.
    pub fn values(&self) -> usize {
        usize::from(self.count.unwrap_or(1))
    }

    /// The bytes it covers: the first one's logical address and how many.
    pub fn span(&self) -> (u32, usize) {
        let len = match self.format {
            Format::Bit => (usize::from(self.bit) + self.values() - 1) / 8 + 1,
            f => f.size() * self.values(),
        };
        (self.address, len)
    }
}

/// A record of a submodule, by one of its logical addresses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RecordItem {
    /// The space `address` is in (`EDS`: inputs or a diagnostic address, `ADS`: outputs).
    pub area: Area,
    /// The letters it was written with.
    pub letters: Letters,
    /// The submodule's logical address.
    pub address: u32,
    /// The record index (`DATA<index>`).
    pub index: u16,
    /// Bytes to read (`,<len>`); `None`: up to [`MAX_ITEM_BYTES`].
    pub length: Option<u16>,
}

/// What an item names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ItemKind {
    /// `mode`.
    Mode,
    /// Image bytes.
    Process(ProcessItem),
    /// A record.
    Record(RecordItem),
}

/// A parsed item name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Item {
    /// `CTRL<n>`: the instance by its CpIndex.
    pub controller: Controller,
    /// What it names.
    pub kind: ItemKind,
}

/// An item name that is not one of the served forms.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "\"{name}\" is no PNIO item: {why}; items are written PNIO:[CTRL1]EB10, PNIO:[CTRL1]AW4, PNIO:[CTRL1]E2.5, PNIO:[CTRL1]EDS10,DATA61450,10 or PNIO:[CTRL1]mode"
)]
pub struct ItemError {
    /// The name as given (at most 100 characters of it).
    pub name: String,
    /// What is wrong.
    pub why: String,
}

/// A cursor over an item name's text.
struct Cursor<'a> {
    rest: &'a str,
}

impl<'a> Cursor<'a> {
    /// Takes `word` (any case) if the text goes on with it.
    fn take(&mut self, word: &str) -> bool {
        let n = word.len();
        match self.rest.get(..n) {
            Some(head) if head.eq_ignore_ascii_case(word) => {
                self.rest = &self.rest[n..];
                true
            }
            _ => false,
        }
    }

    /// A decimal number of at most `max`.
    fn number(&mut self, what: &str, max: u64) -> Result<u64, String> {
        let digits = self.rest.bytes().take_while(u8::is_ascii_digit).count();
        if digits == 0 {
            return Err(format!("{what} expected at \"{}\"", self.rest));
        }
        let (head, tail) = self.rest.split_at(digits);
        let n = head
            .parse::<u64>()
            .ok()
            .filter(|n| *n <= max)
            .ok_or_else(|| format!("{what} {head} is more than {max}"))?;
        self.rest = tail;
        Ok(n)
    }
}

impl Item {
    /// Parses an item name.
    pub fn parse(name: &str) -> Result<Item, ItemError> {
        let err = |why: String| ItemError {
            name: name.chars().take(100).collect(),
            why,
        };
        let mut c = Cursor { rest: name };
        if !c.take("PNIO:[CTRL") {
            return Err(err("it does not start with PNIO:[CTRL".to_owned()));
        }
        let controller = c.number("the controller index", 255).map_err(err)?;
        if controller == 0 {
            return Err(err("controller indexes start at 1".to_owned()));
        }
        if !c.take("]") {
            return Err(err("\"]\" expected after the controller index".to_owned()));
        }
        let kind = Self::parse_kind(&mut c).map_err(err)?;
        if !c.rest.is_empty() {
            return Err(err(format!("\"{}\" follows the item", c.rest)));
        }
        Ok(Item {
            controller: controller as u8,
            kind,
        })
    }

    fn parse_kind(c: &mut Cursor<'_>) -> Result<ItemKind, String> {
        if c.take("mode") {
            return Ok(ItemKind::Mode);
        }
        let (area, letters) = if c.take("E") {
            (Area::Input, Letters::German)
        } else if c.take("I") {
            (Area::Input, Letters::English)
        } else if c.take("A") {
            (Area::Output, Letters::German)
        } else if c.take("Q") {
            (Area::Output, Letters::English)
        } else {
            return Err(format!(
                "the area E (I) or A (Q), or mode, expected at \"{}\"",
                c.rest
            ));
        };
        let max_address = u64::from(u32::MAX - 1);
        if c.take("DS") {
            let address = c.number("the address", max_address)? as u32;
            if !c.take(",DATA") {
                return Err(format!(",DATA<index> expected at \"{}\"", c.rest));
            }
            let index = c.number("the record index", u64::from(u16::MAX))? as u16;
            let length = if c.take(",") {
                let n = c.number("the length", MAX_ITEM_BYTES as u64)?;
                if n == 0 {
                    return Err("a record item's length is at least 1".to_owned());
                }
                Some(n as u16)
            } else {
                None
            };
            return Ok(ItemKind::Record(RecordItem {
                area,
                letters,
                address,
                index,
                length,
            }));
        }
        // Longest tokens first: DINT before D, DWORD before D, BYTE before B.
        let format = [
            ("DINT", Format::DInt),
            ("DWORD", Format::DWord),
            ("INT", Format::Int),
            ("REAL", Format::Real),
            ("BYTE", Format::Byte),
            ("WORD", Format::Word),
            ("B", Format::Byte),
            ("W", Format::Word),
            ("D", Format::DWord),
            ("X", Format::Bit),
        ]
        .into_iter()
        .find(|(token, _)| c.take(token))
        .map(|(_, f)| f);
        let address = c.number("the address", max_address)? as u32;
        let format = match format {
            Some(f) => f,
            None if c.rest.starts_with('.') => Format::Bit,
            None => {
                return Err(format!(
                    "a format (B, W, D, INT, DINT, REAL, X) or .<bit> expected after the area \
                     at address {address}"
                ));
            }
        };
        let bit = if format == Format::Bit {
            if !c.take(".") {
                return Err(format!(
                    "a bit item is written <address>.<bit>: .0 to .7 after {address}"
                ));
            }
            c.number("the bit", 7)? as u8
        } else {
            0
        };
        let count = if c.take(",") {
            let n = c.number("the count", u64::from(u16::MAX))?;
            if n == 0 {
                return Err("an array has at least one value".to_owned());
            }
            Some(n as u16)
        } else {
            None
        };
        let item = ProcessItem {
            area,
            letters,
            format,
            address,
            bit,
            count,
        };
        let (first, len) = item.span();
        if len > MAX_ITEM_BYTES {
            return Err(format!(
                "it covers {len} bytes, more than the {MAX_ITEM_BYTES} one item may"
            ));
        }
        if u64::from(first) + len as u64 > u64::from(u32::MAX) {
            return Err("it runs past the end of the address space".to_owned());
        }
        Ok(ItemKind::Process(item))
    }
}

fn area_letter(area: Area, letters: Letters) -> char {
    match (area, letters) {
        (Area::Input, Letters::German) => 'E',
        (Area::Input, Letters::English) => 'I',
        (Area::Output, Letters::German) => 'A',
        (Area::Output, Letters::English) => 'Q',
    }
}

impl fmt::Display for Item {
    /// The canonical name: what [`Item::parse`] reads back as the same item.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "PNIO:[CTRL{}]", self.controller)?;
        match self.kind {
            ItemKind::Mode => f.write_str("mode"),
            ItemKind::Process(p) => {
                let area = area_letter(p.area, p.letters);
                match p.format {
                    Format::Bit => write!(f, "{area}{}.{}", p.address, p.bit)?,
                    other => write!(f, "{area}{}{}", other.token(), p.address)?,
                }
                if let Some(n) = p.count {
                    write!(f, ",{n}")?;
                }
                Ok(())
            }
            ItemKind::Record(r) => {
                let area = area_letter(r.area, r.letters);
                write!(f, "{area}DS{},DATA{}", r.address, r.index)?;
                if let Some(n) = r.length {
                    write!(f, ",{n}")?;
                }
                Ok(())
            }
        }
    }
}

/// Values of a process item, one of each format.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    /// [`Format::Bit`].
    Bits(Vec<bool>),
    /// [`Format::Byte`].
    Bytes(Vec<u8>),
    /// [`Format::Word`].
    Words(Vec<u16>),
    /// [`Format::Int`].
    Ints(Vec<i16>),
    /// [`Format::DWord`].
    DWords(Vec<u32>),
    /// [`Format::DInt`].
    DInts(Vec<i32>),
    /// [`Format::Real`].
    Reals(Vec<f32>),
}

impl Values {
    /// How many values.
    pub fn len(&self) -> usize {
        match self {
            Values::Bits(v) => v.len(),
            Values::Bytes(v) => v.len(),
            Values::Words(v) => v.len(),
            Values::Ints(v) => v.len(),
            Values::DWords(v) => v.len(),
            Values::DInts(v) => v.len(),
            Values::Reals(v) => v.len(),
        }
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn format(&self) -> Format {
        match self {
            Values::Bits(_) => Format::Bit,
            Values::Bytes(_) => Format::Byte,
            Values::Words(_) => Format::Word,
            Values::Ints(_) => Format::Int,
            Values::DWords(_) => Format::DWord,
            Values::DInts(_) => Format::DInt,
            Values::Reals(_) => Format::Real,
        }
    }
}

/// Values that do not fit an item.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ValueError {
    /// The bytes given are not the item's span.
    #[error("the item covers {want} bytes, {got} were given")]
    Span {
        /// The item's.
        want: usize,
        /// Given.
        got: usize,
    },
    /// Values of another format.
    #[error("the item holds {want:?} values, {got:?} were given")]
    Format {
        /// The item's.
        want: Format,
        /// Given.
        got: Format,
    },
    /// Another number of values.
    #[error("the item holds {want} value(s), {got} were given")]
    Count {
        /// The item's.
        want: usize,
        /// Given.
        got: usize,
    },
}

impl ProcessItem {
    /// Its values in `bytes`, the bytes of its [`span`](Self::span).
    pub fn decode(&self, bytes: &[u8]) -> Result<Values, ValueError> {
        let (_, want) = self.span();
        if bytes.len() != want {
            return Err(ValueError::Span {
                want,
                got: bytes.len(),
            });
        }
        let n = self.values();
        let chunks = |size: usize| bytes.chunks_exact(size).take(n);
        Ok(match self.format {
            Format::Bit => Values::Bits(
                (0..n)
                    .map(|k| {
                        let bit = usize::from(self.bit) + k;
                        bytes[bit / 8] & (1 << (bit % 8)) != 0
                    })
                    .collect(),
            ),
            Format::Byte => Values::Bytes(bytes.to_vec()),
            Format::Word => Values::Words(
                chunks(2)
                    .map(|c| u16::from_be_bytes([c[0], c[1]]))
                    .collect(),
            ),
            Format::Int => Values::Ints(
                chunks(2)
                    .map(|c| i16::from_be_bytes([c[0], c[1]]))
                    .collect(),
            ),
            Format::DWord => Values::DWords(
                chunks(4)
                    .map(|c| u32::from_be_bytes([c[0], c[1], c[2], c[3]]))
                    .collect(),
            ),
            Format::DInt => Values::DInts(
                chunks(4)
                    .map(|c| i32::from_be_bytes([c[0], c[1], c[2], c[3]]))
                    .collect(),
            ),
            Format::Real => Values::Reals(
                chunks(4)
                    .map(|c| f32::from_be_bytes([c[0], c[1], c[2], c[3]]))
                    .collect(),
            ),
        })
    }

    /// Writes `values` into `bytes`, the bytes of its span as they are: the bits of a bit
    /// item's bytes that it does not name stay as they were.
    pub fn encode(&self, values: &Values, bytes: &mut [u8]) -> Result<(), ValueError> {
        let (_, want) = self.span();
        if bytes.len() != want {
            return Err(ValueError::Span {
                want,
                got: bytes.len(),
            });
        }
        if values.format() != self.format {
            return Err(ValueError::Format {
                want: self.format,
                got: values.format(),
            });
        }
        if values.len() != self.values() {
            return Err(ValueError::Count {
                want: self.values(),
                got: values.len(),
            });
        }
        fn put<const N: usize>(bytes: &mut [u8], all: impl Iterator<Item = [u8; N]>) {
            for (chunk, b) in bytes.chunks_exact_mut(N).zip(all) {
                chunk.copy_from_slice(&b);
            }
        }
        match values {
            Values::Bits(v) => {
                for (k, on) in v.iter().enumerate() {
                    let bit = usize::from(self.bit) + k;
                    let mask = 1 << (bit % 8);
                    if *on {
                        bytes[bit / 8] |= mask;
                    } else {
                        bytes[bit / 8] &= !mask;
                    }
                }
            }
            Values::Bytes(v) => bytes.copy_from_slice(v),
            Values::Words(v) => put(bytes, v.iter().map(|x| x.to_be_bytes())),
            Values::Ints(v) => put(bytes, v.iter().map(|x| x.to_be_bytes())),
            Values::DWords(v) => put(bytes, v.iter().map(|x| x.to_be_bytes())),
            Values::DInts(v) => put(bytes, v.iter().map(|x| x.to_be_bytes())),
            Values::Reals(v) => put(bytes, v.iter().map(|x| x.to_be_bytes())),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
