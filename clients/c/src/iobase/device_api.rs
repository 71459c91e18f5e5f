// SPDX-License-Identifier: MIT OR Apache-2.0
//! The exported device functions of `pniousrd.h` for management, configuration, IO data
//! and AR control, with the signatures of `device_types::prototypes`. Each runs inside [`crate::ffi::guard`]: a panic
//! becomes `PNIO_ERR_INTERNAL` and a text, never an unwind into C. What they do on procimgd
//! is in `device`'s documentation.
#![allow(non_snake_case)]

use super::callbacks::in_callback;
use super::device::config;
use super::device::data::{self as io, Classes, Direction};
use super::device::jobs::Job;
use super::device::open::{self, OpenRequest};
use super::device::ready_list;
use super::device::session_failure;
use super::device::state::{Device, Life, lookup, lookup_any, wrong_handle};
use super::device_types::*;
use super::errors::fail;
use super::errors::*;
use super::stopped;
use super::sync::lock;
use super::types::*;
use crate::ffi::guard;
use procimg_client::iobase::{ApplicationReadyError, ArId, ReadyError};
use std::sync::Arc;
use std::sync::mpsc::sync_channel;

/// The answer of these functions when called inside a callback.
fn not_in_callback(f: &str) -> u32 {
    fail(
        f,
        PNIO_ERR_SEQUENCE,
        "not allowed inside a callback: there only the IO data functions may be called; \
         leave the callback (set a flag) and call it from your program's thread",
    )
}

/// The open device with handle `h` for function `f`, checked that the caller is not inside
/// a callback.
fn device(f: &str, h: u32) -> Result<Arc<Device>, u32> {
    if in_callback() {
        return Err(not_in_callback(f));
    }
    lookup(h).ok_or_else(|| wrong_handle(f, h))
}

/// Reads a device address from C.
///
/// # Safety
/// `p` is NULL or points to a readable `PNIO_DEV_ADDR`.
pub(crate) unsafe fn read_addr(f: &str, p: *const PNIO_DEV_ADDR) -> Result<PNIO_DEV_ADDR, u32> {
    if p.is_null() {
        return Err(fail(f, PNIO_ERR_PRM_ADD, "pAddr is NULL"));
    }
    // SAFETY: not NULL, readable by the caller's contract.
    Ok(unsafe { p.read_unaligned() })
}

/// `PNIO_device_open` and `PNIO_device_open_ext` after reading their arguments.
///
/// # Safety
/// The pointers are NULL or valid as `PNIO_device_open` says.
#[allow(clippy::too_many_arguments)]
unsafe fn open_device(
    f: &str,
    CpIndex: PNIO_UINT32,
    ExtPar: PNIO_UINT32,
    VendorId: PNIO_UINT16,
    DeviceId: PNIO_UINT16,
    InstanceId: PNIO_UINT16,
    MaxAr: PNIO_UINT32,
    pDevAnnotation: *mut PNIO_ANNOTATION,
    pCbf: *mut PNIO_CBF_FUNCTIONS,
    high: Option<(u16, u16)>,
    pDevHndl: *mut PNIO_UINT32,
) -> PNIO_UINT32 {
    if in_callback() {
        return not_in_callback(f);
    }
    if pDevHndl.is_null() {
        return fail(f, PNIO_ERR_PRM_HND, "pDevHndl (the out pointer) is NULL");
    }
    let annotation = (!pDevAnnotation.is_null()).then(|| {
        // SAFETY: not NULL, readable by the caller's contract.
        unsafe { pDevAnnotation.read_unaligned() }
    });
    let cbf_size = (!pCbf.is_null()).then(|| {
        // SAFETY: not NULL; every version of the table begins with its size.
        unsafe { std::ptr::addr_of!((*pCbf).size).read_unaligned() }
    });
    let cbf = cbf_size
        .filter(|&s| s as usize == size_of::<PNIO_CBF_FUNCTIONS>())
        .map(|_| {
            // SAFETY: not NULL, and its size says it is this header's table, readable by the
            // caller's contract.
            unsafe { pCbf.read_unaligned() }
        });
    let req = OpenRequest {
        cp_index: CpIndex,
        ext_par: ExtPar,
        vendor_id: VendorId,
        device_id: DeviceId,
        instance_id: InstanceId,
        max_ar: MaxAr,
        annotation,
        cbf_size,
        cbf,
        high,
    };
    let result = open::check(&req).and_then(|cbf| open::open(&req, cbf));
    match result {
        Ok(h) => {
            // SAFETY: not NULL, writable by the caller's contract.
            unsafe { pDevHndl.write_unaligned(h) };
            PNIO_OK
        }
        Err(code) => code,
    }
}

