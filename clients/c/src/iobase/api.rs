// SPDX-License-Identifier: MIT OR Apache-2.0
//! The exported `PNIO_*` controller functions of `pniousrx.h` and `pniobase.h`, with the
//! manual's signatures. Each runs inside [`crate::ffi::guard`]: a panic becomes
//! `PNIO_ERR_INTERNAL` and a text, never an unwind into C.
#![allow(non_snake_case)]

use super::callbacks::in_callback;
use super::controller::{
    Controller, OpenRequest, check_cp_index, is_controller, lookup, wrong_handle,
};
use super::data::{self, ReadArgs, ReadKind, WriteArgs};
use super::device::isochronous as device_iso;
use super::device::state as device_state;
use super::errors::fail;
use super::errors::*;
use super::isochronous;
use super::types::*;
use crate::ffi::guard;
use std::sync::Arc;

/// Whether `h` is a device's handle (from `PNIO_device_open`): the isochronous functions
/// take both kinds, and the two never share a number.
fn is_device(h: u32) -> bool {
    !is_controller(h) && device_state::lookup_any(h).is_some()
}

/// The answer of every function but the IO data ones when called inside a callback.
pub(crate) fn not_in_callback(f: &str) -> u32 {
    fail(
        f,
        PNIO_ERR_SEQUENCE,
        "not allowed inside a callback: there only the IO data functions and \
         PNIO_CP_set_opdone may be called; leave the callback (set a flag) and call it from \
         your program's thread",
    )
}

/// The controller `handle` names, if it was opened with `PNIO_CEP_MODE_CTRL`, which
/// `what` (device activation, reconfiguration) needs: else `PNIO_ERR_DEV_ACT_NOT_ALLOWED`.
fn mode_controller(f: &str, handle: u32, what: &str) -> Result<Arc<Controller>, u32> {
    let Some(ctl) = lookup(handle) else {
        return Err(wrong_handle(f, handle));
    };
    if !ctl.mode_ctrl {
        return Err(fail(
            f,
            PNIO_ERR_DEV_ACT_NOT_ALLOWED,
            format_args!(
                "controller {handle} was opened without PNIO_CEP_MODE_CTRL: it may not {what}"
            ),
        ));
    }
    Ok(ctl)
}

/// Opens an IO controller on CP `CpIndex` and registers the record and alarm callbacks
/// (see `pniousrx.h` for how CpIndex names a procimgd instance).
///
/// # Safety
/// `Handle` is NULL or points to a writable `PNIO_UINT32`; the callbacks are NULL or
/// functions of the `PNIO_CBF` type that stay callable until the controller is closed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_controller_open(
    CpIndex: PNIO_UINT32,
    ExtPar: PNIO_UINT32,
    cbf_rec_read_conf: PNIO_CBF,
    cbf_rec_write_conf: PNIO_CBF,
    cbf_alarm_ind: PNIO_CBF,
    Handle: *mut PNIO_UINT32,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_controller_open";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        if Handle.is_null() {
            return fail(F, PNIO_ERR_PRM_HND, "Handle (the out pointer) is NULL");
        }
        if let Err(code) = check_cp_index(F, CpIndex) {
            return code;
        }
        if let Err(why) = super::pn_driver::controller_may_open() {
            return fail(F, PNIO_ERR_SEQUENCE, why);
        }
        let allowed = PNIO_CEP_MODE_CTRL | PNIO_CEP_SLICE_ACCESS;
        if ExtPar & !allowed != 0 {
            return fail(
                F,
                PNIO_ERR_PRM_EXT_PAR,
                format_args!(
                    "ExtPar {ExtPar:#x} has bits {:#x} that a controller does not take: only \
                     PNIO_CEP_MODE_CTRL and PNIO_CEP_SLICE_ACCESS",
                    ExtPar & !allowed
                ),
            );
        }
        if cbf_rec_read_conf.is_none() || cbf_rec_write_conf.is_none() {
            return fail(
                F,
                PNIO_ERR_PRM_CALLBACK,
                "cbf_rec_read_conf and cbf_rec_write_conf must not be NULL (only \
                 cbf_alarm_ind may be)",
            );
        }
        match Controller::open(OpenRequest {
            cp_index: CpIndex,
            ext_par: ExtPar,
            rec_read: cbf_rec_read_conf,
            rec_write: cbf_rec_write_conf,
            alarm: cbf_alarm_ind,
        }) {
            Ok(h) => {
                // SAFETY: not NULL, writable by the caller's contract.
                unsafe { Handle.write_unaligned(h) };
                PNIO_OK
            }
            Err(code) => code,
        }
    })
}

