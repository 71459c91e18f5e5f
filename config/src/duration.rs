// SPDX-License-Identifier: MIT OR Apache-2.0
//! Durations written as strings: `"1ms"`, `"250us"`, `"31.25us"`, `"0.5ms"`.

use core::fmt;

/// Why a duration string was refused by [`parse_duration`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DurationError {
    /// The text does not start with a decimal number such as `1`, `0.5` or `31.25`.
    BadNumber,
    /// The number has no unit after it.
    MissingUnit,
    /// The unit is not one of `ns`, `us`, `µs`, `ms`, `s`.
    UnknownUnit,
    /// The value is not a whole number of nanoseconds (`"0.1ns"`).
    NotWholeNanoseconds,
    /// The value does not fit in 64 bits of nanoseconds.
    TooLarge,
}

impl fmt::Display for DurationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            DurationError::BadNumber => {
                "is not a duration: write a decimal number and a unit, e.g. \"1ms\" or \"31.25us\""
            }
            DurationError::MissingUnit => {
                "has no unit: add one of ns, us, ms or s, e.g. \"1ms\" or \"250us\""
            }
            DurationError::UnknownUnit => {
                "has an unknown unit: use ns, us (or µs), ms or s, e.g. \"1ms\" or \"250us\""
            }
            DurationError::NotWholeNanoseconds => {
                "is not a whole number of nanoseconds: give fewer decimal places"
            }
            DurationError::TooLarge => "is too long: durations are limited to about 584 years",
        })
    }
}

impl core::error::Error for DurationError {}

/// Nanoseconds per unit, for each accepted unit spelling.
const UNITS: [(&str, u128); 6] = [
    ("ns", 1),
    ("us", 1_000),
    ("µs", 1_000),
    ("μs", 1_000),
    ("ms", 1_000_000),
    ("s", 1_000_000_000),
];

/// Parses a duration such as `"1ms"`, `"250us"`, `"31.25us"` or `"0.5ms"` to nanoseconds.
///
/// The text is a decimal number (digits, optionally a `.` and more digits) followed by a unit,
/// `ns`, `us`, `µs` (also the Greek `μs`), `ms` or `s`; blanks around the text and between number
/// and unit are allowed. The value must be a whole number of nanoseconds that fits in a `u64`.
pub fn parse_duration(text: &str) -> Result<u64, DurationError> {
    let text = text.trim();
    let number_len = text
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(text.len());
    let (number, unit) = text.split_at(number_len);
    let unit = unit.trim_start();

    let (int_part, frac_part) = match number.split_once('.') {
        Some((i, f)) => (i, f),
        None => (number, ""),
    };
    if int_part.is_empty()
        || frac_part.contains('.')
        || (number.contains('.') && frac_part.is_empty())
    {
        return Err(DurationError::BadNumber);
    }
    if unit.is_empty() {
        return Err(DurationError::MissingUnit);
    }
    let unit_ns = UNITS
        .iter()
        .find(|(name, _)| *name == unit)
        .map(|(_, ns)| *ns)
        .ok_or(DurationError::UnknownUnit)?;

    // Trailing zeros of the fraction carry no value (and would only overflow the mantissa).
    let frac_part = frac_part.trim_end_matches('0');
    // A fraction with more than 9 significant digits is finer than 1 ns even in seconds.
    if frac_part.len() > 9 {
        return Err(DurationError::NotWholeNanoseconds);
    }
    let mut mantissa: u128 = 0;
    for digit in int_part.bytes().chain(frac_part.bytes()) {
        mantissa = mantissa
            .checked_mul(10)
            .and_then(|m| m.checked_add(u128::from(digit - b'0')))
            .ok_or(DurationError::TooLarge)?;
    }
    let scaled = mantissa
        .checked_mul(unit_ns)
        .ok_or(DurationError::TooLarge)?;
    // At most 10^9, see above.
    let divisor = 10u128.pow(frac_part.len() as u32);
    if scaled % divisor != 0 {
        return Err(DurationError::NotWholeNanoseconds);
    }
    u64::try_from(scaled / divisor).map_err(|_| DurationError::TooLarge)
}

/// Writes `ns` the way a configuration would: `"1ms"`, `"1.125ms"`, `"31.25us"`, `"2s"`, `"7ns"`.
///
/// [`parse_duration`] reads the result back to the same value.
pub fn format_duration(ns: u64) -> String {
    let (unit, per) = if ns >= 1_000_000_000 && ns.is_multiple_of(1_000_000_000) {
        ("s", 1_000_000_000)
    } else if ns >= 1_000_000 {
        ("ms", 1_000_000)
    } else if ns >= 1_000 {
        ("us", 1_000)
    } else {
        ("ns", 1)
    };
    let whole = ns / per;
    let rest = ns % per;
    if rest == 0 {
        return format!("{whole}{unit}");
    }
    let digits = per.ilog10() as usize;
    let frac = format!("{rest:0digits$}");
    format!("{whole}.{}{unit}", frac.trim_end_matches('0'))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_round_trip() {
        for (ns, text) in [
            (0, "0ns"),
            (7, "7ns"),
            (31_250, "31.25us"),
            (1_000_000, "1ms"),
            (1_125_000, "1.125ms"),
            (500_000, "500us"),
            (2_000_000_000, "2s"),
            (1_500_000_000, "1500ms"),
            (1_000_000_001, "1000.000001ms"),
            (u64::MAX, "18446744073709.551615ms"),
        ] {
            assert_eq!(format_duration(ns), text);
            assert_eq!(parse_duration(text), Ok(ns), "{text}");
        }
    }
}
