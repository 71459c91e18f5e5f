// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg dcp` against a device on a veth pair between two network namespaces this test
//! creates: scan finds it, set-name / set-ip / blink are confirmed, a scan for an unknown name
//! fails clearly. The device is a small DCP responder built on procimg's own codecs. Needs
//! root; skipped otherwise.

use procimg_nic::Nic;
use procimg_nic::af_packet::AfPacket;
use procimg_profinet::dcp_client;
use procimg_profinet::wire::dcp::{self, Block, BlockRepr, ServiceId, ServiceType};
use procimg_profinet::wire::ethernet;
use procimg_testkit::netns::TestNet;
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// Answers Identify (as "echo" until renamed) and every Set with success, recording the Sets.
fn responder(nic: &mut AfPacket, stop: &AtomicBool, sets: &Mutex<Vec<String>>) {
    let mut name = String::from("echo");
    let mut buf = Vec::new();
    while !stop.load(Ordering::Relaxed) {
        // Copied out: the answer is sent through the interface the frame is in.
        let Ok(true) = nic.receive(&mut |f| buf = f.to_vec()) else {
            continue;
        };
        let Ok(eth) = ethernet::Frame::new_checked(&buf[..]) else {
            continue;
        };
        let from = eth.src();
        let Some(req) = dcp::Packet::new_checked(eth.payload())
            .ok()
            .and_then(|p| dcp::Repr::parse(&p).ok())
            .filter(|r| r.service_type == ServiceType::Request)
        else {
            continue;
        };
        let block = |value| Block { prefix: 0, value };
        let reply = match req.service_id {
            ServiceId::Identify => {
                if let Some(wanted) = req.name_of_station()
                    && wanted != name
                {
                    continue;
                }
                dcp::Repr {
                    frame_id: dcp::FRAME_ID_IDENTIFY_RESPONSE,
                    service_id: ServiceId::Identify,
                    service_type: ServiceType::Success,
                    xid: req.xid,
                    response_delay: 0,
                    blocks: vec![
                        block(BlockRepr::NameOfStation(name.clone())),
                        block(BlockRepr::DeviceId {
                            vendor_id: 0x0493,
                            device_id: 0x0001,
                        }),
                        block(BlockRepr::IpParameter {
                            ip: [192, 168, 0, 11],
                            mask: [255, 255, 255, 0],
                            gateway: [192, 168, 0, 11],
                        }),
                    ],
                }
            }
            ServiceId::Set => {
                let mut acks = Vec::new();
                for b in &req.blocks {
                    let what = match &b.value {
                        BlockRepr::NameOfStation(n) => {
                            name = n.clone();
                            acks.push((2, 2));
                            format!("name {n}")
                        }
                        BlockRepr::IpParameter { ip, .. } => {
                            acks.push((1, 2));
                            format!("ip {ip:?}")
                        }
                        BlockRepr::ControlSignal(v) => {
                            acks.push((5, 3));
                            format!("signal {v:#06x}")
                        }
                        other => format!("{other:?}"),
                    };
                    sets.lock().unwrap().push(what);
                }
                dcp::Repr {
                    frame_id: dcp::FRAME_ID_GET_SET,
                    service_id: ServiceId::Set,
                    service_type: ServiceType::Success,
                    xid: req.xid,
                    response_delay: 0,
                    blocks: acks
                        .into_iter()
                        .map(|(option, suboption)| {
                            block(BlockRepr::ControlResponse {
                                option,
                                suboption,
                                error: 0,
                            })
                        })
                        .collect(),
                }
            }
            _ => continue,
        };
        let f = dcp_client::frame(from, nic.mac(), &reply).unwrap();
        nic.send(&f).unwrap();
    }
}

fn procimg(net: &TestNet, args: &[&str]) -> (bool, String, String) {
    let out = Command::new("ip")
        .args(["netns", "exec", &net.ns[0]])
        .arg(env!("CARGO_BIN_EXE_procimg"))
        .args(["dcp", "--iface", &net.ifs[0]])
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
#[ignore = "needs root (network namespaces): run as root with --ignored"]
fn scan_set_and_blink_a_device() {
    assert!(
        procimg_testkit::netns::is_root(),
        "this test builds network namespaces, which needs root: run it as root"
    );
    let net = TestNet::new("d", true);
    let stop = Arc::new(AtomicBool::new(false));
    let sets = Arc::new(Mutex::new(Vec::new()));
    let (mac_tx, mac_rx) = std::sync::mpsc::channel();
    let device = {
        let (stop, sets) = (stop.clone(), sets.clone());
        net.in_ns(1, move |ifname| {
            let mut nic = AfPacket::open(&ifname, Duration::from_millis(10)).unwrap();
            mac_tx.send(nic.mac()).unwrap();
            responder(&mut nic, &stop, &sets);
        })
    };
    let mac = mac_rx.recv().unwrap().to_string();

    let (ok, out, err) = procimg(&net, &["scan", "--wait-ms", "200"]);
    assert!(ok, "scan failed: {err}");
    assert!(
        out.contains(&mac) && out.contains("echo") && out.contains("192.168.0.11"),
        "{out}"
    );
    assert!(out.contains("0493:0001"), "{out}");

    let (ok, out, err) = procimg(&net, &["set-name", &mac, "line1-echo"]);
    assert!(ok && out.contains("done"), "{out}{err}");
    let (ok, out, err) = procimg(&net, &["set-ip", &mac, "10.0.0.5", "255.255.255.0"]);
    assert!(ok && out.contains("done"), "{out}{err}");
    let (ok, out, err) = procimg(&net, &["blink", &mac]);
    assert!(ok && out.contains("done"), "{out}{err}");

    let (ok, out, _) = procimg(&net, &["scan", "--name", "line1-echo", "--wait-ms", "200"]);
    assert!(ok && out.contains("line1-echo"), "{out}");
    let (ok, _, err) = procimg(&net, &["scan", "--name", "nosuch", "--wait-ms", "200"]);
    assert!(!ok && err.contains("no device answered"), "{err}");

    stop.store(true, Ordering::Relaxed);
    device.join().unwrap();
    let sets = sets.lock().unwrap().clone();
    assert_eq!(
        sets,
        ["name line1-echo", "ip [10, 0, 0, 5]", "signal 0x0100"],
        "what the device was asked to set"
    );
}
