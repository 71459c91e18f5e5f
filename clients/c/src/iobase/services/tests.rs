// SPDX-License-Identifier: MIT OR Apache-2.0
//! The worker against a real `procimgd --demo`, with `extern "C"` callbacks as a C program
//! registers them: what each callback receives, and the refusals at the call.

use super::*;
use crate::iobase::types::{
    PNIO_ALARM_DEV_FAILURE, PNIO_ALARM_DEV_RETURN, PNIO_CBE_DEV_ACT_CONF, PNIO_CBE_PRM,
    PNIO_CBE_REC_READ_CONF, PNIO_CBE_REC_WRITE_CONF, PNIO_CBE_TYPE, PNIO_CTRL_ALARM_DATA,
    PNIO_CTRL_DEV_DIAG_AR_IN_DATA, PNIO_CTRL_DEV_DIAG_AR_OFFLINE, PNIO_CTRL_DIAG_CONFIG_SUBMODULE,
    PNIO_CTRL_DIAG_DEVICE, PNIO_CTRL_DIAG_u, PNIO_DATA_IRT, PNIO_DATA_RT, PNIO_ERR_STAT,
    PNIO_IO_IN, PNIO_IO_OUT,
};
use procimg_client::{AttachOptions, Client};
use procimg_testkit::Procimgd;
use std::sync::atomic::AtomicU32;
use std::sync::mpsc;

const WAIT: Duration = Duration::from_secs(5);

/// What a callback saw, copied out of the callback's parameters.
#[derive(Clone, Debug, PartialEq)]
enum Seen {
    Read {
        req_ref: u32,
        index: u32,
        addr: (u32, u32),
        err: PNIO_ERR_STAT,
        data: Vec<u8>,
    },
    Write {
        req_ref: u32,
        index: u32,
        addr: (u32, u32),
        err: PNIO_ERR_STAT,
    },
    Alarm {
        addr: (u32, u32),
        alarm_type: u32,
        device: u16,
        slot: u16,
        usi: u16,
        data: Vec<u8>,
    },
    Activation {
        addr: (u32, u32),
        mode: u32,
        result: u32,
    },
    Diag {
        request: usize,
        code: u32,
        data: Vec<u8>,
    },
}

/// Every callback of every test's controller, by handle (tests run in parallel).
static SEEN: Mutex<Vec<(u32, Seen)>> = Mutex::new(Vec::new());
/// A handle whose REC_READ_CONF callback blocks until the test sends on `HOLD`.
static HOLDING: AtomicU32 = AtomicU32::new(u32::MAX);
static HOLD: Mutex<Option<mpsc::Receiver<()>>> = Mutex::new(None);
static NEXT_HANDLE: AtomicU32 = AtomicU32::new(1000);

/// The space and address of a `PNIO_ADDR`.
///
/// # Safety
/// `a` points to a live PNIO_ADDR.
unsafe fn addr_of(a: *const PNIO_ADDR) -> (u32, u32) {
    // SAFETY: see above.
    let a = unsafe { &*a };
    (a.IODataType, a.addr())
}

unsafe extern "C" fn callback(p: *mut PNIO_CBE_PRM) {
    // SAFETY: the library calls with a live PNIO_CBE_PRM whose union member is the one
    // CbeType names, and whose pointers are valid during the call.
    let (handle, seen) = unsafe {
        let p = &*p;
        let seen = match p.CbeType {
            PNIO_CBE_REC_READ_CONF => {
                let r = p.u.RecReadConf;
                if p.Handle == HOLDING.load(Ordering::Acquire) {
                    // Taken out first: the lock must not be held while the callback waits.
                    let hold = lock(&HOLD).take();
                    if let Some(rx) = hold {
                        let _ = rx.recv_timeout(WAIT);
                    }
                }
                Seen::Read {
                    req_ref: r.ReqRef,
                    index: r.RecordIndex,
                    addr: addr_of(r.pAddr),
                    err: r.Err,
                    data: std::slice::from_raw_parts(r.pBuffer, r.Length as usize).to_vec(),
                }
            }
            PNIO_CBE_REC_WRITE_CONF => {
                let w = p.u.RecWriteConf;
                Seen::Write {
                    req_ref: w.ReqRef,
                    index: w.RecordIndex,
                    addr: addr_of(w.pAddr),
                    err: w.Err,
                }
            }
            PNIO_CBE_ALARM_IND => {
                let a = p.u.AlarmInd;
                let d: &PNIO_CTRL_ALARM_DATA = &*a.pAlarmData;
                let n = d.AlarmAinfo.UserAlarmDataLen as usize;
                Seen::Alarm {
                    addr: addr_of(a.pAddr),
                    alarm_type: d.AlarmType,
                    device: d.DeviceNum,
                    slot: d.SlotNum,
                    usi: d.AlarmAinfo.UserStrucIdent,
                    data: d.AlarmAinfo.UAData.UserAlarmData[..n].to_vec(),
                }
            }
            PNIO_CBE_DEV_ACT_CONF => {
                let c = p.u.DevActConf;
                Seen::Activation {
                    addr: addr_of(c.pAddr),
                    mode: c.Mode,
                    result: c.Result,
                }
            }
            PNIO_CBE_CTRL_DIAG_CONF => {
                let c = p.u.CtrlDiagConf;
                Seen::Diag {
                    request: c.pDiagData as usize,
                    code: c.ErrorCode,
                    data: std::slice::from_raw_parts(
                        c.pDiagDataBuffer,
                        c.DiagDataBufferLen as usize,
                    )
                    .to_vec(),
                }
            }
            // Nothing else is registered; a panic here would abort (no unwinding out of C).
            _ => return,
        };
        (p.Handle, seen)
    };
    lock(&SEEN).push((handle, seen));
}

