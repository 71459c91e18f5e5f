// SPDX-License-Identifier: MIT OR Apache-2.0
//! The value syntax of GSDML attributes: numbers, value lists, data type sizes and the
//! encoding of parameter default values.
//!
//! Everything here works on text from the file and returns `None` or a message instead of
//! panicking; sizes are checked before any buffer is indexed.

use core::fmt;

/// The longest parameter record this import builds (the record data of one write).
pub(super) const MAX_RECORD_LEN: u64 = 0xFFFF;

/// Most bytes of parameter records one submodule's records may add up to: a bound on what a
/// broken file can make the import allocate.
pub(super) const MAX_RECORDS_LEN: u64 = 1 << 20;

/// A number as GSDML writes it: decimal, or hexadecimal with `0x` (ident numbers, IDs).
pub(super) fn number(text: &str) -> Option<u64> {
    let text = text.trim();
    match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) if !hex.is_empty() && hex.bytes().all(|b| b.is_ascii_hexdigit()) => {
            u64::from_str_radix(hex, 16).ok()
        }
        Some(_) => None,
        None if !text.is_empty() && text.bytes().all(|b| b.is_ascii_digit()) => text.parse().ok(),
        None => None,
    }
}

/// A signed number: [`number`] with an optional leading `-` or `+`.
fn signed(text: &str) -> Option<i128> {
    let text = text.trim();
    if let Some(rest) = text.strip_prefix('-') {
        number(rest).map(|n| -i128::from(n))
    } else {
        number(text.strip_prefix('+').unwrap_or(text)).map(i128::from)
    }
}

/// A GSDML value list such as `"0..4 7 9..10"` (slots, subslots): ranges and single values
/// separated by blanks.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ValueList {
    text: String,
    ranges: Vec<(u32, u32)>,
}

impl ValueList {
    /// Parses `text`; `None` if it is not a value list of numbers up to 2^32 - 1.
    pub fn parse(text: &str) -> Option<ValueList> {
        let mut ranges = Vec::new();
        for token in text.split_whitespace() {
            let (low, high) = match token.split_once("..") {
                Some((a, b)) => (number(a)?, number(b)?),
                None => (number(token)?, number(token)?),
            };
            let low = u32::try_from(low).ok()?;
            let high = u32::try_from(high).ok()?;
            if low > high {
                return None;
            }
            ranges.push((low, high));
        }
        if ranges.is_empty() {
            return None;
        }
        Some(ValueList {
            text: text.split_whitespace().collect::<Vec<_>>().join(" "),
            ranges,
        })
    }

    /// A list of one value.
    pub fn single(value: u32) -> ValueList {
        ValueList {
            text: value.to_string(),
            ranges: vec![(value, value)],
        }
    }

    /// Whether `value` is in the list.
    pub fn contains(&self, value: u32) -> bool {
        self.ranges.iter().any(|&(a, b)| a <= value && value <= b)
    }

    /// The smallest value in the list.
    pub fn min(&self) -> u32 {
        self.ranges.iter().map(|&(a, _)| a).min().unwrap_or(0)
    }

    /// The values in ascending order without repeats, at most `limit` of them; `None` if
    /// there are more.
    pub fn values(&self, limit: usize) -> Option<Vec<u32>> {
        let mut out: Vec<u32> = Vec::new();
        for &(a, b) in &self.ranges {
            if u64::from(b - a) >= limit as u64 {
                return None;
            }
            for v in a..=b {
                if !out.contains(&v) {
                    if out.len() == limit {
                        return None;
                    }
                    out.push(v);
                }
            }
        }
        out.sort_unstable();
        Some(out)
    }
}