/// Closes a controller: once it returns, none of its callbacks runs any more.
///
/// # Safety
/// None beyond the C ABI; any value of `Handle` is checked.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_controller_close(Handle: PNIO_UINT32) -> PNIO_UINT32 {
    const F: &str = "PNIO_controller_close";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        Controller::close(Handle)
    })
}

/// Registers a callback for `CbeType` (in OFFLINE, each type once).
///
/// # Safety
/// `Cbf` is NULL or a function of the `PNIO_CBF` type that stays callable until the
/// controller is closed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_register_cbf(
    Handle: PNIO_UINT32,
    CbeType: PNIO_CBE_TYPE,
    Cbf: PNIO_CBF,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_register_cbf";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        let Some(ctl) = lookup(Handle) else {
            return wrong_handle(F, Handle);
        };
        if Cbf.is_none() {
            return fail(F, PNIO_ERR_PRM_CALLBACK, "Cbf is NULL");
        }
        match CbeType {
            PNIO_CBE_MODE_IND
            | PNIO_CBE_DEV_ACT_CONF
            | PNIO_CBE_CP_STOP_REQ
            | PNIO_CBE_START_LED_FLASH
            | PNIO_CBE_STOP_LED_FLASH
            | PNIO_CBE_CTRL_DIAG_CONF
            | PNIO_CBE_IOSYSTEM_RECONFIG => {}
            PNIO_CBE_ALARM_IND | PNIO_CBE_REC_READ_CONF | PNIO_CBE_REC_WRITE_CONF => {
                return fail(
                    F,
                    PNIO_ERR_PRM_TYPE,
                    format_args!(
                        "CbeType {CbeType}: the alarm and record callbacks are given to \
                         PNIO_controller_open, not registered later"
                    ),
                );
            }
            other => {
                return fail(
                    F,
                    PNIO_ERR_PRM_TYPE,
                    format_args!("CbeType {other} is not a controller event procimg offers"),
                );
            }
        }
        if !ctl.may_register() {
            return fail(
                F,
                PNIO_ERR_MODE_VALUE,
                format_args!(
                    "callbacks are registered in OFFLINE only; the controller is in mode {} \
                     (set PNIO_MODE_OFFLINE first, or register before PNIO_set_mode)",
                    ctl.mode()
                ),
            );
        }
        if !ctl.callbacks.set_once(CbeType, Cbf) {
            return fail(
                F,
                PNIO_ERR_ALLREADY_DONE,
                format_args!(
                    "a callback for CbeType {CbeType} is registered already; another one \
                     only after PNIO_controller_close"
                ),
            );
        }
        PNIO_OK
    })
}

/// Asks for a mode; `PNIO_CBE_MODE_IND` reports each step.
///
/// # Safety
/// None beyond the C ABI; every value is checked.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_set_mode(Handle: PNIO_UINT32, Mode: PNIO_MODE_TYPE) -> PNIO_UINT32 {
    const F: &str = "PNIO_set_mode";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        match lookup(Handle) {
            Some(ctl) => ctl.set_mode(Mode),
            None => wrong_handle(F, Handle),
        }
    })
}

