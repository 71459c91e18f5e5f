// SPDX-License-Identifier: MIT OR Apache-2.0
//! The exported diagnosis, alarm and state functions of `pniousrd.h`
//! (`PNIO_build_channel_properties`, `PNIO_diag_*`, `PNIO_process_alarm_send`,
//! `PNIO_diag_alarm_send`, `PNIO_ret_of_sub_alarm_send`, `PNIO_set_dev_state`), with the signatures of `device_types::prototypes`. Each
//! runs inside [`crate::ffi::guard`]. They may be called inside callbacks: they go to
//! procimgd directly, not through the library thread. What they do is in
//! `device::diag` and `device::alarms`.
#![allow(non_snake_case)]

use super::device::Pos;
use super::device::alarms::{self, AlarmCall, MAX_ALARM_DATA};
use super::device::diag::{self, DiagFn};
use super::device::state::{Device, lookup, wrong_handle};
use super::device_api::read_addr;
use super::device_types::*;
use super::errors::*;
use super::sync::lock;
use super::types::*;
use crate::ffi::guard;
use procimg_client::StationAlarmKind;
use std::sync::Arc;

/// The most manufacturer diagnosis data (`PNIO_diag_generic_add`'s InfoDataLen).
const MAX_INFO_DATA: u32 = 1404;

/// The open device with handle `h`.
fn device(f: &str, h: u32) -> Result<Arc<Device>, u32> {
    lookup(h).ok_or_else(|| wrong_handle(f, h))
}

/// The submodule `addr` names in `api`.
///
/// # Safety
/// `addr` is NULL or points to a readable `PNIO_DEV_ADDR`.
unsafe fn position(f: &str, api: u32, addr: *const PNIO_DEV_ADDR) -> Result<Pos, u32> {
    // SAFETY: as the caller's contract.
    let a = unsafe { read_addr(f, addr) }?;
    if a.AddrType != PNIO_ADDR_GEO {
        return Err(fail(
            f,
            PNIO_ERR_PRM_ADD,
            format_args!("pAddr->AddrType {} is not PNIO_ADDR_GEO", a.AddrType),
        ));
    }
    let g = a.geo_addr();
    match (u16::try_from(g.Slot), u16::try_from(g.Subslot)) {
        (Ok(slot), Ok(subslot)) => Ok((api, slot, subslot)),
        _ => Err(fail(
            f,
            PNIO_ERR_PRM_ADD,
            format_args!("slot {} subslot {:#x} is out of range", g.Slot, g.Subslot),
        )),
    }
}

/// The open device with handle `h` and the submodule `addr` names in `api`.
///
/// # Safety
/// `addr` is NULL or points to a readable `PNIO_DEV_ADDR`.
unsafe fn target(
    f: &str,
    h: u32,
    api: u32,
    addr: *const PNIO_DEV_ADDR,
) -> Result<(Arc<Device>, Pos), u32> {
    let dev = device(f, h)?;
    // SAFETY: as the caller's contract.
    let at = unsafe { position(f, api, addr) }?;
    Ok((dev, at))
}

/// `len` bytes at `data` (none for 0); more than `max` answer `too_long`.
///
/// # Safety
/// `data` is NULL or points to `len` readable bytes.
unsafe fn bytes<'a>(
    f: &str,
    data: *const u8,
    len: u32,
    (max, too_long): (u32, u32),
) -> Result<&'a [u8], u32> {
    if len > max {
        return Err(fail(
            f,
            too_long,
            format_args!("{len} bytes are more than the {max} allowed"),
        ));
    }
    if len == 0 {
        return Ok(&[]);
    }
    if data.is_null() {
        return Err(fail(f, PNIO_ERR_PRM_BUF, "the data pointer is NULL"));
    }
    // SAFETY: not NULL, `len` readable bytes by the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(data, len as usize) })
}

/// Builds the ChannelProperties word of a diagnosis: Type, Specifier and Direction
/// (`PNIO_DIAG_CHANPROP_TYPE_*`, `PNIO_DIAG_CHAN_SPEC_*`, `PNIO_DIAG_CHAN_DIRECTION_*`);
/// the handle is not needed for it.
#[unsafe(no_mangle)]
pub extern "C" fn PNIO_build_channel_properties(
    DevHndl: PNIO_UINT32,
    Type: PNIO_UINT16,
    Spec: PNIO_UINT16,
    Dir: PNIO_UINT16,
) -> PNIO_UINT16 {
    let _ = DevHndl;
    diag::channel_properties(Type, Spec, Dir)
}

