// SPDX-License-Identifier: MIT OR Apache-2.0
//! The server's IO system as a client sees it: devices, submodules, sizes.

use procimg_shm_layout::{DeviceEntry, ImageLayout, LayoutHeader, SubmoduleEntry};

/// The layout of an instance's process image.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// The header as published.
    pub header: LayoutHeader,
    /// Devices.
    pub devices: Vec<DeviceEntry>,
    /// Submodules, in image order.
    pub submodules: Vec<SubmoduleEntry>,
}

impl Layout {
    /// Decodes a layout sample; `None` if the payload does not hold the tables it announces.
    pub fn decode(header: &LayoutHeader, payload: &[u8]) -> Option<Layout> {
        // Check the counts against the payload before allocating anything for them.
        let devices_end = header.device_count as u64 * core::mem::size_of::<DeviceEntry>() as u64;
        let need = devices_end.next_multiple_of(8)
            + header.submodule_count as u64 * core::mem::size_of::<SubmoduleEntry>() as u64;
        if need > payload.len() as u64 {
            return None;
        }
        let devices = (0..header.device_count as usize)
            .map(|i| procimg_shm_layout::decode_device(payload, i))
            .collect::<Option<Vec<_>>>()?;
        let submodules = (0..header.submodule_count as usize)
            .map(|i| procimg_shm_layout::decode_submodule(payload, header.device_count, i))
            .collect::<Option<Vec<_>>>()?;
        Some(Layout {
            header: *header,
            devices,
            submodules,
        })
    }

    /// Sizes and offsets of the image regions.
    pub fn image(&self) -> ImageLayout {
        ImageLayout::from_header(&self.header)
    }

    /// Whether the server is an IO device ([`procimg_shm_layout::ROLE_DEVICE`]): then the
    /// image's inputs are the Q data the PLC wrote and its outputs the I data the device
    /// provides (directions named from the PLC's view, as in IO-Base's device interface).
    pub fn is_device(&self) -> bool {
        self.header.role == procimg_shm_layout::ROLE_DEVICE
    }

    /// The layout hash.
    pub fn hash(&self) -> u64 {
        self.header.layout_hash
    }

    /// Station name of device `d` ("?" if out of range).
    pub fn device_name(&self, d: usize) -> &str {
        self.devices
            .get(d)
            .and_then(|d| d.station_name())
            .unwrap_or("?")
    }

    /// Index of the device named `name`.
    pub fn device(&self, name: &str) -> Option<usize> {
        (0..self.devices.len()).find(|&d| self.device_name(d) == name)
    }

    /// Submodule indices of device `d`.
    pub fn submodules_of(&self, d: usize) -> std::ops::Range<usize> {
        match self.devices.get(d) {
            Some(e) => {
                let first = e.first_submodule as usize;
                first..first + e.submodule_count as usize
            }
            None => 0..0,
        }
    }

    /// The submodule of device `name` at `slot`/`subslot`.
    pub fn find(&self, name: &str, slot: u16, subslot: u16) -> Option<usize> {
        let d = self.device(name)?;
        self.submodules_of(d).find(|&s| {
            let e = &self.submodules[s];
            e.slot == slot && e.subslot == subslot
        })
    }

    /// Every submodule with outputs.
    pub fn output_submodules(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.submodules.len()).filter(|&s| self.submodules[s].output_length > 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_shm_layout::{NO_ADDRESS, STATION_NAME_LEN, encode_tables};
    use proptest::prelude::*;

    fn device(name: &str, first: u32, count: u32) -> DeviceEntry {
        let mut station_name = [0u8; STATION_NAME_LEN];
        station_name[..name.len()].copy_from_slice(name.as_bytes());
        DeviceEntry {
            station_name,
            vendor_id: 0x0493,
            device_id: 1,
            instance: 1,
            reduction_ratio: 1,
            ip_address: [192, 168, 0, 10],
            first_submodule: first,
            submodule_count: count,
            watchdog_factor: 3,
            reserved: 0,
        }
    }

    fn submodule(device: u16, slot: u16, input: u16, output: u16) -> SubmoduleEntry {
        SubmoduleEntry {
            device,
            slot,
            subslot: 1,
            input_length: input,
            output_length: output,
            output_address: if output > 0 {
                u32::from(slot)
            } else {
                NO_ADDRESS
            },
            ..SubmoduleEntry::EMPTY
        }
    }

    /// Two devices as the server publishes them: "io" with slots 0 to 2, "di" with slot 1.
    fn published() -> (LayoutHeader, Vec<u8>) {
        let devices = [device("io", 0, 3), device("di", 3, 1)];
        let submodules = [
            submodule(0, 0, 0, 0),
            submodule(0, 1, 2, 2),
            submodule(0, 2, 4, 0),
            submodule(1, 1, 2, 0),
        ];
        let header = LayoutHeader {
            device_count: 2,
            submodule_count: 4,
            ..LayoutHeader::default()
        };
        let mut payload = vec![0u8; 4096];
        assert!(encode_tables(&mut payload, &devices, &submodules));
        (header, payload)
    }

    #[test]
    fn a_published_layout_decodes_and_finds_its_submodules() {
        let (header, payload) = published();
        let l = Layout::decode(&header, &payload).expect("the tables decode");
        assert_eq!((l.devices.len(), l.submodules.len()), (2, 4));
        assert_eq!(l.device("di"), Some(1));
        assert_eq!(l.device("nobody"), None);
        assert_eq!(l.device_name(0), "io");
        assert_eq!(l.device_name(7), "?", "a device out of range has no name");
        assert_eq!(l.submodules_of(0), 0..3);
        assert_eq!(l.submodules_of(1), 3..4);
        assert_eq!(l.submodules_of(9), 0..0);
        assert_eq!(l.find("io", 2, 1), Some(2));
        assert_eq!(l.find("di", 1, 1), Some(3));
        // Slot 2 is "io"'s, not "di"'s.
        assert_eq!(l.find("di", 2, 1), None);
        assert_eq!(l.find("io", 1, 2), None);
        assert_eq!(l.output_submodules().collect::<Vec<_>>(), vec![1]);
        assert!(!l.is_device());
    }

    #[test]
    fn a_payload_shorter_than_its_tables_decodes_to_nothing() {
        let (header, payload) = published();
        let sub_at = procimg_shm_layout::ImageLayout::submodule_table_offset(2) as usize;
        let whole = sub_at + 4 * core::mem::size_of::<SubmoduleEntry>();
        assert!(Layout::decode(&header, &payload[..whole]).is_some());
        assert_eq!(Layout::decode(&header, &payload[..whole - 1]), None);
    }

    proptest! {
        /// Whatever a layout sample holds, decoding it returns a layout or None: no panic,
        /// no allocation beyond what the payload can back.
        #[test]
        fn decode_never_panics(
            devices in any::<u32>(),
            submodules in any::<u32>(),
            payload in proptest::collection::vec(any::<u8>(), 0..4096),
        ) {
            let header = LayoutHeader {
                device_count: devices % 64,
                submodule_count: submodules,
                ..LayoutHeader::default()
            };
            let _ = Layout::decode(&header, &payload);
            let header = LayoutHeader { device_count: devices, submodule_count: submodules % 64, ..header };
            let _ = Layout::decode(&header, &payload);
        }
    }
}
