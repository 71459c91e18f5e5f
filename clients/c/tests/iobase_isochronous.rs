// SPDX-License-Identifier: MIT OR Apache-2.0
//! The isochronous device and the CP application watchdog against a real `procimgd`:
//!
//! * `procimgd --demo-device`: `PNIO_CP_register_cbf` with a device handle and its codes
//!   (wrong handle, NULL, unknown type, STARTOP before OPFAULT, twice, NEWCYCLE after
//!   STARTOP, after start), then a device that follows procimgd's cycle: STARTOP_IND on a
//!   library thread, `PNIO_initiate_data_write`/`_read` and `PNIO_CP_set_opdone` inside it,
//!   for a number of cycles, while the demo PLC echoes the I data as Q = I + 1; no STARTOP
//!   after close;
//! * the watchdog of a device: its parameter codes, no expiry before the first trigger,
//!   then expiry: the callback once, `PNIO_ERR_NO_FW_COMMUNICATION` for every call but
//!   close, the PLC sees the I data with IOPS BAD (Q comes back as 01 .. 01), close, and a
//!   new open that works; deregistration before expiry (no callback);
//! * the watchdog of a controller (`procimgd --demo`): expiry stops its handle, close works.
//!
//! Only counts are asserted, never times: the machine may be slow.

// The Rust half calls the C ABI and gives it callbacks.
#![allow(unsafe_code)]

use procimg::iobase::api::{
    PNIO_CP_register_cbf, PNIO_CP_set_opdone, PNIO_controller_close, PNIO_set_mode,
};
mod iobase_kit;

use iobase_kit::{
    WAIT, ignore, last_error, name_cp, open_controller_in_operate, open_demo_device, quiet_table,
    wait_until,
};
use procimg::iobase::device_api::*;
use procimg::iobase::device_types::*;
use procimg::iobase::errors::*;
use procimg::iobase::types::*;
use procimg::iobase::watchdog::*;
use procimg_client::{AttachOptions, Client};
use procimg_testkit::Launch;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

/// The tests share the process's watchdogs, callbacks and environment: one at a time.
static SERIAL: Mutex<()> = Mutex::new(());

/// The open device the callbacks act on.
static HANDLE: AtomicU32 = AtomicU32::new(0);
/// Set once the program called PNIO_set_appl_state_ready: STARTOP exchanges data.
static READY: AtomicU32 = AtomicU32::new(0);
static STARTOPS: AtomicU32 = AtomicU32::new(0);
static OPDONE_OK: AtomicU32 = AtomicU32::new(0);
static OPDONE_OTHER: AtomicU32 = AtomicU32::new(0);
static OPFAULTS: AtomicU32 = AtomicU32::new(0);
static NEWCYCLES: AtomicU32 = AtomicU32::new(0);
static WRITES_OK: AtomicU32 = AtomicU32::new(0);
/// Rounds in which Q came back as the I data of some round plus one, with IOPS GOOD.
static ECHOED: AtomicU32 = AtomicU32::new(0);
/// The I data pattern's first byte; it counts up each write.
static PATTERN: AtomicU32 = AtomicU32::new(0x10);
static PRM_END: AtomicU32 = AtomicU32::new(0);
static STOPPED: AtomicU32 = AtomicU32::new(0);
static WATCHDOG_CALLS: AtomicU32 = AtomicU32::new(0);
static WATCHDOG_CP: AtomicU32 = AtomicU32::new(0);

