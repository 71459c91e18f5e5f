// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the Rust tests of the IO-Base API share: for the device API a callback table whose
//! entries do nothing (each test sets the ones it watches) and opening the demo device; for
//! the controller API naming a CpIndex and opening a controller in OPERATE; the library's last
//! error text and a bounded wait.
// Each test binary uses a part of it.
#![allow(dead_code)]

use procimg::iobase::api::{PNIO_controller_open, PNIO_register_cbf, PNIO_set_mode};
use procimg::iobase::device_api::PNIO_device_open;
use procimg::iobase::device_types::*;
use procimg::iobase::errors::PNIO_OK;
use procimg::iobase::types::{
    PNIO_CBE_MODE_IND, PNIO_CBE_PRM, PNIO_CEP_MODE_CTRL, PNIO_ERR_STAT, PNIO_IOXS,
    PNIO_MODE_OPERATE, PNIO_S_GOOD,
};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

/// How long a test waits for what the library reports.
pub const WAIT: Duration = Duration::from_secs(20);

/// Waits up to [`WAIT`] until `ok`; fails the test naming `what` otherwise.
pub fn wait_until(what: &str, ok: impl Fn() -> bool) {
    let until = Instant::now() + WAIT;
    while !ok() {
        assert!(
            Instant::now() < until,
            "{what} did not happen within {WAIT:?}"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Points CpIndex `cp` at `instance`.
pub fn name_cp(cp: u32, instance: &str) {
    // SAFETY: the tests that call this run one at a time and read the environment only inside
    // the library's open calls, on this thread.
    unsafe { std::env::set_var(format!("PROCIMG_CP{cp}"), instance) };
}

/// The mode the last MODE_IND reported.
static MODE: AtomicU32 = AtomicU32::new(u32::MAX);

unsafe extern "C" fn on_mode(prm: *mut PNIO_CBE_PRM) {
    // SAFETY: the library's parameters of a MODE_IND, valid for the call.
    MODE.store(unsafe { (*prm).u.ModeInd.Mode }, Ordering::SeqCst);
}

/// A controller callback that ignores what it is given.
pub unsafe extern "C" fn ignore(_: *mut PNIO_CBE_PRM) {}

/// Opens a controller on CpIndex `cp` (named with [`name_cp`]) with the record callbacks
/// `on_read` and `on_write`, and brings it to OPERATE; its handle.
pub fn open_controller_in_operate(
    cp: u32,
    on_read: unsafe extern "C" fn(*mut PNIO_CBE_PRM),
    on_write: unsafe extern "C" fn(*mut PNIO_CBE_PRM),
) -> u32 {
    let mut h = 0;
    // SAFETY: valid pointers and callbacks that live for the whole program.
    unsafe {
        assert_eq!(
            PNIO_controller_open(
                cp,
                PNIO_CEP_MODE_CTRL,
                Some(on_read),
                Some(on_write),
                None,
                &mut h
            ),
            PNIO_OK,
            "{}",
            last_error()
        );
        assert_eq!(
            PNIO_register_cbf(h, PNIO_CBE_MODE_IND, Some(on_mode)),
            PNIO_OK
        );
        assert_eq!(PNIO_set_mode(h, PNIO_MODE_OPERATE), PNIO_OK);
    }
    wait_until("OPERATE", || {
        MODE.load(Ordering::SeqCst) == PNIO_MODE_OPERATE
    });
    h
}

unsafe extern "C" fn data(_: u32, _: *mut PNIO_DEV_ADDR, _: u32, _: *mut u8, _: PNIO_IOXS) -> u32 {
    PNIO_S_GOOD
}
unsafe extern "C" fn rec(
    _: u32,
    _: u32,
    _: u16,
    _: u16,
    _: u32,
    _: *mut PNIO_DEV_ADDR,
    _: u32,
    _: *mut u32,
    _: *mut u8,
    _: *mut PNIO_ERR_STAT,
) {
}
unsafe extern "C" fn req_done(_: u32, _: u32, _: u32, _: *mut PNIO_ERR_STAT) {}
unsafe extern "C" fn check_ind(
    _: u32,
    _: u32,
    _: u16,
    _: u16,
    _: *mut PNIO_DEV_ADDR,
    _: *mut u32,
    _: *mut u16,
    _: *mut u32,
    _: *mut u16,
) {
}
unsafe extern "C" fn ar_check_ind(
    _: u32,
    _: u32,
    _: u16,
    _: PNIO_UUID_TYPE,
    _: u32,
    _: PNIO_UUID_TYPE,
    _: u16,
    _: *mut u8,
    _: *mut PNIO_AR_TYPE,
) {
}
unsafe extern "C" fn ar_info_ind(_: u32, _: u16, _: u16, _: *mut PNIO_AR_TYPE) {}
unsafe extern "C" fn ar_indata_ind(_: u32, _: u16, _: u16) {}
unsafe extern "C" fn ar_end_ind(_: u32, _: u16, _: u16, _: PNIO_AR_REASON) {}
unsafe extern "C" fn apdu_ind(_: u32, _: u16, _: u16, _: PNIO_APDU_STATUS_IND) {}
unsafe extern "C" fn prm_end_ind(_: u32, _: u16, _: u16, _: u32, _: u16, _: u16) {}
unsafe extern "C" fn cp_stop_req(_: u32) {}
unsafe extern "C" fn device_stopped(_: u32, _: u32) {}

/// Every mandatory callback, doing nothing (the data ones return `PNIO_S_GOOD`).
pub fn quiet_table() -> PNIO_CBF_FUNCTIONS {
    PNIO_CBF_FUNCTIONS {
        size: size_of::<PNIO_CBF_FUNCTIONS>() as u32,
        cbf_data_write: Some(data),
        cbf_data_read: Some(data),
        cbf_rec_read: Some(rec),
        cbf_rec_write: Some(rec),
        cbf_alarm_done: Some(req_done),
        cbf_check_ind: Some(check_ind),
        cbf_ar_check_ind: Some(ar_check_ind),
        cbf_ar_info_ind: Some(ar_info_ind),
        cbf_ar_indata_ind: Some(ar_indata_ind),
        cbf_ar_abort_ind: Some(ar_end_ind),
        cbf_ar_offline_ind: Some(ar_end_ind),
        cbf_apdu_status_ind: Some(apdu_ind),
        cbf_prm_end_ind: Some(prm_end_ind),
        cbf_cp_stop_req: Some(cp_stop_req),
        cbf_device_stopped: Some(device_stopped),
        ..PNIO_CBF_FUNCTIONS::default()
    }
}

/// The library's last error text for this thread.
pub fn last_error() -> String {
    // SAFETY: the library's text for this thread, NUL-terminated, valid until its next call.
    unsafe { std::ffi::CStr::from_ptr(procimg::ffi::last_error_ptr()) }
        .to_string_lossy()
        .into_owned()
}

/// Opens the demo device (`procimgd --demo-device`'s VendorID and DeviceID) on CpIndex `cp`
/// with the callbacks `cbf`; its handle.
pub fn open_demo_device(cp: u32, mut cbf: PNIO_CBF_FUNCTIONS) -> u32 {
    let mut ann = PNIO_ANNOTATION {
        deviceType: [0; 26],
        orderId: [0; 21],
        hwRevision: 1,
        swRevisionPrefix: b'V',
        swRevision1: 0,
        swRevision2: 1,
        swRevision3: 0,
    };
    let mut h = 0;
    // SAFETY: valid pointers for the call; the callbacks are functions of the test binary.
    let rc = unsafe {
        PNIO_device_open(
            cp,
            PNIO_CEP_MODE_CTRL,
            0x0493,
            0x0100,
            1,
            1,
            &mut ann,
            &mut cbf,
            &mut h,
        )
    };
    assert_eq!(rc, PNIO_OK, "PNIO_device_open: {}", last_error());
    h
}
