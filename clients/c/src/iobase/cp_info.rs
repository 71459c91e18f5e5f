// SPDX-License-Identifier: MIT OR Apache-2.0
//! The CP info interface of the manual's chapter 8 (`servusrx.h`): `SERV_CP_info_open`,
//! `_register_cbf`, `_close`, over a subscription to the services of the procimgd a CpIndex
//! names, with a thread that calls the program back, one event at a time, with no lock held:
//!
//! * `SERV_CP_INFO_STOP_REQ` when the procimgd is to restart;
//! * `SERV_CP_INFO_PDEV_DATA` for each alarm of the controller's port, and
//!   `SERV_CP_INFO_PDEV_INIT_DATA` once when PDEV_DATA is registered (the interface and its
//!   port: EXISTS, DISTURBED while the port's diagnosis record 0x800C is not empty);
//! * `SERV_CP_INFO_LED_STATE`: both LEDs when it is registered, then each change. BF is lit
//!   while a device of the IO system is neither in data exchange nor deactivated (in the
//!   device role: while the station has no AR in data exchange), SF while the controller's
//!   port has a diagnosis.

#![allow(non_snake_case)]

use super::callbacks::{in_callback, invoke_call};
use super::errors::*;
use super::pn_driver_types::*;
use super::services::build;
use super::sync::lock;
use super::types::{PNIO_APRIO_HIGH, PNIO_APRIO_LOW, PNIO_IO_IN, PNIO_UINT32};
use super::wake::Wake;
use crate::ffi::guard;
use procimg_client::{
    AlarmReport, ArState, DeviceState, Notification, ServiceOptions, Services, StatusReport,
};
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

/// The longest wait of the thread between looks at its stop flag and registrations.
const POLL: Duration = Duration::from_millis(100);

/// How long the thread waits for the port's diagnosis record.
const RECORD_WAIT: Duration = Duration::from_secs(5);

/// The callbacks, by `SERV_CP_INFO_TYPE` (1..=4).
type Callbacks = [SERV_CP_INFO_CBF; 5];

/// What the LEDs show, and what they are made of.
#[derive(Default)]
struct Leds {
    /// Per device: neither in data exchange nor deactivated.
    faulty_devices: Vec<bool>,
    /// The device role's station has no AR in data exchange.
    station_without_ar: bool,
    /// The controller's port has a diagnosis.
    port_diagnosis: bool,
    /// What was last delivered: BF, SF (`None`: nothing yet).
    shown: Option<(bool, bool)>,
}

impl Leds {
    fn now(&self) -> (bool, bool) {
        (
            self.station_without_ar || self.faulty_devices.iter().any(|f| *f),
            self.port_diagnosis,
        )
    }
}

/// Whether a device in `state` lights BF.
fn faulty(state: DeviceState) -> bool {
    !matches!(state, DeviceState::Running | DeviceState::Deactivated)
}

struct Shared {
    handle: u32,
    cp_index: u32,
    callbacks: Mutex<Callbacks>,
    /// The diagnostic addresses of the controller's interface and port (none in the device
    /// role).
    addresses: Option<(u32, u32)>,
    services: Mutex<Option<Services>>,
    leds: Mutex<Leds>,
    /// Registrations the thread has to answer: PDEV_INIT_DATA, the LEDs' first state.
    init_due: AtomicBool,
    leds_due: AtomicBool,
    stop: AtomicBool,
    wake: Wake,
}

/// One open info interface.
struct InfoHandle {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
}

