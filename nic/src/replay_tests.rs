// SPDX-License-Identifier: MIT OR Apache-2.0
//! The capture replay: filtering and pacing against files built from the S7 captures,
//! pcapng details, sent frames, the error messages, and the parser against arbitrary bytes.
//! (The cyclic frame of a replay landing in procimgd's image is a test of the runtime.)

use super::*;
use crate::MAX_FRAME;
use crate::capture::CaptureWriter;
use pcap_file::pcapng::PcapNgWriter;
use pcap_file::pcapng::blocks::enhanced_packet::EnhancedPacketBlock;
use procimg_testkit::files::{pcap, temp_dir};
use procimg_testkit::fixtures::profinet_capture as capture;
use proptest::prelude::*;
use std::borrow::Cow;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// The S7's port MAC: "ours" in the captures.
const OWN: MacAddress = MacAddress([0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f]);
/// The p-net sample device.
const DEVICE: MacAddress = MacAddress([0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8]);
/// A capture's first timestamp: 2026-08-27, as the S7 captures.
const T0: u64 = 1_787_840_000 * NS_PER_SEC;
const MS: u64 = 1_000_000;

/// A clock the test moves, and a pacing that reads it.
fn manual_clock(start: u64) -> (Arc<AtomicU64>, Pacing) {
    let clock = Arc::new(AtomicU64::new(start));
    let c = clock.clone();
    (
        clock,
        Pacing::Clock(Box::new(move || c.load(Ordering::Relaxed))),
    )
}

fn options(pacing: Pacing) -> ReplayOptions {
    ReplayOptions {
        pacing,
        ..ReplayOptions::new(OWN)
    }
}

/// Every frame the replay hands over now.
fn drain(r: &mut Replay) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    while r.receive(&mut |f| out.push(f.to_vec())).unwrap() {}
    out
}

/// The next frame the replay hands over now, if any.
fn next(r: &mut Replay) -> Option<Vec<u8>> {
    let mut got = None;
    r.receive(&mut |f| got = Some(f.to_vec())).unwrap();
    got
}

/// A frame from `src` with the PROFINET EtherType (untagged) and `tag` as payload.
fn pn_frame(src: MacAddress, tag: u8) -> Vec<u8> {
    let mut f = vec![0u8; 60];
    f[..6].copy_from_slice(&OWN.0);
    f[6..12].copy_from_slice(&src.0);
    f[12..14].copy_from_slice(&ETHERTYPE_PROFINET.to_be_bytes());
    f[14..16].copy_from_slice(&[0x80, 0x00]);
    f[16] = tag;
    f
}

#[test]
fn the_filter_is_the_af_packet_one() {
    let mut tagged = vec![0u8; 60];
    tagged[12..14].copy_from_slice(&TPID_VLAN.to_be_bytes());
    tagged[16..18].copy_from_slice(&ETHERTYPE_PROFINET.to_be_bytes());
    assert!(is_profinet(&tagged));
    assert!(is_profinet(&pn_frame(DEVICE, 0)));
    assert!(!is_profinet(&capture("cm/connect_req")), "UDP");
    assert!(!is_profinet(&tagged[..17]), "too short for the inner type");
    tagged[16..18].copy_from_slice(&0x0800u16.to_be_bytes());
    assert!(!is_profinet(&tagged), "tagged IPv4");
    assert!(!is_profinet(&[]));
}

/// `procimg capture` writes with `CaptureWriter` (microsecond pcap): what it wrote replays as
/// it was captured, without our own frames.
#[test]
fn a_file_of_the_capture_writer_replays_its_frames() {
    let dir = temp_dir("replay-round-trip");
    let path = dir.path().join("capture.pcap");
    let mut w = CaptureWriter::create(&path).unwrap();
    let frames = [
        pn_frame(DEVICE, 1),
        pn_frame(OWN, 2),
        capture("cm/connect_res"),
        pn_frame(DEVICE, 3),
        capture("rt/rtc_dev_8000"),
    ];
    for (i, f) in frames.iter().enumerate() {
        w.write(
            Duration::from_micros(1_787_840_000_000_000 + i as u64 * 250),
            f,
        )
        .unwrap();
    }
    w.finish().unwrap();

    let mut r = Replay::open(&path, options(Pacing::AsFastAsPolled)).unwrap();
    assert_eq!(r.origin(), path);
    assert_eq!(
        r.stats(),
        ReplayStats {
            records: 5,
            profinet: 3,
            own: 1,
            other: 1,
            cut: 0,
            too_long: 0,
        }
    );
    assert_eq!(
        drain(&mut r),
        vec![frames[0].clone(), frames[3].clone(), frames[4].clone()]
    );
    assert!(r.is_finished());
}