/// Activates or deactivates the device that has `pAddr`.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_device_activate(
    Handle: PNIO_UINT32,
    pAddr: *mut PNIO_ADDR,
    DeviceMode: PNIO_DEV_ACT_TYPE,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_device_activate";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        let ctl = match mode_controller(F, Handle, "activate or deactivate devices") {
            Ok(ctl) => ctl,
            Err(code) => return code,
        };
        if pAddr.is_null() {
            return fail(F, PNIO_ERR_PRM_ADD, "pAddr is NULL");
        }
        if DeviceMode != PNIO_DA_FALSE && DeviceMode != PNIO_DA_TRUE {
            return fail(
                F,
                PNIO_ERR_PRM_DEV_STATE,
                format_args!("DeviceMode {DeviceMode} is neither PNIO_DA_TRUE nor PNIO_DA_FALSE"),
            );
        }
        if ctl.mode() == PNIO_MODE_OFFLINE {
            return fail(
                F,
                PNIO_ERR_MODE_VALUE,
                "devices cannot be (de)activated in OFFLINE: set CLEAR or OPERATE first",
            );
        }
        // SAFETY: not NULL, readable by the caller's contract.
        let addr = unsafe { pAddr.read_unaligned() };
        ctl.with_services(|s| s.device_activate(&addr, DeviceMode))
            .unwrap_or_else(|| wrong_handle(F, Handle))
    })
}

/// Deactivates every device or tailors the IO system (see `pniousrx.h`).
///
/// # Safety
/// `DeviceList` is NULL or points to `DeviceCnt` readable addresses;
/// `PortInterconnectionList` is NULL or points to `2 × PortInterconnectionCnt` of them.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_iosystem_reconfig(
    Handle: PNIO_UINT32,
    Mode: PNIO_IOS_RECONFIG_MODE,
    DeviceCnt: PNIO_UINT32,
    DeviceList: *mut PNIO_ADDR,
    PortInterconnectionCnt: PNIO_UINT32,
    PortInterconnectionList: *mut PNIO_ADDR,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_iosystem_reconfig";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        let ctl = match mode_controller(F, Handle, "reconfigure the IO system") {
            Ok(ctl) => ctl,
            Err(code) => return code,
        };
        let tailor = match Mode {
            PNIO_IOS_RECONFIG_MODE_DEACT => false,
            PNIO_IOS_RECONFIG_MODE_TAILOR => true,
            other => {
                return fail(
                    F,
                    PNIO_ERR_MODE_VALUE,
                    format_args!(
                        "Mode {other} is neither PNIO_IOS_RECONFIG_MODE_DEACT nor \
                         PNIO_IOS_RECONFIG_MODE_TAILOR"
                    ),
                );
            }
        };
        let (devices, ports) = if tailor {
            let pairs = PortInterconnectionCnt as usize;
            if (DeviceCnt > 0 && DeviceList.is_null())
                || (pairs > 0 && PortInterconnectionList.is_null())
            {
                return fail(F, PNIO_ERR_PRM_BUF, "a list with a count above 0 is NULL");
            }
            let read = |list: *mut PNIO_ADDR, n: usize| -> Vec<PNIO_ADDR> {
                // SAFETY: n readable addresses by the caller's contract (checked not NULL
                // when n > 0); copied here, as the manual says.
                (0..n)
                    .map(|i| unsafe { list.add(i).read_unaligned() })
                    .collect()
            };
            (
                read(DeviceList, DeviceCnt as usize),
                read(PortInterconnectionList, pairs.saturating_mul(2)),
            )
        } else {
            (Vec::new(), Vec::new())
        };
        ctl.with_services(|s| s.iosystem_reconfig(tailor, &devices, &ports))
            .unwrap_or_else(|| wrong_handle(F, Handle))
    })
}