impl InfoHandle {
    fn stop(mut self) {
        *lock(&self.shared.callbacks) = [None; 5];
        self.shared.stop.store(true, Ordering::Release);
        self.shared.wake.raise();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

static INFOS: Mutex<BTreeMap<u32, InfoHandle>> = Mutex::new(BTreeMap::new());

fn wrong_handle(f: &str, handle: u32) -> u32 {
    fail(
        f,
        PNIO_ERR_WRONG_HND,
        format_args!("handle {handle} is not an open info interface (SERV_CP_info_open)"),
    )
}

/// Opens the info interface of CP `CpIndex`.
///
/// # Safety
/// `Handle` is NULL or points to a writable `PNIO_UINT32`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn SERV_CP_info_open(
    CpIndex: PNIO_UINT32,
    Handle: *mut PNIO_UINT32,
    Reserved: PNIO_UINT32,
) -> PNIO_UINT32 {
    const F: &str = "SERV_CP_info_open";
    let _ = Reserved;
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        if Handle.is_null() {
            return fail(F, PNIO_ERR_PRM_HND, "Handle (the out pointer) is NULL");
        }
        let instance = match super::controller::cp_instance(F, CpIndex) {
            Ok(i) => i,
            Err(code) => return code,
        };
        let handle = super::handles::next();
        let opened = Services::open(
            &instance,
            ServiceOptions::new(&format!("SERV_CP_info {handle}")),
        )
        .map_err(|e| e.to_string())
        .and_then(|s| {
            s.control()
                .status()
                .map(|st| (s, st))
                .map_err(|e| e.to_string())
        });
        let (services, status) = match opened {
            Ok(o) => o,
            Err(e) => {
                return fail(
                    F,
                    PNIO_ERR_NO_FW_COMMUNICATION,
                    format_args!("no procimgd answers for instance \"{instance}\": {e}"),
                );
            }
        };
        let wake = match Wake::new() {
            Ok(w) => w,
            Err(e) => return fail(F, PNIO_ERR_NO_RESOURCE, format_args!("no eventfd ({e})")),
        };
        let shared = Arc::new(Shared {
            handle,
            cp_index: CpIndex,
            callbacks: Mutex::new([None; 5]),
            addresses: status
                .controller
                .as_ref()
                .map(|c| (c.interface_address, c.port_address)),
            services: Mutex::new(Some(services)),
            leds: Mutex::new(leds_of(&status)),
            init_due: AtomicBool::new(false),
            leds_due: AtomicBool::new(false),
            stop: AtomicBool::new(false),
            wake,
        });
        let for_thread = shared.clone();
        let thread = match std::thread::Builder::new()
            .name(format!("serv-cp-info-{handle}"))
            .spawn(move || run(&for_thread))
        {
            Ok(t) => t,
            Err(e) => {
                return fail(
                    F,
                    PNIO_ERR_NO_RESOURCE,
                    format_args!("cannot start the info thread: {e}"),
                );
            }
        };
        lock(&INFOS).insert(
            handle,
            InfoHandle {
                shared,
                thread: Some(thread),
            },
        );
        // SAFETY: not NULL, writable by the caller's contract.
        unsafe { Handle.write_unaligned(handle) };
        PNIO_OK
    })
}

/// The LEDs' inputs from a status report.
fn leds_of(s: &StatusReport) -> Leds {
    Leds {
        faulty_devices: s.devices.iter().map(|d| faulty(d.state)).collect(),
        station_without_ar: s
            .station
            .as_ref()
            .is_some_and(|st| st.ar.as_ref().is_none_or(|ar| ar.state != ArState::Data)),
        port_diagnosis: false,
        shown: None,
    }
}

/// Closes the info interface: no callback runs after it returns.
///
/// # Safety
/// None beyond the C ABI.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn SERV_CP_info_close(Handle: PNIO_UINT32) -> PNIO_UINT32 {
    const F: &str = "SERV_CP_info_close";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        match lock(&INFOS).remove(&Handle) {
            Some(h) => {
                h.stop();
                PNIO_OK
            }
            None => wrong_handle(F, Handle),
        }
    })
}

/// Registers (or with `Cbf` NULL deregisters) the callback of `InfoType`.
///
/// # Safety
/// `Cbf` is NULL or a function of the `SERV_CP_INFO_CBF` type that stays callable until it
/// is deregistered or the interface closed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn SERV_CP_info_register_cbf(
    Handle: PNIO_UINT32,
    InfoType: SERV_CP_INFO_TYPE,
    Cbf: SERV_CP_INFO_CBF,
    Reserved: PNIO_UINT32,
) -> PNIO_UINT32 {
    const F: &str = "SERV_CP_info_register_cbf";
    let _ = Reserved;
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        let infos = lock(&INFOS);
        let Some(h) = infos.get(&Handle) else {
            return wrong_handle(F, Handle);
        };
        if !(SERV_CP_INFO_STOP_REQ..=SERV_CP_INFO_LED_STATE).contains(&InfoType) {
            return fail(
                F,
                PNIO_ERR_PRM_TYPE,
                format_args!("InfoType {InfoType} is not 1..4"),
            );
        }
        let s = &h.shared;
        let mut cbfs = lock(&s.callbacks);
        let slot = &mut cbfs[InfoType as usize];
        if Cbf.is_some() && slot.is_some() {
            return fail(
                F,
                PNIO_ERR_ALREADY_DONE,
                format_args!("InfoType {InfoType} has a callback already"),
            );
        }
        *slot = Cbf;
        if Cbf.is_some() {
            match InfoType {
                // PDEV_INIT_DATA comes with PDEV_DATA, to the same callback unless it has
                // its own.
                SERV_CP_INFO_PDEV_DATA => {
                    let init = &mut cbfs[SERV_CP_INFO_PDEV_INIT_DATA as usize];
                    if init.is_none() {
                        *init = Cbf;
                    }
                    s.init_due.store(true, Ordering::Release);
                }
                SERV_CP_INFO_LED_STATE => s.leds_due.store(true, Ordering::Release),
                _ => {}
            }
            s.wake.raise();
        }
        PNIO_OK
    })
}