/// Adds a channel diagnosis with `DiagTag` (≠ 0) to the program's submodule, without an
/// alarm.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_diag_channel_add(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    ChannelNum: PNIO_UINT16,
    ChannelProp: PNIO_UINT16,
    ChannelErrType: PNIO_UINT32,
    DiagTag: PNIO_UINT16,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_diag_channel_add";
    guard(PNIO_ERR_INTERNAL, || {
        // SAFETY: as the function's contract.
        let (dev, at) = match unsafe { target(F, DevHndl, Api, pAddr) } {
            Ok(t) => t,
            Err(c) => return c,
        };
        let Ok(error) = u16::try_from(ChannelErrType) else {
            return fail(
                F,
                PNIO_ERR_PRM_INVALIDARG,
                format_args!("ChannelErrType {ChannelErrType:#x} is above 0xFFFF"),
            );
        };
        let entry = diag::channel_entry(ChannelNum, ChannelProp, error, None);
        diag::add(F, &dev, at, DiagTag, DiagFn::Channel, entry)
    })
}

/// Removes the channel diagnosis with `DiagTag` (0: all) from the program's submodule.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_diag_channel_remove(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    DiagTag: PNIO_UINT16,
) -> PNIO_UINT32 {
    // SAFETY: as the function's contract.
    unsafe {
        remove(
            "PNIO_diag_channel_remove",
            DevHndl,
            Api,
            pAddr,
            DiagTag,
            DiagFn::Channel,
        )
    }
}

/// Adds an extended channel diagnosis with `DiagTag` (≠ 0) to the program's submodule,
/// without an alarm.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn PNIO_diag_ext_channel_add(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    ChannelNum: PNIO_UINT16,
    ChannelProp: PNIO_UINT16,
    ChannelErrType: PNIO_UINT16,
    ExtChannelErrType: PNIO_UINT16,
    ExtChannelAddValue: PNIO_UINT32,
    DiagTag: PNIO_UINT16,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_diag_ext_channel_add";
    guard(PNIO_ERR_INTERNAL, || {
        // SAFETY: as the function's contract.
        let (dev, at) = match unsafe { target(F, DevHndl, Api, pAddr) } {
            Ok(t) => t,
            Err(c) => return c,
        };
        let ext = Some((ExtChannelErrType, ExtChannelAddValue));
        let entry = diag::channel_entry(ChannelNum, ChannelProp, ChannelErrType, ext);
        diag::add(F, &dev, at, DiagTag, DiagFn::ExtChannel, entry)
    })
}

/// Removes the extended channel diagnosis with `DiagTag` (0: all) from the program's
/// submodule.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_diag_ext_channel_remove(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    DiagTag: PNIO_UINT16,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_diag_ext_channel_remove";
    // SAFETY: as the function's contract.
    unsafe { remove(F, DevHndl, Api, pAddr, DiagTag, DiagFn::ExtChannel) }
}

/// Adds a manufacturer diagnosis (USI 0x0000–0x7FFF, at most 1404 bytes) with `DiagTag`
/// (≠ 0) to the program's submodule, without an alarm.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`; `pInfoData` is NULL or points
/// to `InfoDataLen` readable bytes.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn PNIO_diag_generic_add(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    ChannelNum: PNIO_UINT16,
    ChannelProp: PNIO_UINT16,
    DiagTag: PNIO_UINT16,
    UserStructIdent: PNIO_UINT16,
    pInfoData: *mut PNIO_UINT8,
    InfoDataLen: PNIO_UINT32,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_diag_generic_add";
    // Manufacturer data has no ChannelNumber or ChannelProperties of its own in the store.
    let _ = (ChannelNum, ChannelProp);
    guard(PNIO_ERR_INTERNAL, || {
        // SAFETY: as the function's contract.
        let (dev, at) = match unsafe { target(F, DevHndl, Api, pAddr) } {
            Ok(t) => t,
            Err(c) => return c,
        };
        if UserStructIdent > 0x7fff {
            return fail(
                F,
                PNIO_ERR_PRM_INVALIDARG,
                format_args!(
                    "UserStructIdent {UserStructIdent:#06x} is not manufacturer specific \
                     (0x0000 to 0x7FFF)"
                ),
            );
        }
        let limit = (MAX_INFO_DATA, PNIO_ERR_PRM_LEN);
        // SAFETY: as the function's contract.
        let data = match unsafe { bytes(F, pInfoData, InfoDataLen, limit) } {
            Ok(d) => d,
            Err(c) => return c,
        };
        let entry = diag::generic_entry(UserStructIdent, data);
        diag::add(F, &dev, at, DiagTag, DiagFn::Generic, entry)
    })
}

