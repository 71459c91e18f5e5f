// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller's own interface (PN Driver's chapter 10, `pniousrx.h`): `PNIO_interface_open`,
//! `_register_cbf`, `_close`, `_set_ip_and_nos` and `_rec_read_req`.
//!
//! An interface handle is a subscription of its own to the services of the procimgd
//! instance CpIndex names, with a worker thread that delivers its events
//! (`interface_worker`). The checks are PN Driver's, in its order:
//!
//! * open: `Handle` NULL → `PNIO_ERR_PRM_HND`; a CpIndex out of 1..255 →
//!   `PNIO_ERR_PRM_CP_ID`; between `SERV_CP_init` and `SERV_CP_startup` →
//!   `PNIO_ERR_SEQUENCE`; no controller running there → `PNIO_ERR_CREATE_INSTANCE`; the
//!   interface already open → `PNIO_ERR_WRONG_HND` (one open per interface, as PN Driver);
//! * register_cbf: not open → `PNIO_ERR_WRONG_HND`; NULL → `PNIO_ERR_PRM_CALLBACK`; an
//!   event other than `PNIO_CBE_IFC_SET_ADDR_CONF` and `PNIO_CBE_REMA_READ_CONF` →
//!   `PNIO_ERR_PRM_TYPE`; registered before → `PNIO_ERR_ALREADY_DONE`;
//! * set_ip_and_nos: not open → `PNIO_ERR_WRONG_HND`; `Mode` not 1..3 →
//!   `PNIO_ERR_MODE_VALUE`; a change still under way → `PNIO_ERR_NOT_REENTERABLE`; a name
//!   longer than 240 → `PNIO_ERR_PRM_NOS_LEN`; no `PNIO_CBE_IFC_SET_ADDR_CONF` registered
//!   → `PNIO_ERR_SEQUENCE` (its outcome would have nowhere to go). The rest is the server's,
//!   reported in the confirmation's `Err`: `PNIO_ERR_SET_IP_NOS_NOT_ALLOWED` where the
//!   configuration keeps the name or address, `PNIO_ERR_PRM_NOS` / `PNIO_ERR_PRM_IP` for an
//!   invalid one, `PNIO_ERR_INTERNAL` where the network interface would not take the
//!   address;
//! * rec_read_req: not open → `PNIO_ERR_WRONG_HND`; an address that is not the interface's
//!   or its port's diagnostic address (`PNIO_ADDR_LOG`, `PNIO_IO_IN`) → `PNIO_ERR_PRM_ADD`;
//!   `Length` 0 or over 4096 → `PNIO_ERR_VALUE_LEN`; an index over 0xFFFF →
//!   `PNIO_ERR_PRM_REC_INDEX`; 16 reads open → `PNIO_ERR_NO_RESOURCE`.
//!
//! None of them may be called inside a callback (`PNIO_ERR_SEQUENCE`).
#![allow(non_snake_case)]

use super::api::not_in_callback;
use super::callbacks::{CallbackTable, in_callback};
use super::errors::*;
use super::interface_types::{PNIO_IPv4, PNIO_NOS, PNIO_SET_IP_NOS_MODE_TYPE};
use super::interface_worker::{INTERFACES, InterfaceWorker, OwnAddresses};
use super::sync::lock;
use super::types::*;
use crate::ffi::guard;
use procimg_client::ControllerAddress;
use std::net::Ipv4Addr;
use std::sync::Arc;

/// The longest NameOfStation.
const MAX_NOS_LEN: u16 = 240;

/// The open interface `handle` names.
fn lookup(handle: u32) -> Option<Arc<InterfaceWorker>> {
    lock(&INTERFACES).get(&handle).cloned()
}

fn wrong_handle(f: &str, handle: u32) -> u32 {
    fail(
        f,
        PNIO_ERR_WRONG_HND,
        format_args!(
            "handle {handle} is not an open interface (closed, or never returned by \
             PNIO_interface_open)"
        ),
    )
}

