// SPDX-License-Identifier: MIT OR Apache-2.0
//! The capture replay in procimgd: it allocates nothing per frame (with procimgd's allocator
//! installed and this thread marked real-time, receiving and sending thousands of frames,
//! every pacing, repeating, with an output file, must not allocate once; a negative control
//! proves the count moves), and a replayed cyclic frame lands in the image of the cycle
//! thread's PROFINET IO.

use pcap_file::pcap::{PcapPacket, PcapParser, PcapWriter};
use procimg_nic::replay::{Pacing, Replay, ReplayOptions};
use procimg_nic::{MAX_FRAME, Nic};
use procimg_profinet::controller::cyclic::CyclicAr;
use procimg_profinet::wire::MacAddress;
use procimg_runtime::config;
use procimg_runtime::image::{Image, Tables};
use procimg_runtime::io::pnio::PnioIo;
use procimg_runtime::io::pnio::channel::{Channel, FromCycle, ToCycle};
use procimg_runtime::io::{CycleTime, IoSystem};
use procimg_runtime::sys::rt_alloc::{
    RtAllocator, clear_current_thread_realtime, mark_current_thread_realtime, pool_allocations,
    rt_heap_allocations,
};
use procimg_shm_layout::{IOXS_BAD, IOXS_GOOD, Mode, SubmoduleStatus};
use procimg_testkit::files::{pcap, temp_dir};
use procimg_testkit::fixtures::profinet_capture;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

#[global_allocator]
static ALLOCATOR: RtAllocator = RtAllocator;

const OWN: MacAddress = MacAddress([0x02, 0, 0, 0, 0, 1]);
const DEVICE: MacAddress = MacAddress([0x02, 0, 0, 0, 0, 2]);

fn frame(src: MacAddress, ethertype: u16, n: u8) -> Vec<u8> {
    let mut f = vec![n; 60];
    f[..6].copy_from_slice(&OWN.0);
    f[6..12].copy_from_slice(&src.0);
    f[12..14].copy_from_slice(&ethertype.to_be_bytes());
    f
}

/// 200 records, 10 µs apart: device frames, ours, and IPv4.
fn capture() -> Vec<u8> {
    let mut w = PcapWriter::new(Vec::new()).unwrap();
    for i in 0..200u32 {
        let f = match i % 4 {
            0 => frame(OWN, 0x8892, i as u8),
            1 => frame(DEVICE, 0x0800, i as u8),
            _ => frame(DEVICE, 0x8892, i as u8),
        };
        let t = Duration::from_secs(1_787_840_000) + Duration::from_micros(10 * u64::from(i));
        w.write_packet(&PcapPacket::new(t, f.len() as u32, &f))
            .unwrap();
    }
    w.into_writer()
}

/// Runs `rounds` receive/send rounds on `nic`, sending `out`; returns the frames received.
fn exchange(nic: &mut dyn Nic, rounds: usize, out: &[u8]) -> usize {
    let mut got = 0;
    for _ in 0..rounds {
        let _ = nic.receive(&mut |frame| {
            assert!(frame.len() <= MAX_FRAME);
            got += 1;
        });
        let _ = nic.send(out);
    }
    got
}

#[test]
fn replaying_and_sending_allocate_nothing() {
    let file = capture();
    let dir = temp_dir("replay-alloc");
    let mut clock_ns = 0u64;
    let pacings = [
        Pacing::AsFastAsPolled,
        Pacing::Realtime,
        Pacing::Clock(Box::new(move || {
            clock_ns += 5_000;
            clock_ns
        })),
    ];
    let mut replays: Vec<Replay> = pacings
        .into_iter()
        .enumerate()
        .map(|(i, pacing)| {
            Replay::from_bytes(
                Path::new("alloc.pcap"),
                &file,
                ReplayOptions {
                    pacing,
                    repeat: Some(Duration::from_micros(10)),
                    // Fills up within the rounds: dropping must not allocate either.
                    sent_buffer: 64 * 1024,
                    output: Some(dir.path().join(format!("out-{i}.pcap"))),
                    ..ReplayOptions::new(OWN)
                },
            )
            .unwrap()
        })
        .collect();

    let out = frame(OWN, 0x8892, 0xaa);

    mark_current_thread_realtime();
    let (heap, pool) = (rt_heap_allocations(), pool_allocations());
    let mut received = [0usize; 3];
    for (r, got) in replays.iter_mut().zip(&mut received) {
        *got = exchange(r, 5_000, &out);
    }
    let after = (rt_heap_allocations(), pool_allocations());
    // Negative control: an allocation on this thread is counted.
    let control = std::hint::black_box(vec![0u8; 4096]);
    let counted = rt_heap_allocations() + pool_allocations() > after.0 + after.1;
    clear_current_thread_realtime();
    drop(control);

    assert_eq!(
        after,
        (heap, pool),
        "the replay allocated on the real-time thread"
    );
    assert!(counted, "the allocation counter does not count");
    // Half the records are device PROFINET frames; as fast as polled, every round has one.
    assert_eq!(received[0], 5_000);
    assert!(received[2] > 0);
    assert!(replays.iter().all(|r| r.sent_dropped() > 0));
    drop(replays);
}