unsafe extern "C" fn data_write(
    _: u32,
    _: *mut PNIO_DEV_ADDR,
    len: u32,
    buf: *mut u8,
    _: PNIO_IOXS,
) -> u32 {
    let p = PATTERN.load(Ordering::SeqCst) as u8;
    for i in 0..len as usize {
        // SAFETY: the library's buffer of `len` bytes, valid for the call.
        unsafe { *buf.add(i) = p.wrapping_add(i as u8) };
    }
    PNIO_S_GOOD
}
unsafe extern "C" fn data_read(
    _: u32,
    _: *mut PNIO_DEV_ADDR,
    len: u32,
    buf: *mut u8,
    rem: PNIO_IOXS,
) -> u32 {
    // SAFETY: the library's buffer of `len` bytes, valid for the call.
    let q = unsafe { std::slice::from_raw_parts(buf, len as usize) };
    let steps = q.windows(2).all(|w| w[1] == w[0].wrapping_add(1));
    if rem == PNIO_S_GOOD && steps && q.first().is_some_and(|&b| b > 0x10) {
        ECHOED.fetch_add(1, Ordering::SeqCst);
    }
    PNIO_S_GOOD
}
unsafe extern "C" fn prm_end_ind(_: u32, ar: u16, sk: u16, _: u32, _: u16, _: u16) {
    PRM_END.store(u32::from(ar) << 16 | u32::from(sk), Ordering::SeqCst);
}
unsafe extern "C" fn device_stopped(_: u32, _: u32) {
    STOPPED.fetch_add(1, Ordering::SeqCst);
}

unsafe extern "C" fn on_startop(_: *mut PNIO_CP_CBE_PRM) {
    STARTOPS.fetch_add(1, Ordering::SeqCst);
    let h = HANDLE.load(Ordering::SeqCst);
    if READY.load(Ordering::SeqCst) != 0 {
        PATTERN.store(
            0x10 + (STARTOPS.load(Ordering::SeqCst) % 0x80),
            Ordering::SeqCst,
        );
        // SAFETY: the open device's handle; allowed inside the callback.
        if unsafe { PNIO_initiate_data_write(h) } == PNIO_OK {
            WRITES_OK.fetch_add(1, Ordering::SeqCst);
        }
        // SAFETY: as above.
        let _ = unsafe { PNIO_initiate_data_read(h) };
    }
    let mut info = PNIO_CYCLE_INFO::default();
    // SAFETY: as above, with a cycle info that lives for the call.
    match unsafe { PNIO_CP_set_opdone(h, &mut info) } {
        PNIO_OK => OPDONE_OK.fetch_add(1, Ordering::SeqCst),
        _ => OPDONE_OTHER.fetch_add(1, Ordering::SeqCst),
    };
}
unsafe extern "C" fn on_opfault(_: *mut PNIO_CP_CBE_PRM) {
    OPFAULTS.fetch_add(1, Ordering::SeqCst);
}
unsafe extern "C" fn on_newcycle(_: *mut PNIO_CP_CBE_PRM) {
    NEWCYCLES.fetch_add(1, Ordering::SeqCst);
}
unsafe extern "C" fn on_watchdog(cp: u32) {
    WATCHDOG_CP.store(cp, Ordering::SeqCst);
    WATCHDOG_CALLS.fetch_add(1, Ordering::SeqCst);
}

fn table() -> PNIO_CBF_FUNCTIONS {
    PNIO_CBF_FUNCTIONS {
        cbf_data_write: Some(data_write),
        cbf_data_read: Some(data_read),
        cbf_prm_end_ind: Some(prm_end_ind),
        cbf_device_stopped: Some(device_stopped),
        ..quiet_table()
    }
}

/// Waits for the watchdog's callback, and a little more: it comes once.
fn expect_one_watchdog_call() {
    wait_until("the watchdog's callback", || {
        WATCHDOG_CALLS.load(Ordering::SeqCst) > 0
    });
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(
        WATCHDOG_CALLS.load(Ordering::SeqCst),
        1,
        "the callback comes once"
    );
}

/// Opens the device on CpIndex `cp`.
fn open(cp: u32) -> u32 {
    open_demo_device(cp, table())
}

