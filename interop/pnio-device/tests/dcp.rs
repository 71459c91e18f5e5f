// SPDX-License-Identifier: MIT OR Apache-2.0
//! `pnio-interop-device` on its own: the procimgd configuration it prints is one procimgd
//! accepts and matches pnio's model, its GSDML renders, and, on a veth pair between two
//! network namespaces this test creates, the project's DCP client (`procimg dcp`) finds it
//! and an implicit record read of I&M0 returns its identity. The namespace tests need root
//! and are skipped otherwise; they also need the `procimg` binary (built by
//! `cargo build -p procimg-tools`, or by `cargo test --workspace`) next to this test's
//! target directory, or its path in `PROCIMG_BIN`.

mod support;

use procimg_interop_pnio_device as iop;
use procimg_profinet::wire::record::{IOD_HEADER_LEN, Im0, IodHeader, IodKind};
use procimg_profinet::wire::rpc::{self, Header, Ndr};
use procimg_profinet::wire::{PnioStatus, Uuid};
use procimg_testkit::workspace_bin;
use std::net::{Ipv4Addr, SocketAddr, UdpSocket};
use std::path::PathBuf;
use std::process::Command;
use std::time::Duration;
use support::Net;
use support::device::{DEVICE, Device, NAME};

/// Runs the device binary with `args` to completion: (success, stdout, stderr).
fn run_device(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(DEVICE).args(args).output().unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn printed_config_is_a_procimgd_configuration_of_pnios_model() {
    let (ok, block, err) = run_device(&["--name", NAME, "--ip", "10.213.7.2", "--print-config"]);
    assert!(ok, "--print-config failed: {err}");

    let on_iface = format!("network = \"veth-iop\"\n{block}");
    for text in [block.as_str(), on_iface.as_str()] {
        let config = procimg_runtime::config::parse(text, "pnio-interop-device --print-config")
            .unwrap_or_else(|e| panic!("procimgd refuses the printed block: {e}\n{text}"));
        assert_eq!(config.devices.len(), 1);
        let d = &config.devices[0];
        assert_eq!(d.name, NAME);
        assert_eq!(d.ip, Some(Ipv4Addr::new(10, 213, 7, 2)));
        assert_eq!((d.vendor_id, d.device_id, d.instance), (0xFFFF, 0x0001, 1));

        // Exactly the submodules of the model pnio checks the Connect against.
        let model = iop::model(&iop::declaration(NAME, iop::DEFAULT_SERIAL).unwrap());
        let mut want: Vec<_> = model
            .slots
            .iter()
            .flat_map(|s| {
                s.submodules.iter().map(move |sm| {
                    (
                        s.slot,
                        sm.subslot,
                        s.module_ident,
                        sm.submodule_ident,
                        sm.input_len,
                        sm.output_len,
                    )
                })
            })
            .collect();
        let mut got: Vec<_> = d
            .submodules
            .iter()
            .map(|s| {
                assert_eq!(s.api, 0);
                (
                    s.slot,
                    s.subslot,
                    s.module_ident,
                    s.submodule_ident,
                    s.input_length,
                    s.output_length,
                )
            })
            .collect();
        want.sort();
        got.sort();
        assert_eq!(got, want);
        assert_eq!(got.len(), 5, "DAP, interface, port, inputs, outputs");
    }
}

#[test]
fn gsdml_renders_the_declaration() {
    let path = std::env::temp_dir().join(format!("pnio-iop-{}.xml", std::process::id()));
    let p = path.to_str().unwrap();
    let (ok, out, err) = run_device(&[
        "--name",
        NAME,
        "--ip",
        "10.213.7.2",
        "--gsdml-out",
        p,
        "--gsdml-only",
    ]);
    let xml = std::fs::read_to_string(&path);
    let _ = std::fs::remove_file(&path);
    assert!(ok, "--gsdml-only failed: {err}");
    assert!(out.is_empty(), "{out}");
    let xml = xml.unwrap();
    for needle in [
        r#"<DeviceIdentity VendorID="0xFFFF" DeviceID="0x0001">"#,
        r#"ModuleIdentNumber="0x00000001""#,
        r#"<ModuleItem ID="M1" ModuleIdentNumber="0x00000101">"#,
        r#"<ModuleItem ID="M2" ModuleIdentNumber="0x00000102">"#,
        r#"SubmoduleIdentNumber="0x00008000""#,
        r#"SubmoduleIdentNumber="0x00008001""#,
        &format!(r#"DNS_CompatibleName="{NAME}""#),
        &format!(r#"<OrderNumber Value="{}"/>"#, iop::ORDER_ID),
    ] {
        assert!(xml.contains(needle), "no {needle} in the GSDML:\n{xml}");
    }
    assert!(xml.trim_end().ends_with("</ISO15745Profile>"));
}

/// The `procimg` binary: `PROCIMG_BIN`, or beside this test's target directory.
fn procimg_bin() -> PathBuf {
    workspace_bin("procimg", "PROCIMG_BIN", "procimg-tools")
}

/// Runs `procimg dcp --iface <controller end> ARGS` in the controller's namespace.
fn procimg_dcp(net: &Net, args: &[&str]) -> (bool, String, String) {
    let out = Command::new("ip")
        .args(["netns", "exec", net.controller_ns()])
        .arg(procimg_bin())
        .args(["dcp", "--iface", net.controller_if()])
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
fn procimg_dcp_finds_the_device_with_its_name_ip_and_ids() {
    assert!(
        procimg_testkit::netns::is_root(),
        "this test builds network namespaces, which needs root: run it as root"
    );
    let procimg = procimg_bin();
    assert!(procimg.exists());
    let net = Net::new("pd", 7);
    let mut device = Device::start(&net);
    let mac = net.device_mac();
    let ip = net.device_ip.to_string();

    let (ok, out, err) = procimg_dcp(&net, &["scan", "--wait-ms", "300"]);
    assert!(ok, "scan failed: {err}");
    let row = out
        .lines()
        .find(|l| l.starts_with(&mac))
        .unwrap_or_else(|| panic!("no row for {mac} in:\n{out}"));
    let cols: Vec<&str> = row.split_whitespace().collect();
    assert_eq!(cols[1], NAME, "{row}");
    assert_eq!(cols[2], ip, "{row}");
    assert_eq!(cols[3], "255.255.255.0", "{row}");
    assert_eq!(cols[4], "ffff:0001", "{row}");
    assert!(row.ends_with(iop::STATION_TYPE), "{row}");

    let (ok, out, err) = procimg_dcp(&net, &["scan", "--name", NAME, "--wait-ms", "200"]);
    assert!(ok && out.contains(&mac), "{out}{err}");
    let (ok, _, err) = procimg_dcp(
        &net,
        &["scan", "--name", "other-device", "--wait-ms", "200"],
    );
    assert!(!ok && err.contains("no device answered"), "{err}");

    // pnio never changes the interface: a Set of the IP suite it already has is confirmed,
    // any other suite and a new name are refused.
    let (ok, out, err) = procimg_dcp(&net, &["set-ip", &mac, &ip, "255.255.255.0"]);
    assert!(ok && out.contains("done"), "{out}{err}");
    let (ok, out, err) = procimg_dcp(&net, &["set-ip", &mac, "10.213.7.9", "255.255.255.0"]);
    assert!(
        !ok && out.contains("refused") && out.contains("01/02"),
        "{out}{err}"
    );
    let (ok, out, err) = procimg_dcp(&net, &["set-name", &mac, "renamed"]);
    assert!(
        !ok && out.contains("refused") && out.contains("02/02"),
        "{out}{err}"
    );

    let status = device.terminate();
    assert!(status.success(), "device exit: {status}");
    assert_eq!(device.seen, ["READY"], "no AR was made, so no other line");
}

/// An implicit read (ReadImplicit, no AR) of I&M0 of slot 0 subslot 1 from `from`.
fn read_im0(device: SocketAddr, from: Ipv4Addr) -> (PnioStatus, Vec<u8>) {
    let sock = UdpSocket::bind((from, 0)).unwrap();
    sock.set_read_timeout(Some(Duration::from_millis(500)))
        .unwrap();
    let header = Header::request(
        rpc::object_uuid(1, iop::DEVICE_ID, iop::VENDOR_ID),
        rpc::DEVICE_INTERFACE,
        Uuid([0x5a; 16]),
        0,
        rpc::opnum::READ_IMPLICIT,
    );
    let read = IodHeader::read_request(1, Uuid::NIL, 0, 0, 1, 0xAFF0, 1024).to_bytes();
    let request = rpc::emit_request(&header, 1024, &read).unwrap();
    let mut buf = [0u8; 1500];
    for _ in 0..6 {
        sock.send_to(&request, device).unwrap();
        let Ok((n, _)) = sock.recv_from(&mut buf) else {
            continue;
        };
        let (h, ndr, blocks) = rpc::parse_pdu(&buf[..n]).expect("an RPC PDU");
        assert_eq!(h.opnum, rpc::opnum::READ_IMPLICIT);
        let Ndr::Response(r) = ndr else {
            panic!("not a response: {h}")
        };
        return (r.status, blocks.to_vec());
    }
    panic!("no answer to the I&M0 read from {device}");
}

#[test]
#[ignore = "needs root (network namespaces): run as root with --ignored"]
fn implicit_record_read_of_im0_returns_the_identity() {
    assert!(
        procimg_testkit::netns::is_root(),
        "this test builds network namespaces, which needs root: run it as root"
    );
    let net = Net::new("pr", 8);
    let mut device = Device::start(&net);
    let to = SocketAddr::from((net.device_ip, rpc::RPC_PORT));
    let from = net.controller_ip;
    let (status, blocks) = net
        .net
        .in_ns(0, move |_| read_im0(to, from))
        .join()
        .unwrap();
    assert_eq!(status, PnioStatus::OK);
    let (res, data, rest) = IodHeader::split(&blocks).expect("an IODReadResHeader");
    assert_eq!(res.kind, IodKind::ReadRes);
    assert_eq!((res.slot, res.subslot, res.index), (0, 1, 0xAFF0));
    assert!(rest.is_empty());
    assert_eq!(blocks.len(), IOD_HEADER_LEN + data.len());
    let im0 = Im0::parse(data).expect("an I&M0 block");
    assert_eq!(im0.vendor_id, iop::VENDOR_ID);
    assert_eq!(im0.order_id_str(), Some(iop::ORDER_ID));
    assert_eq!(im0.serial_number_str(), Some(iop::DEFAULT_SERIAL));
    assert_eq!(im0.hardware_revision, iop::HARDWARE_REVISION);

    let status = device.terminate();
    assert!(status.success(), "device exit: {status}");
}
