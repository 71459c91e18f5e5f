// SPDX-License-Identifier: MIT OR Apache-2.0
//! IO-Base semantics through a real server: the manual's PNIO_data_read and PNIO_data_write
//! example tables on an IO system laid out as in the manual, and the late-client policies.

use procimg_client::{AccessError, AttachOptions, Client, IoError, Ioxs};
use procimg_testkit::Procimgd;
use std::time::{Duration, Instant};

/// The manual's example modules: inputs 2 bytes at I 0..1 and 4 bytes at I 2..5; outputs
/// 2 bytes at Q 0..1, 4 bytes at Q 2..5 and 4 bytes at Q 10..13.
const MANUAL_LAYOUT: &str = include_str!("fixtures/iobase_manual_layout.toml");

fn attach(server: &Procimgd, slice: bool) -> Client {
    let mut c = Client::attach(
        &server.instance,
        AttachOptions::asynchronous("tables").slice_access(slice),
    )
    .unwrap();
    let outputs: Vec<usize> = c.layout().output_submodules().collect();
    c.claim(&outputs).unwrap();
    let until = Instant::now() + Duration::from_secs(20);
    while c.cycle_info().is_none() {
        let _ = c.wait_startop(Duration::from_millis(20));
        assert!(Instant::now() < until, "no image");
    }
    c
}

#[test]
fn manual_data_read_table() {
    let server = Procimgd::with_config("rdtable", MANUAL_LAYOUT);
    let mut c = attach(&server, true);
    // (I address, BufLen, *pDataLen) — every row returns PNIO_OK.
    for (addr, buf_len, data_len) in [
        (2, 8, 4),
        (2, 2, 4),
        (3, 2, 3),
        (5, 1, 1),
        (5, 8, 1),
        (1, 2, 1),
        (1, 1, 1),
    ] {
        let mut buf = vec![0u8; buf_len];
        let r = c
            .data_read(addr, &mut buf, Ioxs::Good)
            .unwrap_or_else(|e| panic!("I {addr}: {e}"));
        assert_eq!(r.len, data_len, "I {addr} BufLen {buf_len}");
    }
    let mut buf = [0u8; 1];
    assert!(matches!(
        c.data_read(6, &mut buf, Ioxs::Good),
        Err(IoError::Access(AccessError::UnknownAddress {
            address: 6,
            ..
        }))
    ));
}

#[test]
fn manual_data_write_table() {
    let server = Procimgd::with_config("wrtable", MANUAL_LAYOUT);
    let mut c = attach(&server, true);
    for (addr, len, want) in [
        (2, 8, "VALUE_LEN"),
        (2, 2, "OK"),
        (1, 2, "VALUE_LEN"),
        (1, 1, "OK"),
        (3, 3, "OK"),
        (3, 1, "OK"),
        (3, 4, "VALUE_LEN"),
        (6, 4, "UNKNOWN_ADDR"),
        (10, 1, "OK"),
        (11, 1, "OK"),
        (9, 1, "UNKNOWN_ADDR"),
    ] {
        let got = match c.data_write(addr, &vec![0x11; len], Ioxs::Good) {
            Ok(_) => "OK",
            Err(IoError::Access(AccessError::ValueLength { .. })) => "VALUE_LEN",
            Err(IoError::Access(AccessError::UnknownAddress { .. })) => "UNKNOWN_ADDR",
            Err(e) => panic!("Q {addr} BufLen {len}: {e}"),
        };
        assert_eq!(got, want, "Q {addr} BufLen {len}");
        std::thread::sleep(Duration::from_millis(2));
    }
    // The ExtPar example: 2 bytes from Q 3 land in bytes 3..4 of the module at Q 2.
    c.data_write(2, &[1, 2, 3, 4], Ioxs::Good).unwrap();
    c.data_write(3, &[0xaa, 0xbb], Ioxs::Good).unwrap();
    let until = Instant::now() + Duration::from_secs(20);
    loop {
        let mut out = [0u8; 4];
        c.output_data_read(2, &mut out).unwrap();
        if out == [1, 0xaa, 0xbb, 4] {
            break;
        }
        assert!(Instant::now() < until, "outputs are {out:?}");
        std::thread::sleep(Duration::from_millis(2));
    }
}

#[test]
fn without_slice_access_writes_must_be_whole_submodules() {
    let server = Procimgd::with_config("noslice", MANUAL_LAYOUT);
    let mut c = attach(&server, false);
    assert!(c.data_write(2, &[0; 4], Ioxs::Good).is_ok());
    assert!(matches!(
        c.data_write(2, &[0; 2], Ioxs::Good),
        Err(IoError::Access(AccessError::ValueLength { allowed: 4, .. }))
    ));
    assert!(matches!(
        c.data_write(3, &[0; 3], Ioxs::Good),
        Err(IoError::Access(AccessError::ValueLength { .. }))
    ));
    let mut buf = [0u8; 4];
    assert!(c.data_read(3, &mut buf, Ioxs::Good).is_err());
    assert_eq!(c.data_read(2, &mut buf, Ioxs::Good).unwrap().len, 4);
}

