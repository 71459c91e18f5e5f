// SPDX-License-Identifier: MIT OR Apache-2.0
//! The CP service functions of the manual's chapter 8 (`servusrx.h`) over the procimgd a
//! CpIndex names: `SERV_CP_get_fw_info` (its firmware information, from its status
//! report), `SERV_CP_set_type_of_station` (what its station reports by DCP, from its next
//! start on), `SERV_CP_download` (a new configuration: checked, then the programs attached
//! are asked to stop, CP_STOP_REQ, and procimgd starts anew with it) and `SERV_CP_reset`
//! (procimgd starts its instance anew, SAFE only with no program attached, FORCE after
//! asking them to stop). `servusrx.h` says what each answers.
#![allow(non_snake_case)]

use super::callbacks::in_callback;
use super::errors::*;
use super::pn_driver_types::{
    PNIO_CP_DLD_CONFIG, PNIO_CP_DLD_FIRMWARE, PNIO_CP_DLD_TYPE, PNIO_CP_RESET_FORCE,
    PNIO_CP_RESET_SAFE, PNIO_CP_RESET_TYPE, SERV_CP_FW_INFO_TYPE, SERV_FW_VERS_TYPE,
};
use super::services::build::{c_string, in_addr};
use super::types::{PNIO_UINT8, PNIO_UINT32};
use crate::ffi::guard;
use procimg_client::iobase::parse_mac;
use procimg_client::{
    ControlError, ControlHandle, Refusal, RestartClients, RestartError, ServiceOptions, Services,
    StatusReport,
};
use std::time::Duration;

/// How long a download or reset waits: for the programs asked to stop, then for the new
/// server's start.
const RESTART_TIMEOUT: Duration =
    Duration::from_millis(procimg_control::services::RESTART_WAIT_MS + 20_000);

/// The order number a controller reports (a procimgd is no ordered part).
const CONTROLLER_ORDER_NUMBER: &str = "procimgd";

/// `0.1.0` as `SERV_FW_VERS_TYPE` (v1 0, v2 1, v3 0); parts that are no number are 0.
fn version(text: &str) -> SERV_FW_VERS_TYPE {
    let mut parts = text
        .split(['.', '-', '+'])
        .map(|p| p.parse::<u16>().unwrap_or(0));
    let mut next = || parts.next().unwrap_or(0);
    SERV_FW_VERS_TYPE {
        v1: next(),
        v2: next(),
        v3: next(),
        v4: 0,
        v5: 0,
        reserved: 0,
    }
}

/// The firmware information of the procimgd whose status is `s`.
pub(crate) fn fw_info(s: &StatusReport) -> SERV_CP_FW_INFO_TYPE {
    let mut info = SERV_CP_FW_INFO_TYPE {
        fw_version: version(&s.server_version),
        cp_ser_nr: [0; 16],
        mlfb: [0; 32],
        hw_version: 0,
        mac: [0; 6],
        ip_addr: 0,
        ip_mask: 0,
        default_router: 0,
        name: [0; 256],
        TypeOfStation: [0; 256],
    };
    c_string(&mut info.cp_ser_nr, &s.instance);
    let (mac, name, type_of_station) = if let Some(st) = &s.station {
        c_string(&mut info.mlfb, &st.order_number);
        info.hw_version = st.hardware_revision;
        info.ip_addr = in_addr(&st.ip);
        info.ip_mask = in_addr(&st.netmask);
        info.default_router = in_addr(&st.gateway);
        (&st.mac, &st.name, &st.type_of_station)
    } else if let Some(c) = &s.controller {
        c_string(&mut info.mlfb, CONTROLLER_ORDER_NUMBER);
        info.ip_addr = in_addr(&c.ip);
        info.ip_mask = in_addr(&c.netmask);
        info.default_router = in_addr(&c.gateway);
        (&c.mac, &c.station_name, &c.type_of_station)
    } else {
        return info;
    };
    info.mac = parse_mac(mac).unwrap_or_default();
    c_string(&mut info.name, name);
    c_string(&mut info.TypeOfStation, type_of_station);
    info
}