/// Plugs the demo station's DAP and slot 1 (as the demo PLC expects them), starts, and
/// says ready at PRM_END_IND.
fn plug_start_ready(h: u32) {
    PRM_END.store(0, Ordering::SeqCst);
    let mut dap = PNIO_DEV_ADDR::geo(PNIO_IO_IN, 0, 1);
    let mut one = PNIO_DEV_ADDR::geo(PNIO_IO_IN, 1, 1);
    // SAFETY: each call gets a valid handle and addresses that live for the call.
    unsafe {
        assert_eq!(PNIO_api_add(h, 0, 2, 0x8001), PNIO_OK);
        assert_eq!(PNIO_mod_plug(h, 0, &mut dap, 0x1), PNIO_OK);
        assert_eq!(PNIO_sub_plug(h, 0, &mut dap, 0x1), PNIO_OK);
        assert_eq!(PNIO_mod_plug(h, 0, &mut one, 0x10), PNIO_OK);
        assert_eq!(PNIO_sub_plug(h, 0, &mut one, 0x2), PNIO_OK);
        assert_eq!(PNIO_device_start(h), PNIO_OK, "{}", last_error());
    }
    wait_until("PNIO_CBF_PRM_END_IND", || {
        PRM_END.load(Ordering::SeqCst) != 0
    });
    let p = PRM_END.load(Ordering::SeqCst);
    // SAFETY: a valid handle; the list may be NULL.
    let rc =
        unsafe { PNIO_set_appl_state_ready(h, (p >> 16) as u16, p as u16, std::ptr::null_mut()) };
    assert_eq!(rc, PNIO_OK, "{}", last_error());
    READY.store(1, Ordering::SeqCst);
}

/// Stops (waiting for DEVICE_STOPPED), pulls and closes.
fn stop_and_close(h: u32) {
    READY.store(0, Ordering::SeqCst);
    let stopped = STOPPED.load(Ordering::SeqCst);
    // SAFETY: a valid handle.
    assert_eq!(unsafe { PNIO_device_stop(h) }, PNIO_OK, "{}", last_error());
    wait_until("PNIO_CBF_DEVICE_STOPPED", || {
        STOPPED.load(Ordering::SeqCst) > stopped
    });
    let mut dap = PNIO_DEV_ADDR::geo(PNIO_IO_IN, 0, 1);
    let mut one = PNIO_DEV_ADDR::geo(PNIO_IO_IN, 1, 1);
    // SAFETY: each call gets a valid handle and addresses that live for the call.
    unsafe {
        assert_eq!(PNIO_mod_pull(h, 0, &mut one), PNIO_OK);
        assert_eq!(PNIO_mod_pull(h, 0, &mut dap), PNIO_OK);
        assert_eq!(PNIO_api_remove(h, 0), PNIO_OK);
        assert_eq!(PNIO_device_close(h), PNIO_OK, "{}", last_error());
    }
}

