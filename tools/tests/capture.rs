// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg capture` on a veth pair between two network namespaces this test creates: frames
//! arriving from the other side and frames sent on the capturing side both land in the pcap
//! file, nothing else does, and tshark reads it. Needs root; skipped otherwise.

use procimg_nic::Nic;
use procimg_nic::af_packet::AfPacket;
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::dcp;
use procimg_profinet::wire::ethernet::ETHERTYPE_PROFINET;
use procimg_testkit::netns::{TestNet, frame, is_root};
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::Duration;

fn send_in(net: &TestNet, side: usize, frames: Vec<(bool, u16, Vec<u8>)>) {
    net.in_ns(side, move |ifname| {
        let mut nic = AfPacket::open(&ifname, Duration::from_millis(10)).unwrap();
        for (multicast, ethertype, payload) in frames {
            let dst = if multicast {
                MacAddress::DCP_IDENTIFY
            } else {
                MacAddress([2, 9, 9, 9, 9, 9])
            };
            nic.send(&frame(dst.0, nic.mac().0, ethertype, &payload))
                .unwrap();
        }
    })
    .join()
    .expect("sending failed");
}

#[test]
#[ignore = "needs root (network namespaces): run as root with --ignored"]
fn capture_records_both_directions_of_profinet_only() {
    assert!(
        is_root(),
        "this test builds network namespaces, which needs root: run it as root"
    );
    let net = TestNet::new("c", true);
    let out = std::env::temp_dir().join(format!("procimg-capture-{}.pcap", std::process::id()));
    let mut child = Command::new("ip")
        .args(["netns", "exec", &net.ns[1]])
        .arg(env!("CARGO_BIN_EXE_procimg"))
        .args([
            "capture",
            "--iface",
            &net.ifs[1],
            "--count",
            "3",
            "--seconds",
            "10",
            "-o",
        ])
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until it captures.
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    err.read_line(&mut line).unwrap();
    assert!(line.contains("capturing"), "procimg capture said: {line}");

    let identify = dcp::Repr::identify_all(7, 1).to_vec().unwrap();
    let set_name = dcp::Repr::set_name(8, "echo", false).to_vec().unwrap();
    // From the other side: a DCP Identify and an IPv4 frame (not PROFINET: not recorded).
    send_in(
        &net,
        0,
        vec![
            (true, ETHERTYPE_PROFINET, identify.clone()),
            (false, 0x0800, vec![0x45; 40]),
        ],
    );
    // From the capturing side itself: a DCP Set (outgoing: recorded too), then one more Identify.
    send_in(&net, 1, vec![(false, ETHERTYPE_PROFINET, set_name)]);
    send_in(&net, 0, vec![(true, ETHERTYPE_PROFINET, identify)]);

    let status = child.wait().unwrap();
    let mut stdout = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut stdout)
        .unwrap();
    assert!(status.success(), "procimg capture failed: {stdout}");
    assert!(stdout.contains("3 frames written"), "{stdout}");

    let frames = read_pcap(&out);
    let _ = std::fs::remove_file(&out);
    let d = procimg_testkit::tshark::dissect_clean("captured", &frames);
    let infos: Vec<&str> = d.iter().map(|f| f.info.as_str()).collect();
    assert!(d.iter().all(|f| f.protocol == "PN-DCP"), "{d:?}");
    assert!(
        infos[0].contains("Ident Req") && infos[1].contains("Set Req"),
        "{infos:?}"
    );
}

/// The frames of a pcap file (classic format, as procimg writes it).
fn read_pcap(path: &std::path::Path) -> Vec<Vec<u8>> {
    let b = std::fs::read(path).unwrap();
    let mut at = 24;
    let mut frames = Vec::new();
    while at + 16 <= b.len() {
        let len = u32::from_le_bytes(b[at + 8..at + 12].try_into().unwrap()) as usize;
        at += 16;
        frames.push(b[at..at + len].to_vec());
        at += len;
    }
    frames
}