/// A capture of a connection built from the S7 fixtures: DCP, RPC over UDP, cyclic and alarm
/// frames of both sides, 1 ms apart. The replay returns exactly the device's PROFINET
/// frames, in order, each at its time and not before.
#[test]
fn the_device_profinet_frames_of_a_capture_come_in_order_and_in_time() {
    // The S7 sends alarm frames from its interface MAC: put them on the port MAC like the
    // rest of what it sent, so that they count as ours.
    let ours = |name: &str| {
        let mut f = capture(name);
        f[6..12].copy_from_slice(&OWN.0);
        f
    };
    let records: Vec<(u64, Vec<u8>, bool)> = [
        (capture("cm/ident_ok_pnet"), true),
        (capture("cm/dcp_set_req"), false),
        (capture("cm/dcp_set_res"), true),
        (capture("cm/connect_req"), false),
        (capture("cm/connect_res"), false),
        (capture("cm/write_req"), false),
        (capture("cm/write_res"), false),
        (capture("cm/prmend_req"), false),
        (capture("cm/prmend_res"), false),
        (capture("cm/appready_req"), false),
        (capture("cm/appready_res"), false),
        (capture("rt/rtc_cpu_8001"), false),
        (capture("rt/rtc_dev_8000"), true),
        (capture("alarm/alarm_process_notif"), true),
        (ours("alarm/alarm_ack_rta_high_cpu"), false),
        (ours("alarm/alarm_ack_high_cpu"), false),
        (capture("alarm/alarm_ack_rta_high_dev"), true),
        (capture("alarm/im0_read_res"), false),
    ]
    .into_iter()
    .enumerate()
    .map(|(i, (f, device))| (T0 + i as u64 * MS, f, device))
    .collect();
    let file = pcap(
        &records
            .iter()
            .map(|(t, f, _)| (*t, f.clone()))
            .collect::<Vec<_>>(),
    );
    let expected: Vec<(u64, Vec<u8>)> = records
        .iter()
        .filter(|(_, _, device)| *device)
        .map(|(t, f, _)| (t - T0, f.clone()))
        .collect();

    // The clock starts somewhere; the replay counts from the first receive.
    let start = 42 * MS;
    let (clock, pacing) = manual_clock(start);
    let mut r = Replay::from_bytes(Path::new("s7.pcap"), &file, options(pacing)).unwrap();
    assert_eq!(r.stats().profinet, expected.len() as u64);
    assert_eq!(r.stats().records, records.len() as u64);
    let mut got = Vec::new();
    for (due, frame) in &expected {
        if *due > 0 {
            clock.store(start + due - 1, Ordering::Relaxed);
            assert_eq!(next(&mut r), None, "a frame before {due} ns");
        }
        clock.store(start + due, Ordering::Relaxed);
        let f = next(&mut r).expect("the frame due now");
        assert_eq!(&f, frame, "the frame due at {due} ns");
        got.push(f);
        assert_eq!(next(&mut r), None, "only one frame at {due} ns");
    }
    clock.store(start + 3_600_000 * MS, Ordering::Relaxed);
    assert_eq!(next(&mut r), None);
    assert!(r.is_finished());
    for f in &got {
        assert!(is_profinet(f), "no UDP");
        assert_ne!(&f[6..12], &OWN.0, "none of ours");
        assert_eq!(&f[6..12], &DEVICE.0, "the device's");
    }
}

#[test]
fn realtime_pacing_holds_frames_until_their_time() {
    let file = pcap(&[
        (T0, pn_frame(DEVICE, 1)),
        (T0 + 3_600 * NS_PER_SEC, pn_frame(DEVICE, 2)),
    ]);
    let mut r = Replay::from_bytes(Path::new("x.pcap"), &file, options(Pacing::Realtime)).unwrap();
    assert_eq!(drain(&mut r), vec![pn_frame(DEVICE, 1)]);
    assert!(!r.is_finished());
}

