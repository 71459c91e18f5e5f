// SPDX-License-Identifier: MIT OR Apache-2.0
//! The AF_PACKET backend on a veth pair between two network namespaces that this test creates
//! (and removes, also when it fails). Needs root; skipped otherwise.

use procimg_nic::af_packet::{AfPacket, OpenError};
use procimg_nic::{MAX_FRAME, Nic};
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::dcp;
use procimg_profinet::wire::ethernet::{self, ETHERTYPE_PROFINET};
use std::time::{Duration, Instant};

use procimg_testkit::netns::{TestNet, frame, is_root};

fn recv_within(nic: &mut AfPacket, t: Duration) -> Option<Vec<u8>> {
    let until = Instant::now() + t;
    let mut buf = [0u8; MAX_FRAME];
    while Instant::now() < until {
        if let Some(n) = nic.recv(&mut buf).unwrap() {
            return Some(buf[..n].to_vec());
        }
    }
    None
}

#[test]
#[ignore = "needs root (network namespaces): run as root with --ignored"]
fn profinet_frames_cross_a_veth_pair_and_nothing_else_does() {
    assert!(
        is_root(),
        "this test builds network namespaces, which needs root: run it as root"
    );
    let net = TestNet::new("x", true);
    let (to_device, device_mac) = std::sync::mpsc::channel::<MacAddress>();
    let (ready_tx, ready_rx) = std::sync::mpsc::channel::<()>();
    // The device side: answers an Identify, reports what else it saw.
    let device = net.in_ns(1, move |ifname| {
        let mut nic = AfPacket::open(&ifname, Duration::from_millis(20)).unwrap();
        to_device.send(nic.mac()).unwrap();
        ready_tx.send(()).unwrap();
        let mut seen = Vec::new();
        let until = Instant::now() + Duration::from_secs(3);
        while Instant::now() < until {
            let Some(f) = recv_within(&mut nic, Duration::from_millis(50)) else {
                continue;
            };
            let eth = ethernet::Frame::new_checked(&f[..]).unwrap();
            let src = eth.src();
            let pdu = eth.payload();
            let request = dcp::Packet::new_checked(pdu)
                .ok()
                .and_then(|p| dcp::Repr::parse(&p).ok())
                .filter(|r| r.frame_id == dcp::FRAME_ID_IDENTIFY_REQUEST);
            if let Some(req) = request {
                let mut resp = dcp::Repr::identify_all(req.xid, 0);
                resp.frame_id = dcp::FRAME_ID_IDENTIFY_RESPONSE;
                resp.service_type = dcp::ServiceType::Success;
                resp.response_delay = 0;
                resp.blocks = vec![dcp::Block {
                    prefix: 0,
                    value: dcp::BlockRepr::NameOfStation("echo".into()),
                }];
                let bytes = resp.to_vec().unwrap();
                nic.send(&frame(src.0, nic.mac().0, ETHERTYPE_PROFINET, &bytes))
                    .unwrap();
            }
            seen.push(u16::from_be_bytes([pdu[0], pdu[1]]));
            if seen.len() >= 2 {
                break;
            }
        }
        seen
    });
    let device_mac = device_mac.recv().unwrap();
    ready_rx.recv().unwrap();
    let controller = net.in_ns(0, move |ifname| {
        let mut nic = AfPacket::open(&ifname, Duration::from_millis(20)).unwrap();
        let me = nic.mac();
        // Not PROFINET: the kernel filter keeps it from the device's socket.
        nic.send(&frame(device_mac.0, me.0, 0x0800, &[0x45; 40]))
            .unwrap();
        let ident = dcp::Repr::identify_by_name(0x4242, 1, "echo")
            .to_vec()
            .unwrap();
        nic.send(&frame(
            MacAddress::DCP_IDENTIFY.0,
            me.0,
            ETHERTYPE_PROFINET,
            &ident,
        ))
        .unwrap();
        let answer = recv_within(&mut nic, Duration::from_secs(2)).expect("no Identify response");
        let eth = ethernet::Frame::new_checked(&answer[..]).unwrap();
        assert_eq!(eth.src(), device_mac, "our own frame came back");
        let resp = dcp::Repr::parse(&dcp::Packet::new_checked(eth.payload()).unwrap()).unwrap();
        assert_eq!(resp.xid, 0x4242);
        assert_eq!(resp.name_of_station(), Some("echo"));
        // A cyclic frame, tagged as PROFINET RT sends it.
        let mut rt = vec![0x80, 0x00];
        rt.extend_from_slice(&[0x80; 40]);
        rt.extend_from_slice(&[0x00, 0x20, 0x35, 0x00]);
        let eth = ethernet::Repr {
            dst: device_mac,
            src: me,
            vlan: Some(ethernet::VlanTag::RT),
            ethertype: ETHERTYPE_PROFINET,
        };
        let mut f = vec![0u8; eth.buffer_len()];
        eth.emit(&mut f).unwrap();
        f.extend(rt);
        nic.send(&f).unwrap();
    });
    controller.join().expect("controller side failed");
    let seen = device.join().expect("device side failed");
    assert_eq!(seen, [0xfefe, 0x8000], "the device saw {seen:04x?}");
}

#[test]
#[ignore = "needs root (network namespaces): run as root with --ignored"]
fn opening_a_missing_or_down_interface_says_what_is_wrong() {
    assert!(
        is_root(),
        "this test builds network namespaces, which needs root: run it as root"
    );
    let net = TestNet::new("e", false);
    let r = net
        .in_ns(1, |ifname| {
            let missing = AfPacket::open("nosuchif0", Duration::from_millis(1))
                .err()
                .unwrap();
            let down = AfPacket::open(&ifname, Duration::from_millis(1))
                .err()
                .unwrap();
            (
                missing.to_string(),
                matches!(down, OpenError::Down { .. }),
                down.to_string(),
            )
        })
        .join()
        .unwrap();
    assert!(
        r.0.contains("nosuchif0") && r.0.contains("does not exist"),
        "{}",
        r.0
    );
    assert!(r.1, "{}", r.2);
    assert!(r.2.contains("ip link set"), "{}", r.2);
}