/// Opens the IO device on CP `CpIndex` (the procimgd instance it names, in the device role
/// with this VendorId and DeviceId) and registers the callbacks; the station takes no AR
/// until `PNIO_device_start`.
///
/// # Safety
/// `pDevHndl` is NULL or writable; `pDevAnnotation` and `pCbf` are NULL or readable, and the
/// callbacks stay callable until the device is closed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_device_open(
    CpIndex: PNIO_UINT32,
    ExtPar: PNIO_UINT32,
    VendorId: PNIO_UINT16,
    DeviceId: PNIO_UINT16,
    InstanceId: PNIO_UINT16,
    MaxAr: PNIO_UINT32,
    pDevAnnotation: *mut PNIO_ANNOTATION,
    pCbf: *mut PNIO_CBF_FUNCTIONS,
    pDevHndl: *mut PNIO_UINT32,
) -> PNIO_UINT32 {
    guard(PNIO_ERR_INTERNAL, || {
        // SAFETY: the pointers come with the caller's contract.
        unsafe {
            open_device(
                "PNIO_device_open",
                CpIndex,
                ExtPar,
                VendorId,
                DeviceId,
                InstanceId,
                MaxAr,
                pDevAnnotation,
                pCbf,
                None,
                pDevHndl,
            )
        }
    })
}

/// `PNIO_device_open` with the highest slot and subslot numbers that `PNIO_api_add_ext`
/// gives every API.
///
/// # Safety
/// As `PNIO_device_open`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_device_open_ext(
    CpIndex: PNIO_UINT32,
    ExtPar: PNIO_UINT32,
    VendorId: PNIO_UINT16,
    DeviceId: PNIO_UINT16,
    InstanceId: PNIO_UINT16,
    MaxAr: PNIO_UINT32,
    pDevAnnotation: *mut PNIO_ANNOTATION,
    pCbf: *mut PNIO_CBF_FUNCTIONS,
    highSlotNum: PNIO_UINT16,
    highSubslotNum: PNIO_UINT16,
    pDevHndl: *mut PNIO_UINT32,
) -> PNIO_UINT32 {
    guard(PNIO_ERR_INTERNAL, || {
        // SAFETY: the pointers come with the caller's contract.
        unsafe {
            open_device(
                "PNIO_device_open_ext",
                CpIndex,
                ExtPar,
                VendorId,
                DeviceId,
                InstanceId,
                MaxAr,
                pDevAnnotation,
                pCbf,
                Some((highSlotNum, highSubslotNum)),
                pDevHndl,
            )
        }
    })
}

/// Closes the device: before start or after `PNIO_CBF_DEVICE_STOPPED`, with every plug and
/// pull confirmed; no callback runs once it returned.
///
/// # Safety
/// None beyond the C ABI; any value of `DevHndl` is checked.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_device_close(DevHndl: PNIO_UINT32) -> PNIO_UINT32 {
    const F: &str = "PNIO_device_close";
    guard(PNIO_ERR_INTERNAL, || {
        if !in_callback()
            && let Some(dev) = lookup_any(DevHndl).filter(|d| stopped::expired(d.handle))
        {
            // The watchdog stopped the program: close is the one call left, and it stops
            // the device as well.
            dev.close_stopped();
            return PNIO_OK;
        }
        let dev = match device(F, DevHndl) {
            Ok(d) => d,
            Err(code) => return code,
        };
        {
            let c = lock(&dev.config);
            if matches!(c.life, Life::Started | Life::Stopping) {
                return fail(
                    F,
                    PNIO_ERR_SEQUENCE,
                    format_args!(
                        "the device is {}: PNIO_device_stop and its PNIO_CBF_DEVICE_STOPPED \
                         come first",
                        c.life.name()
                    ),
                );
            }
            if c.pending > 0 && dev.cbf.cbf_pull_plug_conf.is_some() {
                return fail(
                    F,
                    PNIO_ERR_SEQUENCE,
                    format_args!(
                        "{} plug or pull jobs are not confirmed yet: wait for their \
                         PNIO_CBF_PULL_PLUG_CONF and close again",
                        c.pending
                    ),
                );
            }
        }
        dev.close();
        PNIO_OK
    })
}

