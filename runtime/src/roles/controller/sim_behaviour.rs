// SPDX-License-Identifier: MIT OR Apache-2.0
//! How the demo's simulated devices compute their inputs: the byte logic behind a
//! configuration's [`SimBehaviour`], run by the protocol crate's device engine as
//! [`DemoApplication`].
//!
//! * **echo**: a submodule's inputs are its own last outputs (the first `min(in, out)` bytes);
//! * **counter**: every 4 input bytes hold the count `k` as a big-endian u32;
//! * **digital-io**: input byte `i` of every submodule is byte `i` of the device's outputs
//!   (all its submodules' outputs concatenated in submodule order), except the last input
//!   byte of the device, a walking bit that moves every 100 counts (a simulated sensor);
//! * **none**: the inputs are left as they are.
//!
//! `k` counts the device's produced frames. Nothing here allocates.

use crate::config::SimBehaviour;
use procimg_profinet::device::Application;

/// Counts per position of the digital-io walking bit.
pub const WALKING_BIT_PERIOD: u64 = 100;

/// Fills one submodule's `inputs` for count `k`.
///
/// `own_outputs` are the outputs this submodule last received (empty if it has none),
/// `device_outputs` those of the whole device concatenated in submodule order, and `sensor`
/// says whether this is the device's last submodule with inputs (whose last byte is the
/// digital-io walking bit).
pub fn fill_inputs(
    behaviour: SimBehaviour,
    k: u64,
    inputs: &mut [u8],
    own_outputs: &[u8],
    device_outputs: &[u8],
    sensor: bool,
) {
    match behaviour {
        // An absent device is never simulated.
        SimBehaviour::None | SimBehaviour::Absent => {}
        SimBehaviour::Echo => {
            let n = inputs.len().min(own_outputs.len());
            inputs[..n].copy_from_slice(&own_outputs[..n]);
        }
        SimBehaviour::Counter => {
            // Truncation intended: the counter wraps at 2^32 like a u32 register.
            let word = (k as u32).to_be_bytes();
            for (i, b) in inputs.iter_mut().enumerate() {
                *b = word[i % 4];
            }
        }
        SimBehaviour::DigitalIo => {
            let n = inputs.len();
            for (i, b) in inputs.iter_mut().enumerate() {
                *b = if sensor && i + 1 == n {
                    walking_bit(k)
                } else {
                    device_outputs.get(i).copied().unwrap_or(0)
                };
            }
        }
    }
}

/// A demo device's program: the behaviour its configuration chose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DemoApplication(pub SimBehaviour);

impl Application for DemoApplication {
    fn fill_inputs(
        &mut self,
        k: u64,
        inputs: &mut [u8],
        own_outputs: &[u8],
        device_outputs: &[u8],
        last: bool,
    ) {
        fill_inputs(self.0, k, inputs, own_outputs, device_outputs, last);
    }
}

/// The digital-io sensor byte for count `k`: one bit set, moving every
/// [`WALKING_BIT_PERIOD`] counts.
pub const fn walking_bit(k: u64) -> u8 {
    1 << ((k / WALKING_BIT_PERIOD) % 8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn echo_copies_the_common_prefix() {
        let mut inputs = [0u8; 3];
        fill_inputs(SimBehaviour::Echo, 7, &mut inputs, &[1, 2], &[9, 9], false);
        assert_eq!(inputs, [1, 2, 0]);
        let mut short = [0u8; 1];
        fill_inputs(SimBehaviour::Echo, 7, &mut short, &[5, 6, 7], &[], false);
        assert_eq!(short, [5]);
    }

    #[test]
    fn counter_repeats_the_big_endian_count() {
        let mut inputs = [0u8; 6];
        fill_inputs(
            SimBehaviour::Counter,
            0x0102_0304,
            &mut inputs,
            &[],
            &[],
            false,
        );
        assert_eq!(inputs, [1, 2, 3, 4, 1, 2]);
    }

    #[test]
    fn digital_io_loops_back_with_a_walking_sensor_bit() {
        let mut inputs = [0u8; 3];
        fill_inputs(
            SimBehaviour::DigitalIo,
            250,
            &mut inputs,
            &[],
            &[0xaa, 0x55, 0x11],
            true,
        );
        assert_eq!(inputs, [0xaa, 0x55, 1 << 2]);
        fill_inputs(
            SimBehaviour::DigitalIo,
            250,
            &mut inputs,
            &[],
            &[0xaa],
            false,
        );
        assert_eq!(inputs, [0xaa, 0, 0]);
        assert_eq!(walking_bit(799), 0x80);
        assert_eq!(walking_bit(800), 0x01);
    }

    #[test]
    fn none_leaves_inputs_alone() {
        let mut inputs = [3u8; 2];
        fill_inputs(SimBehaviour::None, 1, &mut inputs, &[1, 1], &[1, 1], true);
        assert_eq!(inputs, [3, 3]);
    }
}