/// The firmware information of CP `CpIndex`: the procimgd serving the instance it names.
///
/// # Safety
/// `p_info` is NULL or points to a writable `SERV_CP_FW_INFO_TYPE`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn SERV_CP_get_fw_info(
    CpIndex: PNIO_UINT32,
    p_info: *mut SERV_CP_FW_INFO_TYPE,
) -> PNIO_UINT32 {
    const F: &str = "SERV_CP_get_fw_info";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        if let Err(code) = super::controller::check_cp_index(F, CpIndex) {
            return code;
        }
        if p_info.is_null() {
            return fail(F, PNIO_ERR_PRM_POINTER, "p_info is NULL");
        }
        let instance = super::controller::instance_for(CpIndex);
        let status = ControlHandle::open(&instance, "fw-info")
            .map_err(|e| e.to_string())
            .and_then(|c| c.status().map_err(|e| e.to_string()));
        match status {
            Ok(s) => {
                // SAFETY: not NULL, writable by the caller's contract.
                unsafe { p_info.write_unaligned(fw_info(&s)) };
                PNIO_OK
            }
            Err(e) => fail(
                F,
                PNIO_ERR_NO_FW_COMMUNICATION,
                format_args!("no procimgd answers for instance \"{instance}\": {e}"),
            ),
        }
    })
}

/// The handles this process has open (the manual's "registered applications"), in words.
fn own_handles() -> Option<String> {
    let controllers = super::controller::open_handles();
    let interfaces = super::interface_worker::open_handles();
    let devices = super::device::state::open_handles();
    let all: Vec<String> = controllers
        .iter()
        .map(|h| format!("controller {h}"))
        .chain(interfaces.iter().map(|h| format!("interface {h}")))
        .chain(devices.iter().map(|h| format!("device {h}")))
        .collect();
    (!all.is_empty()).then(|| all.join(", "))
}

/// Restarts the procimgd of `instance` and waits for its new start.
fn restart(f: &str, instance: &str, configuration: Option<String>, clients: RestartClients) -> u32 {
    if let Some(open) = own_handles() {
        return fail(
            f,
            PNIO_ERR_MAX_REACHED,
            format_args!("this program has {open} open: close them first (exclusive access)"),
        );
    }
    let mut services = match Services::open(instance, ServiceOptions::new(f)) {
        Ok(s) => s,
        Err(e) => {
            return fail(
                f,
                PNIO_ERR_NO_FW_COMMUNICATION,
                format_args!("no procimgd answers for instance \"{instance}\": {e}"),
            );
        }
    };
    match services.restart_and_wait(configuration, clients, RESTART_TIMEOUT) {
        Ok(_) => PNIO_OK,
        Err(RestartError::Control(ControlError::Refused(r))) => {
            let code = match r {
                Refusal::BadConfiguration { .. } => PNIO_ERR_CORRUPTED_DATA,
                Refusal::ClientsAttached { .. } | Refusal::RestartPending => PNIO_ERR_MAX_REACHED,
                _ => PNIO_ERR_INTERNAL,
            };
            fail(f, code, r)
        }
        Err(e @ RestartError::GivenUp(_)) => fail(f, PNIO_ERR_MAX_REACHED, e),
        Err(e) => fail(f, PNIO_ERR_NO_FW_COMMUNICATION, e),
    }
}

/// Sets the type of station CP `CpIndex` reports by DCP, from its next start
/// (`SERV_CP_reset`) on; at most 255 bytes are taken.
///
/// # Safety
/// `TypeName` is NULL or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn SERV_CP_set_type_of_station(
    CpIndex: PNIO_UINT32,
    TypeName: *mut core::ffi::c_char,
) -> PNIO_UINT32 {
    const F: &str = "SERV_CP_set_type_of_station";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        let instance = match super::controller::cp_instance(F, CpIndex) {
            Ok(i) => i,
            Err(code) => return code,
        };
        if TypeName.is_null() {
            return fail(F, PNIO_ERR_PRM_POINTER, "TypeName is NULL");
        }
        // SAFETY: not NULL, NUL-terminated by the caller's contract.
        let name = unsafe { core::ffi::CStr::from_ptr(TypeName) };
        let bytes = &name.to_bytes()[..name.to_bytes().len().min(255)];
        let text = String::from_utf8_lossy(bytes).into_owned();
        if text.is_empty() {
            return fail(F, PNIO_ERR_PRM_INVALIDARG, "TypeName is empty");
        }
        let done = Services::open(&instance, ServiceOptions::new(F))
            .map_err(|e| e.to_string())
            .and_then(|s| s.set_type_of_station(&text).map_err(|e| e.to_string()));
        match done {
            Ok(()) => PNIO_OK,
            Err(e) => fail(
                F,
                PNIO_ERR_NO_FW_COMMUNICATION,
                format_args!("procimg instance \"{instance}\": {e}"),
            ),
        }
    })
}