/// The thread's loop, until close.
fn run(s: &Shared) {
    let notify_fd = lock(&s.services).as_ref().map_or(-1, Services::notify_fd);
    while !s.stop.load(Ordering::Acquire) {
        if s.init_due.swap(false, Ordering::AcqRel) {
            init_data(s);
        }
        if s.leds_due.swap(false, Ordering::AcqRel) {
            lock(&s.leds).shown = None;
            leds_changed(s);
        }
        let batch: Vec<Notification> = lock(&s.services)
            .as_mut()
            .map(|sv| std::iter::from_fn(|| sv.try_next()).take(64).collect())
            .unwrap_or_default();
        let idle = batch.is_empty();
        for n in batch {
            if s.stop.load(Ordering::Acquire) {
                break;
            }
            handle(s, n);
        }
        if idle {
            procimg_shm_layout::os::wait_any_readable(
                [notify_fd, s.wake.fd()],
                POLL.as_nanos() as u64,
            );
            s.wake.clear();
        }
    }
    drop(lock(&s.services).take());
}

fn handle(s: &Shared, n: Notification) {
    match n {
        Notification::StopRequest { .. } => deliver(s, SERV_CP_INFO_STOP_REQ, |_| {}),
        Notification::InterfaceAlarm(a) => {
            lock(&s.leds).port_diagnosis = a.specifier & 0x2000 != 0;
            pdev_data(s, &a);
            leds_changed(s);
        }
        Notification::DeviceState { device, state, .. } => {
            {
                let mut leds = lock(&s.leds);
                let d = device as usize;
                if leds.faulty_devices.len() <= d {
                    leds.faulty_devices.resize(d + 1, false);
                }
                leds.faulty_devices[d] = faulty(state);
            }
            leds_changed(s);
        }
        Notification::StationAr { state, .. } => {
            lock(&s.leds).station_without_ar = state != ArState::Data;
            leds_changed(s);
        }
        Notification::StationArEnded { .. } => {
            lock(&s.leds).station_without_ar = true;
            leds_changed(s);
        }
        // A new server: its devices come up anew.
        Notification::ServerStarted { .. } => {
            let status = lock(&s.services)
                .as_ref()
                .and_then(|sv| sv.control().status().ok());
            if let Some(st) = status {
                let shown = lock(&s.leds).shown;
                *lock(&s.leds) = Leds {
                    shown,
                    ..leds_of(&st)
                };
                leds_changed(s);
            }
        }
        _ => {}
    }
}

/// Calls the callback of `info` with the parameters `fill` writes.
fn deliver(s: &Shared, info: SERV_CP_INFO_TYPE, fill: impl FnOnce(&mut SERV_CP_INFO_PRM)) {
    let Some(f) = lock(&s.callbacks)[info as usize] else {
        return;
    };
    let mut prm = SERV_CP_INFO_PRM {
        Version: 0,
        Handle: s.handle,
        CpIndex: s.cp_index,
        InfoType: info,
        u: SERV_CP_INFO_PRM_u {
            PdevInitData: SERV_CIB_PDEV_INIT_DATA::default(),
        },
    };
    fill(&mut prm);
    let p: *mut SERV_CP_INFO_PRM = &mut prm;
    // SAFETY: the program registered `f` for this event; `p` points to a live, initialised
    // SERV_CP_INFO_PRM for the duration of the call.
    invoke_call(|| unsafe { f(p) });
}