#[test]
fn a_device_follows_the_cycle_with_startop_and_opdone() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let server = Launch::demo_device("deviso").start();
    name_cp(8, &server.instance);
    let h = open(8);
    HANDLE.store(h, Ordering::SeqCst);
    let wrong = h + 1000;
    // SAFETY: handles and callbacks of any value are checked; the callbacks live for the
    // whole program.
    unsafe {
        assert_eq!(
            PNIO_CP_register_cbf(wrong, PNIO_CP_CBE_OPFAULT_IND, Some(on_opfault)),
            PNIO_ERR_WRONG_HND
        );
        assert_eq!(
            PNIO_CP_register_cbf(h, PNIO_CP_CBE_OPFAULT_IND, None),
            PNIO_ERR_PRM_CALLBACK
        );
        assert_eq!(
            PNIO_CP_register_cbf(h, 9, Some(on_opfault)),
            PNIO_ERR_PRM_TYPE
        );
        assert_eq!(
            PNIO_CP_register_cbf(h, PNIO_CP_CBE_STARTOP_IND, Some(on_startop)),
            PNIO_ERR_OPFAULT_NOT_REG
        );
        assert_eq!(
            PNIO_CP_set_opdone(h, std::ptr::null_mut()),
            PNIO_ERR_STARTOP_NOT_REGISTERED
        );
        assert_eq!(
            PNIO_CP_set_opdone(wrong, std::ptr::null_mut()),
            PNIO_ERR_WRONG_HND
        );
        assert_eq!(
            PNIO_CP_register_cbf(h, PNIO_CP_CBE_OPFAULT_IND, Some(on_opfault)),
            PNIO_OK
        );
        assert_eq!(
            PNIO_CP_register_cbf(h, PNIO_CP_CBE_OPFAULT_IND, Some(on_opfault)),
            PNIO_ERR_ALLREADY_DONE
        );
        assert_eq!(
            PNIO_CP_register_cbf(h, PNIO_CP_CBE_NEWCYCLE_IND, Some(on_newcycle)),
            PNIO_OK,
            "{}",
            last_error()
        );
        // The STARTOP thread's lead comes from the environment: a value that is no number
        // fails the registration, which takes no effect; 0 sleeps until STARTOP. (Setting
        // it is sound: the tests of this file run one at a time, `SERIAL`, and the library
        // reads it only inside the registration, on this thread.)
        std::env::set_var("PROCIMG_WAKE_AHEAD_US", "soon");
        assert_eq!(
            PNIO_CP_register_cbf(h, PNIO_CP_CBE_STARTOP_IND, Some(on_startop)),
            PNIO_ERR_INVALID_CONFIG
        );
        assert!(
            last_error().contains("PROCIMG_WAKE_AHEAD_US=\"soon\""),
            "{}",
            last_error()
        );
        std::env::set_var("PROCIMG_WAKE_AHEAD_US", "0");
        assert_eq!(
            PNIO_CP_register_cbf(h, PNIO_CP_CBE_STARTOP_IND, Some(on_startop)),
            PNIO_OK,
            "{}",
            last_error()
        );
        std::env::remove_var("PROCIMG_WAKE_AHEAD_US");
        assert_eq!(
            PNIO_CP_register_cbf(h, PNIO_CP_CBE_STARTOP_IND, Some(on_startop)),
            PNIO_ERR_ALLREADY_DONE
        );
        assert_eq!(
            PNIO_CP_register_cbf(h, PNIO_CP_CBE_NEWCYCLE_IND, Some(on_newcycle)),
            PNIO_ERR_NEWCYCLE_SEQUENCE_REG
        );
    }
    // STARTOP comes from the registration on, before start and without an AR.
    wait_until("STARTOP_IND before start", || {
        OPDONE_OK.load(Ordering::SeqCst) >= 10
    });
    wait_until("NEWCYCLE_IND", || NEWCYCLES.load(Ordering::SeqCst) >= 10);
    plug_start_ready(h);
    // SAFETY: a valid handle and callback.
    let rc = unsafe { PNIO_CP_register_cbf(h, PNIO_CP_CBE_OPFAULT_IND, Some(on_opfault)) };
    assert_eq!(rc, PNIO_ERR_SEQUENCE, "registration after start");
    let writes = WRITES_OK.load(Ordering::SeqCst);
    let opdone = OPDONE_OK.load(Ordering::SeqCst);
    wait_until("100 cycles with I data written inside STARTOP", || {
        WRITES_OK.load(Ordering::SeqCst) >= writes + 100
    });
    wait_until(
        "the PLC's echo of the I data written inside STARTOP",
        || ECHOED.load(Ordering::SeqCst) > 0,
    );
    assert!(OPDONE_OK.load(Ordering::SeqCst) >= opdone + 100);
    assert_eq!(
        OPDONE_OTHER.load(Ordering::SeqCst),
        0,
        "PNIO_CP_set_opdone inside STARTOP_IND always answers PNIO_OK (late ones too)"
    );
    // Outside the window (between two STARTOPs, or in one whose OPDONE came) the call is
    // out of sequence, unless a window is open right now.
    // SAFETY: a valid handle.
    let rc = unsafe { PNIO_CP_set_opdone(h, std::ptr::null_mut()) };
    assert!(rc == PNIO_ERR_SEQUENCE || rc == PNIO_OK, "{rc:#x}");
    stop_and_close(h);
    let after = STARTOPS.load(Ordering::SeqCst);
    std::thread::sleep(Duration::from_millis(200));
    assert_eq!(
        STARTOPS.load(Ordering::SeqCst),
        after,
        "no STARTOP_IND after PNIO_device_close"
    );
    println!(
        "STARTOP {after}, OPDONE {} ok, OPFAULT {}, NEWCYCLE {}, echoed {}",
        OPDONE_OK.load(Ordering::SeqCst),
        OPFAULTS.load(Ordering::SeqCst),
        NEWCYCLES.load(Ordering::SeqCst),
        ECHOED.load(Ordering::SeqCst)
    );
}