impl fmt::Display for ValueList {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

/// Why a data item has no size.
#[derive(Debug, PartialEq, Eq)]
pub(super) enum SizeError {
    /// The data type is one whose size is its `Length` attribute, and that is missing.
    NeedsLength,
    /// The data type is not one this import knows.
    Unknown,
}

/// Data types whose size is given by the `Length` attribute.
const LENGTH_TYPES: [&str; 5] = [
    "VisibleString",
    "OctetString",
    "UnicodeString8",
    "61131_STRING",
    "61131_WSTRING",
];

/// The size in bytes of an IO data item of `data_type`; `length` is its `Length` attribute.
///
/// The sizes are those of the GSDML specification's data type table (as reproduced in the
/// OPC UA companion specification for GSDML, table 58), plus the PROFIsafe message trailers,
/// whose size is in their name.
pub(super) fn io_size(data_type: &str, length: Option<u64>) -> Result<u64, SizeError> {
    let fixed = match data_type {
        "Integer8" | "Unsigned8" | "Boolean" | "Unsigned8_S" => 1,
        "Integer16" | "Unsigned16" | "Unsigned8+Unsigned8" | "Unsigned16_S" | "Integer16_S" => 2,
        "OctetString2+Unsigned8" => 3,
        "Integer32" | "Unsigned32" | "Float32" | "F_MessageTrailer4Byte" => 4,
        "Float32+Unsigned8" | "F_MessageTrailer5Byte" => 5,
        "Date" => 7,
        "Integer64" | "Unsigned64" | "Float64" | "TimeStampDifferenceShort" => 8,
        "TimeStamp" | "TimeStampDifference" => 12,
        t if LENGTH_TYPES.contains(&t) => return length.ok_or(SizeError::NeedsLength),
        _ => return Err(SizeError::Unknown),
    };
    Ok(fixed)
}

/// The data types [`io_size`] knows, for messages.
pub(super) const IO_TYPES: &str = "Integer8/16/32/64, Unsigned8/16/32/64, Float32, Float64, \
    Boolean, Date, Unsigned8+Unsigned8, Float32+Unsigned8, OctetString2+Unsigned8, \
    Unsigned8_S, Unsigned16_S, Integer16_S, TimeStamp, TimeStampDifference, \
    TimeStampDifferenceShort, F_MessageTrailer4Byte, F_MessageTrailer5Byte, and with a \
    Length: VisibleString, OctetString, UnicodeString8, 61131_STRING, 61131_WSTRING";

/// A `Ref` element of a parameter record: one value at a byte (and bit) offset.
#[derive(Clone, Debug)]
pub(super) struct RefValue<'a> {
    pub data_type: &'a str,
    pub byte_offset: u64,
    pub bit_offset: Option<u64>,
    pub bit_length: Option<u64>,
    pub length: Option<u64>,
    pub default: &'a str,
}

/// Which attribute a record problem is about, with the message.
#[derive(Debug, PartialEq, Eq)]
pub(super) struct RefError {
    pub attribute: &'static str,
    pub message: String,
}

fn ref_error(attribute: &'static str, message: String) -> RefError {
    RefError { attribute, message }
}

