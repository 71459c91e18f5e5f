// SPDX-License-Identifier: MIT OR Apache-2.0
//! The server's own copy of the input-image payload: input data, status bytes and the mirror
//! of the outputs as last sent. The IO system writes inputs into it and reads outputs from
//! it; each cycle it is copied once into the published shared-memory sample.

use procimg_shm_layout::{
    DeviceEntry, ImageLayout, LayoutError, STATION_NAME_LEN, SubmoduleEntry, SubmoduleStatus,
    layout_hash,
};

use crate::config::Config;

/// The tables of an IO system as shared memory describes them.
#[derive(Clone, Debug, PartialEq)]
pub struct Tables {
    /// Device table.
    pub devices: Vec<DeviceEntry>,
    /// Submodule table, with offsets assigned.
    pub submodules: Vec<SubmoduleEntry>,
    /// Region sizes and offsets.
    pub layout: ImageLayout,
    /// Hash over all of it.
    pub hash: u64,
}

impl Tables {
    /// Builds the tables of a validated configuration.
    pub fn from_config(config: &Config) -> Result<Tables, LayoutError> {
        let mut devices = Vec::with_capacity(config.devices.len());
        let mut submodules = Vec::new();
        for (d, dev) in config.devices.iter().enumerate() {
            let mut station_name = [0u8; STATION_NAME_LEN];
            let name = dev.name.as_bytes();
            let n = name.len().min(STATION_NAME_LEN);
            station_name[..n].copy_from_slice(&name[..n]);
            devices.push(DeviceEntry {
                station_name,
                vendor_id: dev.vendor_id,
                device_id: dev.device_id,
                instance: dev.instance,
                reduction_ratio: dev.reduction_ratio,
                ip_address: dev.ip.map(|ip| ip.octets()).unwrap_or([0; 4]),
                first_submodule: submodules.len() as u32,
                submodule_count: dev.submodules.len() as u32,
                watchdog_factor: dev.watchdog_factor,
                reserved: 0,
            });
            for s in &dev.submodules {
                submodules.push(SubmoduleEntry {
                    device: d as u16,
                    slot: s.slot,
                    subslot: s.subslot,
                    rt_class: s.rt_class,
                    api: s.api,
                    module_ident: s.module_ident,
                    submodule_ident: s.submodule_ident,
                    input_address: s.input_address,
                    output_address: s.output_address,
                    input_length: s.input_length,
                    output_length: s.output_length,
                    ..SubmoduleEntry::EMPTY
                });
            }
        }
        let layout = ImageLayout::assign(&mut submodules)?;
        let hash = layout_hash(&layout, &devices, &submodules);
        Ok(Tables {
            devices,
            submodules,
            layout,
            hash,
        })
    }

    /// The station name of device `d`.
    pub fn device_name(&self, d: usize) -> &str {
        self.devices
            .get(d)
            .and_then(|d| d.station_name())
            .unwrap_or("?")
    }
}

/// The server's master copy of the input-image payload.
pub struct Image {
    payload: Vec<u8>,
    submodules: Vec<SubmoduleEntry>,
}

impl Image {
    /// A zeroed image for `tables`, with every status BAD (nothing has been exchanged yet)
    /// except for submodules without data, which are GOOD as IO-Base specifies.
    pub fn new(tables: &Tables) -> Image {
        let mut image = Image {
            payload: vec![0; tables.layout.input_payload_size as usize],
            submodules: tables.submodules.clone(),
        };
        use procimg_shm_layout::{IOXS_BAD_BY_CONTROLLER as BAD, IOXS_GOOD as GOOD};
        for s in 0..image.submodules.len() {
            let e = image.submodules[s];
            // A direction without data is GOOD (IO-Base: slots without data report GOOD);
            // a direction with data is BAD until something is exchanged.
            let input = if e.input_length == 0 { GOOD } else { BAD };
            let output = if e.output_length == 0 { GOOD } else { BAD };
            image.set_status(
                s,
                SubmoduleStatus {
                    input_iops: input,
                    input_iocs: input,
                    output_iops: output,
                    output_iocs: output,
                },
            );
        }
        image
    }

    /// The whole payload, as published.
    pub fn payload(&self) -> &[u8] {
        &self.payload
    }

    /// The submodule table.
    pub fn submodules(&self) -> &[SubmoduleEntry] {
        &self.submodules
    }

    /// Inputs of submodule `s`.
    pub fn inputs(&self, s: usize) -> &[u8] {
        let e = &self.submodules[s];
        let at = e.input_offset as usize;
        &self.payload[at..at + e.input_length as usize]
    }

    /// Inputs of submodule `s`, writable.
    pub fn inputs_mut(&mut self, s: usize) -> &mut [u8] {
        let e = &self.submodules[s];
        let at = e.input_offset as usize;
        &mut self.payload[at..at + e.input_length as usize]
    }

    /// Outputs of submodule `s` as they will be (or were last) sent.
    pub fn outputs(&self, s: usize) -> &[u8] {
        let e = &self.submodules[s];
        let at = e.output_mirror_offset as usize;
        &self.payload[at..at + e.output_length as usize]
    }

    /// Outputs of submodule `s`, writable.
    pub fn outputs_mut(&mut self, s: usize) -> &mut [u8] {
        let e = &self.submodules[s];
        let at = e.output_mirror_offset as usize;
        &mut self.payload[at..at + e.output_length as usize]
    }

    /// Status bytes of submodule `s`.
    pub fn status(&self, s: usize) -> SubmoduleStatus {
        let at = self.submodules[s].status_offset as usize;
        let b = &self.payload[at..at + 4];
        SubmoduleStatus {
            input_iops: b[0],
            input_iocs: b[1],
            output_iops: b[2],
            output_iocs: b[3],
        }
    }

    /// Sets the status bytes of submodule `s`.
    pub fn set_status(&mut self, s: usize, v: SubmoduleStatus) {
        let at = self.submodules[s].status_offset as usize;
        self.payload[at..at + 4].copy_from_slice(&[
            v.input_iops,
            v.input_iocs,
            v.output_iops,
            v.output_iocs,
        ]);
    }
}
