// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO-Base device management and configuration functions against `procimgd
//! --demo-device`: `tests/c/iobase_device.c` built with strict warnings against
//! `pniousrd.h`, linked static and shared (with ASan and UBSan when `PROCIMG_C_SANITIZE=1`),
//! checks open's parameters, wrong handles, calls out of sequence, plug and pull with their
//! confirmations, start, the AR indications in the manual's order with
//! `PNIO_set_appl_state_ready`, ArNumber and SessionKey checks, `PNIO_device_ar_abort` and
//! the PLC's next AR, the IO data (`PNIO_initiate_data_write`/`_read` and `_ext`: I data
//! out with IOPS GOOD until the PLC's Q data comes back as I + 1, then with IOPS BAD until
//! the PLC takes it as zeros, the callbacks' lengths and addresses), stop (`AR_OFFLINE_IND` before `DEVICE_STOPPED`) and close; and the
//! functions called from Rust check what the PLC sees: the AR ends at open (OFFLINE), the
//! program's tree once it started (a position with other ident numbers pulled and plugged,
//! one it did not plug pulled), data exchange after `PNIO_set_appl_state_ready`, and the
//! AR's end at stop.

// The Rust half calls the C ABI and gives it callbacks.
#![allow(unsafe_code)]

mod iobase_kit;

use iobase_kit::{last_error, open_demo_device, quiet_table};
use procimg::iobase::device_api::*;
use procimg::iobase::device_types::*;
use procimg::iobase::errors::*;
use procimg::iobase::types::{PNIO_IO_IN, PNIO_IOXS};
use procimg_client::{ArState, Mode, Notification, ServiceOptions, Services, StatusReport};
use procimg_testkit::Launch;
use procimg_testkit::c::{
    Link, assert_success, compile, crate_dir, run, sanitize_from_env, scratch,
};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

const RUN_TIMEOUT: Duration = Duration::from_secs(90);
const WAIT: Duration = Duration::from_secs(20);

/// Held while this binary spawns a program or changes its environment: the two must not
/// meet.
static ENV: Mutex<()> = Mutex::new(());

#[test]
fn management_and_configuration_from_c() {
    for link in [Link::Static, Link::Shared] {
        let server = Launch::demo_device(&format!("devapi-c-{link:?}").to_lowercase())
            .debug_log()
            .start();
        let src = crate_dir().join("tests/c/iobase_device.c");
        let program = scratch("iobase_device").join(format!("{link:?}").to_lowercase());
        compile(&[src], &program, link, sanitize_from_env());
        let o = {
            let _env = ENV.lock().unwrap_or_else(|e| e.into_inner());
            run(&program, &[], &server.instance, RUN_TIMEOUT)
        };
        assert_success(&o, &format!("iobase_device ({link:?})"));
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(
            stdout.contains("all checks held"),
            "iobase_device ({link:?}) said:\n{stdout}"
        );
    }
}

// ---- The program's side, in Rust --------------------------------------------------------

static STOPPED: AtomicU32 = AtomicU32::new(0);
static STOPPED_CODE: AtomicU32 = AtomicU32::new(u32::MAX);
/// ArNumber << 16 | SessionKey of the last PRM_END_IND (0: none yet).
static PRM_END: AtomicU32 = AtomicU32::new(0);
/// ArNumber << 16 | SessionKey of the last AR_OFFLINE_IND, and whether it came before
/// DEVICE_STOPPED.
static OFFLINE: AtomicU32 = AtomicU32::new(0);
static OFFLINE_BEFORE_STOPPED: AtomicU32 = AtomicU32::new(0);

unsafe extern "C" fn data(_: u32, _: *mut PNIO_DEV_ADDR, _: u32, _: *mut u8, _: PNIO_IOXS) -> u32 {
    0
}
unsafe extern "C" fn ar_offline_ind(_: u32, ar: u16, sk: u16, _: PNIO_AR_REASON) {
    OFFLINE.store(u32::from(ar) << 16 | u32::from(sk), Ordering::SeqCst);
    if STOPPED.load(Ordering::SeqCst) == 0 {
        OFFLINE_BEFORE_STOPPED.store(1, Ordering::SeqCst);
    }
}
unsafe extern "C" fn prm_end_ind(_: u32, ar: u16, sk: u16, _: u32, _: u16, _: u16) {
    PRM_END.store(u32::from(ar) << 16 | u32::from(sk), Ordering::SeqCst);
}
unsafe extern "C" fn device_stopped(_: u32, code: u32) {
    STOPPED_CODE.store(code, Ordering::SeqCst);
    STOPPED.fetch_add(1, Ordering::SeqCst);
}

/// Every mandatory callback; no PULL_PLUG_CONF (plugs before start need none).
fn table() -> PNIO_CBF_FUNCTIONS {
    PNIO_CBF_FUNCTIONS {
        cbf_data_write: Some(data),
        cbf_data_read: Some(data),
        cbf_ar_offline_ind: Some(ar_offline_ind),
        cbf_prm_end_ind: Some(prm_end_ind),
        cbf_device_stopped: Some(device_stopped),
        ..quiet_table()
    }
}

fn ar_state(s: &StatusReport) -> Option<ArState> {
    s.station
        .as_ref()
        .and_then(|s| s.ar.as_ref())
        .map(|a| a.state)
}

