// SPDX-License-Identifier: MIT OR Apache-2.0
//! The layout hash: FNV-1a over every field of the tables, in a fixed byte order.
//!
//! A client compiled for one IO configuration can insist on its hash, and refuses to run
//! against a server whose image differs, instead of reading the wrong bytes.

use crate::image_layout::ImageLayout;
use crate::types::{DeviceEntry, LAYOUT_VERSION, SubmoduleEntry};

struct Fnv(u64);

impl Fnv {
    fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 ^= x as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    fn u16(&mut self, v: u16) {
        self.bytes(&v.to_le_bytes());
    }
    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }
}

/// The hash of a layout: its version, its sizes and every field of its tables.
pub fn layout_hash(
    layout: &ImageLayout,
    devices: &[DeviceEntry],
    submodules: &[SubmoduleEntry],
) -> u64 {
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    h.u32(LAYOUT_VERSION);
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
        h.bytes(&d.station_name);
        for v in [d.vendor_id, d.device_id, d.instance, d.reduction_ratio] {
            h.u16(v);
        }
        h.bytes(&d.ip_address);
        h.u32(d.first_submodule);
        h.u32(d.submodule_count);
        h.u16(d.watchdog_factor);
    }
    for s in submodules {
        for v in [s.device, s.slot, s.subslot, s.rt_class as u16] {
            h.u16(v);
        }
        for v in [
            s.api,
            s.module_ident,
            s.submodule_ident,
            s.input_address,
            s.output_address,
            s.input_length as u32,
            s.output_length as u32,
            s.input_offset,
            s.output_offset,
            s.output_mirror_offset,
            s.status_offset,
            s.client_status_offset,
        ] {
            h.u32(v);
        }
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
        let a = layout_hash(&l, &[], &t);
        t[0].input_address = 0;
        let b = layout_hash(&l, &[], &t);
        assert_ne!(a, b);
        assert_eq!(b, layout_hash(&l, &[], &t));
    }
}
