// SPDX-License-Identifier: MIT OR Apache-2.0
//! The layout hash: FNV-1a over every field of the tables, in a fixed byte order.
//!
//! A client compiled for one IO configuration can insist on its hash, and refuses to run
//! against a server whose image differs, instead of reading the wrong bytes.

use crate::image_layout::ImageLayout;
use crate::table_codec::{device_fields, submodule_fields};
use crate::types::{DeviceEntry, LAYOUT_VERSION, SubmoduleEntry};

struct Fnv(u64);

impl Fnv {
    fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 ^= x as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }
}

/// The hash of a layout: its version, the server's role, its sizes and every field of its
/// tables.
pub fn layout_hash(
    role: u32,
    layout: &ImageLayout,
    devices: &[DeviceEntry],
    submodules: &[SubmoduleEntry],
) -> u64 {
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    h.u32(LAYOUT_VERSION);
    h.u32(role);
    for v in [
        layout.submodule_count,
        layout.input_size,
        layout.output_size,
        layout.status_offset,
        layout.output_mirror_offset,
        layout.input_payload_size,
        layout.client_status_offset,
        layout.output_payload_size,
    ] {
        h.u32(v);
    }
    h.u32(devices.len() as u32);
    for d in devices {
        device_fields(d, &mut |b| h.bytes(b));
    }
    for s in submodules {
        submodule_fields(s, &mut |b| h.bytes(b));
    }
    h.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn any_field_change_changes_the_hash() {
        let mut t = [SubmoduleEntry {
            input_length: 4,
            ..SubmoduleEntry::EMPTY
        }];
        let l = ImageLayout::assign(&mut t).unwrap();
        let a = layout_hash(crate::ROLE_CONTROLLER, &l, &[], &t);
        t[0].input_address = 0;
        let b = layout_hash(crate::ROLE_CONTROLLER, &l, &[], &t);
        assert_ne!(a, b);
        assert_eq!(b, layout_hash(crate::ROLE_CONTROLLER, &l, &[], &t));
    }
}