/// Removes the manufacturer diagnosis with `DiagTag` (0: all) from the program's submodule.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_diag_generic_remove(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    DiagTag: PNIO_UINT16,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_diag_generic_remove";
    // SAFETY: as the function's contract.
    unsafe { remove(F, DevHndl, Api, pAddr, DiagTag, DiagFn::Generic) }
}

/// A remove function after its arguments.
///
/// # Safety
/// `addr` is NULL or points to a readable `PNIO_DEV_ADDR`.
unsafe fn remove(
    f: &str,
    h: u32,
    api: u32,
    addr: *const PNIO_DEV_ADDR,
    tag: u16,
    kind: DiagFn,
) -> u32 {
    guard(PNIO_ERR_INTERNAL, || {
        // SAFETY: as the caller's contract.
        match unsafe { target(f, h, api, addr) } {
            Ok((dev, at)) => diag::remove(f, &dev, at, tag, kind),
            Err(c) => c,
        }
    })
}

/// Sends a process alarm (UserStructIdent 0x0000–0x7FFF, at most 172 bytes of data) of the
/// program's submodule to the AR; `PNIO_CBF_REQ_DONE` with `UserHndl` follows.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`; `pData` is NULL or points to
/// `DataLen` readable bytes.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn PNIO_process_alarm_send(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    ArNumber: PNIO_UINT16,
    SessionKey: PNIO_UINT16,
    pAddr: *mut PNIO_DEV_ADDR,
    pData: *mut PNIO_UINT8,
    DataLen: PNIO_UINT32,
    UserStructIdent: PNIO_UINT16,
    UserHndl: PNIO_UINT32,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_process_alarm_send";
    guard(PNIO_ERR_INTERNAL, || {
        if UserStructIdent > 0x7fff {
            return fail(
                F,
                PNIO_ERR_PRM_INVALIDARG,
                format_args!(
                    "UserStructIdent {UserStructIdent:#06x} is not manufacturer specific \
                     (0x0000 to 0x7FFF)"
                ),
            );
        }
        // SAFETY: as the function's contract.
        unsafe {
            alarm(
                F,
                DevHndl,
                Api,
                (ArNumber, SessionKey),
                pAddr,
                (pData, DataLen),
                StationAlarmKind::Process,
                UserStructIdent,
                UserHndl,
            )
        }
    })
}

/// Sends a diagnosis alarm (`PNIO_STATE_ALARM_APPEARS` or `_DISAPPEARS`) of the program's
/// submodule to the AR, with the data after its UserStructIdent; `PNIO_CBF_REQ_DONE` with
/// `UserHndl` follows.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`; `pData` is NULL or points to
/// `DataLen` readable bytes.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn PNIO_diag_alarm_send(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    ArNumber: PNIO_UINT16,
    SessionKey: PNIO_UINT16,
    AlarmState: PNIO_UINT32,
    pAddr: *mut PNIO_DEV_ADDR,
    pData: *mut PNIO_UINT8,
    DataLen: PNIO_UINT32,
    UserStructIdent: PNIO_UINT16,
    UserHndl: PNIO_UINT32,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_diag_alarm_send";
    guard(PNIO_ERR_INTERNAL, || {
        let kind = match AlarmState {
            PNIO_STATE_ALARM_APPEARS => StationAlarmKind::DiagnosisAppears,
            PNIO_STATE_ALARM_DISAPPEARS => StationAlarmKind::DiagnosisDisappears,
            other => {
                return fail(
                    F,
                    PNIO_ERR_PRM_INVALIDARG,
                    format_args!(
                        "AlarmState {other} is neither PNIO_STATE_ALARM_APPEARS nor \
                         PNIO_STATE_ALARM_DISAPPEARS"
                    ),
                );
            }
        };
        if u32::from(UserStructIdent) == PNIO_USR_STRUC_ID_MULTI_MANUFAC_DIAG {
            return fail(
                F,
                PNIO_ERR_PRM_INVALIDARG,
                "UserStructIdent 0x8001 (several diagnoses in one alarm) is not allowed",
            );
        }
        // SAFETY: as the function's contract.
        unsafe {
            alarm(
                F,
                DevHndl,
                Api,
                (ArNumber, SessionKey),
                pAddr,
                (pData, DataLen),
                kind,
                UserStructIdent,
                UserHndl,
            )
        }
    })
}

