// SPDX-License-Identifier: MIT OR Apache-2.0
//! A device's isochronous mode: `PNIO_CP_register_cbf` and `PNIO_CP_set_opdone` with a
//! device handle, and the thread that delivers `PNIO_CP_CBE_STARTOP_IND`, `_OPFAULT_IND`
//! and `_NEWCYCLE_IND`.
//!
//! Registering STARTOP (allowed before `PNIO_device_start` only, after OPFAULT) re-attaches
//! the device's client of procimgd as a synchronous one: procimgd's cycle then waits for
//! this device's OPDONE as for an isochronous controller's. Every cycle the device's
//! isochronous thread takes the STARTOP and calls the program's callback; inside it the
//! program calls `PNIO_initiate_data_read`/`_write` (the I data written goes out with this
//! cycle's OPDONE, applied whole) and `PNIO_CP_set_opdone`. An OPDONE after the cycle's
//! deadline is answered `PNIO_OK` and reported with OPFAULT_IND; the I data of that window
//! is not used. STARTOP comes from registration on, also before start and without an AR,
//! as the manual says. Registering NEWCYCLE (before STARTOP) asks procimgd for NEWCYCLE
//! events. The window and the rules are the controller's (`crate::iobase::isochronous`),
//! and so is the thread's loop (`crate::iobase::cycle_thread`): the device's thread calls
//! only the isochronous callbacks, and none once the CP watchdog's expiry stopped the
//! device.
//!
//! While the library thread carries out a plug or pull it holds the client, and a STARTOP
//! of that time is missed (procimgd counts an OPFAULT).

use super::held::Isochronous;
use super::state::{Device, Life, lookup, wrong_handle};
use crate::iobase::callbacks::CallbackTable;
use crate::iobase::cycle_thread::{self, CycleSide};
use crate::iobase::errors::*;
use crate::iobase::isochronous::{self, OPDONE, REGISTER, Window};
use crate::iobase::sync::lock;
use crate::iobase::types::*;
use crate::iobase::wake_ahead_env;
use procimg_client::{AttachOptions, Client};
use std::sync::Arc;
use std::sync::atomic::Ordering;

impl Isochronous {
    /// Ends the thread (a callback running now finishes first).
    pub(crate) fn stop(&self) {
        self.stop.store(true, Ordering::Release);
        if let Some(t) = lock(&self.thread).take() {
            // A panic on that thread already ended it.
            let _ = t.join();
        }
        self.callbacks.clear();
    }
}

/// `PNIO_CP_register_cbf` with a device handle, after the caller check.
pub(crate) fn register(handle: u32, t: PNIO_CP_CBE_TYPE, cbf: PNIO_CP_CBF) -> u32 {
    let Some(dev) = lookup(handle) else {
        return wrong_handle(REGISTER, handle);
    };
    if let Err(code) = isochronous::check_args(t, cbf) {
        return code;
    }
    let life = lock(&dev.config).life;
    if life != Life::Opened {
        return fail(
            REGISTER,
            PNIO_ERR_SEQUENCE,
            format_args!(
                "the device is {}: isochronous callbacks are registered before \
                 PNIO_device_start only",
                life.name()
            ),
        );
    }
    if let Err(code) = isochronous::store(&dev.iso.callbacks, t, cbf) {
        return code;
    }
    if !isochronous::needs_reattach(t) {
        return PNIO_OK;
    }
    match reattach(&dev).and_then(|()| start_thread(&dev)) {
        Ok(()) => PNIO_OK,
        Err(code) => {
            dev.iso.callbacks.unset_cp(t);
            // Back to what it was; if that fails too, the data functions say so.
            let _ = reattach(&dev);
            code
        }
    }
}

/// Attaches the device's client again as the registered callbacks need (synchronous with
/// STARTOP, NEWCYCLE events with NEWCYCLE). Before start the client holds no claims.
fn reattach(dev: &Device) -> Result<(), u32> {
    let sync = dev.iso.callbacks.get_cp(PNIO_CP_CBE_STARTOP_IND).is_some();
    let newcycle = dev.iso.callbacks.get_cp(PNIO_CP_CBE_NEWCYCLE_IND).is_some();
    let name = format!("PNIO device (CP {})", dev.cp_index);
    let opts = if sync {
        AttachOptions::synchronous(&name).wake_ahead(
            wake_ahead_env::from_env().map_err(|e| fail(REGISTER, PNIO_ERR_INVALID_CONFIG, e))?,
        )
    } else {
        AttachOptions::asynchronous(&name)
    }
    .newcycle(newcycle);
    let mut client = lock(&dev.client);
    lock(&dev.iso.window).end();
    let fresh = Client::attach(&dev.instance, opts).map_err(|e| {
        fail(
            REGISTER,
            PNIO_ERR_INTERNAL,
            format_args!(
                "re-attaching to instance \"{}\" for the isochronous events failed: {e}",
                dev.instance
            ),
        )
    })?;
    // The old registration goes with the old client.
    *client = fresh;
    dev.iso.on.store(sync, Ordering::Release);
    Ok(())
}

fn start_thread(dev: &Arc<Device>) -> Result<(), u32> {
    let mut thread = lock(&dev.iso.thread);
    if thread.is_some() {
        return Ok(());
    }
    let d = dev.clone();
    let t = std::thread::Builder::new()
        .name(format!("pnio-iso-{}", dev.handle))
        .spawn(move || cycle_thread::run(IsoThread(d)))
        .map_err(|e| {
            fail(
                REGISTER,
                PNIO_ERR_START_THREAD_FAILED,
                format_args!("cannot start the device's isochronous thread: {e}"),
            )
        })?;
    *thread = Some(t);
    Ok(())
}

/// The isochronous thread's view of a device: only the `PNIO_CP_CBE_*` callbacks.
struct IsoThread(Arc<Device>);

impl CycleSide for IsoThread {
    // A stopped device hears of nothing more: it is only to be closed.
    const EVENTS_WHEN_STOPPED: bool = false;

    fn stopping(&self) -> bool {
        self.0.iso.stop.load(Ordering::Acquire)
    }

    fn handle(&self) -> u32 {
        self.0.handle
    }

    fn cp_index(&self) -> u32 {
        self.0.cp_index
    }

    fn callbacks(&self) -> &CallbackTable {
        &self.0.iso.callbacks
    }

    fn synchronous(&self) -> bool {
        self.0.iso.on.load(Ordering::Acquire)
    }

    fn with_io<R>(&self, f: impl FnOnce(&mut Client, &mut Window) -> R) -> Option<R> {
        // The window is locked after the client, as everywhere.
        let mut client = lock(&self.0.client);
        let mut window = lock(&self.0.iso.window);
        Some(f(&mut client, &mut window))
    }
}

/// `PNIO_CP_set_opdone` with a device handle (allowed inside callbacks).
pub(crate) fn set_opdone(handle: u32) -> Result<PNIO_CYCLE_INFO, u32> {
    let Some(dev) = lookup(handle) else {
        return Err(wrong_handle(OPDONE, handle));
    };
    if !dev.iso.on.load(Ordering::Acquire) {
        return Err(fail(
            OPDONE,
            PNIO_ERR_STARTOP_NOT_REGISTERED,
            "no PNIO_CP_CBE_STARTOP_IND callback is registered: the device takes no part in \
             the cycle (register OPFAULT_IND, then STARTOP_IND with PNIO_CP_register_cbf, \
             before PNIO_device_start)",
        ));
    }
    let mut client = lock(&dev.client);
    let mut window = lock(&dev.iso.window);
    window.set_opdone(&mut client)
}
