// SPDX-License-Identifier: MIT OR Apache-2.0
//! Simulated devices for `procimgd --demo` and tests: an in-process IO system that needs no
//! network and no privileges.
//!
//! * **echo**: its inputs are the outputs it received, one cycle later, submodule by
//!   submodule (the first `min(in, out)` bytes);
//! * **counter**: every input byte group holds the cycle number k (u32, big-endian) in which
//!   the device sampled it, so the inputs change every cycle;
//! * **digital-io**: the inputs loop the outputs back byte for byte, except the last input
//!   byte, a walking bit that moves every 100 cycles (a simulated sensor);
//! * **none**: inputs stay zero.
//!
//! A device is connected while the mode is not OFFLINE: then its IOPS and IOCS are GOOD;
//! otherwise they are BAD. Each device updates only every `reduction_ratio` cycles.

use super::{CycleTime, IoSystem};
use crate::config::{Config, SimBehaviour};
use crate::image::Image;
use procimg_shm_layout::{IOXS_BAD_BY_CONTROLLER, IOXS_GOOD, Mode, SubmoduleStatus};

struct SimDevice {
    behaviour: SimBehaviour,
    reduction_ratio: u64,
    /// Submodule table indices of this device.
    submodules: std::ops::Range<usize>,
    /// The outputs last received, concatenated in submodule order (pre-allocated).
    received: Vec<u8>,
}

/// The simulated IO system.
pub struct SimIo {
    devices: Vec<SimDevice>,
}

impl SimIo {
    /// Simulated devices for every device of `config`.
    pub fn new(config: &Config) -> SimIo {
        let mut first = 0;
        let devices = config
            .devices
            .iter()
            .map(|d| {
                let n = d.submodules.len();
                let out: usize = d.submodules.iter().map(|s| s.output_length as usize).sum();
                let dev = SimDevice {
                    behaviour: d.sim,
                    reduction_ratio: d.reduction_ratio.max(1) as u64,
                    submodules: first..first + n,
                    received: vec![0; out],
                };
                first += n;
                dev
            })
            .collect();
        SimIo { devices }
    }
}

impl SimDevice {
    fn produce(&self, cycle: u64, image: &mut Image) {
        let mut out_at = 0;
        let last = self
            .submodules
            .clone()
            .rev()
            .find(|&s| image.submodules()[s].input_length > 0);
        for s in self.submodules.clone() {
            let out_len = image.submodules()[s].output_length as usize;
            let received = &self.received[out_at..out_at + out_len];
            out_at += out_len;
            let inputs = image.inputs_mut(s);
            match self.behaviour {
                SimBehaviour::None => {}
                SimBehaviour::Echo => {
                    let n = inputs.len().min(received.len());
                    inputs[..n].copy_from_slice(&received[..n]);
                }
                SimBehaviour::Counter => {
                    let k = (cycle as u32).to_be_bytes();
                    for (i, b) in inputs.iter_mut().enumerate() {
                        *b = k[i % 4];
                    }
                }
                SimBehaviour::DigitalIo => {
                    let n = inputs.len();
                    for (i, b) in inputs.iter_mut().enumerate() {
                        let is_sensor = Some(s) == last && i + 1 == n;
                        *b = if is_sensor {
                            1 << ((cycle / 100) % 8)
                        } else {
                            self.received.get(i).copied().unwrap_or(0)
                        };
                    }
                }
            }
        }
    }
}

impl IoSystem for SimIo {
    fn receive(&mut self, t: CycleTime, mode: Mode, image: &mut Image) {
        let connected = mode != Mode::Offline;
        for dev in &self.devices {
            if connected && t.cycle.is_multiple_of(dev.reduction_ratio) {
                dev.produce(t.cycle, image);
            }
            for s in dev.submodules.clone() {
                let e = image.submodules()[s];
                if e.input_length == 0 && e.output_length == 0 {
                    continue; // data-less submodules stay GOOD
                }
                let remote = if connected {
                    IOXS_GOOD
                } else {
                    IOXS_BAD_BY_CONTROLLER
                };
                let st = image.status(s);
                image.set_status(
                    s,
                    SubmoduleStatus {
                        input_iops: if e.input_length > 0 {
                            remote
                        } else {
                            IOXS_GOOD
                        },
                        output_iocs: if e.output_length > 0 {
                            remote
                        } else {
                            IOXS_GOOD
                        },
                        ..st
                    },
                );
            }
        }
    }

    fn send(&mut self, t: CycleTime, _mode: Mode, image: &Image) {
        for dev in &mut self.devices {
            if !t.cycle.is_multiple_of(dev.reduction_ratio) {
                continue;
            }
            let mut at = 0;
            for s in dev.submodules.clone() {
                let out = image.outputs(s);
                dev.received[at..at + out.len()].copy_from_slice(out);
                at += out.len();
            }
        }
    }
}