/// Starts the device: pulls the station's positions outside slot 0 the program did not
/// plug, then takes procimgd to OPERATE, where PLCs may connect.
///
/// # Safety
/// None beyond the C ABI; any value of `DevHndl` is checked.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_device_start(DevHndl: PNIO_UINT32) -> PNIO_UINT32 {
    const F: &str = "PNIO_device_start";
    guard(PNIO_ERR_INTERNAL, || {
        let dev = match device(F, DevHndl) {
            Ok(d) => d,
            Err(code) => return code,
        };
        {
            let c = lock(&dev.config);
            if !matches!(c.life, Life::Opened | Life::Stopped) {
                return fail(
                    F,
                    PNIO_ERR_SEQUENCE,
                    format_args!("the device is {}", c.life.name()),
                );
            }
        }
        let (reply, answer) = sync_channel(1);
        if dev.send(Job::Start(reply)).is_err() {
            return fail(F, PNIO_ERR_INTERNAL, "the device's thread has ended");
        }
        match answer.recv() {
            Ok(Ok(())) => {
                lock(&dev.config).life = Life::Started;
                PNIO_OK
            }
            Ok(Err((code, text))) => fail(F, code, text),
            Err(_) => fail(F, PNIO_ERR_INTERNAL, "the device's thread has ended"),
        }
    })
}

/// Stops the device: procimgd goes OFFLINE (the PLC's AR ends) and
/// `PNIO_CBF_DEVICE_STOPPED` confirms on the library thread.
///
/// # Safety
/// None beyond the C ABI; any value of `DevHndl` is checked.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_device_stop(DevHndl: PNIO_UINT32) -> PNIO_UINT32 {
    const F: &str = "PNIO_device_stop";
    guard(PNIO_ERR_INTERNAL, || {
        let dev = match device(F, DevHndl) {
            Ok(d) => d,
            Err(code) => return code,
        };
        let mut c = lock(&dev.config);
        if c.life != Life::Started {
            return fail(
                F,
                PNIO_ERR_SEQUENCE,
                format_args!(
                    "the device is {}: only a started device can be stopped",
                    c.life.name()
                ),
            );
        }
        c.life = Life::Stopping;
        drop(c);
        if dev.send(Job::Stop).is_err() {
            lock(&dev.config).life = Life::Started;
            return fail(F, PNIO_ERR_INTERNAL, "the device's thread has ended");
        }
        PNIO_OK
    })
}

/// Adds an API with the highest slot and subslot numbers used in it.
///
/// # Safety
/// None beyond the C ABI; every value is checked.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_api_add(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    MaxSlots: PNIO_UINT16,
    MaxSubslots: PNIO_UINT16,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_api_add";
    guard(PNIO_ERR_INTERNAL, || match device(F, DevHndl) {
        Ok(dev) => config::api_add(F, &dev, Api, (MaxSlots, MaxSubslots)),
        Err(code) => code,
    })
}

/// Adds an API with the highest numbers given to `PNIO_device_open_ext`.
///
/// # Safety
/// None beyond the C ABI; every value is checked.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_api_add_ext(DevHndl: PNIO_UINT32, Api: PNIO_UINT32) -> PNIO_UINT32 {
    const F: &str = "PNIO_api_add_ext";
    guard(PNIO_ERR_INTERNAL, || match device(F, DevHndl) {
        Ok(dev) => match dev.high {
            Some(high) => config::api_add(F, &dev, Api, high),
            None => fail(
                F,
                PNIO_ERR_SEQUENCE,
                "the device was opened with PNIO_device_open, which gives no highest slot and \
                 subslot numbers: use PNIO_api_add",
            ),
        },
        Err(code) => code,
    })
}

/// Removes an API without modules.
///
/// # Safety
/// None beyond the C ABI; every value is checked.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_api_remove(DevHndl: PNIO_UINT32, Api: PNIO_UINT32) -> PNIO_UINT32 {
    const F: &str = "PNIO_api_remove";
    guard(PNIO_ERR_INTERNAL, || match device(F, DevHndl) {
        Ok(dev) => config::api_remove(F, &dev, Api),
        Err(code) => code,
    })
}