/// Opens the controller's own interface on CP `CpIndex`.
///
/// # Safety
/// `Handle` is NULL or points to a writable `PNIO_UINT32`; the callbacks are NULL or
/// functions of the `PNIO_CBF` type that stay callable until the interface is closed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_interface_open(
    CpIndex: PNIO_UINT32,
    cbf_rec_read_conf: PNIO_CBF,
    cbf_alarm_ind: PNIO_CBF,
    Handle: *mut PNIO_UINT32,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_interface_open";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        if Handle.is_null() {
            return fail(F, PNIO_ERR_PRM_HND, "Handle (the out pointer) is NULL");
        }
        if let Err(code) = super::controller::check_cp_index(F, CpIndex) {
            return code;
        }
        if let Err(why) = super::pn_driver::controller_may_open() {
            return fail(F, PNIO_ERR_SEQUENCE, why);
        }
        let instance = super::controller::instance_for(CpIndex);
        // Held across the open, so that two threads cannot both open the one interface.
        let mut open = lock(&INTERFACES);
        if let Some(h) = open.values().find(|w| w.instance() == instance) {
            return fail(
                F,
                PNIO_ERR_WRONG_HND,
                format_args!(
                    "the interface of CP {CpIndex} (procimg instance \"{instance}\") is open \
                     already, as handle {}: one PNIO_interface_open per interface",
                    h.handle()
                ),
            );
        }
        let callbacks = Arc::new(CallbackTable::new());
        callbacks.set_once(PNIO_CBE_IFC_REC_READ_CONF, cbf_rec_read_conf);
        callbacks.set_once(PNIO_CBE_IFC_ALARM_IND, cbf_alarm_ind);
        let handle = super::handles::next();
        match InterfaceWorker::start(handle, CpIndex, instance, callbacks) {
            Ok(worker) => {
                open.insert(handle, Arc::new(worker));
                // SAFETY: not NULL, writable by the caller's contract.
                unsafe { Handle.write_unaligned(handle) };
                PNIO_OK
            }
            Err(code) => code,
        }
    })
}

/// Registers `PNIO_CBE_IFC_SET_ADDR_CONF` or `PNIO_CBE_REMA_READ_CONF`, each once.
///
/// # Safety
/// `Cbf` is NULL or a function of the `PNIO_CBF` type that stays callable until the
/// interface is closed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_interface_register_cbf(
    Handle: PNIO_UINT32,
    CbeType: PNIO_CBE_TYPE,
    Cbf: PNIO_CBF,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_interface_register_cbf";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        let Some(w) = lookup(Handle) else {
            return wrong_handle(F, Handle);
        };
        if Cbf.is_none() {
            return fail(F, PNIO_ERR_PRM_CALLBACK, "Cbf is NULL");
        }
        if CbeType != PNIO_CBE_IFC_SET_ADDR_CONF && CbeType != PNIO_CBE_REMA_READ_CONF {
            return fail(
                F,
                PNIO_ERR_PRM_TYPE,
                format_args!(
                    "event {CbeType} is not registered here: an interface takes \
                     PNIO_CBE_IFC_SET_ADDR_CONF (10) and PNIO_CBE_REMA_READ_CONF (11); its \
                     record and alarm callbacks are PNIO_interface_open's"
                ),
            );
        }
        if !w.callbacks().set_once(CbeType, Cbf) {
            return fail(
                F,
                PNIO_ERR_ALREADY_DONE,
                format_args!("event {CbeType} has a callback already"),
            );
        }
        PNIO_OK
    })
}

/// Closes the interface; once it returns, none of its callbacks runs any more.
///
/// # Safety
/// None beyond the C ABI; any value of `Handle` is checked.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_interface_close(Handle: PNIO_UINT32) -> PNIO_UINT32 {
    const F: &str = "PNIO_interface_close";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        let Some(w) = lock(&INTERFACES).remove(&Handle) else {
            return wrong_handle(F, Handle);
        };
        w.stop();
        PNIO_OK
    })
}