#[test]
fn a_repeating_replay_starts_over_after_the_gap() {
    let file = pcap(&[(T0, pn_frame(DEVICE, 1)), (T0 + MS, pn_frame(DEVICE, 2))]);
    let (clock, pacing) = manual_clock(0);
    let mut r = Replay::from_bytes(
        Path::new("x.pcap"),
        &file,
        ReplayOptions {
            repeat: Some(Duration::from_millis(1)),
            ..options(pacing)
        },
    )
    .unwrap();
    // Each pass takes the file's 1 ms plus the 1 ms gap.
    for pass in 0..3u64 {
        clock.store(pass * 2 * MS, Ordering::Relaxed);
        assert_eq!(drain(&mut r), vec![pn_frame(DEVICE, 1)], "pass {pass}");
        clock.store(pass * 2 * MS + MS, Ordering::Relaxed);
        assert_eq!(drain(&mut r), vec![pn_frame(DEVICE, 2)], "pass {pass}");
        assert!(!r.is_finished());
    }
}

#[test]
fn a_capture_without_profinet_frames_returns_nothing_even_repeating() {
    let file = pcap(&[(T0, capture("cm/connect_res"))]);
    let mut r = Replay::from_bytes(
        Path::new("x.pcap"),
        &file,
        ReplayOptions {
            repeat: Some(Duration::ZERO),
            ..options(Pacing::AsFastAsPolled)
        },
    )
    .unwrap();
    assert!(drain(&mut r).is_empty());
}

#[test]
fn snap_length_cut_frames_are_skipped() {
    let full = pn_frame(DEVICE, 1);
    let header = PcapHeader {
        snaplen: 40,
        ..PcapHeader::default()
    };
    let mut w = PcapWriter::with_header(Vec::new(), header).unwrap();
    w.write_raw_packet(&pcap_file::pcap::RawPcapPacket {
        ts_sec: 1,
        ts_frac: 0,
        incl_len: 40,
        orig_len: full.len() as u32,
        data: Cow::Borrowed(&full[..40]),
    })
    .unwrap();
    let mut r = Replay::from_bytes(
        Path::new("x.pcap"),
        &w.into_writer(),
        options(Pacing::AsFastAsPolled),
    )
    .unwrap();
    assert_eq!(r.stats().cut, 1);
    assert!(drain(&mut r).is_empty());
}

/// A frame longer than the AF_PACKET backend takes is skipped, as that backend drops it; the
/// frames around it come through.
#[test]
fn frames_longer_than_max_frame_are_skipped() {
    let mut long = pn_frame(DEVICE, 2);
    long.resize(MAX_FRAME + 1, 0xee);
    let mut longest = pn_frame(DEVICE, 3);
    longest.resize(MAX_FRAME, 0xee);
    let file = pcap(&[
        (T0, pn_frame(DEVICE, 1)),
        (T0 + MS, long),
        (T0 + 2 * MS, longest.clone()),
    ]);
    let mut r =
        Replay::from_bytes(Path::new("x.pcap"), &file, options(Pacing::AsFastAsPolled)).unwrap();
    assert_eq!(r.stats().too_long, 1);
    assert_eq!(r.stats().profinet, 2);
    assert_eq!(drain(&mut r), vec![pn_frame(DEVICE, 1), longest]);
}

#[test]
fn pcapng_timestamp_resolutions() {
    assert_eq!(ng_timestamp_ns(1_500, 6), 1_500_000);
    assert_eq!(ng_timestamp_ns(7, 9), 7);
    assert_eq!(ng_timestamp_ns(7, 0), 7 * NS_PER_SEC);
    assert_eq!(ng_timestamp_ns(1, 0x80 | 10), 976_562);
    assert_eq!(ng_timestamp_ns(12_345, 12), 12);
    assert_eq!(ng_timestamp_ns(u64::MAX, 127), 0);
    assert_eq!(ng_timestamp_ns(u64::MAX, 0), u64::MAX);
    assert_eq!(ng_timestamp_ns(u64::MAX, 0xff), 0);
}