/// Writes the default value of `r` into `record` (big-endian, as PROFINET transfers it).
pub(super) fn write_ref(record: &mut [u8], r: &RefValue<'_>) -> Result<(), RefError> {
    let value = r.default.trim();
    let int_size = match r.data_type {
        "Integer8" | "Unsigned8" => Some(1),
        "Integer16" | "Unsigned16" => Some(2),
        "Integer32" | "Unsigned32" => Some(4),
        "Integer64" | "Unsigned64" => Some(8),
        _ => None,
    };
    if let Some(size) = int_size {
        let signed_type = r.data_type.starts_with("Integer");
        let n = signed(value).ok_or_else(|| {
            ref_error(
                "DefaultValue",
                format!("{value:?} is not an integer (decimal or 0x hex)"),
            )
        })?;
        let bits = 8 * size as u32;
        let (min, max) = if signed_type {
            (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
        } else {
            (0, (1i128 << bits) - 1)
        };
        if n < min || n > max {
            return Err(ref_error(
                "DefaultValue",
                format!(
                    "{n} is outside the range of {} ({min} to {max})",
                    r.data_type
                ),
            ));
        }
        // Two's complement in the low `size` bytes of the 16-byte big-endian form.
        let bytes = n.to_be_bytes();
        return place(record, r.byte_offset, &bytes[16 - size..]);
    }
    match r.data_type {
        "Float32" => {
            let v: f32 = value
                .parse()
                .map_err(|_| ref_error("DefaultValue", format!("{value:?} is not a number")))?;
            place(record, r.byte_offset, &v.to_be_bytes())
        }
        "Float64" => {
            let v: f64 = value
                .parse()
                .map_err(|_| ref_error("DefaultValue", format!("{value:?} is not a number")))?;
            place(record, r.byte_offset, &v.to_be_bytes())
        }
        "Boolean" => {
            let v = match value {
                "true" | "1" => 1u8,
                "false" | "0" => 0u8,
                _ => {
                    return Err(ref_error(
                        "DefaultValue",
                        format!("{value:?} is not a Boolean (true, false, 1 or 0)"),
                    ));
                }
            };
            place(record, r.byte_offset, &[v])
        }
        "Bit" => {
            let bit = r.bit_offset.unwrap_or(0);
            if bit > 7 {
                return Err(ref_error(
                    "BitOffset",
                    format!("{bit} is not a bit of a byte (0 to 7)"),
                ));
            }
            let on = match signed(value) {
                Some(0) => false,
                Some(1) => true,
                _ => {
                    return Err(ref_error(
                        "DefaultValue",
                        format!("{value:?} is not a bit value (0 or 1)"),
                    ));
                }
            };
            set_bits(record, r.byte_offset, bit as u32, 1, u64::from(on))
        }
        "BitArea" => {
            let bit = r.bit_offset.unwrap_or(0);
            let len = r.bit_length.unwrap_or(1);
            if len == 0 || bit.saturating_add(len) > 8 {
                return Err(ref_error(
                    "BitLength",
                    format!(
                        "a bit area of {len} bits from bit {bit} does not fit in one byte, \
                         which is all this import encodes"
                    ),
                ));
            }
            let v = match signed(value) {
                Some(v) if v >= 0 && v < (1i128 << len) => v as u64,
                _ => {
                    return Err(ref_error(
                        "DefaultValue",
                        format!(
                            "{value:?} is not a value of {len} bits (0 to {})",
                            (1u64 << len) - 1
                        ),
                    ));
                }
            };
            set_bits(record, r.byte_offset, bit as u32, len as u32, v)
        }
        "OctetString" => {
            let length = string_length(r)?;
            let mut bytes = Vec::new();
            for part in value.split(',').map(str::trim).filter(|p| !p.is_empty()) {
                match number(part) {
                    Some(b) if b <= 0xFF => bytes.push(b as u8),
                    _ => {
                        return Err(ref_error(
                            "DefaultValue",
                            format!("{part:?} is not a byte; write bytes like \"0x01,0x02\""),
                        ));
                    }
                }
            }
            fill(record, r.byte_offset, length, &bytes, 0)
        }
        "VisibleString" => {
            let length = string_length(r)?;
            if !r.default.bytes().all(|b| (0x20..0x7F).contains(&b)) {
                return Err(ref_error(
                    "DefaultValue",
                    format!("{:?} has characters a VisibleString cannot hold", r.default),
                ));
            }
            // Fixed-length PROFINET strings are padded with blanks (as the I&M records are).
            fill(record, r.byte_offset, length, r.default.as_bytes(), b' ')
        }
        other => Err(ref_error(
            "DataType",
            format!(
                "this import cannot encode a default value of type {other:?} (it encodes \
                 Bit, BitArea, Integer8..64, Unsigned8..64, Float32, Float64, Boolean, \
                 OctetString and VisibleString)"
            ),
        )),
    }
}

fn string_length(r: &RefValue<'_>) -> Result<u64, RefError> {
    r.length.ok_or_else(|| {
        ref_error(
            "Length",
            format!("a {} value needs a Length attribute", r.data_type),
        )
    })
}

/// `bytes` at `offset`, all inside `record`.
fn place(record: &mut [u8], offset: u64, bytes: &[u8]) -> Result<(), RefError> {
    let range = inside(record.len(), offset, bytes.len() as u64)?;
    record[range].copy_from_slice(bytes);
    Ok(())
}

/// `bytes` at `offset` in a field of `length` bytes, the rest of the field `pad`.
fn fill(
    record: &mut [u8],
    offset: u64,
    length: u64,
    bytes: &[u8],
    pad: u8,
) -> Result<(), RefError> {
    if bytes.len() as u64 > length {
        return Err(ref_error(
            "DefaultValue",
            format!(
                "the default value has {} bytes, more than the Length of {length}",
                bytes.len()
            ),
        ));
    }
    let range = inside(record.len(), offset, length)?;
    let field = &mut record[range];
    field.fill(pad);
    field[..bytes.len()].copy_from_slice(bytes);
    Ok(())
}

/// Sets `len` bits from bit `bit` (0 = least significant) of the byte at `offset` to `value`.
fn set_bits(
    record: &mut [u8],
    offset: u64,
    bit: u32,
    len: u32,
    value: u64,
) -> Result<(), RefError> {
    let range = inside(record.len(), offset, 1)?;
    let mask = (((1u16 << len) - 1) << bit) as u8;
    let byte = &mut record[range][0];
    *byte = (*byte & !mask) | (((value as u16) << bit) as u8 & mask);
    Ok(())
}

/// The range of `len` bytes at `offset` if it lies inside a record of `record_len` bytes.
fn inside(record_len: usize, offset: u64, len: u64) -> Result<core::ops::Range<usize>, RefError> {
    match offset.checked_add(len) {
        Some(end) if end <= record_len as u64 => Ok(offset as usize..end as usize),
        _ => Err(ref_error(
            "ByteOffset",
            format!(
                "{len} byte(s) at offset {offset} do not fit in the record's Length of \
                 {record_len}"
            ),
        )),
    }
}

/// The bytes of a `Const` element's `Data` attribute: `"0x01,0x02,..."` (files also separate
/// them with blanks).
pub(super) fn const_bytes(data: &str) -> Result<Vec<u8>, String> {
    let mut bytes = Vec::new();
    for part in data.split(|c: char| c == ',' || c.is_whitespace()) {
        if part.is_empty() {
            continue;
        }
        match number(part) {
            Some(b) if b <= 0xFF => bytes.push(b as u8),
            _ => {
                return Err(format!(
                    "{part:?} is not a byte; Data is a list of bytes like \"0x01,0x02\""
                ));
            }
        }
    }
    Ok(bytes)
}

/// Writes `bytes` at `offset` of `record`, for a `Const` element.
pub(super) fn write_const(record: &mut [u8], offset: u64, bytes: &[u8]) -> Result<(), RefError> {
    place(record, offset, bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(number("0x00000101"), Some(0x101));
        assert_eq!(number(" 32768 "), Some(32768));
        assert_eq!(number("0X1f"), Some(31));
        for bad in [
            "",
            "0x",
            "-1",
            "1.5",
            "0x1g",
            "12a",
            "99999999999999999999999",
        ] {
            assert_eq!(number(bad), None, "{bad:?}");
        }
        assert_eq!(signed("-128"), Some(-128));
        assert_eq!(signed("+7"), Some(7));
    }

    #[test]
    fn value_lists() {
        let l = ValueList::parse("0..4  7").unwrap();
        assert!(l.contains(0) && l.contains(4) && l.contains(7));
        assert!(!l.contains(5) && !l.contains(8));
        assert_eq!(l.to_string(), "0..4 7");
        assert_eq!(l.min(), 0);
        assert_eq!(l.values(10), Some(vec![0, 1, 2, 3, 4, 7]));
        assert_eq!(l.values(5), None);
        assert_eq!(ValueList::parse("1..4294967295").unwrap().values(100), None);
        for bad in ["", "  ", "4..1", "a", "1..", "..2", "1...3", "4294967296"] {
            assert_eq!(ValueList::parse(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn io_sizes() {
        assert_eq!(io_size("Float32", None), Ok(4));
        assert_eq!(io_size("Unsigned8+Unsigned8", None), Ok(2));
        assert_eq!(io_size("Float32+Unsigned8", None), Ok(5));
        assert_eq!(io_size("OctetString", Some(16)), Ok(16));
        assert_eq!(io_size("VisibleString", None), Err(SizeError::NeedsLength));
        assert_eq!(io_size("Real", None), Err(SizeError::Unknown));
    }

    fn r<'a>(data_type: &'a str, offset: u64, default: &'a str) -> RefValue<'a> {
        RefValue {
            data_type,
            byte_offset: offset,
            bit_offset: None,
            bit_length: None,
            length: None,
            default,
        }
    }

    #[test]
    fn ref_values() {
        let mut rec = [0u8; 12];
        write_ref(&mut rec, &r("Unsigned16", 0, "1000")).unwrap();
        write_ref(&mut rec, &r("Integer8", 2, "-2")).unwrap();
        write_ref(&mut rec, &r("Integer32", 3, "0x01020304")).unwrap();
        write_ref(&mut rec, &r("Float32", 7, "1.5")).unwrap();
        write_ref(&mut rec, &r("Boolean", 11, "true")).unwrap();
        assert_eq!(rec, [0x03, 0xE8, 0xFE, 1, 2, 3, 4, 0x3F, 0xC0, 0, 0, 1]);

        let mut rec = [0xFFu8; 2];
        let bit = RefValue {
            bit_offset: Some(3),
            ..r("Bit", 0, "0")
        };
        write_ref(&mut rec, &bit).unwrap();
        let area = RefValue {
            bit_offset: Some(4),
            bit_length: Some(3),
            ..r("BitArea", 1, "5")
        };
        write_ref(&mut rec, &area).unwrap();
        assert_eq!(rec, [0xF7, 0xDF]);

        let mut rec = [0u8; 6];
        let octets = RefValue {
            length: Some(3),
            ..r("OctetString", 0, "0x01,0x02")
        };
        write_ref(&mut rec, &octets).unwrap();
        let text = RefValue {
            length: Some(3),
            ..r("VisibleString", 3, "ab")
        };
        write_ref(&mut rec, &text).unwrap();
        assert_eq!(rec, [1, 2, 0, b'a', b'b', b' ']);
    }

    #[test]
    fn bad_ref_values() {
        let mut rec = [0u8; 2];
        let cases = [
            (r("Unsigned8", 0, "256"), "DefaultValue"),
            (r("Integer8", 0, "-129"), "DefaultValue"),
            (r("Unsigned16", 1, "1"), "ByteOffset"),
            (r("Unsigned8", u64::MAX, "1"), "ByteOffset"),
            (
                RefValue {
                    bit_offset: Some(u64::MAX),
                    bit_length: Some(2),
                    ..r("BitArea", 0, "1")
                },
                "BitLength",
            ),
            (r("Unsigned8", 0, "x"), "DefaultValue"),
            (r("Float32", 0, "1"), "ByteOffset"),
            (r("Bit", 0, "2"), "DefaultValue"),
            (r("OctetString", 0, "0x01"), "Length"),
            (r("TimeStamp", 0, "0"), "DataType"),
            (
                RefValue {
                    bit_offset: Some(6),
                    bit_length: Some(3),
                    ..r("BitArea", 0, "1")
                },
                "BitLength",
            ),
            (
                RefValue {
                    length: Some(1),
                    ..r("VisibleString", 0, "ab")
                },
                "DefaultValue",
            ),
        ];
        for (value, attribute) in cases {
            let e = write_ref(&mut rec, &value).unwrap_err();
            assert_eq!(e.attribute, attribute, "{value:?}: {e:?}");
        }
    }

    #[test]
    fn const_data() {
        assert_eq!(const_bytes("0x01, 0x02,3"), Ok(vec![1, 2, 3]));
        assert_eq!(const_bytes("0x42 0x43"), Ok(vec![0x42, 0x43]));
        assert!(const_bytes("0x100").is_err());
        let mut rec = [0u8; 3];
        write_const(&mut rec, 1, &[7, 8]).unwrap();
        assert_eq!(rec, [0, 7, 8]);
        assert!(write_const(&mut rec, 2, &[7, 8]).is_err());
    }
}
