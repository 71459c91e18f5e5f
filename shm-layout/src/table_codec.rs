// SPDX-License-Identifier: MIT OR Apache-2.0
//! The layout payload: the device table, then (at
//! [`ImageLayout::submodule_table_offset`]) the submodule table, every field little-endian in
//! its `repr(C)` order. On the little-endian machines procimg runs on, these are exactly the
//! bytes of the `repr(C)` arrays, so C clients may also read them in place.

use crate::image_layout::ImageLayout;
use crate::types::{DeviceEntry, STATION_NAME_LEN, SubmoduleEntry};
use core::mem::size_of;

/// Calls `out` with the bytes of every field of a device entry, little-endian, in order.
pub fn device_fields(d: &DeviceEntry, out: &mut impl FnMut(&[u8])) {
    out(&d.station_name);
    for v in [d.vendor_id, d.device_id, d.instance, d.reduction_ratio] {
        out(&v.to_le_bytes());
    }
    out(&d.ip_address);
    out(&d.first_submodule.to_le_bytes());
    out(&d.submodule_count.to_le_bytes());
    out(&d.watchdog_factor.to_le_bytes());
    out(&d.reserved.to_le_bytes());
}

/// Calls `out` with the bytes of every field of a submodule entry, little-endian, in order.
pub fn submodule_fields(s: &SubmoduleEntry, out: &mut impl FnMut(&[u8])) {
    for v in [s.device, s.slot, s.subslot] {
        out(&v.to_le_bytes());
    }
    out(&[s.rt_class, s.reserved0]);
    for v in [
        s.api,
        s.module_ident,
        s.submodule_ident,
        s.input_address,
        s.output_address,
    ] {
        out(&v.to_le_bytes());
    }
    out(&s.input_length.to_le_bytes());
    out(&s.output_length.to_le_bytes());
    for v in [
        s.input_offset,
        s.output_offset,
        s.output_mirror_offset,
        s.status_offset,
        s.client_status_offset,
        s.reserved1,
        s.reserved2,
        s.reserved3,
    ] {
        out(&v.to_le_bytes());
    }
}

/// Writes both tables into `buf`, which must hold
/// [`ImageLayout::layout_payload_size`] bytes. Returns `false` (writing nothing past `buf`)
/// when it is too short.
pub fn encode_tables(
    buf: &mut [u8],
    devices: &[DeviceEntry],
    submodules: &[SubmoduleEntry],
) -> bool {
    let sub_at = ImageLayout::submodule_table_offset(devices.len() as u32) as usize;
    let need = sub_at + core::mem::size_of_val(submodules);
    if buf.len() < need {
        return false;
    }
    let mut w = Cursor { buf, at: 0 };
    for d in devices {
        device_fields(d, &mut |b| w.put(b));
    }
    w.at = sub_at;
    for s in submodules {
        submodule_fields(s, &mut |b| w.put(b));
    }
    true
}

/// Reads device `i` of a layout payload; `None` if the payload is too short.
pub fn decode_device(buf: &[u8], i: usize) -> Option<DeviceEntry> {
    let at = i.checked_mul(size_of::<DeviceEntry>())?;
    let mut r = Reader {
        buf: buf.get(at..at.checked_add(size_of::<DeviceEntry>())?)?,
        at: 0,
    };
    let mut station_name = [0u8; STATION_NAME_LEN];
    station_name.copy_from_slice(r.take(STATION_NAME_LEN));
    Some(DeviceEntry {
        station_name,
        vendor_id: r.u16(),
        device_id: r.u16(),
        instance: r.u16(),
        reduction_ratio: r.u16(),
        ip_address: [r.u8(), r.u8(), r.u8(), r.u8()],
        first_submodule: r.u32(),
        submodule_count: r.u32(),
        watchdog_factor: r.u16(),
        reserved: r.u16(),
    })
}