/// Reads inputs at a logical address.
///
/// # Safety
/// The pointers are NULL or valid as the IO-Base prototype says: `pBuffer` for `BufLen`
/// bytes, the others for one value each.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_data_read(
    Handle: PNIO_UINT32,
    pAddr: *mut PNIO_ADDR,
    BufLen: PNIO_UINT32,
    pDataLen: *mut PNIO_UINT32,
    pBuffer: *mut PNIO_UINT8,
    IOlocState: PNIO_IOXS,
    pIOremState: *mut PNIO_IOXS,
) -> PNIO_UINT32 {
    let a = ReadArgs {
        handle: Handle,
        addr: pAddr,
        buf_len: BufLen,
        data_len: pDataLen,
        buf: pBuffer,
        loc: IOlocState,
        loc_out: std::ptr::null_mut(),
        rem: pIOremState,
    };
    // SAFETY: the pointers come with the caller's contract.
    guard(PNIO_ERR_INTERNAL, || unsafe {
        data::read("PNIO_data_read", ReadKind::Direct, &a)
    })
}

/// Reads back outputs at a logical address as they were last sent.
///
/// # Safety
/// As [`PNIO_data_read`]; `pIOlocState` is written.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_output_data_read(
    Handle: PNIO_UINT32,
    pAddr: *mut PNIO_ADDR,
    BufLen: PNIO_UINT32,
    pDataLen: *mut PNIO_UINT32,
    pBuffer: *mut PNIO_UINT8,
    pIOlocState: *mut PNIO_IOXS,
    pIOremState: *mut PNIO_IOXS,
) -> PNIO_UINT32 {
    let a = ReadArgs {
        handle: Handle,
        addr: pAddr,
        buf_len: BufLen,
        data_len: pDataLen,
        buf: pBuffer,
        loc: PNIO_S_GOOD,
        loc_out: pIOlocState,
        rem: pIOremState,
    };
    // SAFETY: the pointers come with the caller's contract.
    guard(PNIO_ERR_INTERNAL, || unsafe {
        data::read("PNIO_output_data_read", ReadKind::Outputs, &a)
    })
}

/// Copies the inputs and the outputs' remote status into the read cache.
///
/// # Safety
/// None beyond the C ABI.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_data_read_cache_refresh(Handle: PNIO_UINT32) -> PNIO_UINT32 {
    guard(PNIO_ERR_INTERNAL, || {
        data::cache("PNIO_data_read_cache_refresh", Handle, false)
    })
}

/// Reads inputs from the read cache.
///
/// # Safety
/// As [`PNIO_data_read`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_data_read_cache(
    Handle: PNIO_UINT32,
    pAddr: *mut PNIO_ADDR,
    BufLen: PNIO_UINT32,
    pDataLen: *mut PNIO_UINT32,
    pBuffer: *mut PNIO_UINT8,
    IOlocState: PNIO_IOXS,
    pIOremState: *mut PNIO_IOXS,
) -> PNIO_UINT32 {
    let a = ReadArgs {
        handle: Handle,
        addr: pAddr,
        buf_len: BufLen,
        data_len: pDataLen,
        buf: pBuffer,
        loc: IOlocState,
        loc_out: std::ptr::null_mut(),
        rem: pIOremState,
    };
    // SAFETY: the pointers come with the caller's contract.
    guard(PNIO_ERR_INTERNAL, || unsafe {
        data::read("PNIO_data_read_cache", ReadKind::Cache, &a)
    })
}

/// Writes outputs at a logical address.
///
/// # Safety
/// The pointers are NULL or valid as the IO-Base prototype says: `pBuffer` for `BufLen`
/// bytes, `pIOremState` for one value.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_data_write(
    Handle: PNIO_UINT32,
    pAddr: *mut PNIO_ADDR,
    BufLen: PNIO_UINT32,
    pBuffer: *mut PNIO_UINT8,
    IOlocState: PNIO_IOXS,
    pIOremState: *mut PNIO_IOXS,
) -> PNIO_UINT32 {
    let a = WriteArgs {
        handle: Handle,
        addr: pAddr,
        buf_len: BufLen,
        buf: pBuffer,
        loc: IOlocState,
        rem: pIOremState,
    };
    // SAFETY: the pointers come with the caller's contract.
    guard(PNIO_ERR_INTERNAL, || unsafe {
        data::write("PNIO_data_write", false, &a)
    })
}