#[test]
fn the_watchdog_stops_a_device_program_once() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let server = Launch::demo_device("devwd").start();
    const CP: u32 = 7;
    name_cp(CP, &server.instance);
    WATCHDOG_CALLS.store(0, Ordering::SeqCst);
    // SAFETY: every value is checked; the callback lives for the whole program.
    unsafe {
        assert_eq!(
            PNIO_CP_set_appl_watchdog(0, 50, Some(on_watchdog)),
            PNIO_ERR_PRM_CP_ID
        );
        assert_eq!(
            PNIO_CP_set_appl_watchdog(CP, 0, Some(on_watchdog)),
            PNIO_ERR_PRM_TIMEOUT
        );
        assert_eq!(
            PNIO_CP_set_appl_watchdog(CP, 50, None),
            PNIO_ERR_PRM_CALLBACK
        );
        assert_eq!(PNIO_CP_trigger_watchdog(CP), PNIO_ERR_SEQUENCE);
    }
    let h = open(CP);
    HANDLE.store(h, Ordering::SeqCst);
    plug_start_ready(h);
    // The program exchanges data from its own thread (an asynchronous device).
    let exchange = |n: u32| {
        for _ in 0..n {
            // SAFETY: a valid handle.
            unsafe {
                let _ = PNIO_initiate_data_write(h);
                let _ = PNIO_initiate_data_read(h);
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    };
    ECHOED.store(0, Ordering::SeqCst);
    let until = Instant::now() + WAIT;
    while ECHOED.load(Ordering::SeqCst) == 0 {
        assert!(Instant::now() < until, "the PLC did not echo the I data");
        exchange(10);
    }
    // SAFETY: every value is checked; the callback lives for the whole program.
    unsafe {
        assert_eq!(
            PNIO_CP_set_appl_watchdog(CP, 30, Some(on_watchdog)),
            PNIO_OK
        );
        assert_eq!(
            PNIO_CP_set_appl_watchdog(CP, 30, Some(on_watchdog)),
            PNIO_ERR_ALLREADY_DONE
        );
    }
    // Monitoring starts at the first trigger: nothing expires before it.
    exchange(100);
    assert_eq!(
        WATCHDOG_CALLS.load(Ordering::SeqCst),
        0,
        "expired before the first trigger"
    );
    // SAFETY: a valid CPIndex.
    assert_eq!(unsafe { PNIO_CP_trigger_watchdog(CP) }, PNIO_OK);
    expect_one_watchdog_call();
    assert_eq!(WATCHDOG_CP.load(Ordering::SeqCst), CP);
    // SAFETY: valid handles and values.
    unsafe {
        assert_eq!(PNIO_initiate_data_write(h), PNIO_ERR_NO_FW_COMMUNICATION);
        assert_eq!(PNIO_initiate_data_read(h), PNIO_ERR_NO_FW_COMMUNICATION);
        assert_eq!(PNIO_device_stop(h), PNIO_ERR_NO_FW_COMMUNICATION);
        assert_eq!(
            PNIO_CP_set_opdone(h, std::ptr::null_mut()),
            PNIO_ERR_NO_FW_COMMUNICATION
        );
        assert_eq!(PNIO_CP_trigger_watchdog(CP), PNIO_ERR_NO_FW_COMMUNICATION);
    }
    assert!(last_error().contains("watchdog"), "{}", last_error());
    // The PLC sees the I data with IOPS BAD: it takes it as zeros, so its Q data (the
    // station's input image, seen by another client) comes back as 01 .. 01.
    let mut observer = Client::attach(&server.instance, AttachOptions::asynchronous("wd-observer"))
        .expect("attach an observer");
    let slot1 = observer
        .layout()
        .submodules
        .iter()
        .position(|e| e.slot == 1 && e.subslot == 1)
        .expect("slot 1 in the layout");
    let until = Instant::now() + WAIT;
    loop {
        let q = observer
            .newest_input(slot1)
            .ok()
            .flatten()
            .map(<[u8]>::to_vec);
        if q.as_deref() == Some(&[1u8; 8][..]) {
            break;
        }
        assert!(
            Instant::now() < until,
            "the PLC did not take the I data as BAD after the expiry: Q {q:02x?}"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    drop(observer);
    // SAFETY: a valid handle: close is the one call left, also when started.
    assert_eq!(unsafe { PNIO_device_close(h) }, PNIO_OK, "{}", last_error());
    // SAFETY: as above.
    assert_eq!(unsafe { PNIO_device_close(h) }, PNIO_ERR_WRONG_HND);
    // Deregister, register again; a new open works.
    // SAFETY: every value is checked.
    unsafe {
        assert_eq!(PNIO_CP_set_appl_watchdog(CP, 0, None), PNIO_OK);
        assert_eq!(
            PNIO_CP_set_appl_watchdog(CP, 30, Some(on_watchdog)),
            PNIO_OK
        );
        assert_eq!(PNIO_CP_trigger_watchdog(CP), PNIO_OK);
        // Deregistered before it could expire: no callback.
        assert_eq!(PNIO_CP_set_appl_watchdog(CP, 0, None), PNIO_OK);
        assert_eq!(PNIO_CP_trigger_watchdog(CP), PNIO_ERR_SEQUENCE);
    }
    let calls = WATCHDOG_CALLS.load(Ordering::SeqCst);
    let h2 = open(CP);
    HANDLE.store(h2, Ordering::SeqCst);
    std::thread::sleep(Duration::from_millis(200));
    assert_eq!(
        WATCHDOG_CALLS.load(Ordering::SeqCst),
        calls,
        "deregistered: no expiry"
    );
    plug_start_ready(h2);
    // SAFETY: a valid handle.
    let rc = unsafe { PNIO_initiate_data_write(h2) };
    assert!(
        rc == PNIO_OK || rc == PNIO_WARN_NO_SUBMODULES,
        "{rc:#x}: {}",
        last_error()
    );
    stop_and_close(h2);
}

#[test]
fn the_watchdog_stops_a_controller_program_once() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let server = Launch::demo("ctlwd").start();
    const CP: u32 = 6;
    name_cp(CP, &server.instance);
    WATCHDOG_CALLS.store(0, Ordering::SeqCst);
    let h = open_controller_in_operate(CP, ignore, ignore);
    // SAFETY: every value is checked; the callback lives for the whole program.
    unsafe {
        assert_eq!(
            PNIO_CP_set_appl_watchdog(CP, 20, Some(on_watchdog)),
            PNIO_OK
        );
        assert_eq!(PNIO_CP_trigger_watchdog(CP), PNIO_OK);
    }
    expect_one_watchdog_call();
    // SAFETY: a valid handle.
    unsafe {
        assert_eq!(
            PNIO_set_mode(h, PNIO_MODE_OFFLINE),
            PNIO_ERR_NO_FW_COMMUNICATION
        );
        assert_eq!(PNIO_controller_close(h), PNIO_OK, "{}", last_error());
        assert_eq!(PNIO_controller_close(h), PNIO_ERR_WRONG_HND);
        assert_eq!(PNIO_CP_set_appl_watchdog(CP, 0, None), PNIO_OK);
    }
}
