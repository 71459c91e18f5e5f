// SPDX-License-Identifier: MIT OR Apache-2.0
//! The input-image payload as the server builds it: input data, status bytes and the mirror
//! of the outputs as last sent. The IO system writes inputs into it (straight into the
//! shared-memory sample about to be published) and reads outputs from it. The mirror holds
//! each frame the server produces with outputs in it ([`Tables::output_frames`]): each
//! device's output frame in the controller role, the station's frame to its PLC in the
//! device role. The IO system completes it around the outputs and sends it from there.

use crate::roles::controller::plan::{device_spec, submodule_spec};
use procimg_profinet::controller::plan::{DeviceSpec, SubmoduleSpec};
use procimg_profinet::cyclic::{PRODUCED_C_SDU_OFFSET, produced_frame_len};
use procimg_profinet::iocr_layout::CrLayout;
use procimg_shm_layout::{
    DeviceEntry, ImageLayout, LayoutError, MirrorArea, ROLE_CONTROLLER, ROLE_DEVICE,
    STATION_NAME_LEN, SubmoduleEntry, SubmoduleStatus, layout_hash,
};

use crate::config::{Config, StationConfig, SubmoduleConfig};
use core::ptr::NonNull;
use region::{Place, Region};

#[allow(unsafe_code)]
mod region;

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
    /// Per device: the frame with its outputs the server sends, in the output mirror, if the
    /// image holds one (the controller role's devices with outputs; in the device role, the
    /// station's frame to its PLC, if the station has inputs).
    pub output_frames: Vec<Option<OutputFrame>>,
}

/// A device's output frame as the input-image payload holds it: the frame the controller
/// sends it, its outputs inside where the frame carries them. The cycle writes the header and
/// status bytes around them and sends the frame from there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutputFrame {
    /// Where the frame lies in the payload.
    pub range: core::ops::Range<usize>,
    /// How many submodules' outputs it holds.
    pub outputs: usize,
}