/// Writes outputs into the write cache.
///
/// # Safety
/// As [`PNIO_data_write`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_data_write_cache(
    Handle: PNIO_UINT32,
    pAddr: *mut PNIO_ADDR,
    BufLen: PNIO_UINT32,
    pBuffer: *mut PNIO_UINT8,
    IOlocState: PNIO_IOXS,
    pIOremState: *mut PNIO_IOXS,
) -> PNIO_UINT32 {
    let a = WriteArgs {
        handle: Handle,
        addr: pAddr,
        buf_len: BufLen,
        buf: pBuffer,
        loc: IOlocState,
        rem: pIOremState,
    };
    // SAFETY: the pointers come with the caller's contract.
    guard(PNIO_ERR_INTERNAL, || unsafe {
        data::write("PNIO_data_write_cache", true, &a)
    })
}

/// Sends the write cache.
///
/// # Safety
/// None beyond the C ABI.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_data_write_cache_flush(Handle: PNIO_UINT32) -> PNIO_UINT32 {
    guard(PNIO_ERR_INTERNAL, || {
        data::cache("PNIO_data_write_cache_flush", Handle, true)
    })
}

/// Registers an isochronous callback (in OFFLINE; OPFAULT before STARTOP; each once).
///
/// # Safety
/// `Cbf` is NULL or a function of the `PNIO_CP_CBF` type that stays callable until the
/// controller is closed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_CP_register_cbf(
    CpHandle: PNIO_UINT32,
    CbeType: PNIO_CP_CBE_TYPE,
    Cbf: PNIO_CP_CBF,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_CP_register_cbf";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        if is_device(CpHandle) {
            return device_iso::register(CpHandle, CbeType, Cbf);
        }
        let Some(ctl) = lookup(CpHandle) else {
            return wrong_handle(F, CpHandle);
        };
        if let Err(code) = isochronous::check_args(CbeType, Cbf) {
            return code;
        }
        if !ctl.may_register() {
            return fail(
                F,
                PNIO_ERR_MODE_VALUE,
                format_args!(
                    "callbacks are registered in OFFLINE only; the controller is in mode {}",
                    ctl.mode()
                ),
            );
        }
        if let Err(code) = isochronous::store(&ctl.callbacks, CbeType, Cbf) {
            return code;
        }
        if !isochronous::needs_reattach(CbeType) {
            return PNIO_OK;
        }
        // STARTOP makes the client synchronous, NEWCYCLE asks for NEWCYCLE events: both
        // are options of the registration with the server.
        match ctl.reattach() {
            Ok(()) => PNIO_OK,
            Err(code) => {
                // SAFETY: the pointer is this thread's last error text, NUL-terminated and
                // valid until this thread's next call into the library (the copy is taken
                // before that).
                let why = unsafe { std::ffi::CStr::from_ptr(crate::ffi::last_error_ptr()) }
                    .to_string_lossy()
                    .into_owned();
                // The registration takes no effect; the client goes back to what it was
                // (if that fails too, the data functions say the server is lost).
                ctl.callbacks.unset_cp(CbeType);
                let _ = ctl.reattach();
                fail(
                    F,
                    PNIO_ERR_INTERNAL,
                    format_args!(
                        "re-attaching to instance \"{}\" for the isochronous events failed \
                         with {}: {why}",
                        ctl.instance,
                        name(code)
                    ),
                )
            }
        }
    })
}

/// Ends this cycle's processing (OPDONE) and fills `CycleInfo` (when not NULL).
///
/// # Safety
/// `CycleInfo` is NULL or points to a writable `PNIO_CYCLE_INFO`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_CP_set_opdone(
    CpHandle: PNIO_UINT32,
    CycleInfo: *mut PNIO_CYCLE_INFO,
) -> PNIO_UINT32 {
    guard(PNIO_ERR_INTERNAL, || {
        if !is_device(CpHandle) {
            // SAFETY: the pointer comes with the caller's contract.
            return unsafe { data::set_opdone(CpHandle, CycleInfo) };
        }
        match device_iso::set_opdone(CpHandle) {
            Ok(info) => {
                if !CycleInfo.is_null() {
                    // SAFETY: not NULL, writable by the caller's contract.
                    unsafe { CycleInfo.write_unaligned(info) };
                }
                PNIO_OK
            }
            Err(code) => code,
        }
    })
}

