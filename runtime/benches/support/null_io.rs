// SPDX-License-Identifier: MIT OR Apache-2.0
//! An IO system that exchanges nothing: the engine measured alone.

use procimg_runtime::image::Image;
use procimg_runtime::io::{CycleTime, IoSystem};
use procimg_shm_layout::Mode;

/// Takes no inputs and sends no outputs.
pub struct NullIo;

impl IoSystem for NullIo {
    fn receive(&mut self, _t: CycleTime, _mode: Mode, _image: &mut Image) {}
    fn send(&mut self, _t: CycleTime, _mode: Mode, _image: &mut Image) {}
}