/// Reads submodule `i` of a layout payload with `devices` devices; `None` if too short.
pub fn decode_submodule(buf: &[u8], devices: u32, i: usize) -> Option<SubmoduleEntry> {
    let base = ImageLayout::submodule_table_offset(devices) as usize;
    let at = base.checked_add(i.checked_mul(size_of::<SubmoduleEntry>())?)?;
    let mut r = Reader {
        buf: buf.get(at..at.checked_add(size_of::<SubmoduleEntry>())?)?,
        at: 0,
    };
    Some(SubmoduleEntry {
        device: r.u16(),
        slot: r.u16(),
        subslot: r.u16(),
        rt_class: r.u8(),
        reserved0: r.u8(),
        api: r.u32(),
        module_ident: r.u32(),
        submodule_ident: r.u32(),
        input_address: r.u32(),
        output_address: r.u32(),
        input_length: r.u16(),
        output_length: r.u16(),
        input_offset: r.u32(),
        output_offset: r.u32(),
        output_mirror_offset: r.u32(),
        status_offset: r.u32(),
        client_status_offset: r.u32(),
        reserved1: r.u32(),
        reserved2: r.u32(),
        reserved3: r.u32(),
    })
}

struct Cursor<'a> {
    buf: &'a mut [u8],
    at: usize,
}

impl Cursor<'_> {
    fn put(&mut self, b: &[u8]) {
        self.buf[self.at..self.at + b.len()].copy_from_slice(b);
        self.at += b.len();
    }
}

/// Reads fixed-size fields from a slice whose length was checked by the caller to hold the
/// whole entry.
struct Reader<'a> {
    buf: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> &'a [u8] {
        let b = &self.buf[self.at..self.at + n];
        self.at += n;
        b
    }
    fn u8(&mut self) -> u8 {
        self.take(1)[0]
    }
    fn u16(&mut self) -> u16 {
        let b = self.take(2);
        u16::from_le_bytes([b[0], b[1]])
    }
    fn u32(&mut self) -> u32 {
        let b = self.take(4);
        u32::from_le_bytes([b[0], b[1], b[2], b[3]])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    proptest::proptest! {
        #[test]
        fn decoding_arbitrary_bytes_never_panics(
            buf in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..2048),
            devices in proptest::prelude::any::<u32>(),
            i in proptest::prelude::any::<usize>(),
        ) {
            let _ = decode_device(&buf, i);
            let _ = decode_device(&buf, i % 8);
            let _ = decode_submodule(&buf, devices, i);
            let _ = decode_submodule(&buf, devices % 8, i % 32);
        }
    }

    #[test]
    fn tables_round_trip() {
        let mut name = [0u8; STATION_NAME_LEN];
        name[..4].copy_from_slice(b"echo");
        let devices = [DeviceEntry {
            station_name: name,
            vendor_id: 0x493,
            device_id: 2,
            instance: 1,
            reduction_ratio: 4,
            ip_address: [192, 168, 0, 11],
            first_submodule: 0,
            submodule_count: 2,
            watchdog_factor: 3,
            reserved: 0,
        }];
        let mut subs = [
            SubmoduleEntry {
                slot: 1,
                subslot: 1,
                input_length: 3,
                api: 7,
                ..SubmoduleEntry::EMPTY
            },
            SubmoduleEntry {
                slot: 2,
                subslot: 9,
                output_length: 5,
                module_ident: 0x41,
                ..SubmoduleEntry::EMPTY
            },
        ];
        let l = ImageLayout::assign(&mut subs).unwrap();
        let mut buf = [0u8; 1024];
        assert!(encode_tables(
            &mut buf[..l.layout_payload_size(1) as usize],
            &devices,
            &subs
        ));
        assert_eq!(decode_device(&buf, 0), Some(devices[0]));
        assert_eq!(decode_submodule(&buf, 1, 0), Some(subs[0]));
        assert_eq!(decode_submodule(&buf, 1, 1), Some(subs[1]));
        assert_eq!(decode_submodule(&buf[..300], 1, 1), None);
        assert_eq!(decode_device(&buf, usize::MAX), None);
    }
}