/// Sends a Return of Submodule alarm of the program's submodule to the AR (its data turned
/// GOOD again); `PNIO_CBF_REQ_DONE` with `UserHndl` follows.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_DEV_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_ret_of_sub_alarm_send(
    DevHndl: PNIO_UINT32,
    Api: PNIO_UINT32,
    ArNumber: PNIO_UINT16,
    SessionKey: PNIO_UINT16,
    pAddr: *mut PNIO_DEV_ADDR,
    UserHndl: PNIO_UINT32,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_ret_of_sub_alarm_send";
    guard(PNIO_ERR_INTERNAL, || {
        // SAFETY: as the function's contract; no data.
        unsafe {
            alarm(
                F,
                DevHndl,
                Api,
                (ArNumber, SessionKey),
                pAddr,
                (std::ptr::null(), 0),
                StationAlarmKind::ReturnOfSubmodule,
                0,
                UserHndl,
            )
        }
    })
}

/// An alarm function after its own checks.
///
/// # Safety
/// `addr` is NULL or points to a readable `PNIO_DEV_ADDR`; `data.0` is NULL or points to
/// `data.1` readable bytes.
#[allow(clippy::too_many_arguments)]
unsafe fn alarm(
    f: &str,
    h: u32,
    api: u32,
    ar: (u16, u16),
    addr: *const PNIO_DEV_ADDR,
    data: (*const u8, u32),
    kind: StationAlarmKind,
    usi: u16,
    user: u32,
) -> u32 {
    // SAFETY: as the caller's contract.
    let (dev, at) = match unsafe { target(f, h, api, addr) } {
        Ok(t) => t,
        Err(c) => return c,
    };
    // SAFETY: as the caller's contract.
    let data = match unsafe { bytes(f, data.0, data.1, (MAX_ALARM_DATA, PNIO_ERR_VALUE_LEN)) } {
        Ok(d) => d,
        Err(c) => return c,
    };
    alarms::send(
        &dev,
        AlarmCall {
            f,
            ar,
            at,
            kind,
            usi,
            data,
            user,
        },
    )
}

/// Reports the station's state to the PLC: `PNIO_DEVSTAT_STATION_PROBLEM` sets the
/// StationProblemIndicator of the input data (as a pending fault diagnosis does),
/// `PNIO_DEVSTAT_OK` takes the report back.
#[unsafe(no_mangle)]
pub extern "C" fn PNIO_set_dev_state(DevHndl: PNIO_UINT32, DevState: PNIO_UINT32) -> PNIO_UINT32 {
    const F: &str = "PNIO_set_dev_state";
    guard(PNIO_ERR_INTERNAL, || {
        let dev = match device(F, DevHndl) {
            Ok(d) => d,
            Err(c) => return c,
        };
        let problem = match DevState {
            PNIO_DEVSTAT_OK => false,
            PNIO_DEVSTAT_STATION_PROBLEM => true,
            other => {
                return fail(
                    F,
                    PNIO_ERR_PRM_DEV_STATE,
                    format_args!(
                        "DevState {other} is neither PNIO_DEVSTAT_OK nor \
                         PNIO_DEVSTAT_STATION_PROBLEM"
                    ),
                );
            }
        };
        match lock(&dev.client).set_station_problem(problem) {
            Ok(()) => PNIO_OK,
            Err(e) => fail(F, PNIO_ERR_NO_FW_COMMUNICATION, format_args!("{e}")),
        }
    })
}

const _: prototypes::PNIO_set_dev_state = PNIO_set_dev_state;
const _: prototypes::PNIO_build_channel_properties = PNIO_build_channel_properties;
const _: prototypes::PNIO_diag_channel_add = PNIO_diag_channel_add;
const _: prototypes::PNIO_diag_channel_remove = PNIO_diag_channel_remove;
const _: prototypes::PNIO_diag_ext_channel_add = PNIO_diag_ext_channel_add;
const _: prototypes::PNIO_diag_ext_channel_remove = PNIO_diag_ext_channel_remove;
const _: prototypes::PNIO_diag_generic_add = PNIO_diag_generic_add;
const _: prototypes::PNIO_diag_generic_remove = PNIO_diag_generic_remove;
const _: prototypes::PNIO_process_alarm_send = PNIO_process_alarm_send;
const _: prototypes::PNIO_diag_alarm_send = PNIO_diag_alarm_send;
const _: prototypes::PNIO_ret_of_sub_alarm_send = PNIO_ret_of_sub_alarm_send;