fn wait_for(server: &procimg_testkit::Procimgd, what: &str, ok: impl Fn(&StatusReport) -> bool) {
    let until = Instant::now() + WAIT;
    loop {
        let s = server.status();
        if ok(&s) {
            return;
        }
        assert!(
            Instant::now() < until,
            "{what} did not happen within {WAIT:?}: AR {:?}, mode {:?}",
            ar_state(&s),
            s.mode
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// (slot, subslot, plugged, submodule ident) of every station_plug notification so far.
fn plugs(services: &mut Services, into: &mut Vec<(u16, u16, bool, u32)>) {
    while let Some(n) = services.try_next() {
        if let Notification::StationPlug {
            slot,
            subslot,
            plugged,
            submodule_ident,
            ..
        } = n
        {
            into.push((slot, subslot, plugged, submodule_ident));
        }
    }
}

#[test]
fn the_plc_sees_the_programs_tree_between_start_and_stop() {
    let server = Launch::demo_device("devapi-tree").start();
    assert_eq!(ar_state(&server.status()), Some(ArState::Data));
    {
        let _env = ENV.lock().unwrap_or_else(|e| e.into_inner());
        // SAFETY: this binary's other test spawns its programs and reads nothing of the
        // environment outside this lock; no other thread of this test touches it.
        unsafe { std::env::set_var("PROCIMG_CP9", &server.instance) };
    }
    let mut services = Services::open(&server.instance, ServiceOptions::new("devapi-tree"))
        .expect("the station's notifications");
    let h = open_demo_device(9, table());
    wait_for(&server, "the AR's end at open (OFFLINE)", |s| {
        s.mode == Mode::Offline && ar_state(s).is_none()
    });

    let mut dap = PNIO_DEV_ADDR::geo(PNIO_IO_IN, 0, 1);
    let mut one = PNIO_DEV_ADDR::geo(PNIO_IO_IN, 1, 1);
    // SAFETY: each call gets a valid handle or value and addresses that live for the call.
    unsafe {
        assert_eq!(PNIO_api_add(h, 0, 2, 0x8001), PNIO_OK);
        assert_eq!(PNIO_mod_plug(h, 0, &mut dap, 0x1), PNIO_OK);
        assert_eq!(
            PNIO_sub_plug_ext_IM(
                h,
                0,
                &mut dap,
                0x1,
                PNIO_ALARM_TYPE_PLUG,
                PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MOD_DEV
            ),
            PNIO_OK
        );
        assert_eq!(PNIO_mod_plug(h, 0, &mut one, 0x10), PNIO_OK);
        // Other ident numbers than the configuration's: pulled and plugged again.
        assert_eq!(PNIO_sub_plug(h, 0, &mut one, 0x2), PNIO_OK);
        assert_eq!(PNIO_device_start(h), PNIO_OK, "{}", last_error());
    }
    // The program says it is ready once the PLC's parameters came.
    let until = Instant::now() + WAIT;
    let prm_end = loop {
        let p = PRM_END.load(Ordering::SeqCst);
        if p != 0 {
            break p;
        }
        assert!(Instant::now() < until, "no PNIO_CBF_PRM_END_IND");
        std::thread::sleep(Duration::from_millis(10));
    };
    let (ar, sk) = ((prm_end >> 16) as u16, prm_end as u16);
    // SAFETY: a valid handle; the list may be NULL.
    unsafe {
        assert_eq!(
            PNIO_set_appl_state_ready(h, ar, sk.wrapping_add(1), std::ptr::null_mut()),
            PNIO_ERR_SESSION
        );
        assert_eq!(
            PNIO_set_appl_state_ready(h, ar, sk, std::ptr::null_mut()),
            PNIO_OK,
            "{}",
            last_error()
        );
    }
    wait_for(&server, "the PLC's AR in data exchange after start", |s| {
        s.mode == Mode::Operate && ar_state(s) == Some(ArState::Data)
    });
    let mut seen: Vec<(u16, u16, bool, u32)> = Vec::new();
    let until = Instant::now() + WAIT;
    while !seen.iter().any(|p| p.0 == 2) && Instant::now() < until {
        plugs(&mut services, &mut seen);
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(
        seen,
        vec![(1, 1, false, 0), (1, 1, true, 0x2), (2, 1, false, 0)],
        "slot 1 pulled and plugged with the program's ident numbers, slot 2 (not the \
         program's) pulled, the DAP taken as it is"
    );

    // SAFETY: a valid handle.
    assert_eq!(unsafe { PNIO_device_stop(h) }, PNIO_OK);
    let until = Instant::now() + WAIT;
    while STOPPED.load(Ordering::SeqCst) == 0 {
        assert!(Instant::now() < until, "no PNIO_CBF_DEVICE_STOPPED");
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_eq!(STOPPED_CODE.load(Ordering::SeqCst), PNIO_OK);
    assert_eq!(
        (
            OFFLINE.load(Ordering::SeqCst),
            OFFLINE_BEFORE_STOPPED.load(Ordering::SeqCst)
        ),
        (prm_end, 1),
        "AR_OFFLINE_IND for the AR, before DEVICE_STOPPED"
    );
    wait_for(&server, "the AR's end at stop (OFFLINE)", |s| {
        s.mode == Mode::Offline && ar_state(s).is_none()
    });
    // SAFETY: each call gets a valid handle and addresses that live for the call.
    unsafe {
        assert_eq!(PNIO_mod_pull(h, 0, &mut one), PNIO_OK);
        assert_eq!(PNIO_mod_pull(h, 0, &mut dap), PNIO_OK);
        assert_eq!(PNIO_api_remove(h, 0), PNIO_OK);
        assert_eq!(PNIO_device_close(h), PNIO_OK, "{}", last_error());
    }
}