/// Plugs a module: records its ident number for its submodules; `PNIO_CBF_PULL_PLUG_CONF`
/// confirms.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_mod_plug(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    ModIdent: PNIO_UINT32,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_mod_plug";
    guard(PNIO_ERR_INTERNAL, || {
        let dev = match device(F, DevHndl) {
            Ok(d) => d,
            Err(code) => return code,
        };
        // SAFETY: the pointer comes with the caller's contract.
        match unsafe { read_addr(F, pAddr) } {
            Ok(addr) => config::mod_plug(F, &dev, Api, addr, ModIdent),
            Err(code) => code,
        }
    })
}

/// Pulls a module and the program's submodules in it; `PNIO_CBF_PULL_PLUG_CONF` confirms.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_mod_pull(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_mod_pull";
    guard(PNIO_ERR_INTERNAL, || {
        let dev = match device(F, DevHndl) {
            Ok(d) => d,
            Err(code) => return code,
        };
        // SAFETY: the pointer comes with the caller's contract.
        match unsafe { read_addr(F, pAddr) } {
            Ok(addr) => config::mod_pull(F, &dev, Api, addr),
            Err(code) => code,
        }
    })
}

/// The three submodule plugs after their own checks.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
unsafe fn plug_sub(
    f: &str,
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    SubIdent: PNIO_UINT32,
    AlarmType: PNIO_UINT32,
    IM0_bits: PNIO_PLUG_IM0_BITS,
) -> PNIO_UINT32 {
    let dev = match device(f, DevHndl) {
        Ok(d) => d,
        Err(code) => return code,
    };
    // SAFETY: the pointer comes with the caller's contract.
    match unsafe { read_addr(f, pAddr) } {
        Ok(addr) => config::sub_plug(f, &dev, Api, addr, SubIdent, AlarmType, IM0_bits),
        Err(code) => code,
    }
}

/// Plugs a submodule (deprecated form: a Plug alarm, no I&M data).
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_sub_plug(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    SubIdent: PNIO_UINT32,
) -> PNIO_UINT32 {
    guard(PNIO_ERR_INTERNAL, || {
        // SAFETY: the pointer comes with the caller's contract.
        unsafe {
            plug_sub(
                "PNIO_sub_plug",
                DevHndl,
                Api,
                pAddr,
                SubIdent,
                PNIO_ALARM_TYPE_PLUG,
                PNIO_PLUG_IM0_BITS_NOTHING,
            )
        }
    })
}

/// Plugs a submodule with an alarm type (deprecated form, no I&M data).
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_sub_plug_ext(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    SubIdent: PNIO_UINT32,
    AlarmType: PNIO_UINT32,
) -> PNIO_UINT32 {
    guard(PNIO_ERR_INTERNAL, || {
        // SAFETY: the pointer comes with the caller's contract.
        unsafe {
            plug_sub(
                "PNIO_sub_plug_ext",
                DevHndl,
                Api,
                pAddr,
                SubIdent,
                AlarmType,
                PNIO_PLUG_IM0_BITS_NOTHING,
            )
        }
    })
}

/// Plugs a submodule; `PNIO_CBF_PULL_PLUG_CONF` confirms.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_sub_plug_ext_IM(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    SubIdent: PNIO_UINT32,
    AlarmType: PNIO_UINT32,
    IM0_bits: PNIO_PLUG_IM0_BITS,
) -> PNIO_UINT32 {
    guard(PNIO_ERR_INTERNAL, || {
        // SAFETY: the pointer comes with the caller's contract.
        unsafe {
            plug_sub(
                "PNIO_sub_plug_ext_IM",
                DevHndl,
                Api,
                pAddr,
                SubIdent,
                AlarmType,
                IM0_bits,
            )
        }
    })
}

/// Pulls the program's submodule; `PNIO_CBF_PULL_PLUG_CONF` confirms.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_sub_pull(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_sub_pull";
    guard(PNIO_ERR_INTERNAL, || {
        let dev = match device(F, DevHndl) {
            Ok(d) => d,
            Err(code) => return code,
        };
        // SAFETY: the pointer comes with the caller's contract.
        match unsafe { read_addr(F, pAddr) } {
            Ok(addr) => config::sub_pull(F, &dev, Api, addr),
            Err(code) => code,
        }
    })
}