/// Little-endian pcapng blocks written by hand, for what pcap-file's writer does not write.
fn block_le(kind: u32, body: &[u8]) -> Vec<u8> {
    let len = (12 + body.len().div_ceil(4) * 4) as u32;
    let mut b = Vec::new();
    b.extend_from_slice(&kind.to_le_bytes());
    b.extend_from_slice(&len.to_le_bytes());
    b.extend_from_slice(body);
    b.resize(len as usize - 4, 0);
    b.extend_from_slice(&len.to_le_bytes());
    b
}

fn packet_body_le(interface: u32, raw_ts: u64, frame: &[u8], obsolete: bool) -> Vec<u8> {
    let mut b = Vec::new();
    if obsolete {
        b.extend_from_slice(&(interface as u16).to_le_bytes());
        b.extend_from_slice(&0u16.to_le_bytes());
    } else {
        b.extend_from_slice(&interface.to_le_bytes());
    }
    b.extend_from_slice(&((raw_ts >> 32) as u32).to_le_bytes());
    b.extend_from_slice(&(raw_ts as u32).to_le_bytes());
    b.extend_from_slice(&(frame.len() as u32).to_le_bytes());
    b.extend_from_slice(&(frame.len() as u32).to_le_bytes());
    b.extend_from_slice(frame);
    b
}

/// Two interfaces with different timestamp resolutions, packets in enhanced, obsolete and
/// simple blocks, a name resolution block in between: all on one time line.
#[test]
fn pcapng_interfaces_blocks_and_resolutions() {
    let mut w = PcapNgWriter::with_endianness(Vec::new(), Endianness::Little).unwrap();
    // Interface 0: nanoseconds; interface 1: the default, microseconds.
    w.write_pcapng_block(InterfaceDescriptionBlock {
        linktype: DataLink::ETHERNET,
        snaplen: 0,
        options: vec![InterfaceDescriptionOption::IfTsResol(9)],
    })
    .unwrap();
    w.write_pcapng_block(InterfaceDescriptionBlock {
        linktype: DataLink::ETHERNET,
        snaplen: 0xffff,
        options: vec![],
    })
    .unwrap();
    let epb = |interface_id, raw: u64, frame: &[u8]| EnhancedPacketBlock {
        interface_id,
        // pcap-file 2 writes this many units of the interface's resolution.
        timestamp: Duration::from_nanos(raw),
        original_len: frame.len() as u32,
        data: Cow::Owned(frame.to_vec()),
        options: vec![],
    };
    let t0_us = T0 / 1_000;
    w.write_pcapng_block(epb(0, T0, &pn_frame(DEVICE, 1)))
        .unwrap();
    w.write_pcapng_block(epb(1, t0_us + 1_000, &pn_frame(DEVICE, 2)))
        .unwrap();
    w.write_pcapng_block(epb(0, T0 + 2 * MS, &capture("cm/connect_res")))
        .unwrap();
    let mut file = w.into_inner();
    // A name resolution block (IPv4 record), which pcap-file cannot always parse safely.
    let mut nrb = Vec::new();
    nrb.extend_from_slice(&1u16.to_le_bytes());
    nrb.extend_from_slice(&6u16.to_le_bytes());
    nrb.extend_from_slice(&[172, 16, 2, 10, b'd', 0]);
    nrb.extend_from_slice(&[0, 0]);
    nrb.extend_from_slice(&[0, 0, 0, 0]);
    file.extend(block_le(4, &nrb));
    file.extend(block_le(
        PACKET_BLOCK,
        &packet_body_le(0, T0 + 3 * MS, &pn_frame(DEVICE, 3), true),
    ));
    // A simple packet block: no timestamp, so the one before (3 ms).
    let spb_frame = pn_frame(DEVICE, 4);
    let mut spb = (spb_frame.len() as u32).to_le_bytes().to_vec();
    spb.extend_from_slice(&spb_frame);
    spb.extend_from_slice(&[0; 2]);
    file.extend(block_le(SIMPLE_PACKET_BLOCK, &spb));
    file.extend(block_le(
        ENHANCED_PACKET_BLOCK,
        &packet_body_le(1, t0_us + 5_000, &pn_frame(OWN, 5), false),
    ));

    let (clock, pacing) = manual_clock(0);
    let mut r = Replay::from_bytes(Path::new("x.pcapng"), &file, options(pacing)).unwrap();
    assert_eq!(
        r.stats(),
        ReplayStats {
            records: 6,
            profinet: 4,
            own: 1,
            other: 1,
            cut: 0,
            too_long: 0,
        }
    );
    let at = |ms: u64, r: &mut Replay| {
        clock.store(ms * MS, Ordering::Relaxed);
        drain(r)
    };
    assert_eq!(at(0, &mut r), vec![pn_frame(DEVICE, 1)]);
    assert_eq!(at(1, &mut r), vec![pn_frame(DEVICE, 2)]);
    assert!(at(2, &mut r).is_empty());
    assert_eq!(
        at(3, &mut r),
        vec![pn_frame(DEVICE, 3), pn_frame(DEVICE, 4)]
    );
    assert!(r.is_finished());
}