/// `SERV_CP_INFO_PDEV_DATA` for alarm `a` of the controller's port.
fn pdev_data(s: &Shared, a: &AlarmReport) {
    let (interface, port) = s.addresses.unwrap_or_default();
    let data = build::interface_alarm(a);
    let user = a.payload.get(2..).unwrap_or_default();
    let word = |i: usize| {
        user.get(i..i + 2)
            .map_or(0, |b| u16::from_be_bytes([b[0], b[1]]))
    };
    let ext_diag = a.usi() == Some(0x8002);
    let diagnostics = if ext_diag {
        SERV_CIB_PDEV_EXTCHNL_DIAG {
            Channel: word(0),
            Properties: word(2),
            ErrType: word(4),
            ExtErrType: word(6),
            // ExtChannelAddValue is one 32-bit word, high half first.
            ExtAdvAlHi: word(8),
            ExtAdvAlLo: word(10),
        }
    } else {
        SERV_CIB_PDEV_EXTCHNL_DIAG::default()
    };
    deliver(s, SERV_CP_INFO_PDEV_DATA, |p| {
        p.u.PdevData = SERV_CIB_PDEV_DATA {
            Version: 0,
            IODataType: PNIO_IO_IN,
            LogAddr: if a.subslot & 0x00ff == 0 {
                interface
            } else {
                port
            },
            Slot: u32::from(a.slot),
            Subslot: u32::from(a.subslot),
            AlarmType: u32::from(a.alarm_type),
            AlarmPriority: if a.high_priority {
                PNIO_APRIO_HIGH
            } else {
                PNIO_APRIO_LOW
            },
            AlarmSequence: u32::from(a.specifier & 0x07ff),
            StationNr: 0,
            Reserved1: [0; 4],
            Reserved2: [0; 48],
            AlarmTinfo: data.AlarmTinfo,
            Diagnostics: diagnostics,
            DiagDs: [0; 4],
            AlarmAinfo: data.AlarmAinfo,
        };
    });
}

/// `SERV_CP_INFO_PDEV_INIT_DATA`: the interface and its port, as they are now.
fn init_data(s: &Shared) {
    let Some((interface, port)) = s.addresses else {
        // The device role's ports are the PLC's to watch: none here.
        deliver(s, SERV_CP_INFO_PDEV_INIT_DATA, |_| {});
        return;
    };
    let disturbed = lock(&s.services)
        .as_mut()
        .and_then(|sv| {
            sv.read_interface_record(0x8001, 0x800c, 4096, RECORD_WAIT)
                .ok()
        })
        .is_some_and(|d| !d.is_empty());
    lock(&s.leds).port_diagnosis = disturbed;
    let entry = |addr: u32, subslot: u32, extra: u16| SERV_CIB_PDEV_INIT_STATE {
        IODataType: PNIO_IO_IN,
        LogAddr: addr,
        Slot: 0,
        Subslot: subslot,
        PortState: SERV_CIB_PDEV_PORT_STATE_EXISTS | extra,
        ..SERV_CIB_PDEV_INIT_STATE::default()
    };
    let mut data = SERV_CIB_PDEV_INIT_DATA {
        ItemNumber: 2,
        ..SERV_CIB_PDEV_INIT_DATA::default()
    };
    data.InitState[0] = entry(interface, 0x8000, 0);
    data.InitState[1] = entry(
        port,
        0x8001,
        if disturbed {
            SERV_CIB_PDEV_PORT_STATE_DISTURBED
        } else {
            0
        },
    );
    deliver(s, SERV_CP_INFO_PDEV_INIT_DATA, |p| p.u.PdevInitData = data);
}

/// `SERV_CP_INFO_LED_STATE` for each LED that changed since last delivered.
fn leds_changed(s: &Shared) {
    let (now, before) = {
        let mut leds = lock(&s.leds);
        let now = leds.now();
        let before = leds.shown;
        if lock(&s.callbacks)[SERV_CP_INFO_LED_STATE as usize].is_some() {
            leds.shown = Some(now);
        }
        (now, before)
    };
    let state = |on: bool| {
        if on {
            SERV_CIB_LED_ON
        } else {
            SERV_CIB_LED_OFF
        }
    };
    for (led, on, was) in [
        (SERV_CIB_LED_BF, now.0, before.map(|b| b.0)),
        (SERV_CIB_LED_SF, now.1, before.map(|b| b.1)),
    ] {
        if was != Some(on) {
            deliver(s, SERV_CP_INFO_LED_STATE, |p| {
                p.u.LedInfo = SERV_CIB_LED {
                    LedType: led,
                    LedState: state(on),
                    Reserved1: [0; 4],
                }
            });
        }
    }
}