impl Tables {
    /// Builds the tables of a validated configuration.
    pub fn from_config(config: &Config) -> Result<Tables, LayoutError> {
        if let Some(station) = &config.station {
            return Tables::of_station(station);
        }
        let mut devices = Vec::with_capacity(config.devices.len());
        let mut submodules = Vec::new();
        let mut frames = Vec::new();
        for (d, dev) in config.devices.iter().enumerate() {
            let (_, layout) = device_spec(dev).iocr_layout();
            if let Some(frame) = layout
                .ok()
                .and_then(|l| frame_area(&l.output, submodules.len()))
            {
                frames.push((d, frame));
            }
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
        Tables::laid_out(ROLE_CONTROLLER, devices, submodules, &frames)
    }

    /// The device role's tables: the station as the one device, each submodule with its Q
    /// data in the server-written part and its I data in the client-written part.
    pub fn of_station(station: &StationConfig) -> Result<Tables, LayoutError> {
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
        // The PLC lays out the station's frame (its input CR) at Connect, after the image is
        // made. The image holds it as a PLC that plans the station by its configuration lays
        // it out (an S7-1500, procimgd's own controller, the demo PLC): an AR laid out so
        // goes out from the image, any other is written from it.
        let specs: Vec<SubmoduleSpec> = station.submodule_configs().map(submodule_spec).collect();
        let (_, layout) = DeviceSpec::iocr_layout_of(&specs);
        let frames: Vec<(usize, MirrorArea)> = layout
            .ok()
            .and_then(|l| frame_area(&l.input, 0))
            .map(|area| (0, area))
            .into_iter()
            .collect();
        Tables::laid_out(ROLE_DEVICE, devices, submodules, &frames)
    }

    /// The tables with offsets assigned, the output mirror holding `frames` (device, its
    /// frame's area).
    fn laid_out(
        role: u32,
        devices: Vec<DeviceEntry>,
        mut submodules: Vec<SubmoduleEntry>,
        frames: &[(usize, MirrorArea)],
    ) -> Result<Tables, LayoutError> {
        let areas: Vec<MirrorArea> = frames.iter().map(|(_, a)| a.clone()).collect();
        let layout = ImageLayout::assign_framed(&mut submodules, &areas)?;
        let mut output_frames = vec![None; devices.len()];
        for (d, area) in frames {
            // Where the area starts: its first output's place less its offset in the area.
            if let Some(&(s, offset)) = area.placed.first() {
                let start = submodules[s].output_mirror_offset as usize - offset as usize;
                output_frames[*d] = Some(OutputFrame {
                    range: start..start + area.len as usize,
                    outputs: area.placed.len(),
                });
            }
        }
        let hash = layout_hash(role, &layout, &devices, &submodules);
        Ok(Tables {
            output_frames,
            role,
            devices,
            submodules,
            layout,
            hash,
        })
    }

    /// Where the output mirror ends in the input-image payload: its output frames (with
    /// their headers and status bytes around the outputs), then the packed outputs.
    pub fn output_mirror_end(&self) -> usize {
        let outputs = self
            .submodules
            .iter()
            .map(|e| e.output_mirror_offset as usize + e.output_length as usize);
        let frames = self.output_frames.iter().flatten().map(|f| f.range.end);
        outputs
            .chain(frames)
            .fold(self.layout.output_mirror_offset as usize, usize::max)
    }

    /// The station name of device `d`.
    pub fn device_name(&self, d: usize) -> &str {
        self.devices
            .get(d)
            .and_then(|d| d.station_name())
            .unwrap_or("?")
    }
}

/// A frame the server produces (`cr`, the C_SDU layout of one IO CR) as its area of the
/// output mirror: the submodules' outputs where the frame carries them (`first` is the
/// table index of the CR's submodule 0), so that the cycle sends the frame from the image as
/// it stands. `None` for a frame without outputs.
fn frame_area(cr: &CrLayout, first: usize) -> Option<MirrorArea> {
    let placed: Vec<(usize, u32)> = cr
        .objects
        .iter()
        .filter(|o| o.length > 0)
        .map(|o| {
            let at = PRODUCED_C_SDU_OFFSET + usize::from(o.data_offset);
            (first + o.submodule, at as u32)
        })
        .collect();
    (!placed.is_empty()).then(|| MirrorArea {
        len: produced_frame_len(usize::from(cr.data_length)) as u32,
        placed,
    })
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

/// The server's input-image payload, built in place in the shared-memory sample that will be
/// published: input data straight from the frames ([`Image::bind_inputs`]), client outputs
/// straight into the mirror of the next image ([`Image::bind_outputs`]); whatever was not
/// written anew is carried over from the last image. The status bytes are the server's own
/// (they change after a publication too) and are copied in when the sample is published.
pub struct Image {
    /// The whole payload: the status bytes always, input data and mirror while they are not
    /// bound to a sample.
    payload: Vec<u8>,
    submodules: Vec<SubmoduleEntry>,
    /// Per device: its output frame in the mirror, if the image holds one.
    output_frames: Vec<Option<OutputFrame>>,
    /// The input data: the first region of the payload.
    inputs: Region,
    /// The mirror of the outputs as last sent: the last region (but for padding).
    outputs: Region,
}

impl Image {
    /// A zeroed image for `tables`, with every status BAD (nothing has been exchanged yet)
    /// except for submodules without data, which are GOOD as IO-Base specifies.
    pub fn new(tables: &Tables) -> Image {
        let l = &tables.layout;
        let spans = |at: fn(&SubmoduleEntry) -> (u32, u16)| {
            tables
                .submodules
                .iter()
                .map(|e| {
                    let (offset, len) = at(e);
                    (offset as usize, offset as usize + len as usize)
                })
                .collect()
        };
        let mirror = l.output_mirror_offset as usize;
        let mirror_end = tables.output_mirror_end();
        let mut image = Image {
            payload: vec![0; l.input_payload_size as usize],
            submodules: tables.submodules.clone(),
            output_frames: tables.output_frames.clone(),
            inputs: Region::new(
                spans(|e| (e.input_offset, e.input_length)),
                (0, l.input_size as usize),
            ),
            outputs: Region::new(
                spans(|e| (e.output_mirror_offset, e.output_length)),
                (mirror, mirror_end),
            ),
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

    /// From now on the input data are written in `sample`, the start of the payload of a
    /// sample loaned to be published, or in the image's own payload for `None`. Inputs
    /// written until [`Image::carry_over_inputs`] are fresh; the others are carried over
    /// from where they were.
    ///
    /// # Safety
    ///
    /// `sample` must be valid for reads and writes of [`Image::payload_len`] bytes, and
    /// written by nobody else, from now until [`Image::publish_into`] has filled it; then
    /// readable and unchanged until the image is bound to another sample and carried over
    /// (as the newest sample of a publisher with a history of one is). It must be the sample
    /// the outputs are bound to, if they are bound to one. A sample the image was bound to
    /// before must hold what it held when it was published: the carry-over copies only what
    /// changed since (see `image::region`).
    #[allow(unsafe_code)]
    pub unsafe fn bind_inputs(&mut self, sample: Option<NonNull<u8>>) {
        // SAFETY: passed on to the caller.
        unsafe { self.inputs.bind(sample, &mut self.payload) };
    }

    /// From now on the mirror of the outputs is written in `sample` (the next sample to be
    /// published), or in the own payload for `None`. Outputs set until
    /// [`Image::carry_over_outputs`] are fresh; the others are carried over from the last
    /// image.
    ///
    /// # Safety
    ///
    /// As for [`Image::bind_inputs`]; the inputs are bound to the same sample before it is
    /// published.
    #[allow(unsafe_code)]
    pub unsafe fn bind_outputs(&mut self, sample: Option<NonNull<u8>>) {
        // SAFETY: passed on to the caller.
        unsafe { self.outputs.bind(sample, &mut self.payload) };
    }

    /// Copies the inputs of every submodule not written since [`Image::bind_inputs`] from the
    /// last image (devices that sent nothing in this cycle keep their last inputs).
    pub fn carry_over_inputs(&mut self) {
        self.inputs.carry_over(&mut self.payload);
    }

    /// Copies the outputs of every submodule not set since [`Image::bind_outputs`] from the
    /// last image (outputs nobody wrote in this cycle stay as last sent).
    pub fn carry_over_outputs(&mut self) {
        self.outputs.carry_over(&mut self.payload);
    }

    /// Bytes of inputs and outputs carried over from the last image since the image was made
    /// (what was neither written anew nor held already by the sample it went into).
    pub fn carried_bytes(&self) -> u64 {
        self.inputs.carried() + self.outputs.carried()
    }

    /// Completes the bound sample for publication: carries over what was not written and
    /// writes the status bytes, the padding, and the mirror if it is not in the sample. From
    /// then on the sample is read-only. With no sample bound there is nothing to do.
    pub fn publish_into(&mut self) {
        self.carry_over_inputs();
        self.carry_over_outputs();
        let Place::Sample(p) = self.inputs.place() else {
            return;
        };
        let (mirror_start, mirror_end) = self.outputs.extent();
        let input_end = self.inputs.extent().1;
        let mirror_apart = self.outputs.place() != Place::Sample(p);
        let len = self.payload.len();
        let outputs_base = self.outputs.base(&self.payload);
        let own = self.payload.as_ptr();
        let put = |from: *const u8, start: usize, end: usize| {
            if start < end && end <= len {
                #[allow(unsafe_code)]
                // SAFETY: the sample holds the whole payload and is written by nobody else
                // until it is sent (`bind_inputs`); `from` is the own payload or the sample
                // the outputs are in, which hold it too; a region of one is never copied
                // onto the same region of itself.
                unsafe {
                    core::ptr::copy(from.add(start), p.as_ptr().add(start), end - start)
                };
            }
        };
        put(own, input_end, mirror_start);
        if mirror_apart {
            put(outputs_base, mirror_start, mirror_end);
        }
        put(own, mirror_end, len);
        self.inputs.published();
        self.outputs.published();
    }

    /// The sample bound could not be published: inputs and outputs are taken into the
    /// image's own payload, where the next cycle carries them over from.
    pub fn keep_unpublished(&mut self) {
        self.inputs.keep(&mut self.payload);
        self.outputs.keep(&mut self.payload);
    }

    /// The submodule table.
    pub fn submodules(&self) -> &[SubmoduleEntry] {
        &self.submodules
    }

    /// Inputs of submodule `s`.
    pub fn inputs(&self, s: usize) -> &[u8] {
        self.inputs.get(s, &self.payload)
    }

    /// Inputs of submodule `s`, writable in place (as they were, so a partial write keeps
    /// the rest).
    pub fn inputs_mut(&mut self, s: usize) -> &mut [u8] {
        self.inputs.get_mut(s, &mut self.payload)
    }

    /// Sets all inputs of submodule `s` to `data`, which makes them fresh in this cycle.
    /// `false` (and nothing written) if `data` has another length.
    pub fn set_inputs(&mut self, s: usize, data: &[u8]) -> bool {
        self.inputs.set(s, data, &mut self.payload)
    }

    /// Outputs of submodule `s` as they will be (or were last) sent.
    pub fn outputs(&self, s: usize) -> &[u8] {
        self.outputs.get(s, &self.payload)
    }

    /// Outputs of submodule `s`, writable in place (as they were, so a partial write keeps
    /// the rest).
    pub fn outputs_mut(&mut self, s: usize) -> &mut [u8] {
        self.outputs.get_mut(s, &mut self.payload)
    }

    /// Sets all outputs of submodule `s` to `data` (a client's whole submodule). `false` (and
    /// nothing written) if `data` has another length.
    pub fn set_outputs(&mut self, s: usize, data: &[u8]) -> bool {
        self.outputs.set(s, data, &mut self.payload)
    }

    /// Device `d`'s output frame in the mirror of the outputs, if the image holds one.
    pub fn output_frame(&self, d: usize) -> Option<&OutputFrame> {
        self.output_frames.get(d)?.as_ref()
    }

    /// Device `d`'s output frame as the next image holds it, its outputs current (carried
    /// over first), writable around them: the cycle writes the header and status bytes and
    /// sends it from there. No submodule counts as written. `None` if the image holds no
    /// frame for `d`.
    pub fn output_frame_mut(&mut self, d: usize) -> Option<&mut [u8]> {
        let range = self.output_frames.get(d)?.as_ref()?.range.clone();
        self.outputs
            .range_mut(range.start, range.end, &mut self.payload)
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