#[test]
fn sent_frames_are_kept_and_written_on_flush_and_on_drop() {
    let dir = temp_dir("replay-sent");
    let out = dir.path().join("sent.pcap");
    let file = pcap(&[
        (T0, pn_frame(DEVICE, 1)),
        (T0 + 10 * MS, pn_frame(DEVICE, 2)),
    ]);
    let (clock, pacing) = manual_clock(1_000 * MS);
    let mut r = Replay::from_bytes(
        Path::new("x.pcap"),
        &file,
        ReplayOptions {
            // Room for two 60-byte frames.
            sent_buffer: 120,
            output: Some(out.clone()),
            ..options(pacing)
        },
    )
    .unwrap();
    next(&mut r);
    clock.store(1_004 * MS, Ordering::Relaxed);
    r.send(&pn_frame(OWN, 10)).unwrap();
    r.send(&pn_frame(OWN, 11)).unwrap();
    r.send(&pn_frame(OWN, 12)).unwrap();
    let e = r.send(&[0; MAX_FRAME + 1]).unwrap_err();
    assert!(matches!(e, SendError::TooLong { len: 1519, .. }), "{e}");
    assert!(e.to_string().contains("\"x.pcap\""), "{e}");
    assert_eq!(r.sent_dropped(), 1);
    let sent: Vec<_> = r.sent().map(|(t, f)| (t, f.to_vec())).collect();
    // On the capture's time line: 4 ms after its start.
    let at = Duration::from_nanos(T0 + 4 * MS);
    assert_eq!(sent, vec![(at, pn_frame(OWN, 10)), (at, pn_frame(OWN, 11))]);
    r.flush().unwrap();
    assert_eq!(r.sent().count(), 0);
    clock.store(1_007 * MS, Ordering::Relaxed);
    r.send(&pn_frame(OWN, 13)).unwrap();
    drop(r);

    // The output replays like any capture: from the device's point of view, what we sent.
    let mut back = Replay::open(
        &out,
        ReplayOptions {
            mac: DEVICE,
            pacing: Pacing::AsFastAsPolled,
            ..ReplayOptions::new(DEVICE)
        },
    )
    .unwrap();
    assert_eq!(back.stats().records, 3);
    assert_eq!(
        drain(&mut back),
        vec![pn_frame(OWN, 10), pn_frame(OWN, 11), pn_frame(OWN, 13)]
    );
    // Timestamps kept to the nanosecond.
    let bytes = std::fs::read(&out).unwrap();
    let (mut rest, parser) = PcapParser::new(&bytes).unwrap();
    let mut stamps = Vec::new();
    while !rest.is_empty() {
        let (rem, p) = parser.next_packet(rest).unwrap();
        stamps.push(p.timestamp);
        rest = rem;
    }
    assert_eq!(stamps, vec![at, at, Duration::from_nanos(T0 + 7 * MS)]);
}

