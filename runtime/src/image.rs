// SPDX-License-Identifier: MIT OR Apache-2.0
//! The server's own copy of the input-image payload: input data, status bytes and the mirror
//! of the outputs as last sent. The IO system writes inputs into it and reads outputs from
//! it; each cycle it is copied once into the published shared-memory sample.

use procimg_shm_layout::{
    DeviceEntry, ImageLayout, LayoutError, ROLE_CONTROLLER, ROLE_DEVICE, STATION_NAME_LEN,
    SubmoduleEntry, SubmoduleStatus, layout_hash,
};

use crate::config::{Config, StationConfig, SubmoduleConfig};

/// The tables of an IO system as shared memory describes them.
///
/// In the device role the device table has one entry, the station itself, and the image's
/// directions are those of the data: the server-written part (a submodule's `input_*`
/// fields) holds the Q data the PLC wrote, the client-written part (`output_*`) the I data
/// clients provide (see [`ROLE_DEVICE`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Tables {
    /// The server's role: [`ROLE_CONTROLLER`] or [`ROLE_DEVICE`].
    pub role: u32,
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
        if let Some(station) = &config.station {
            return Tables::of_station(station);
        }
        let mut devices = Vec::with_capacity(config.devices.len());
        let mut submodules = Vec::new();
        for (d, dev) in config.devices.iter().enumerate() {
            devices.push(DeviceEntry {
                station_name: station_name(&dev.name),
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
            submodules.extend(dev.submodules.iter().map(|s| entry(d, s)));
        }
        Tables::laid_out(ROLE_CONTROLLER, devices, submodules)
    }

    /// The device role's tables: the station as the one device, each submodule with its Q
    /// data in the server-written part and its I data in the client-written part.
    fn of_station(station: &StationConfig) -> Result<Tables, LayoutError> {
        let devices = vec![DeviceEntry {
            station_name: station_name(&station.name),
            vendor_id: station.vendor_id,
            device_id: station.device_id,
            instance: station.instance,
            reduction_ratio: 1,
            ip_address: station.ip.map(|ip| ip.octets()).unwrap_or([0; 4]),
            first_submodule: 0,
            submodule_count: station.submodules.len() as u32,
            watchdog_factor: 0,
            reserved: 0,
        }];
        let submodules = station
            .submodule_configs()
            .map(|s| {
                let e = entry(0, s);
                SubmoduleEntry {
                    input_length: s.output_length,
                    output_length: s.input_length,
                    input_address: s.output_address,
                    output_address: s.input_address,
                    ..e
                }
            })
            .collect();
        Tables::laid_out(ROLE_DEVICE, devices, submodules)
    }

    fn laid_out(
        role: u32,
        devices: Vec<DeviceEntry>,
        mut submodules: Vec<SubmoduleEntry>,
    ) -> Result<Tables, LayoutError> {
        let layout = ImageLayout::assign(&mut submodules)?;
        let hash = layout_hash(role, &layout, &devices, &submodules);
        Ok(Tables {
            role,
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

/// A station name as the device table holds it: NUL-padded, cut at the field's length.
fn station_name(name: &str) -> [u8; STATION_NAME_LEN] {
    let mut field = [0u8; STATION_NAME_LEN];
    let n = name.len().min(STATION_NAME_LEN);
    field[..n].copy_from_slice(&name.as_bytes()[..n]);
    field
}

/// The table entry of submodule `s` of device `d`, in the controller's directions.
fn entry(d: usize, s: &SubmoduleConfig) -> SubmoduleEntry {
    SubmoduleEntry {
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
