// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO system behind the image: what fills the inputs and takes the outputs each cycle.
//!
//! The cycle engine calls [`IoSystem::receive`] at the start of a cycle and
//! [`IoSystem::send`] when the cycle's outputs are complete. Implementations run on the cycle
//! thread: they must not allocate, block or log inside these calls.

pub mod pnio;

use crate::image::Image;
use procimg_shm_layout::Mode;

/// Timing of the call, for implementations that keep time (watchdogs, reduction ratios).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CycleTime {
    /// Cycle index k.
    pub cycle: u64,
    /// `CLOCK_MONOTONIC` ns at the call.
    pub now_ns: u64,
}

/// A source of inputs and sink of outputs, driven by the cycle.
pub trait IoSystem: Send {
    /// Updates the inputs, the input IOPS and the output IOCS in `image` with what arrived
    /// since the last call.
    fn receive(&mut self, t: CycleTime, mode: Mode, image: &mut Image);
    /// Sends the outputs of `image` with their IOPS (the mirror region). It may write the
    /// bytes around the outputs of an output frame the image holds, never the outputs. Not
    /// called in OFFLINE.
    fn send(&mut self, t: CycleTime, mode: Mode, image: &mut Image);
}