#[test]
fn as_fast_as_polled_stamps_sent_frames_with_the_replay_position() {
    let file = pcap(&[
        (T0, pn_frame(DEVICE, 1)),
        (T0 + 10 * MS, pn_frame(DEVICE, 2)),
    ]);
    let mut r =
        Replay::from_bytes(Path::new("x.pcap"), &file, options(Pacing::AsFastAsPolled)).unwrap();
    next(&mut r);
    next(&mut r);
    r.send(&pn_frame(OWN, 1)).unwrap();
    let (t, _) = r.sent().next().unwrap();
    assert_eq!(t, Duration::from_nanos(T0 + 10 * MS));
    // No output file: flush only empties the buffer.
    r.flush().unwrap();
    assert_eq!(r.sent().count(), 0);
}

#[test]
fn errors_name_the_file_and_say_what_to_do() {
    let dir = temp_dir("replay-errors");
    let msg = |r: Result<Replay, ReplayError>| match r {
        Ok(_) => panic!("accepted"),
        Err(e) => (e.to_string(), e),
    };
    let fast = || options(Pacing::AsFastAsPolled);

    let missing = dir.path().join("missing.pcap");
    let (m, e) = msg(Replay::open(&missing, fast()));
    assert!(matches!(e, ReplayError::NotFound { .. }), "{m}");
    assert!(m.contains(&missing.display().to_string()) && m.contains("check the path"));

    let (m, e) = msg(Replay::from_bytes(Path::new("notes.txt"), b"hello", fast()));
    assert!(matches!(e, ReplayError::NotPcap { .. }), "{m}");
    assert!(m.contains("notes.txt") && m.contains("68 65 6c 6c") && m.contains("procimg capture"));
    let (m, _) = msg(Replay::from_bytes(Path::new("empty.pcap"), b"", fast()));
    assert!(m.contains("empty"), "{m}");

    let sll = PcapHeader {
        datalink: DataLink::LINUX_SLL,
        ..PcapHeader::default()
    };
    let file = PcapWriter::with_header(Vec::new(), sll)
        .unwrap()
        .into_writer();
    let (m, e) = msg(Replay::from_bytes(Path::new("any.pcap"), &file, fast()));
    assert!(matches!(e, ReplayError::LinkType { .. }), "{m}");
    assert!(m.contains("any.pcap") && m.contains("LINUX_SLL (113)") && m.contains("not \"any\""));

    let mut ng = PcapNgWriter::with_endianness(Vec::new(), Endianness::Big).unwrap();
    ng.write_pcapng_block(InterfaceDescriptionBlock {
        linktype: DataLink::IEEE802_11,
        snaplen: 0,
        options: vec![],
    })
    .unwrap();
    let unused = ng.get_ref().clone();
    ng.write_pcapng_block(EnhancedPacketBlock {
        interface_id: 0,
        timestamp: Duration::ZERO,
        original_len: 4,
        data: Cow::Borrowed(&[0; 4]),
        options: vec![],
    })
    .unwrap();
    let (m, _) = msg(Replay::from_bytes(
        Path::new("wifi.pcapng"),
        &ng.into_inner(),
        fast(),
    ));
    assert!(m.contains("wifi.pcapng") && m.contains("IEEE802_11"), "{m}");
    // An interface of another link type without packets does no harm.
    assert!(Replay::from_bytes(Path::new("wifi.pcapng"), &unused, fast()).is_ok());

    let mut file = pcap(&[(T0, pn_frame(DEVICE, 1)), (T0 + MS, pn_frame(DEVICE, 2))]);
    file.truncate(file.len() - 7);
    let (m, e) = msg(Replay::from_bytes(Path::new("cut.pcap"), &file, fast()));
    assert!(
        matches!(
            e,
            ReplayError::Truncated {
                offset: 100,
                records: 1,
                ..
            }
        ),
        "{m}"
    );
    assert!(m.contains("cut.pcap") && m.contains("byte 100") && m.contains("Ctrl-C"));

    let mut file = pcap(&[(T0, pn_frame(DEVICE, 1))]);
    // The fraction of the first record's timestamp (nanoseconds, big-endian): 10^9.
    file[28..32].copy_from_slice(&1_000_000_000u32.to_be_bytes());
    let (m, e) = msg(Replay::from_bytes(Path::new("bad.pcap"), &file, fast()));
    assert!(matches!(e, ReplayError::Corrupt { offset: 24, .. }), "{m}");
    assert!(m.contains("bad.pcap") && m.contains("re-save"));

    let mut file = PcapNgWriter::with_endianness(Vec::new(), Endianness::Little)
        .unwrap()
        .into_inner();
    let at = file.len();
    file.extend(block_le(
        ENHANCED_PACKET_BLOCK,
        &packet_body_le(3, 0, &pn_frame(DEVICE, 1), false),
    ));
    let (m, e) = msg(Replay::from_bytes(Path::new("ng.pcapng"), &file, fast()));
    assert!(
        matches!(e, ReplayError::Corrupt { offset, .. } if offset == at),
        "{m}"
    );
    assert!(m.contains("interface 3"), "{m}");

    let file = pcap(&[(T0, pn_frame(DEVICE, 1))]);
    let out = dir.path().join("no-such-dir").join("out.pcap");
    let (m, e) = msg(Replay::from_bytes(
        Path::new("x.pcap"),
        &file,
        ReplayOptions {
            output: Some(out.clone()),
            ..fast()
        },
    ));
    assert!(matches!(e, ReplayError::Output { .. }), "{m}");
    assert!(m.contains(&out.display().to_string()) && m.contains("writable"));
}

