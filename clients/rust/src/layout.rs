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
    use proptest::prelude::*;

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
