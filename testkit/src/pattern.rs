// SPDX-License-Identifier: MIT OR Apache-2.0
//! A data pattern that shows a torn image: each buffer written in cycle k carries k and its
//! complement, so any mix of two writes breaks the relation between the halves.

/// The pattern of cycle k for a buffer of `len` bytes: k little-endian, then its complement,
/// repeated.
pub fn pattern(k: u64, len: usize) -> Vec<u8> {
    let mut block = k.to_le_bytes().to_vec();
    block.extend_from_slice(&(!k).to_le_bytes());
    block.iter().copied().cycle().take(len).collect()
}

/// The k a buffer was written with, if it is an untorn pattern.
pub fn pattern_value(b: &[u8]) -> Option<u64> {
    if b.len() < 16 {
        return None;
    }
    let k = u64::from_le_bytes(b[..8].try_into().ok()?);
    (pattern(k, b.len()) == b).then_some(k)
}