/// Opens `bytes` and, if that works, plays it to the end (repeating files once around).
fn play(bytes: &[u8]) {
    let opened = Replay::from_bytes(
        Path::new("fuzz.pcap"),
        bytes,
        ReplayOptions {
            repeat: Some(Duration::ZERO),
            sent_buffer: 256,
            ..options(Pacing::AsFastAsPolled)
        },
    );
    if let Ok(mut r) = opened {
        let frames = r.stats().profinet as usize;
        for _ in 0..2 * frames + 1 {
            let mut len = 0;
            let _ = r.receive(&mut |f| len = f.len());
            assert!(len <= MAX_FRAME, "a frame of {len} bytes handed over");
            let _ = r.send(&[0; 64]);
        }
    }
}

fn seed_files() -> Vec<Vec<u8>> {
    let frames = [
        (T0, capture("rt/rtc_dev_8000")),
        (T0 + MS, capture("cm/connect_res")),
        (T0 + 2 * MS, capture("cm/ident_ok_pnet")),
    ];
    let mut ng = PcapNgWriter::with_endianness(Vec::new(), Endianness::Little).unwrap();
    ng.write_pcapng_block(InterfaceDescriptionBlock {
        linktype: DataLink::ETHERNET,
        snaplen: 0,
        options: vec![
            InterfaceDescriptionOption::IfTsResol(9),
            InterfaceDescriptionOption::IfName("eth0".into()),
        ],
    })
    .unwrap();
    for (t, f) in &frames {
        ng.write_pcapng_block(EnhancedPacketBlock {
            interface_id: 0,
            timestamp: Duration::from_nanos(*t),
            original_len: f.len() as u32,
            data: Cow::Borrowed(f),
            options: vec![],
        })
        .unwrap();
    }
    let mut ng = ng.into_inner();
    ng.extend(block_le(SIMPLE_PACKET_BLOCK, &{
        let mut b = 60u32.to_le_bytes().to_vec();
        b.extend_from_slice(&pn_frame(DEVICE, 9));
        b
    }));
    vec![pcap(&frames), ng]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..512)) {
        play(&bytes);
    }

    #[test]
    fn a_file_header_then_arbitrary_bytes_never_panic(
        ng in any::<bool>(),
        tail in proptest::collection::vec(any::<u8>(), 0..512),
    ) {
        let seeds = seed_files();
        // The pcap header, or the section header block of the pcapng file.
        let head = if ng { &seeds[1][..28] } else { &seeds[0][..24] };
        let mut bytes = head.to_vec();
        bytes.extend(tail);
        play(&bytes);
    }

    #[test]
    fn damaged_captures_never_panic(
        which in 0..2usize,
        edits in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
        cut in any::<prop::sample::Index>(),
    ) {
        let mut bytes = seed_files().swap_remove(which);
        for (at, value) in edits {
            let i = at.index(bytes.len());
            bytes[i] = value;
        }
        play(&bytes);
        bytes.truncate(cut.index(bytes.len() + 1));
        play(&bytes);
    }
}