/// With `late_client_policy = "iops-bad"` a late client's outputs go out BAD in the cycle it
/// missed; with the default they keep their last value and status.
#[test]
fn late_client_policies() {
    for (policy, expect) in [("iops-bad", Ioxs::Bad), ("hold-last-outputs", Ioxs::Good)] {
        let config = format!("late_client_policy = \"{policy}\"\n{MANUAL_LAYOUT}");
        let server = Procimgd::with_config("late", &config);
        let mut c = Client::attach(&server.instance, AttachOptions::synchronous("late")).unwrap();
        let _ = procimg_client::realtime::make_current_thread_realtime(60);
        let q = c.layout().find("manual", 4, 1).unwrap();
        c.claim(&[q]).unwrap();
        for _ in 0..20 {
            let mut cycle = c.wait_startop(Duration::from_secs(1)).unwrap();
            cycle.output_mut(q).unwrap().copy_from_slice(&[9, 9, 9, 9]);
            cycle.set_opdone().unwrap();
        }
        // Miss one deadline, then look at the image of the cycle after it. A loaded machine
        // may hold this thread back past that image too: then the attempt says nothing, and
        // the next one tries again.
        let mut seen = None;
        for _attempt in 0..20 {
            let mut cycle = c.wait_startop(Duration::from_secs(1)).unwrap();
            let late = cycle.number();
            // Past the 500 µs deadline, before the next cycle starts.
            let past_deadline = cycle.info().cycle_start_ns + 700_000;
            std::thread::sleep(Duration::from_nanos(
                past_deadline.saturating_sub(procimg_client::now_ns()),
            ));
            cycle.output_mut(q).unwrap().copy_from_slice(&[7, 7, 7, 7]);
            cycle.set_opdone().unwrap();
            // The image after the missed cycle shows how its outputs went out.
            let mut cycle = c.wait_startop(Duration::from_secs(1)).unwrap();
            if cycle.number() == late + 1 {
                let st = cycle.status(q).unwrap();
                seen = Some((st.output_local, cycle.outputs_sent(q).unwrap().to_vec()));
            }
            // Back to the held outputs, in time, before the next attempt.
            cycle.output_mut(q).unwrap().copy_from_slice(&[9, 9, 9, 9]);
            cycle.set_opdone().unwrap();
            if seen.is_some() {
                break;
            }
            for _ in 0..5 {
                let mut cycle = c.wait_startop(Duration::from_secs(1)).unwrap();
                cycle.output_mut(q).unwrap().copy_from_slice(&[9, 9, 9, 9]);
                cycle.set_opdone().unwrap();
            }
        }
        assert!(
            seen.is_some(),
            "policy {policy}: in 20 attempts this thread never saw the image after its late \
             cycle"
        );
        let (status, data) = seen.unwrap();
        assert_eq!(status, expect, "policy {policy}");
        assert_eq!(
            data,
            [9, 9, 9, 9],
            "policy {policy}: the late outputs must not be used"
        );
        assert!(server.status().opfaults >= 1);
    }
}

/// A late client that stays silent keeps its outputs BAD under "iops-bad" for as long as it is
/// silent, and gets them GOOD again with its next OPDONE in time.
#[test]
fn iops_bad_lasts_while_the_late_client_is_silent() {
    let config = format!("late_client_policy = \"iops-bad\"\n{MANUAL_LAYOUT}");
    let server = Procimgd::with_config("silent", &config);
    let instance = server.instance.clone();
    let mut c = Client::attach(&instance, AttachOptions::synchronous("silent")).unwrap();
    let _ = procimg_client::realtime::make_current_thread_realtime(60);
    let q = c.layout().find("manual", 4, 1).unwrap();
    c.claim(&[q]).unwrap();
    let run = |c: &mut Client, n: usize| {
        for _ in 0..n {
            let mut cycle = c.wait_startop(Duration::from_secs(1)).unwrap();
            cycle.output_mut(q).unwrap().copy_from_slice(&[5, 5, 5, 5]);
            cycle.set_opdone().unwrap();
        }
    };
    run(&mut c, 20);
    // Silent for 50 cycles: an observer sees the outputs go out BAD, and stay BAD.
    let mut observer = Client::attach(&instance, AttachOptions::asynchronous("observer")).unwrap();
    std::thread::sleep(Duration::from_millis(20));
    let mut buf = [0u8; 4];
    let mut bad = 0;
    for _ in 0..10 {
        std::thread::sleep(Duration::from_millis(3));
        if observer.output_data_read(2, &mut buf).unwrap().local == Ioxs::Bad {
            bad += 1;
        }
    }
    assert_eq!(bad, 10, "the outputs of a silent late client must stay BAD");
    assert_eq!(buf, [5, 5, 5, 5], "the data is held");
    // Back in time: GOOD again with an OPDONE in time. A synchronous client that stops calling
    // wait_startop is late again, and on a loaded machine one of its OPDONEs can miss the
    // deadline by itself, so the observer looks between the client's cycles until it sees GOOD.
    run(&mut c, 20);
    let until = Instant::now() + Duration::from_secs(20);
    loop {
        run(&mut c, 1);
        if observer.output_data_read(2, &mut buf).unwrap().local == Ioxs::Good {
            break;
        }
        assert!(
            Instant::now() < until,
            "the outputs never went GOOD again while the client answered in time"
        );
    }
    assert_eq!(buf, [5, 5, 5, 5]);
}

/// Outputs whose claim is released go out invalid until someone claims and writes them.
#[test]
fn released_outputs_go_out_invalid() {
    let server = Procimgd::with_config("release", MANUAL_LAYOUT);
    let mut c = attach(&server, true);
    c.data_write(10, &[1, 2, 3, 4], Ioxs::Good).unwrap();
    let wait_for = |c: &mut Client, want: Ioxs| {
        let until = Instant::now() + Duration::from_secs(20);
        let mut buf = [0u8; 4];
        while c.output_data_read(10, &mut buf).unwrap().local != want {
            assert!(
                Instant::now() < until,
                "output status never became {want:?}"
            );
            std::thread::sleep(Duration::from_millis(2));
        }
    };
    wait_for(&mut c, Ioxs::Good);
    let q = c.layout().find("manual", 5, 1).unwrap();
    c.release(&[q]).unwrap();
    wait_for(&mut c, Ioxs::Bad);
}
