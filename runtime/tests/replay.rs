// SPDX-License-Identifier: MIT OR Apache-2.0
//! The capture replay allocates nothing per frame: with procimgd's allocator installed and
//! this thread marked real-time, receiving and sending thousands of frames (every pacing,
//! repeating, with an output file) must not allocate once; a negative control proves the
//! count moves.

use pcap_file::pcap::{PcapPacket, PcapWriter};
use procimg_profinet::wire::MacAddress;
use procimg_runtime::phy::replay::{Pacing, Replay, ReplayOptions};
use procimg_runtime::phy::{MAX_FRAME, Nic};
use procimg_runtime::sys::rt_alloc::{
    RtAllocator, clear_current_thread_realtime, mark_current_thread_realtime, pool_allocations,
    rt_heap_allocations,
};
use std::path::Path;
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
    let mut buf = [0u8; MAX_FRAME];
    let mut got = 0;
    for _ in 0..rounds {
        if let Ok(Some(_)) = nic.recv(&mut buf) {
            got += 1;
        }
        let _ = nic.send(out);
    }
    got
}

#[test]
fn replaying_and_sending_allocate_nothing() {
    let file = capture();
    let dir = std::env::temp_dir().join(format!("procimg-replay-alloc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
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
                    output: Some(dir.join(format!("out-{i}.pcap"))),
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
    let _ = std::fs::remove_dir_all(&dir);
}
