// SPDX-License-Identifier: MIT OR Apache-2.0
//! The station making itself seen, and a request to let go of it: `PNIO_CBF_START_LED_FLASH`
//! and `PNIO_CBF_STOP_LED_FLASH` for an engineering tool's DCP Signal, and
//! `PNIO_CBF_CP_STOP_REQ` when a DCP "reset to factory" takes the station's name and
//! address: the station is being set up anew over the network, so the program is to close
//! the device (and may open it again) outside the callback.
//!
//! A DCP Signal asks the station to flash for three seconds ("flash once"): START comes at
//! once with 2 Hz, STOP when the three seconds are over; another Signal meanwhile extends
//! the flashing without a second START.

use super::state::Device;
use crate::iobase::callbacks::invoke_device;
use crate::iobase::sync::lock;
use std::time::{Duration, Instant};

/// How long the station identifies itself after a DCP Signal.
const FLASH_FOR: Duration = Duration::from_secs(3);
/// The flashing frequency, in Hz, as DCP Signal's "flash once" has it.
const FLASH_HZ: u32 = 2;

/// A DCP Signal: flashing starts (or goes on).
pub(crate) fn blink(dev: &Device) {
    let started = lock(&dev.flashing_until)
        .replace(Instant::now() + FLASH_FOR)
        .is_none();
    if started && let Some(f) = dev.cbf.cbf_start_led_flash {
        // SAFETY: a PNIO_CBF_START_LED_FLASH the program gave PNIO_device_open, callable
        // until PNIO_device_close (which waits for this thread).
        invoke_device(|| unsafe { f(dev.handle, FLASH_HZ) });
    }
}

/// Ends the flashing when its time is over.
pub(crate) fn tick(dev: &Device) {
    let over = {
        let mut until = lock(&dev.flashing_until);
        match *until {
            Some(t) if t <= Instant::now() => until.take().is_some(),
            _ => false,
        }
    };
    if over && let Some(f) = dev.cbf.cbf_stop_led_flash {
        // SAFETY: a PNIO_CBF_STOP_LED_FLASH the program gave PNIO_device_open, callable
        // until PNIO_device_close (which waits for this thread).
        invoke_device(|| unsafe { f(dev.handle) });
    }
}

/// The station is reset to factory over the network: `PNIO_CBF_CP_STOP_REQ`.
pub(crate) fn stop_request(dev: &Device) {
    if let Some(f) = dev.cbf.cbf_cp_stop_req {
        // SAFETY: a PNIO_CBF_CP_STOP_REQ the program gave PNIO_device_open, callable until
        // PNIO_device_close (which waits for this thread).
        invoke_device(|| unsafe { f(dev.handle) });
    }
}