/// Downloads a configuration (procimg's TOML text) to CP `CpIndex`: checked, then the
/// programs attached are asked to stop, and procimgd starts anew with it.
///
/// # Safety
/// `pData` is NULL or points to `DataLen` readable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn SERV_CP_download(
    CpIndex: PNIO_UINT32,
    DataType: PNIO_CP_DLD_TYPE,
    pData: *mut PNIO_UINT8,
    DataLen: PNIO_UINT32,
) -> PNIO_UINT32 {
    const F: &str = "SERV_CP_download";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        let instance = match super::controller::cp_instance(F, CpIndex) {
            Ok(i) => i,
            Err(code) => return code,
        };
        match DataType {
            PNIO_CP_DLD_CONFIG => {}
            PNIO_CP_DLD_FIRMWARE => {
                return fail(
                    F,
                    PNIO_ERR_PRM_TYPE,
                    "procimgd has no firmware to download: its program is updated as a \
                     package (PNIO_CP_DLD_CONFIG downloads a configuration)",
                );
            }
            other => {
                return fail(
                    F,
                    PNIO_ERR_PRM_TYPE,
                    format_args!("DataType {other} is not PNIO_CP_DLD_CONFIG (2)"),
                );
            }
        }
        if pData.is_null() || DataLen == 0 {
            return fail(
                F,
                PNIO_ERR_CORRUPTED_DATA,
                "no configuration: pData NULL or DataLen 0",
            );
        }
        // SAFETY: not NULL; DataLen readable bytes by the caller's contract.
        let bytes = unsafe { std::slice::from_raw_parts(pData.cast_const(), DataLen as usize) };
        let bytes = bytes.split(|b| *b == 0).next().unwrap_or_default();
        let Ok(text) = std::str::from_utf8(bytes) else {
            return fail(
                F,
                PNIO_ERR_CORRUPTED_DATA,
                "the configuration is not UTF-8 text",
            );
        };
        restart(F, &instance, Some(text.to_owned()), RestartClients::Ask)
    })
}

/// Starts CP `CpIndex`'s procimgd anew: SAFE only with no program attached, FORCE after
/// asking them to stop, whoever stays.
///
/// # Safety
/// None beyond the C ABI.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn SERV_CP_reset(
    CpIndex: PNIO_UINT32,
    ResetType: PNIO_CP_RESET_TYPE,
) -> PNIO_UINT32 {
    const F: &str = "SERV_CP_reset";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        let instance = match super::controller::cp_instance(F, CpIndex) {
            Ok(i) => i,
            Err(code) => return code,
        };
        let clients = match ResetType {
            PNIO_CP_RESET_SAFE => RestartClients::Refuse,
            PNIO_CP_RESET_FORCE => RestartClients::Force,
            other => {
                return fail(
                    F,
                    PNIO_ERR_PRM_TYPE,
                    format_args!(
                        "ResetType {other} is not PNIO_CP_RESET_SAFE (0) or PNIO_CP_RESET_FORCE (1)"
                    ),
                );
            }
        };
        restart(F, &instance, None, clients)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn versions_take_their_numbers_in_order() {
        let v = version("0.1.0");
        assert_eq!((v.v1, v.v2, v.v3, v.v4), (0, 1, 0, 0));
        let v = version("2.13.7-rc.1");
        assert_eq!((v.v1, v.v2, v.v3), (2, 13, 7));
        let v = version("");
        assert_eq!((v.v1, v.v2, v.v3), (0, 0, 0));
    }
}