/// The open, started device with handle `h` for per-AR function `f`.
fn started(f: &str, h: u32) -> Result<Arc<Device>, u32> {
    let dev = device(f, h)?;
    let life = lock(&dev.config).life;
    if life != Life::Started {
        return Err(fail(
            f,
            PNIO_ERR_SEQUENCE,
            format_args!("the device is {}: it has no AR", life.name()),
        ));
    }
    Ok(dev)
}

/// Says that the program is ready for the AR after `PNIO_CBF_PRM_END_IND`: the station's
/// ApplicationReady goes out, with the submodules of `pList` (NULL: none) as "application
/// ready pending" for the PLC until a Return of Submodule alarm of each
/// (`PNIO_ret_of_sub_alarm_send`). After a `PRM_END_IND` for a submodule plugged in data
/// exchange it lets that one's PlugApplicationReady go.
///
/// # Safety
/// `pList` is NULL or points to a list built as the manual says (`PNIO_LIST_*`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_set_appl_state_ready(
    DevHndl: PNIO_UINT32,
    ArNumber: PNIO_UINT16,
    SessionKey: PNIO_UINT16,
    pList: *mut PNIO_APPL_READY_LIST_TYPE,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_set_appl_state_ready";
    guard(PNIO_ERR_INTERNAL, || {
        let dev = match started(F, DevHndl) {
            Ok(d) => d,
            Err(code) => return code,
        };
        // SAFETY: as the function's contract.
        let Ok(not_ready) = (unsafe { ready_list::not_ready(pList) }) else {
            return fail(
                F,
                PNIO_ERR_PRM_INVALIDARG,
                "pList does not end: build it with PNIO_LIST_INITIALIZE and PNIO_LIST_INSERT_*",
            );
        };
        let ar = ArId {
            number: ArNumber,
            session_key: SessionKey,
        };
        io::before_application_ready(&dev);
        match dev.iobase.application_ready(ar, &not_ready) {
            Ok(()) => PNIO_OK,
            Err(ApplicationReadyError::Refused(ReadyError::Session(e))) => session_failure(F, e),
            Err(e @ ApplicationReadyError::Refused(_)) => fail(F, PNIO_ERR_SEQUENCE, e),
            Err(e @ ApplicationReadyError::NotTaken { .. }) => {
                fail(F, PNIO_ERR_NO_FW_COMMUNICATION, e)
            }
        }
    })
}

/// Aborts the AR: an ERR-RTA with AbortRequest goes to the PLC, and
/// `PNIO_CBF_AR_OFFLINE_IND` (after `AR_INDATA_IND`) or `PNIO_CBF_AR_ABORT_IND` follows on
/// the library thread with `PNIO_AR_REASON_ABORT`. The station stays on the wire: the PLC
/// may connect again at once, with a new AR.
///
/// # Safety
/// None beyond the C ABI; every value is checked.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_device_ar_abort(
    DevHndl: PNIO_UINT32,
    ArNumber: PNIO_UINT16,
    SessionKey: PNIO_UINT16,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_device_ar_abort";
    guard(PNIO_ERR_INTERNAL, || {
        let dev = match started(F, DevHndl) {
            Ok(d) => d,
            Err(code) => return code,
        };
        let ar = ArId {
            number: ArNumber,
            session_key: SessionKey,
        };
        if let Err(e) = dev.iobase.check(ar) {
            return session_failure(F, e);
        }
        match dev.send(Job::Abort(ar)) {
            Ok(()) => PNIO_OK,
            Err(_) => fail(F, PNIO_ERR_INTERNAL, "the device's thread has ended"),
        }
    })
}