/// The S7's port MAC: "ours" in the captures.
const S7: MacAddress = MacAddress([0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f]);
/// The p-net sample device.
const PNET_DEVICE: MacAddress = MacAddress([0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8]);
/// A capture's first timestamp: 2026-08-27, as the S7 captures.
const T0: u64 = 1_787_840_000 * 1_000_000_000;
const MS: u64 = 1_000_000;

/// The p-net sample device as the S7 configured it (its records do not change the frames
/// replayed here).
const PNET_SAMPLE: &str = include_str!("fixtures/pnet_sample.toml");

/// The cycle thread's PROFINET IO on a replay of the S7 capture, with the AR the S7's Connect
/// set up: the device's cyclic frame lands in the image when it is due, its alarm goes to the
/// controller, and the output frame the cycle sends equals the S7's (CycleCounter aside).
#[test]
fn a_replayed_cyclic_frame_lands_in_the_image() {
    let config = config::parse(PNET_SAMPLE, "pnet-sample.toml").unwrap();
    let plans = procimg_runtime::roles::controller::plan_devices(&config).unwrap();
    let ar = Box::new(CyclicAr::new(
        &plans[0],
        1,
        S7,
        PNET_DEVICE,
        (0x8000, 0x8001),
    ));
    let tables = Tables::from_config(&config).unwrap();
    let mut image = Image::new(&tables);
    // Outputs valid and consumed, as the cycle has them in OPERATE with clients attached.
    for s in 0..tables.submodules.len() {
        image.set_status(
            s,
            SubmoduleStatus {
                input_iops: IOXS_BAD,
                input_iocs: IOXS_GOOD,
                output_iops: IOXS_GOOD,
                output_iocs: IOXS_BAD,
            },
        );
    }

    let dir = temp_dir("replay-image");
    let out = dir.path().join("sent.pcap");
    let file = pcap(&[
        (T0, profinet_capture("rt/rtc_cpu_8001")),
        (T0 + MS / 2, profinet_capture("cm/connect_res")),
        (T0 + MS, profinet_capture("rt/rtc_dev_8000")),
        (T0 + 2 * MS, profinet_capture("alarm/alarm_process_notif")),
    ]);
    let clock = Arc::new(AtomicU64::new(0));
    let pacing = {
        let clock = clock.clone();
        Pacing::Clock(Box::new(move || clock.load(Ordering::Relaxed)))
    };
    let replay = Replay::from_bytes(
        Path::new("s7.pcap"),
        &file,
        ReplayOptions {
            pacing,
            output: Some(out.clone()),
            ..ReplayOptions::new(S7)
        },
    )
    .unwrap();
    let channel = Arc::new(Channel::new());
    let ranges = std::iter::once(0..tables.submodules.len()).collect();
    let mut io = PnioIo::new(Box::new(replay), channel.clone(), ranges, config.cycle_ns);
    assert!(channel.to_cycle.push(ToCycle::Start(ar)).is_ok());
    let t = |cycle| CycleTime {
        cycle,
        now_ns: cycle * MS,
    };
    let (di8, dio8) = (3, 5); // slots 1 and 3

    io.receive(t(0), Mode::Operate, &mut image);
    io.send(t(0), Mode::Operate, &mut image);
    assert_eq!(image.inputs(di8), &[0], "not due yet");
    assert_eq!(image.status(di8).input_iops, IOXS_BAD);

    clock.store(MS, Ordering::Relaxed);
    io.receive(t(1), Mode::Operate, &mut image);
    assert_eq!(image.inputs(di8), &[0x2c]);
    assert_eq!(image.inputs(dio8), &[0x2d]);
    assert_eq!(image.status(di8).input_iops, IOXS_GOOD);
    assert_eq!(image.status(dio8).output_iocs, IOXS_GOOD);
    assert!(channel.from_cycle.pop().is_some_and(|r| matches!(
        r,
        FromCycle::DataStarted {
            device: 0,
            epoch: 1
        }
    )));

    clock.store(2 * MS, Ordering::Relaxed);
    io.receive(t(2), Mode::Operate, &mut image);
    match channel.from_cycle.pop() {
        Some(FromCycle::Received(buf)) => {
            assert_eq!(
                buf.bytes(),
                &profinet_capture("alarm/alarm_process_notif")[..]
            )
        }
        _ => panic!("the alarm frame did not reach the controller"),
    }
    let counters = &channel.counters;
    assert_eq!(counters.cyclic_frames.load(Ordering::Relaxed), 1);
    assert_eq!(
        counters.unknown.load(Ordering::Relaxed),
        0,
        "ours and UDP are filtered"
    );
    drop(io);

    let sent = std::fs::read(&out).unwrap();
    let (rest, parser) = PcapParser::new(&sent).unwrap();
    let (_, p) = parser.next_packet(rest).unwrap();
    let expected = profinet_capture("rt/rtc_cpu_8001");
    let n = p.data.len();
    assert_eq!(n, expected.len());
    assert_eq!(&p.data[..n - 4], &expected[..n - 4], "cyclic output frame");
    assert_eq!(&p.data[n - 2..], &expected[n - 2..]);
    assert_eq!(p.timestamp, Duration::from_nanos(T0));
}
