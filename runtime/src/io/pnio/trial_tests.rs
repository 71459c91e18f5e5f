// SPDX-License-Identifier: MIT OR Apache-2.0
//! The consumer trial ([`procimg_profinet::cyclic::trial`]) at the cycle thread: procimgd
//! (and the fuzz world, which runs this IO system) judges the frames as the protocol
//! crate's consumer does, takes only accepted data into the image, says BAD where the
//! provider said its data were invalid, and reports the watchdog when the rule says.

use super::PnioIo;
use super::channel::{Channel, FromCycle, ToCycle};
use crate::config;
use crate::image::{Image, Tables};
use crate::io::{CycleTime, IoSystem};
use procimg_nic::{Nic, sim_link};
use procimg_profinet::controller::cyclic::CyclicAr;
use procimg_profinet::cyclic::VerdictKind;
use procimg_profinet::cyclic::trial::TrialSetup;
use procimg_profinet::wire::MacAddress;
use procimg_shm_layout::{IOXS_BAD, Mode};
use std::sync::Arc;
use std::sync::atomic::Ordering;

const CONTROLLER: MacAddress = MacAddress([2, 0, 0, 0, 0, 1]);
const DEVICE: MacAddress = MacAddress([2, 0, 0, 0, 0, 2]);
const MS: u64 = 1_000_000;

#[test]
fn the_cycle_thread_judges_the_consumer_trial_as_the_consumer_does() {
    let config = config::parse(
        r#"
        [[device]]
        name = "io"
        vendor_id = 1
        device_id = 1
        watchdog_factor = 10
        [[device.submodule]]
        slot = 1
        subslot = 1
        module_ident = 1
        submodule_ident = 1
        input_length = 4
        "#,
        "trial.toml",
    )
    .unwrap();
    let tables = Tables::from_config(&config).unwrap();
    let mut image = Image::new(&tables);
    let plan = &crate::roles::controller::plan_devices(&config).unwrap()[0];
    let ar = CyclicAr::new(plan, 1, CONTROLLER, DEVICE, plan.frame_ids);
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
    let (ours, mut wire) = sim_link::link(CONTROLLER, DEVICE);
    let channel = Arc::new(Channel::new());
    let mut io = PnioIo::new(
        Box::new(ours),
        channel.clone(),
        std::iter::once(0..1).collect(),
        config.cycle_ns,
    );
    assert!(channel.to_cycle.push(ToCycle::Start(Box::new(ar))).is_ok());
    let t = |k: u64| CycleTime {
        cycle: k,
        now_ns: k * MS,
    };
    io.receive(t(0), Mode::Operate, &mut image);
    // Each frame in a cycle of its own, so that the image shows what each did (the
    // watchdog of 10 cycles outlasts them); the cycle's time is when the cycle thread took
    // it.
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
    let expires = last_accepted + ar_watchdog(&config);
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

fn ar_watchdog(config: &config::Config) -> u64 {
    let plan = &crate::roles::controller::plan_devices(config).unwrap()[0];
    CyclicAr::new(plan, 1, CONTROLLER, DEVICE, plan.frame_ids)
        .timing
        .watchdog_ns()
}
