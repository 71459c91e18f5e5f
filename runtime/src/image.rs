// SPDX-License-Identifier: MIT OR Apache-2.0
//! The input-image payload as the server builds it: input data, status bytes and the mirror
//! of the outputs as last sent. The IO system writes inputs into it (straight into the
//! shared-memory sample about to be published) and reads outputs from it.

use procimg_shm_layout::{
    DeviceEntry, ImageLayout, LayoutError, ROLE_CONTROLLER, ROLE_DEVICE, STATION_NAME_LEN,
    SubmoduleEntry, SubmoduleStatus, layout_hash,
};

use crate::config::{Config, StationConfig, SubmoduleConfig};
use core::ptr::NonNull;

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

/// The server's input-image payload. Its input data are written straight into the sample
/// that will be published ([`Image::bind_inputs`]), so that a received byte is copied once on
/// its way to the clients; the rest (status bytes, the mirror of the outputs) is the server's
/// own, changed after a publication too, and copied into the sample when it is published.
pub struct Image {
    /// The whole payload: status and mirror always, input data when no sample is bound.
    payload: Vec<u8>,
    submodules: Vec<SubmoduleEntry>,
    /// Bytes of input data: the first region of the payload.
    input_size: usize,
    /// Where the input data are read and written now.
    inputs: InputData,
    /// Where the input data of the last image were, until [`Image::carry_over_inputs`].
    previous: InputData,
    /// Per submodule: its inputs were written since the inputs were bound.
    fresh: Vec<bool>,
}

/// Where an image's input data are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum InputData {
    /// In the image's own payload.
    Own,
    /// At the start of a loaned shared-memory sample, being written.
    Sample(NonNull<u8>),
    /// At the start of a published sample: read-only, clients read it.
    Published(NonNull<u8>),
}