/// Starts a record read; `PNIO_CBE_REC_READ_CONF` delivers the record.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_rec_read_req(
    Handle: PNIO_UINT32,
    pAddr: *mut PNIO_ADDR,
    RecordIndex: PNIO_UINT32,
    ReqRef: PNIO_REF,
    Length: PNIO_UINT32,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_rec_read_req";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        let Some(ctl) = lookup(Handle) else {
            return wrong_handle(F, Handle);
        };
        if pAddr.is_null() {
            return fail(F, PNIO_ERR_PRM_ADD, "pAddr is NULL");
        }
        // SAFETY: not NULL, readable by the caller's contract.
        let addr = unsafe { pAddr.read_unaligned() };
        ctl.with_services(|s| s.rec_read_req(&addr, RecordIndex, ReqRef, Length))
            .unwrap_or_else(|| wrong_handle(F, Handle))
    })
}

/// Starts a record write; `PNIO_CBE_REC_WRITE_CONF` reports the result.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_ADDR`; `pBuffer` is NULL or readable for
/// `Length` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_rec_write_req(
    Handle: PNIO_UINT32,
    pAddr: *mut PNIO_ADDR,
    RecordIndex: PNIO_UINT32,
    ReqRef: PNIO_REF,
    Length: PNIO_UINT32,
    pBuffer: *mut PNIO_UINT8,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_rec_write_req";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        let Some(ctl) = lookup(Handle) else {
            return wrong_handle(F, Handle);
        };
        if pAddr.is_null() {
            return fail(F, PNIO_ERR_PRM_ADD, "pAddr is NULL");
        }
        if pBuffer.is_null() {
            return fail(F, PNIO_ERR_PRM_BUF, "pBuffer is NULL");
        }
        // SAFETY: not NULL, readable by the caller's contract.
        let addr = unsafe { pAddr.read_unaligned() };
        // The services check the length (1..=4096); a longer buffer is never read.
        let len = (Length as usize).min(PNIO_MAX_REC_LEN as usize + 1);
        // SAFETY: not NULL and readable for Length bytes by the caller's contract; at most
        // Length bytes are taken.
        let data = unsafe { std::slice::from_raw_parts(pBuffer.cast_const(), len) };
        if (Length as usize) > len {
            return fail(
                F,
                PNIO_ERR_VALUE_LEN,
                format_args!("Length {Length}: a record write takes 1 to {PNIO_MAX_REC_LEN} bytes"),
            );
        }
        ctl.with_services(|s| s.rec_write_req(&addr, RecordIndex, ReqRef, data))
            .unwrap_or_else(|| wrong_handle(F, Handle))
    })
}

/// Asks for a diagnosis; `PNIO_CBE_CTRL_DIAG_CONF` delivers it. `*pDiagReq` belongs to the
/// library until then.
///
/// # Safety
/// `pDiagReq` is NULL or points to a `PNIO_CTRL_DIAG` that stays valid until its
/// confirmation has been delivered.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_ctrl_diag_req(
    Handle: PNIO_UINT32,
    pDiagReq: *mut PNIO_CTRL_DIAG,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_ctrl_diag_req";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        let Some(ctl) = lookup(Handle) else {
            return wrong_handle(F, Handle);
        };
        if pDiagReq.is_null() {
            return fail(F, PNIO_ERR_PRM_POINTER, "pDiagReq is NULL");
        }
        ctl.with_services(|s| s.ctrl_diag_req(pDiagReq))
            .unwrap_or_else(|| wrong_handle(F, Handle))
    })
}
