// SPDX-License-Identifier: MIT OR Apache-2.0
//! The AF_PACKET backend on a veth pair between two network namespaces that these tests
//! create (and remove, also when they fail): PROFINET frames cross and nothing else does, a
//! frame too long for the receive buffer is reported and not handed over cut, a socket being
//! opened takes no frame of another interface, and opening a missing or down interface says
//! what is wrong. Need root; skipped otherwise.

use procimg_nic::af_packet::{AfPacket, OpenError};
use procimg_nic::{MAX_FRAME, Nic, RecvError, SendError};
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::dcp;
use procimg_profinet::wire::ethernet::{self, ETHERTYPE_PROFINET};
use procimg_testkit::netns::{TestNet, frame, ip, is_root};
use std::time::{Duration, Instant};

/// The next frame within `t`, copied out of the backend's buffer.
fn recv_within(nic: &mut AfPacket, t: Duration) -> Option<Vec<u8>> {
    let until = Instant::now() + t;
    let mut got = None;
    while got.is_none() && Instant::now() < until {
        nic.receive(&mut |f| got = Some(f.to_vec())).unwrap();
    }
    got
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

#[test]
#[ignore = "needs root (network namespaces): run as root with --ignored"]
fn a_frame_longer_than_the_buffer_is_reported_not_cut() {
    assert!(
        is_root(),
        "this test builds network namespaces, which needs root: run it as root"
    );
    let net = TestNet::new("t", true);
    // Jumbo frames on the link, as on a network where a station's MTU is too large.
    for i in 0..2 {
        ip(&["-n", &net.ns[i], "link", "set", &net.ifs[i], "mtu", "3000"]);
    }
    let (ready_tx, ready_rx) = std::sync::mpsc::channel::<()>();
    let receiver = net.in_ns(1, move |ifname| {
        let mut nic = AfPacket::open(&ifname, Duration::from_millis(20)).unwrap();
        ready_tx.send(()).unwrap();
        let until = Instant::now() + Duration::from_secs(3);
        let mut results = Vec::new();
        while results.len() < 3 && Instant::now() < until {
            let mut len = None;
            match nic.receive(&mut |f| len = Some(f.len())) {
                Ok(true) => results.push(Ok(len.expect("the closure ran"))),
                Ok(false) => {}
                Err(e) => results.push(Err(e)),
            }
        }
        results
    });
    ready_rx.recv().unwrap();
    net.in_ns(0, move |ifname| {
        let mut nic = AfPacket::open(&ifname, Duration::from_millis(1)).unwrap();
        let (dst, src) = ([2, 9, 9, 9, 9, 9], nic.mac().0);
        let pn = |len: usize| frame(dst, src, ETHERTYPE_PROFINET, &vec![0x80; len - 14]);
        // The backend sends no frame longer than MAX_FRAME: the long one goes out through a
        // pnet channel, which sends what it is given.
        let e = nic.send(&pn(2000)).unwrap_err();
        assert!(matches!(e, SendError::TooLong { len: 2000, .. }), "{e}");
        nic.send(&pn(60)).unwrap();
        send_unchecked(&ifname, &pn(2000));
        nic.send(&pn(MAX_FRAME)).unwrap();
    })
    .join()
    .expect("sending failed");
    let results = receiver.join().expect("receiving failed");
    assert_eq!(results.len(), 3, "{results:?}");
    assert!(matches!(results[0], Ok(60)), "{results:?}");
    match &results[1] {
        Err(e @ RecvError::TooLong { len: 2000, max, .. }) => {
            assert_eq!(*max, MAX_FRAME);
            let m = e.to_string();
            assert!(
                m.contains(&net.ifs[1]) && m.contains("2000") && m.contains("MTU"),
                "{m}"
            );
        }
        other => panic!("the long frame came as {other:?}"),
    }
    assert!(matches!(results[2], Ok(MAX_FRAME)), "{results:?}");
}

/// Sends `f` on `ifname` whatever its length, through pnet's channel.
#[test]
#[ignore = "needs root (network namespaces): run as root with --ignored"]
fn a_socket_being_opened_takes_no_frame_of_another_interface() {
    assert!(
        is_root(),
        "this test builds network namespaces, which needs root: run it as root"
    );
    let net = TestNet::new("o", true);
    ip(&["-n", &net.ns[0], "link", "set", "lo", "up"]);
    // PROFINET frames, which the kernel filter lets through, flood the loopback interface of
    // the namespace while sockets on the veth end are opened: a socket that took frames
    // before it was bound to its interface would queue some of them.
    const MARK: [u8; 6] = [2, 0x10, 0x10, 0x10, 0x10, 0x10];
    let opened = net.in_ns(0, move |ifname| {
        let lo = pnet_datalink::interfaces()
            .into_iter()
            .find(|i| i.name == "lo")
            .expect("the loopback interface");
        let config = pnet_datalink::Config {
            read_timeout: Some(Duration::from_millis(100)),
            ..Default::default()
        };
        let pnet_datalink::Channel::Ethernet(mut tx, mut rx) =
            pnet_datalink::channel(&lo, config).expect("a pnet channel on lo")
        else {
            panic!("not an Ethernet channel");
        };
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let flood = {
            let stop = stop.clone();
            let f = frame([0xff; 6], MARK, ETHERTYPE_PROFINET, &[0xfe, 0xfe, 5, 0]);
            std::thread::spawn(move || {
                let mut sent = 0u64;
                while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                    if let Some(Ok(())) = tx.send_to(&f, None) {
                        sent += 1;
                    }
                }
                sent
            })
        };
        // The flood is on the wire of lo.
        let until = Instant::now() + Duration::from_secs(2);
        let mut on_lo = false;
        while !on_lo && Instant::now() < until {
            on_lo = rx.next().is_ok_and(|f| f.get(6..12) == Some(&MARK[..]));
        }
        drop(rx);
        let mut leaked = 0;
        for _ in 0..200 {
            let mut nic = AfPacket::open(&ifname, Duration::from_millis(1)).unwrap();
            let until = Instant::now() + Duration::from_millis(2);
            while Instant::now() < until {
                nic.receive(&mut |f| {
                    if f.get(6..12) == Some(&MARK[..]) {
                        leaked += 1;
                    }
                })
                .unwrap();
            }
        }
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        let sent = flood.join().expect("the flood");
        (on_lo, sent, leaked)
    });
    let (on_lo, sent, leaked) = opened.join().expect("the veth side failed");
    assert!(on_lo && sent > 0, "no flood on lo ({sent} frames sent)");
    assert_eq!(
        leaked, 0,
        "sockets on the veth end took {leaked} frames of lo ({sent} sent meanwhile)"
    );
}

fn send_unchecked(ifname: &str, f: &[u8]) {
    let iface = pnet_datalink::interfaces()
        .into_iter()
        .find(|i| i.name == ifname)
        .expect("the interface");
    let pnet_datalink::Channel::Ethernet(mut tx, _rx) =
        pnet_datalink::channel(&iface, Default::default()).expect("a pnet channel")
    else {
        panic!("not an Ethernet channel");
    };
    tx.send_to(f, None)
        .expect("pnet took the frame")
        .expect("the long frame was sent");
}
