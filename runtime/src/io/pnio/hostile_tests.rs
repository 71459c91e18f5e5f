// SPDX-License-Identifier: MIT OR Apache-2.0
//! Malformed and hostile frames at the cycle thread: each is counted and dropped, the AR's
//! data and watchdog are not disturbed.

use super::test_rig::{CONTROLLER, DEVICE, Rig, at};
use crate::io::IoSystem;
use procimg_nic::Nic;
use procimg_profinet::wire::MacAddress;
use procimg_shm_layout::{IOXS_GOOD, Mode};
use std::sync::atomic::Ordering;

const STRANGER: MacAddress = MacAddress([2, 0, 0, 0, 0, 66]);

fn cyclic(src: MacAddress, frame_id: u16, sdu: &[u8], counter: u16) -> Vec<u8> {
    let mut f = Vec::new();
    f.extend_from_slice(&CONTROLLER.0);
    f.extend_from_slice(&src.0);
    f.extend_from_slice(&[0x88, 0x92]);
    f.extend_from_slice(&frame_id.to_be_bytes());
    f.extend_from_slice(sdu);
    f.extend_from_slice(&counter.to_be_bytes());
    f.extend_from_slice(&[0x35, 0x00]);
    f
}

#[test]
fn hostile_frames_are_counted_and_dropped_without_breaking_the_ar() {
    let Rig {
        mut io,
        channel,
        mut wire,
        mut image,
        ar,
    } = Rig::one_device(3);
    let input_id = ar.input.frame_id;
    let t = at;
    // A good frame: data 1 2 3 4, IOPS GOOD.
    let mut sdu = [0u8; 40];
    sdu[..5].copy_from_slice(&[1, 2, 3, 4, 0x80]);
    wire.send(&cyclic(DEVICE, input_id, &sdu, 32)).unwrap();
    io.receive(t(1), Mode::Operate, &mut image);
    assert_eq!(image.inputs(0), &[1, 2, 3, 4]);

    // Hostile: truncated, unknown FrameID, a stranger using the AR's FrameID, a repeat of an
    // old CycleCounter, not PROFINET at all, a runt of 10 bytes.
    let mut evil = [0u8; 40];
    evil[..5].copy_from_slice(&[6, 6, 6, 6, 0x80]);
    let good_len = cyclic(DEVICE, input_id, &sdu, 64).len();
    wire.send(&cyclic(DEVICE, input_id, &evil, 64)[..good_len - 10])
        .unwrap();
    wire.send(&cyclic(DEVICE, 0x8123, &evil, 64)).unwrap();
    wire.send(&cyclic(STRANGER, input_id, &evil, 64)).unwrap();
    wire.send(&cyclic(DEVICE, input_id, &evil, 32)).unwrap();
    let mut ip = cyclic(DEVICE, input_id, &evil, 64);
    ip[12..14].copy_from_slice(&[0x08, 0x00]);
    wire.send(&ip).unwrap();
    wire.send(&[0xff; 10]).unwrap();
    io.receive(t(2), Mode::Operate, &mut image);

    let c = &channel.counters;
    assert_eq!(c.malformed.load(Ordering::Relaxed), 2, "truncated and runt");
    assert_eq!(
        c.unknown.load(Ordering::Relaxed),
        3,
        "FrameID, stranger, not PROFINET"
    );
    assert_eq!(c.stale.load(Ordering::Relaxed), 1, "old CycleCounter");
    assert_eq!(image.inputs(0), &[1, 2, 3, 4], "no hostile byte got in");
    assert_eq!(image.status(0).input_iops, IOXS_GOOD);

    // The AR lives on: the next good frame is taken, no watchdog fired.
    sdu[..4].copy_from_slice(&[5, 6, 7, 8]);
    wire.send(&cyclic(DEVICE, input_id, &sdu, 96)).unwrap();
    io.receive(t(3), Mode::Operate, &mut image);
    assert_eq!(image.inputs(0), &[5, 6, 7, 8]);
    assert_eq!(c.watchdog_expiries.load(Ordering::Relaxed), 0);
    assert_eq!(c.cyclic_frames.load(Ordering::Relaxed), 2);
}
