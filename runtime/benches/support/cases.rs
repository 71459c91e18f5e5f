// SPDX-License-Identifier: MIT OR Apache-2.0
//! The cases both benchmarks run, and the bytes the server copies in each.

use super::rig::Io;
use super::shape::{self, Shape};
use procimg_profinet::cyclic::produced_frame_len;
use procimg_profinet::iocr_layout::IocrLayout;
use procimg_runtime::image::Tables;

const KIB: usize = 1024;

/// The image-size sweep: inputs (and as many outputs) of 64 B to 1 MiB, in submodules of at
/// most 1 KiB, one per device up to 256 devices. 256 × 1438 B is the most a PROFINET IO
/// system of 256 devices carries; 1 MiB needs four 1 KiB submodules per device, more than
/// one frame holds, so it runs with the null IO system only.
pub const SIZES: [Shape; 6] = [
    sized(1, 1, 64),
    sized(1, 1, KIB),
    sized(4, 4, 4 * KIB),
    sized(64, 64, 64 * KIB),
    sized(256, 256, 256 * 1438),
    sized(256, 1024, 1024 * KIB),
];

/// The submodule sweep: 12 KiB over 16 devices, in 16 to 4096 submodules.
pub const SUBMODULES: [Shape; 5] = [
    sized(16, 16, 12 * KIB),
    sized(16, 64, 12 * KIB),
    sized(16, 256, 12 * KIB),
    sized(16, 1024, 12 * KIB),
    sized(16, 4096, 12 * KIB),
];

/// The shape of the client sweep: the largest submodule count, where a cost per client
/// and submodule shows most.
pub const CLIENT_SHAPE: Shape = sized(16, 4096, 12 * KIB);

/// Clients in the client sweep, up to half of MAX_CLIENTS: each has an output service of its
/// own, so the merge looks at one port per client.
pub const CLIENTS: [usize; 6] = [1, 2, 4, 8, 16, 32];

/// The device sweep of the PROFINET IO system: 1 to 256 devices, one 64-byte submodule each.
pub const DEVICES: [Shape; 5] = [
    sized(1, 1, 64),
    sized(4, 4, 4 * 64),
    sized(16, 16, 16 * 64),
    sized(64, 64, 64 * 64),
    sized(256, 256, 256 * 64),
];

/// The frame-size sweep of the PROFINET IO system: 16 devices, one submodule each, of 16 to
/// 1438 bytes (C_SDU 40 to 1440 bytes).
pub const FRAMES: [Shape; 4] = [
    sized(16, 16, 16 * 16),
    sized(16, 16, 16 * 256),
    sized(16, 16, 16 * 1024),
    sized(16, 16, 16 * 1438),
];

const fn sized(devices: usize, submodules: usize, bytes: usize) -> Shape {
    Shape {
        devices,
        submodules,
        bytes,
    }
}

/// A short label: `64K/64d/64s`.
pub fn label(s: Shape) -> String {
    let b = if s.bytes >= KIB && s.bytes.is_multiple_of(KIB) {
        format!("{}K", s.bytes / KIB)
    } else if s.bytes >= KIB {
        format!("{:.1}K", s.bytes as f64 / KIB as f64)
    } else {
        format!("{}B", s.bytes)
    };
    format!("{b}/{}d/{}s", s.devices, s.submodules)
}

/// The bytes the server copies per cycle, by part.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Copied {
    /// Into the input sample besides what arrives: the status bytes and the padding outside
    /// the output mirror. The inputs and outputs nobody sent are not copied: each sample
    /// comes back holding them (`image::region`), and in these cases they do not change.
    pub publish: usize,
    /// Output samples → the next input sample: the output data the clients wrote.
    pub merge: usize,
    /// Input frames → input sample: the input data.
    pub receive: usize,
    /// Output frames: each frame the image holds is written around its outputs (header,
    /// IOPS, IOCS, APDU status); a device's frame without outputs is written from the image
    /// (IOPS, IOCS, APDU status).
    pub send: usize,
}

impl Copied {
    /// The bytes of a cycle of `shape` with `io` and `clients` clients (each cycle every
    /// output is written by some client).
    pub fn cycle(shape: Shape, io: Io, clients: usize) -> Copied {
        let tables = match io {
            Io::PnioDevice => {
                let station = shape::as_station(&shape::config("bytes", shape));
                Tables::from_config(&station).expect("the shape lays out")
            }
            _ => tables(shape),
        };
        let l = &tables.layout;
        let mirror = tables.output_mirror_end() - l.output_mirror_offset as usize;
        let mut c = Copied {
            publish: l.input_payload_size as usize - l.input_size as usize - mirror,
            ..Copied::default()
        };
        if clients > 0 {
            // The clients write every output.
            c.merge = l.output_size as usize;
        }
        if io != Io::Null {
            // Every device sends every cycle.
            c.receive = l.input_size as usize;
            c.send = match io {
                Io::PnioDevice => Copied::device_frames(shape),
                _ => Copied::frames(shape),
            };
        }
        c
    }

    /// Bytes the device role's send writes into its input frames of one cycle: the PLC lays
    /// them out, so each is written whole from the image (data, IOPS, IOCS, APDU status).
    pub fn device_frames(shape: Shape) -> usize {
        per_device(shape, |layout| {
            let i = &layout.input;
            let data: usize = i.objects.iter().map(|d| d.length as usize + 1).sum();
            data + i.iocs.len() + 4
        })
    }

    /// Bytes the controller's send writes into the output frames of one cycle: around the
    /// outputs of each frame the image holds, all of a frame without outputs.
    pub fn frames(shape: Shape) -> usize {
        per_device(shape, |layout| {
            let o = &layout.output;
            let data: usize = o.objects.iter().map(|d| d.length as usize).sum();
            if data > 0 {
                produced_frame_len(o.data_length as usize) - data
            } else {
                o.objects.len() + o.iocs.len() + 4
            }
        })
    }

    /// All of it.
    pub fn total(&self) -> usize {
        self.publish + self.merge + self.receive + self.send
    }
}

/// `bytes` of each device's CR layout in `shape`, summed.
fn per_device(shape: Shape, bytes: impl Fn(&IocrLayout) -> usize) -> usize {
    let config = shape::config("bytes", shape);
    procimg_runtime::roles::controller::plan_devices(&config)
        .expect("the shape fits PROFINET frames")
        .iter()
        .map(|p| bytes(&p.layout))
        .sum()
}

/// The tables of `shape`.
pub fn tables(shape: Shape) -> Tables {
    Tables::from_config(&shape::config("bytes", shape)).expect("the shape lays out")
}
