// SPDX-License-Identifier: MIT OR Apache-2.0
//! Record jobs of a server that is killed and started again, against a real `procimgd
//! --demo`: the jobs it had taken but not answered are confirmed with IO-Base's "no
//! connection" status (0xC0, 0x80, 0xA3) as soon as the services thread learns that the
//! server is gone or that a new one started, not after the 60 s job timeout; a job sent to
//! the new server is answered by it.
//!
//! To hold jobs unanswered, the server is stopped (SIGSTOP) right after it took a burst of
//! reads; a burst it answered before the stop is simply tried again.

// The Rust half calls the C ABI and gives it callbacks.
#![allow(unsafe_code)]

use procimg::iobase::api::{PNIO_controller_close, PNIO_rec_read_req};
use procimg::iobase::errors::*;
use procimg::iobase::types::*;

mod iobase_kit;

use iobase_kit::{WAIT, ignore, last_error, name_cp, open_controller_in_operate, wait_until};
use procimg_testkit::Launch;
use procimg_testkit::signal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Reads per burst: the most a controller may have open.
const BURST: u32 = 16;

/// The REC_READ_CONFs seen: (ReqRef, Err).
static CONFIRMED: Mutex<Vec<(PNIO_REF, PNIO_ERR_STAT)>> = Mutex::new(Vec::new());

fn confirmed() -> Vec<(PNIO_REF, PNIO_ERR_STAT)> {
    CONFIRMED.lock().unwrap_or_else(|e| e.into_inner()).clone()
}

unsafe extern "C" fn on_read(prm: *mut PNIO_CBE_PRM) {
    // SAFETY: the library's parameters of a REC_READ_CONF, valid for the call.
    let c = unsafe { (*prm).u.RecReadConf };
    CONFIRMED
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push((c.ReqRef, c.Err));
}
/// The echo device's input submodule at logical address I 0.
fn echo_in() -> PNIO_ADDR {
    // SAFETY: PNIO_ADDR is made of integers: all zero is a valid value.
    let mut a: PNIO_ADDR = unsafe { std::mem::zeroed() };
    a.AddrType = PNIO_ADDR_LOG;
    a.IODataType = PNIO_IO_IN;
    a.u.Addr = 0;
    a
}

fn read(h: u32, req_ref: PNIO_REF) {
    let mut addr = echo_in();
    // SAFETY: a valid handle and address; I&M0 (0xAFF0) of at most 4096 bytes.
    let rc = unsafe { PNIO_rec_read_req(h, &mut addr, 0xAFF0, req_ref, 4096) };
    assert_eq!(rc, PNIO_OK, "PNIO_rec_read_req: {}", last_error());
}

fn no_connection(e: &PNIO_ERR_STAT) -> bool {
    (e.ErrCode, e.ErrDecode, e.ErrCode1) == (0xC0, 0x80, 0xA3)
}

#[test]
fn jobs_of_a_killed_and_restarted_server_fail_at_once() {
    let mut server = Launch::demo("svcrestart").start();
    const CP: u32 = 9;
    name_cp(CP, &server.instance);
    let h = open_controller_in_operate(CP, on_read, ignore);

    // A burst of reads, the server stopped right after it took them, until some are held.
    let mut held = Vec::new();
    for attempt in 0..30 {
        let base = 1000 * (attempt + 1);
        let refs: Vec<PNIO_REF> = (0..BURST).map(|i| base + i).collect();
        for &r in &refs {
            read(h, r);
        }
        signal::send(server.pid(), libc::SIGSTOP);
        // What the server published before the stop reaches the callback meanwhile.
        std::thread::sleep(Duration::from_millis(500));
        let done: Vec<PNIO_REF> = confirmed().iter().map(|c| c.0).collect();
        held = refs.into_iter().filter(|r| !done.contains(r)).collect();
        if !held.is_empty() {
            break;
        }
        signal::send(server.pid(), libc::SIGCONT);
    }
    assert!(
        !held.is_empty(),
        "the server answered every burst before it could be stopped"
    );

    // SIGKILL works on a stopped process; then a new server under the same name.
    server.kill();
    server.restart();
    wait_until("the confirmation of every held read", || {
        let c = confirmed();
        held.iter().all(|r| c.iter().any(|x| x.0 == *r))
    });
    for (r, e) in confirmed().iter().filter(|c| held.contains(&c.0)) {
        assert!(
            no_connection(e),
            "read {r} of the killed server: Err {:#04x} {:#04x} {:#04x} {:#04x}, not \
             \"no connection\"",
            e.ErrCode,
            e.ErrDecode,
            e.ErrCode1,
            e.ErrCode2
        );
    }
    let per_ref = |r: PNIO_REF| confirmed().iter().filter(|c| c.0 == r).count();
    for &r in &held {
        assert_eq!(per_ref(r), 1, "read {r} confirmed once");
    }

    // The new server answers a job of the same controller handle. Its subscription is
    // renewed by the services thread when it sees the new server; a read refused or failed
    // for lack of connection before that is tried again.
    let until = Instant::now() + WAIT;
    let mut req_ref = 900_000;
    loop {
        req_ref += 1;
        let mut addr = echo_in();
        // SAFETY: as in `read`.
        let rc = unsafe { PNIO_rec_read_req(h, &mut addr, 0xAFF0, req_ref, 4096) };
        if rc == PNIO_OK {
            wait_until("the new server's confirmation", || per_ref(req_ref) == 1);
            let c = confirmed();
            let e = &c.iter().find(|c| c.0 == req_ref).expect("confirmed").1;
            if e.ErrCode == 0 {
                break;
            }
            assert!(
                no_connection(e),
                "read of the new server: Err {:#04x} {:#04x} {:#04x} {:#04x}",
                e.ErrCode,
                e.ErrDecode,
                e.ErrCode1,
                e.ErrCode2
            );
        }
        assert!(
            Instant::now() < until,
            "the new server did not answer a read within {WAIT:?} (last call {rc:#x}: {})",
            last_error()
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    // SAFETY: a valid handle.
    assert_eq!(unsafe { PNIO_controller_close(h) }, PNIO_OK);
}