/// A worker for `server` with the callbacks of `types`.
fn worker(server: &Procimgd, types: &[PNIO_CBE_TYPE]) -> (u32, ServiceWorker) {
    let client = Client::attach(&server.instance, AttachOptions::asynchronous("svc-test"))
        .expect("attach for the layout");
    let callbacks = Arc::new(CallbackTable::new());
    for &t in types {
        assert!(callbacks.set_once(t, Some(callback)));
    }
    let handle = NEXT_HANDLE.fetch_add(1, Ordering::Relaxed);
    let w = ServiceWorker::start(ServiceContext {
        instance: server.instance.clone(),
        handle,
        cp_index: 1,
        layout: client.layout().clone(),
        callbacks,
        devices_up: Arc::new(DevicesUp::new(client.layout().devices.len())),
    })
    .expect("the services worker starts");
    (handle, w)
}

const ALL: &[PNIO_CBE_TYPE] = &[
    PNIO_CBE_REC_READ_CONF,
    PNIO_CBE_REC_WRITE_CONF,
    PNIO_CBE_ALARM_IND,
    PNIO_CBE_DEV_ACT_CONF,
    PNIO_CBE_CTRL_DIAG_CONF,
];

/// Waits for the first event of `handle` that `pick` takes, removing it.
fn wait_for<T>(handle: u32, what: &str, mut pick: impl FnMut(&Seen) -> Option<T>) -> T {
    let until = Instant::now() + WAIT;
    loop {
        {
            let mut seen = lock(&SEEN);
            if let Some(i) = seen
                .iter()
                .position(|(h, s)| *h == handle && pick(s).is_some())
            {
                let (_, s) = seen.remove(i);
                return pick(&s).expect("picked before");
            }
        }
        assert!(
            Instant::now() < until,
            "no {what} within {WAIT:?}; seen: {:?}",
            lock(&SEEN)
                .iter()
                .filter(|(h, _)| *h == handle)
                .collect::<Vec<_>>()
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

fn read_conf(handle: u32, req_ref: u32) -> (PNIO_ERR_STAT, Vec<u8>, (u32, u32), u32) {
    wait_for(handle, "REC_READ_CONF", |s| match s {
        Seen::Read {
            req_ref: r,
            err,
            data,
            addr,
            index,
        } if *r == req_ref => Some((*err, data.clone(), *addr, *index)),
        _ => None,
    })
}

fn write_conf(handle: u32, req_ref: u32) -> PNIO_ERR_STAT {
    wait_for(handle, "REC_WRITE_CONF", |s| match s {
        Seen::Write {
            req_ref: r, err, ..
        } if *r == req_ref => Some(*err),
        _ => None,
    })
}

fn diag(w: &ServiceWorker, handle: u32, service: u32, addr: PNIO_ADDR) -> (u32, Vec<u8>) {
    let mut req = Box::new(PNIO_CTRL_DIAG {
        DiagService: service,
        u: PNIO_CTRL_DIAG_u { Addr: addr },
        ReqRef: 99,
        Reserved2: 0,
    });
    let p: *mut PNIO_CTRL_DIAG = &mut *req;
    assert_eq!(w.ctrl_diag_req(p), PNIO_OK);
    wait_for(handle, "CTRL_DIAG_CONF", |s| match s {
        Seen::Diag {
            request,
            code,
            data,
        } if *request == p as usize => Some((*code, data.clone())),
        _ => None,
    })
}

fn device_state(w: &ServiceWorker, handle: u32, addr: PNIO_ADDR) -> PNIO_CTRL_DIAG_DEVICE {
    let (code, data) = diag(w, handle, PNIO_CTRL_DIAG_DEVICE_STATE, addr);
    assert_eq!(code, PNIO_OK);
    assert_eq!(data.len(), std::mem::size_of::<PNIO_CTRL_DIAG_DEVICE>());
    // SAFETY: the answer holds one PNIO_CTRL_DIAG_DEVICE, made of integers.
    unsafe { std::ptr::read_unaligned(data.as_ptr().cast()) }
}

fn subscriber_waiting(server: &Procimgd, name: &str) -> Option<u32> {
    let c = procimg_client::ControlHandle::open(&server.instance, "svc-test-status").ok()?;
    c.status()
        .ok()?
        .subscribers
        .into_iter()
        .find(|s| s.name == name)
        .map(|s| s.alarms_waiting)
}

#[test]
fn records_reach_the_callbacks_with_their_reference_and_status() {
    let server = Procimgd::demo("svc-records");
    let (h, w) = worker(&server, ALL);
    let echo_in = PNIO_ADDR::logical(PNIO_IO_IN, 0);

    // I&M0 of the echo device's module.
    assert_eq!(w.rec_read_req(&echo_in, 0xAFF0, 4711, 4096), PNIO_OK);
    let (err, data, addr, index) = read_conf(h, 4711);
    assert_eq!(err, PNIO_ERR_STAT::default());
    assert_eq!((addr, index), ((PNIO_IO_IN, 0), 0xAFF0));
    assert_eq!(data.len(), 60, "an I&M0 block");
    assert_eq!(data[6..8], [0x04, 0x93], "the demo's vendor id");
    assert!(data[8..28].starts_with(b"PROCIMG-SIM"));

    // A write, confirmed, then read back through the output address of the same module.
    assert_eq!(w.rec_write_req(&echo_in, 0x10, 1, &[1, 2, 3]), PNIO_OK);
    assert_eq!(write_conf(h, 1), PNIO_ERR_STAT::default());
    let echo_out = PNIO_ADDR::logical(PNIO_IO_OUT, 15);
    assert_eq!(w.rec_read_req(&echo_out, 0x10, 2, 16), PNIO_OK);
    let (err, data, addr, _) = read_conf(h, 2);
    assert_eq!(
        (err, data, addr),
        (PNIO_ERR_STAT::default(), vec![1, 2, 3], (PNIO_IO_OUT, 15))
    );

    // A record the device does not have: its PNIORW status.
    assert_eq!(w.rec_read_req(&echo_in, 0x1234, 3, 16), PNIO_OK);
    let (err, data, _, _) = read_conf(h, 3);
    assert_eq!((err.ErrCode, err.ErrDecode), (0xDE, 0x80));
    assert!(data.is_empty());

    // Refused at the call.
    let nowhere = PNIO_ADDR::logical(PNIO_IO_IN, 100);
    assert_eq!(w.rec_read_req(&nowhere, 0xAFF0, 4, 16), PNIO_ERR_PRM_ADD);
    assert_eq!(
        w.rec_read_req(&echo_in, 0x10000, 4, 16),
        PNIO_ERR_PRM_REC_INDEX
    );
    assert_eq!(w.rec_read_req(&echo_in, 0xAFF0, 4, 0), PNIO_ERR_VALUE_LEN);
    assert_eq!(
        w.rec_read_req(&echo_in, 0xAFF0, 4, 4097),
        PNIO_ERR_VALUE_LEN
    );
    assert_eq!(w.rec_write_req(&echo_in, 0x10, 4, &[]), PNIO_ERR_VALUE_LEN);
    assert_eq!(
        w.rec_write_req(&echo_in, 0x10, 4, &[0; 4097]),
        PNIO_ERR_VALUE_LEN
    );
    assert_eq!(w.rec_write_req(&nowhere, 0x10, 4, &[0]), PNIO_ERR_PRM_ADD);

    // 16 jobs may be open; the 17th is refused. The first confirmation's callback holds the
    // worker, so the other jobs stay open meanwhile.
    let (release, hold) = mpsc::channel();
    *lock(&HOLD) = Some(hold);
    HOLDING.store(h, Ordering::Release);
    assert_eq!(w.rec_read_req(&echo_in, 0xAFF0, 100, 8), PNIO_OK);
    let until = Instant::now() + WAIT;
    while lock(&HOLD).is_some() {
        assert!(Instant::now() < until, "the first confirmation never came");
        std::thread::sleep(Duration::from_millis(2));
    }
    for r in 101..=116 {
        assert_eq!(w.rec_read_req(&echo_in, 0xAFF0, r, 8), PNIO_OK, "job {r}");
    }
    assert_eq!(
        w.rec_read_req(&echo_in, 0xAFF0, 117, 8),
        PNIO_ERR_NO_RESOURCE
    );
    release.send(()).expect("release the callback");
    for r in 100..=116 {
        let (err, data, _, _) = read_conf(h, r);
        assert_eq!((err, data.len()), (PNIO_ERR_STAT::default(), 8), "job {r}");
    }
    HOLDING.store(u32::MAX, Ordering::Release);
    w.stop();
}

#[test]
fn alarms_activation_and_diagnosis_reach_the_callbacks() {
    let server = Procimgd::demo("svc-alarms");
    let (h, w) = worker(&server, ALL);
    let name = format!("PNIO controller {h} (CP 1)");
    let echo_in = PNIO_ADDR::logical(PNIO_IO_IN, 0);
    let dio_in = PNIO_ADDR::logical(PNIO_IO_IN, 20);

    // The simulated device raises a process alarm when this record is written.
    assert_eq!(w.rec_write_req(&echo_in, 0x7FF0, 5, &[0xab]), PNIO_OK);
    assert_eq!(write_conf(h, 5), PNIO_ERR_STAT::default());
    let alarm = wait_for(h, "process alarm", |s| match s {
        Seen::Alarm { alarm_type: 2, .. } => Some(s.clone()),
        _ => None,
    });
    assert_eq!(
        alarm,
        Seen::Alarm {
            addr: (PNIO_IO_IN, 0),
            alarm_type: 2,
            device: 1,
            slot: 1,
            usi: 1,
            data: vec![0xab],
        }
    );
    // Acknowledged when the callback returned: nothing waits for this controller.
    assert_eq!(subscriber_waiting(&server, &name), Some(0));

    // Deactivation: confirmed, and a station failure; activation: a station return.
    assert_eq!(w.device_activate(&dio_in, PNIO_DA_FALSE), PNIO_OK);
    let conf = wait_for(h, "DEV_ACT_CONF", |s| match s {
        Seen::Activation { .. } => Some(s.clone()),
        _ => None,
    });
    assert_eq!(
        conf,
        Seen::Activation {
            addr: (PNIO_IO_IN, 20),
            mode: PNIO_DA_FALSE,
            result: PNIO_OK
        }
    );
    let failure = wait_for(h, "DEV_FAILURE", |s| match s {
        Seen::Alarm {
            alarm_type: PNIO_ALARM_DEV_FAILURE,
            addr,
            device,
            ..
        } => Some((*addr, *device)),
        _ => None,
    });
    // Named by the device's DAP, diagnostic address I 24.
    assert_eq!(failure, ((PNIO_IO_IN, 24), 3));
    let s = device_state(&w, h, dio_in);
    assert_eq!(
        (s.Mode, s.DiagState & PNIO_CTRL_DEV_DIAG_AR_OFFLINE),
        (PNIO_DA_FALSE, PNIO_CTRL_DEV_DIAG_AR_OFFLINE)
    );

    assert_eq!(
        w.device_activate(&PNIO_ADDR::logical(PNIO_IO_OUT, 16), PNIO_DA_TRUE),
        PNIO_OK
    );
    let conf = wait_for(h, "DEV_ACT_CONF", |s| match s {
        Seen::Activation { mode, result, .. } => Some((*mode, *result)),
        _ => None,
    });
    assert_eq!(conf, (PNIO_DA_TRUE, PNIO_OK));
    let ret = wait_for(h, "DEV_RETURN", |s| match s {
        Seen::Alarm {
            alarm_type: PNIO_ALARM_DEV_RETURN,
            addr,
            ..
        } => Some(*addr),
        _ => None,
    });
    assert_eq!(ret, (PNIO_IO_IN, 24));
    let s = device_state(&w, h, dio_in);
    assert_eq!(
        (s.Mode, s.DiagState & PNIO_CTRL_DEV_DIAG_AR_IN_DATA),
        (PNIO_DA_TRUE, PNIO_CTRL_DEV_DIAG_AR_IN_DATA)
    );
    assert_eq!(w.device_activate(&dio_in, 7), PNIO_ERR_PRM_DEV_STATE);
    assert_eq!(
        w.device_activate(&PNIO_ADDR::logical(PNIO_IO_OUT, 99), PNIO_DA_TRUE),
        PNIO_ERR_PRM_ADD
    );

    // The configured submodules, as the demo has them.
    let (code, data) = diag(&w, h, PNIO_CTRL_DIAG_CONFIG_SUBMODULE_LIST, echo_in);
    assert_eq!(code, PNIO_OK);
    let size = std::mem::size_of::<PNIO_CTRL_DIAG_CONFIG_SUBMODULE>();
    assert_eq!(data.len() % size, 0);
    let list: Vec<(u32, u32, u32, u32, u32)> = data
        .chunks(size)
        .map(|c| {
            // SAFETY: each chunk is one PNIO_CTRL_DIAG_CONFIG_SUBMODULE, made of integers.
            let e: PNIO_CTRL_DIAG_CONFIG_SUBMODULE =
                unsafe { std::ptr::read_unaligned(c.as_ptr().cast()) };
            // The echo's data (I/Q 0, 16 bytes) is IRT in the demo, the rest RT.
            let irt = e.Address.addr() == 0 && e.DataLength == 16;
            assert_eq!(
                (e.DataType, e.CycleTime, e.ReductionFactor),
                (if irt { PNIO_DATA_IRT } else { PNIO_DATA_RT }, 32, 1)
            );
            (
                e.Address.IODataType,
                e.Address.addr(),
                e.DataLength,
                e.StatNo,
                e.Slot,
            )
        })
        .collect();
    assert_eq!(
        list,
        [
            (PNIO_IO_IN, 22, 0, 1, 0),
            (PNIO_IO_IN, 0, 16, 1, 1),
            (PNIO_IO_OUT, 0, 16, 1, 1),
            (PNIO_IO_IN, 23, 0, 2, 0),
            (PNIO_IO_IN, 16, 4, 2, 1),
            (PNIO_IO_IN, 24, 0, 3, 0),
            (PNIO_IO_IN, 20, 2, 3, 1),
            (PNIO_IO_OUT, 16, 2, 3, 2),
        ]
    );

    // Refused at the call: an unknown device, a service that is none of ctrl_diag_req's.
    let mut req = PNIO_CTRL_DIAG {
        DiagService: PNIO_CTRL_DIAG_DEVICE_STATE,
        u: PNIO_CTRL_DIAG_u {
            Addr: PNIO_ADDR::logical(PNIO_IO_IN, 300),
        },
        ReqRef: 0,
        Reserved2: 0,
    };
    assert_eq!(w.ctrl_diag_req(&mut req), PNIO_ERR_PRM_ADD);
    req.DiagService = 9;
    assert_eq!(w.ctrl_diag_req(&mut req), PNIO_ERR_PRM_INVALIDARG);
    w.stop();
    assert_eq!(
        subscriber_waiting(&server, &name),
        None,
        "unsubscribed at stop"
    );
}

#[test]
fn without_the_diag_callback_the_request_is_refused_and_stop_survives_the_server() {
    let server = Procimgd::demo("svc-gone");
    let (_, w) = worker(&server, &[PNIO_CBE_REC_READ_CONF, PNIO_CBE_REC_WRITE_CONF]);
    let mut req = PNIO_CTRL_DIAG {
        DiagService: PNIO_CTRL_DIAG_CONFIG_SUBMODULE_LIST,
        u: PNIO_CTRL_DIAG_u { Reserved1: [0; 8] },
        ReqRef: 0,
        Reserved2: 0,
    };
    assert_eq!(w.ctrl_diag_req(&mut req), PNIO_ERR_SEQUENCE);
    drop(server);
    let echo_in = PNIO_ADDR::logical(PNIO_IO_IN, 0);
    assert_eq!(
        w.rec_read_req(&echo_in, 0xAFF0, 1, 16),
        PNIO_ERR_NO_FW_COMMUNICATION
    );
    let t = Instant::now();
    w.stop();
    assert!(
        t.elapsed() < Duration::from_secs(3),
        "stop took {:?}",
        t.elapsed()
    );
}