// Each implementation has the type `pniousrd.h` declares.
const _: prototypes::PNIO_device_open = PNIO_device_open;
const _: prototypes::PNIO_device_open_ext = PNIO_device_open_ext;
const _: prototypes::PNIO_device_close = PNIO_device_close;
const _: prototypes::PNIO_device_start = PNIO_device_start;
const _: prototypes::PNIO_device_stop = PNIO_device_stop;
const _: prototypes::PNIO_api_add = PNIO_api_add;
const _: prototypes::PNIO_api_add_ext = PNIO_api_add_ext;
const _: prototypes::PNIO_api_remove = PNIO_api_remove;
const _: prototypes::PNIO_mod_plug = PNIO_mod_plug;
const _: prototypes::PNIO_mod_pull = PNIO_mod_pull;
const _: prototypes::PNIO_sub_plug = PNIO_sub_plug;
const _: prototypes::PNIO_sub_plug_ext = PNIO_sub_plug_ext;
const _: prototypes::PNIO_sub_plug_ext_IM = PNIO_sub_plug_ext_IM;
const _: prototypes::PNIO_sub_pull = PNIO_sub_pull;
const _: prototypes::PNIO_set_appl_state_ready = PNIO_set_appl_state_ready;
const _: prototypes::PNIO_device_ar_abort = PNIO_device_ar_abort;

/// The device for an IO data function: these may be called inside callbacks.
fn data_device(f: &str, h: u32) -> Result<Arc<Device>, u32> {
    lookup(h).ok_or_else(|| wrong_handle(f, h))
}

/// An IO data function after its arguments: `addr` NULL or readable.
///
/// # Safety
/// `addr` is NULL or points to a readable `PNIO_DEV_ADDR`.
unsafe fn initiate(
    f: &str,
    h: u32,
    addr: *const PNIO_DEV_ADDR,
    access: Result<Classes, u32>,
    dir: Direction,
) -> u32 {
    let dev = match data_device(f, h) {
        Ok(d) => d,
        Err(code) => return code,
    };
    let classes = match access {
        Ok(c) => c,
        Err(code) => return code,
    };
    // SAFETY: NULL or readable by the caller's contract.
    let addr = (!addr.is_null()).then(|| unsafe { addr.read_unaligned() });
    io::initiate(f, &dev, addr, classes, dir)
}

/// Calls `PNIO_CBF_DATA_WRITE` on this thread for each of the program's submodules with RT
/// input data while an AR is up, and sends what they wrote with the IOPS they returned.
///
/// # Safety
/// None beyond the C ABI; any value of `DevHndl` is checked.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_initiate_data_write(DevHndl: PNIO_UINT32) -> PNIO_UINT32 {
    const F: &str = "PNIO_initiate_data_write";
    guard(PNIO_ERR_INTERNAL, || {
        // SAFETY: no address.
        unsafe {
            initiate(
                F,
                DevHndl,
                std::ptr::null(),
                Ok(Classes::Rt),
                Direction::Write,
            )
        }
    })
}

/// `PNIO_initiate_data_write` for the submodules `pAddr` selects (NULL: all; subslot 0:
/// the slot's) and the data `AccessType` selects.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_initiate_data_write_ext(
    DevHndl: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    AccessType: PNIO_ACCESS_ENUM,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_initiate_data_write_ext";
    guard(PNIO_ERR_INTERNAL, || {
        let access = Classes::of(F, AccessType);
        // SAFETY: pAddr as the caller's contract says.
        unsafe { initiate(F, DevHndl, pAddr, access, Direction::Write) }
    })
}

/// Calls `PNIO_CBF_DATA_READ` on this thread for each of the program's submodules with RT
/// output data while an AR is up, with the PLC's data and IOPS; the IOCS they return go to
/// the PLC.
///
/// # Safety
/// None beyond the C ABI; any value of `DevHndl` is checked.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_initiate_data_read(DevHndl: PNIO_UINT32) -> PNIO_UINT32 {
    const F: &str = "PNIO_initiate_data_read";
    guard(PNIO_ERR_INTERNAL, || {
        // SAFETY: no address.
        unsafe {
            initiate(
                F,
                DevHndl,
                std::ptr::null(),
                Ok(Classes::Rt),
                Direction::Read,
            )
        }
    })
}

/// `PNIO_initiate_data_read` selected as `PNIO_initiate_data_write_ext` selects.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_initiate_data_read_ext(
    DevHndl: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    AccessType: PNIO_ACCESS_ENUM,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_initiate_data_read_ext";
    guard(PNIO_ERR_INTERNAL, || {
        let access = Classes::of(F, AccessType);
        // SAFETY: pAddr as the caller's contract says.
        unsafe { initiate(F, DevHndl, pAddr, access, Direction::Read) }
    })
}
