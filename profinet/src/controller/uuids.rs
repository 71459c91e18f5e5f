// SPDX-License-Identifier: MIT OR Apache-2.0
//! The UUIDs of ARs and RPC activities, drawn from a seed the caller gives, as smoltcp takes
//! its random seed: the protocol crate holds no random source, procimgd seeds it from the
//! kernel, and a test or a simulation seeds it with a constant so that its exchanges replay
//! byte for byte.

use crate::wire::Uuid;

/// A stream of version-4 (random, RFC 4122 variant) UUIDs from a 64-bit seed: SplitMix64,
/// which gives well-spread, distinct outputs for any seed, even adjacent ones.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UuidSource {
    state: u64,
}

impl UuidSource {
    /// A stream from `seed`.
    pub const fn new(seed: u64) -> UuidSource {
        UuidSource { state: seed }
    }

    fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A stream of its own, seeded from this one (one per device, so that a device's UUIDs
    /// do not depend on what the others did).
    pub fn split(&mut self) -> UuidSource {
        UuidSource::new(self.next_u64())
    }

    /// The next UUID.
    pub fn next_uuid(&mut self) -> Uuid {
        let mut b = [0u8; 16];
        b[..8].copy_from_slice(&self.next_u64().to_be_bytes());
        b[8..].copy_from_slice(&self.next_u64().to_be_bytes());
        b[6] = (b[6] & 0x0f) | 0x40;
        b[8] = (b[8] & 0x3f) | 0x80;
        Uuid(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uuids_are_version_4_distinct_and_follow_the_seed() {
        let mut a = UuidSource::new(1);
        let mut b = UuidSource::new(1);
        let mut c = UuidSource::new(2);
        let first: Vec<Uuid> = (0..100).map(|_| a.next_uuid()).collect();
        assert_eq!(first[0], b.next_uuid());
        assert_ne!(first[0], c.next_uuid());
        for (i, u) in first.iter().enumerate() {
            assert_eq!(u.0[6] >> 4, 4, "version of {u:?}");
            assert_eq!(u.0[8] >> 6, 0b10, "variant of {u:?}");
            assert!(first[..i].iter().all(|v| v != u), "{u:?} repeated");
        }
    }
}
