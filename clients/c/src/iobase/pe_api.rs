// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFIenergy on a controller (`pniousrx.h`): `PNIO_register_pe_cbf` and `PNIO_pe_cmd_req`;
//! the work is the services worker's (`services`).
#![allow(non_snake_case)]

use super::api::not_in_callback;
use super::callbacks::in_callback;
use super::controller::{lookup, wrong_handle};
use super::errors::*;
use super::pe_types::{PNIO_PE_CBF, PNIO_PE_REQ_PRM};
use super::types::{PNIO_ADDR, PNIO_REF, PNIO_UINT32};
use crate::ffi::guard;

/// Registers the PE confirmation callback, once, before the first `PNIO_pe_cmd_req`.
///
/// # Safety
/// `cbf_pe_cmd_conf` is NULL or a function of the `PNIO_PE_CBF` type that stays callable
/// until the controller is closed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_register_pe_cbf(
    Handle: PNIO_UINT32,
    cbf_pe_cmd_conf: PNIO_PE_CBF,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_register_pe_cbf";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        let Some(ctl) = lookup(Handle) else {
            return wrong_handle(F, Handle);
        };
        if cbf_pe_cmd_conf.is_none() {
            return fail(F, PNIO_ERR_PRM_CALLBACK, "cbf_pe_cmd_conf is NULL");
        }
        ctl.with_services(|s| s.register_pe_cbf(cbf_pe_cmd_conf))
            .unwrap_or_else(|| wrong_handle(F, Handle))
    })
}

/// Sends a PE command to the submodule at `pAddr`; the answer comes to the PE callback.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_ADDR`; `pPeReqPrm` is NULL or points to a
/// readable `PNIO_PE_REQ_PRM`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_pe_cmd_req(
    Handle: PNIO_UINT32,
    pAddr: *mut PNIO_ADDR,
    ReqRef: PNIO_REF,
    pPeReqPrm: *mut PNIO_PE_REQ_PRM,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_pe_cmd_req";
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
        if pPeReqPrm.is_null() {
            return fail(F, PNIO_ERR_PRM_BUF, "pPeReqPrm is NULL");
        }
        // SAFETY: not NULL, readable by the caller's contract; copied, as the manual says.
        let (addr, prm) = unsafe { (pAddr.read_unaligned(), pPeReqPrm.read_unaligned()) };
        ctl.with_services(|s| s.pe_cmd_req(&addr, ReqRef, &prm))
            .unwrap_or_else(|| wrong_handle(F, Handle))
    })
}
