// SPDX-License-Identifier: MIT OR Apache-2.0
//! The CP service functions of the manual's chapter 8 that procimg has (`servusrx.h`):
//! `SERV_CP_get_fw_info`, the firmware information of the procimgd a CpIndex names, read from
//! its status report.
#![allow(non_snake_case)]

use super::callbacks::in_callback;
use super::errors::*;
use super::pn_driver_types::{SERV_CP_FW_INFO_TYPE, SERV_FW_VERS_TYPE};
use super::services::build::{c_string, in_addr};
use super::types::PNIO_UINT32;
use crate::ffi::guard;
use procimg_client::iobase::parse_mac;
use procimg_client::{ControlHandle, StatusReport};

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
        if CpIndex == 0 || CpIndex > 255 {
            return fail(
                F,
                PNIO_ERR_PRM_CP_ID,
                format_args!("CpIndex {CpIndex} is not 1..255"),
            );
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
