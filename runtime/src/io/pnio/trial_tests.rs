// SPDX-License-Identifier: MIT OR Apache-2.0
//! The consumer trial ([`procimg_profinet::cyclic::trial`]) at the cycle thread: procimgd
//! (and the fuzz world, which runs this IO system) judges the frames as the protocol
//! crate's consumer does, takes only accepted data into the image, says BAD where the
//! provider said its data were invalid, and reports the watchdog when the rule says.

use super::channel::FromCycle;
use super::test_rig::{CONTROLLER, DEVICE, MS, Rig, at};
use crate::io::IoSystem;
use procimg_nic::Nic;
use procimg_profinet::cyclic::VerdictKind;
use procimg_profinet::cyclic::trial::TrialSetup;
use procimg_shm_layout::{IOXS_BAD, Mode};
use std::sync::atomic::Ordering;

#[test]
fn the_cycle_thread_judges_the_consumer_trial_as_the_consumer_does() {
    // A watchdog of 10 cycles outlasts the trial's frames, one per cycle below.
    let Rig {
        mut io,
        channel,
        mut wire,
        mut image,
        ar,
    } = Rig::one_device(10);
    let input = ar.input.clone();
    let trial = TrialSetup {
        peer: DEVICE,
        own: CONTROLLER,
        frame_id: input.frame_id,
        data_length: input.data_length,
        timing: ar.timing,
        first_at_ns: MS,
        first_counter: 0x4000,
    }
    .trial();
    let t = at;
    io.receive(t(0), Mode::Operate, &mut image);
    // Each frame in a cycle of its own, so that the image shows what each did; the cycle's
    // time is when the cycle thread took it.
    let mut last_accepted = 0;
    let data = &input.objects[0];
    for (k, f) in (1..).zip(&trial.frames) {
        wire.send(&f.frame).unwrap();
        io.receive(t(k), Mode::Operate, &mut image);
        let status = image.status(data.submodule);
        match f.verdict {
            VerdictKind::Accepted => {
                last_accepted = k * MS;
                let byte = f.frame[f.frame.len() - 5];
                assert_eq!(image.inputs(data.submodule), &[byte; 4]);
                assert_eq!(status.input_iops, byte, "the frame's IOPS");
            }
            VerdictKind::Invalid => {
                assert_eq!(status.input_iops, IOXS_BAD, "the provider said invalid")
            }
            _ => {}
        }
    }
    let c = &channel.counters;
    let n = |a: &std::sync::atomic::AtomicU64| a.load(Ordering::Relaxed);
    let counts = trial.counts;
    assert_eq!(
        (
            n(&c.cyclic_frames),
            n(&c.stale),
            n(&c.unknown),
            n(&c.malformed)
        ),
        (
            counts.accepted + counts.invalid,
            counts.stale,
            counts.foreign,
            counts.too_short
        ),
        "the IO system's counters are the verdicts"
    );
    let mut reports = Vec::new();
    while let Some(r) = channel.from_cycle.pop() {
        reports.push(r);
    }
    assert_eq!(
        reports
            .iter()
            .filter(|r| matches!(r, FromCycle::DataStarted { .. }))
            .count(),
        1,
        "data started once"
    );
    // Silence: the watchdog runs out its time after the last accepted frame, not before.
    let expires = last_accepted + ar.timing.watchdog_ns();
    let mut k = trial.frames.len() as u64 + 1;
    while k * MS < expires {
        io.receive(t(k), Mode::Operate, &mut image);
        assert!(
            !std::iter::from_fn(|| channel.from_cycle.pop())
                .any(|r| matches!(r, FromCycle::WatchdogExpired { .. })),
            "expired at {k} ms, before {expires} ns"
        );
        k += 1;
    }
    io.receive(t(k), Mode::Operate, &mut image);
    assert!(
        std::iter::from_fn(|| channel.from_cycle.pop())
            .any(|r| matches!(r, FromCycle::WatchdogExpired { .. })),
        "the watchdog ran out at {k} ms"
    );
    assert_eq!(n(&c.watchdog_expiries), 1);
}
