// SPDX-License-Identifier: MIT OR Apache-2.0
//! Serde for 64-bit identifiers (generation, layout hash) as 16 hex digits: JSON numbers
//! above 2^53 lose their low bits in JavaScript and jq. Numbers are still read, for
//! messages from older servers.

use serde::{Deserialize, Deserializer, Serializer};

/// Writes `v` as 16 lowercase hex digits.
pub fn serialize<S: Serializer>(v: &u64, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&format!("{v:016x}"))
}

#[derive(Deserialize)]
#[serde(untagged)]
enum Either {
    Hex(String),
    Number(u64),
}

/// Reads hex digits (with or without `0x`) or a number.
pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    match Either::deserialize(d)? {
        Either::Number(n) => Ok(n),
        Either::Hex(h) => {
            let digits = h.strip_prefix("0x").unwrap_or(&h);
            u64::from_str_radix(digits, 16)
                .map_err(|e| serde::de::Error::custom(format!("{h:?} is not hex: {e}")))
        }
    }
}