/// Gives the controller's station a new IP suite and/or NameOfStation; the outcome comes
/// as `PNIO_CBE_IFC_SET_ADDR_CONF`.
///
/// # Safety
/// None beyond the C ABI: both structs are passed by value.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_interface_set_ip_and_nos(
    Handle: PNIO_UINT32,
    Mode: PNIO_SET_IP_NOS_MODE_TYPE,
    IpV4: PNIO_IPv4,
    NoS: PNIO_NOS,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_interface_set_ip_and_nos";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        let Some(w) = lookup(Handle) else {
            return wrong_handle(F, Handle);
        };
        if !(1..=3).contains(&Mode) {
            return fail(
                F,
                PNIO_ERR_MODE_VALUE,
                format_args!(
                    "Mode {Mode} is not PNIO_SET_IP_MODE (1), PNIO_SET_NOS_MODE (2) or both (3)"
                ),
            );
        }
        let set_ip = Mode & super::interface_types::PNIO_SET_IP_MODE != 0;
        let set_name = Mode & super::interface_types::PNIO_SET_NOS_MODE != 0;
        if set_name && NoS.Length > MAX_NOS_LEN {
            return fail(
                F,
                PNIO_ERR_PRM_NOS_LEN,
                format_args!(
                    "NoS.Length {} is more than a NameOfStation's {MAX_NOS_LEN}",
                    NoS.Length
                ),
            );
        }
        if w.callbacks().get(PNIO_CBE_IFC_SET_ADDR_CONF).is_none() {
            return fail(
                F,
                PNIO_ERR_SEQUENCE,
                "register PNIO_CBE_IFC_SET_ADDR_CONF first (PNIO_interface_register_cbf): the \
                 change is confirmed there",
            );
        }
        let name = set_name.then(|| {
            let bytes = &NoS.Nos[..usize::from(NoS.Length)];
            String::from_utf8_lossy(bytes).into_owned()
        });
        let ip_suite =
            set_ip.then(|| [IpV4.IpAddress, IpV4.NetMask, IpV4.Gateway].map(Ipv4Addr::from));
        let permanent = (set_name && NoS.Remanent != 0) || (set_ip && IpV4.Remanent != 0);
        w.set_address(
            Mode,
            ControllerAddress {
                name,
                ip_suite,
                permanent,
            },
        )
    })
}

/// Reads a record of the interface or its port; the record comes as
/// `PNIO_CBE_IFC_REC_READ_CONF`.
///
/// # Safety
/// `pAddr` is NULL or points to a readable `PNIO_ADDR`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn PNIO_interface_rec_read_req(
    Handle: PNIO_UINT32,
    pAddr: *mut PNIO_ADDR,
    RecordIndex: PNIO_UINT32,
    ReqRef: PNIO_REF,
    Length: PNIO_UINT32,
) -> PNIO_UINT32 {
    const F: &str = "PNIO_interface_rec_read_req";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return not_in_callback(F);
        }
        let Some(w) = lookup(Handle) else {
            return wrong_handle(F, Handle);
        };
        if pAddr.is_null() {
            return fail(F, PNIO_ERR_PRM_ADD, "pAddr is NULL");
        }
        // SAFETY: not NULL, readable by the caller's contract.
        let addr = unsafe { pAddr.read_unaligned() };
        let OwnAddresses { interface, port } = w.addresses();
        // SAFETY: every bit pattern of the union is a valid u32.
        let logical = unsafe { addr.u.Addr };
        let subslot = match (addr.AddrType, addr.IODataType, logical) {
            (PNIO_ADDR_LOG, PNIO_IO_IN, a) if a == interface => 0x8000,
            (PNIO_ADDR_LOG, PNIO_IO_IN, a) if a == port => 0x8001,
            _ => {
                return fail(
                    F,
                    PNIO_ERR_PRM_ADD,
                    format_args!(
                        "the interface's submodules are named by their diagnostic addresses \
                         {interface} (the interface) and {port} (its port), PNIO_ADDR_LOG \
                         and PNIO_IO_IN; the address given is not one of them"
                    ),
                );
            }
        };
        if Length == 0 || Length > PNIO_MAX_REC_LEN {
            return fail(
                F,
                PNIO_ERR_VALUE_LEN,
                format_args!("Length {Length} is not 1..{PNIO_MAX_REC_LEN}"),
            );
        }
        let Ok(index) = u16::try_from(RecordIndex) else {
            return fail(
                F,
                PNIO_ERR_PRM_REC_INDEX,
                format_args!("RecordIndex {RecordIndex:#x} is more than 0xFFFF"),
            );
        };
        w.read_record(addr, subslot, index, ReqRef, Length)
    })
}