impl Image {
    /// A zeroed image for `tables`, with every status BAD (nothing has been exchanged yet)
    /// except for submodules without data, which are GOOD as IO-Base specifies.
    pub fn new(tables: &Tables) -> Image {
        let mut image = Image {
            payload: vec![0; tables.layout.input_payload_size as usize],
            submodules: tables.submodules.clone(),
            input_size: tables.layout.input_size as usize,
            inputs: InputData::Own,
            previous: InputData::Own,
            fresh: vec![false; tables.submodules.len()],
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

    /// Bytes of the whole payload, as published.
    pub fn payload_len(&self) -> usize {
        self.payload.len()
    }

    /// Writes the whole payload into `dst` (of [`Image::payload_len`] bytes; shorter copies
    /// what fits).
    pub fn copy_payload(&self, dst: &mut [u8]) {
        let n = dst.len().min(self.payload.len());
        dst[..n].copy_from_slice(&self.payload[..n]);
        let inputs = self.input_size.min(n);
        dst[..inputs].copy_from_slice(&self.input_data()[..inputs]);
    }

    /// From now on the input data are read and written in `sample`, the payload of a sample
    /// loaned to be published, or in the image's own payload for `None`. Inputs written
    /// until then are fresh; the others are taken over from the last image by
    /// [`Image::carry_over_inputs`].
    ///
    /// # Safety
    ///
    /// `sample` must be valid for reads and writes of [`Image::payload_len`] bytes, and
    /// written by nobody else, from now until [`Image::publish_into`] has filled it; then
    /// readable and unchanged until the image is bound to another sample and its inputs have
    /// been carried over (as the newest sample of a publisher with a history of one is).
    #[allow(unsafe_code)]
    pub unsafe fn bind_inputs(&mut self, sample: Option<NonNull<u8>>) {
        self.previous = self.inputs;
        self.inputs = sample.map_or(InputData::Own, InputData::Sample);
        self.fresh.iter_mut().for_each(|f| *f = false);
    }

    /// Copies the inputs of every submodule not written since [`Image::bind_inputs`] from the
    /// last image (devices that sent nothing in this cycle keep their last inputs). Runs of
    /// neighbouring submodules are one copy each.
    #[allow(unsafe_code)]
    pub fn carry_over_inputs(&mut self) {
        let (from, to) = (self.previous, self.inputs);
        self.previous = self.inputs;
        if from == to {
            return;
        }
        let from = self.region_ptr(from);
        let to = self.region_ptr_mut(to);
        let n = self.submodules.len();
        let mut s = 0;
        while s < n {
            if self.fresh[s] {
                s += 1;
                continue;
            }
            let start = self.submodules[s].input_offset as usize;
            let mut end = start + self.submodules[s].input_length as usize;
            s += 1;
            while s < n && !self.fresh[s] && self.submodules[s].input_offset as usize == end {
                end += self.submodules[s].input_length as usize;
                s += 1;
            }
            let end = end.min(self.input_size);
            if start < end {
                // SAFETY: both regions hold `input_size` bytes (the own payload, or a sample
                // as `bind_inputs` requires) and `start..end` lies inside them; `copy` allows
                // the two to overlap.
                unsafe { core::ptr::copy(from.add(start), to.add(start), end - start) };
            }
        }
    }

    /// Writes the rest of the payload (status bytes, output mirror, padding) into the bound
    /// sample, ready to be sent. With no sample bound there is nothing to do.
    #[allow(unsafe_code)]
    pub fn publish_into(&mut self) {
        if let InputData::Sample(p) = self.inputs {
            self.inputs = InputData::Published(p);
            let rest = &self.payload[self.input_size..];
            // SAFETY: the sample holds `payload_len` bytes and is written by nobody else until
            // it is sent (`bind_inputs`); the rest lies after its input data.
            unsafe {
                core::ptr::copy_nonoverlapping(
                    rest.as_ptr(),
                    p.as_ptr().add(self.input_size),
                    rest.len(),
                )
            };
        }
    }

    /// The sample bound could not be published: its input data are taken into the image's
    /// own payload, where the next cycle carries them over from.
    #[allow(unsafe_code)]
    pub fn keep_inputs(&mut self) {
        if let InputData::Sample(p) | InputData::Published(p) = self.inputs {
            let n = self.input_size;
            // SAFETY: as `bind_inputs` requires, the sample stays readable and unchanged
            // until another is bound; it is not the own payload.
            unsafe { core::ptr::copy_nonoverlapping(p.as_ptr(), self.payload.as_mut_ptr(), n) };
            self.inputs = InputData::Own;
            self.previous = InputData::Own;
        }
    }

    fn region_ptr(&self, at: InputData) -> *const u8 {
        match at {
            InputData::Own => self.payload.as_ptr(),
            InputData::Sample(p) | InputData::Published(p) => p.as_ptr(),
        }
    }

    /// Where inputs are written: a published sample is not; its inputs are taken into the
    /// own payload first (nothing in a cycle writes inputs after publishing; this keeps a
    /// published image immutable whatever calls come).
    fn region_ptr_mut(&mut self, at: InputData) -> *mut u8 {
        match at {
            InputData::Own => self.payload.as_mut_ptr(),
            InputData::Sample(p) => p.as_ptr(),
            InputData::Published(_) => {
                self.keep_inputs();
                self.payload.as_mut_ptr()
            }
        }
    }

    #[allow(unsafe_code)]
    fn input_data(&self) -> &[u8] {
        let p = self.region_ptr(self.inputs);
        // SAFETY: the own payload or a bound sample, both at least `input_size` bytes long and
        // not written through another path while the image is borrowed (`bind_inputs`).
        unsafe { core::slice::from_raw_parts(p, self.input_size) }
    }

    #[allow(unsafe_code)]
    fn input_data_mut(&mut self) -> &mut [u8] {
        let p = self.region_ptr_mut(self.inputs);
        // SAFETY: as in `input_data`, and the image is borrowed mutably.
        unsafe { core::slice::from_raw_parts_mut(p, self.input_size) }
    }

    /// The submodule table.
    pub fn submodules(&self) -> &[SubmoduleEntry] {
        &self.submodules
    }

    /// Inputs of submodule `s`.
    pub fn inputs(&self, s: usize) -> &[u8] {
        let e = &self.submodules[s];
        let at = e.input_offset as usize;
        &self.input_data()[at..at + e.input_length as usize]
    }

    /// Inputs of submodule `s`, writable. Writing through it does not make them fresh: a
    /// device's new inputs go through [`Image::set_inputs`].
    pub fn inputs_mut(&mut self, s: usize) -> &mut [u8] {
        let e = self.submodules[s];
        let at = e.input_offset as usize;
        &mut self.input_data_mut()[at..at + e.input_length as usize]
    }

    /// Sets all inputs of submodule `s` to `data`, which makes them fresh in this cycle.
    /// `false` (and nothing written) if `data` has another length.
    pub fn set_inputs(&mut self, s: usize, data: &[u8]) -> bool {
        let dst = self.inputs_mut(s);
        if dst.len() != data.len() {
            return false;
        }
        dst.copy_from_slice(data);
        self.fresh[s] = true;
        true
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

#[cfg(test)]
#[path = "image_tests.rs"]
mod tests;
