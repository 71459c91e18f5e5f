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
//! events. The window and the rules are the controller's (`crate::iobase::isochronous`).
//!
//! While the library thread carries out a plug or pull it holds the client, and a STARTOP
//! of that time is missed (procimgd counts an OPFAULT).

use super::held::Isochronous;
use super::state::{Device, Life, lookup, wrong_handle};
use crate::iobase::errors::*;
use crate::iobase::isochronous::{self, OPDONE, REGISTER, cycle_info};
use crate::iobase::stopped;
use crate::iobase::sync::lock;
use crate::iobase::types::*;
use procimg_client::{AttachOptions, Client, Event, EventWait, now_ns};
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::Duration;

/// The longest the thread sleeps before it looks at its stop flag.
const POLL: Duration = Duration::from_millis(20);

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
        AttachOptions::synchronous(&name)
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
        .spawn(move || run(d))
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

/// The isochronous thread: STARTOP_IND, OPFAULT_IND and NEWCYCLE_IND, in the order they
/// happened.
fn run(dev: Arc<Device>) {
    // Taken before each look at the client: what the server signals after it ends the
    // next sleep at once. A re-attach meanwhile costs one short sleep.
    let mut wait: Option<EventWait> = None;
    while !dev.iso.stop.load(Ordering::Acquire) {
        match wait.take() {
            Some(w) => {
                let _ = w.wait(POLL);
            }
            None => std::thread::sleep(POLL),
        }
        if dev.iso.stop.load(Ordering::Acquire) {
            break;
        }
        wait = lock(&dev.client).event_wait();
        let expired = stopped::expired(dev.handle);
        let (startop, events, newest) = {
            let mut client = lock(&dev.client);
            let mut window = lock(&dev.iso.window);
            let mut startop = None;
            if dev.iso.on.load(Ordering::Acquire) {
                startop = window.take_startop(&mut client);
                if startop.is_some() && expired {
                    // After the watchdog's expiry the program gets no cycle.
                    window.finish_bad(&mut client);
                    startop = None;
                }
            }
            (startop, client.events(), client.cycle_info())
        };
        if expired {
            continue;
        }
        let info_now = || cycle_info(&newest.unwrap_or_default(), now_ns());
        for e in events {
            let t = match e {
                Event::OpFault { .. } => PNIO_CP_CBE_OPFAULT_IND,
                Event::NewCycle => PNIO_CP_CBE_NEWCYCLE_IND,
                _ => continue,
            };
            isochronous::report(&dev.iso.callbacks, t, dev.cp_index, dev.handle, info_now());
        }
        if let Some(info) = startop {
            let info = cycle_info(&info, now_ns());
            isochronous::report(
                &dev.iso.callbacks,
                PNIO_CP_CBE_STARTOP_IND,
                dev.cp_index,
                dev.handle,
                info,
            );
        }
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
