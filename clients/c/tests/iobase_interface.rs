// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller's own interface (PN Driver's `PNIO_interface_*`) over a veth pair: a C
//! program (`tests/c/iobase_interface.c`, strict warnings) opens it on a procimgd whose
//! `[interface]` lets programs set the name and address and checks the port's link, with
//! procimg's device as the port's configured neighbour. The program reads the interface's
//! records, hears the port's alarms as the neighbour comes and the link goes down and up,
//! names the station and gives it another address (which the Linux interface then carries,
//! and which an engineering tool's DCP scan finds), and hears of the tool's own DCP rename.
//! Every frame on the wire is tshark-clean.

use procimg_testkit::Launch;
use procimg_testkit::c::{Link, compile, crate_dir, sanitize_from_env, scratch};
use procimg_testkit::netns::TestNet;
use procimg_testkit::procimg_in_netns as procimg;
use procimg_testkit::tshark::{LiveCapture, flagged};
use procimg_testkit::veth_station::{CONTROLLER_TOML, DEVICE_TOML};
use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};
use std::time::Duration;

fn ip(args: &[&str]) -> String {
    let out = Command::new("ip").args(args).output().expect("run ip");
    assert!(out.status.success(), "ip {args:?}: {out:?}");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The controller's interface section of the test.
const INTERFACE: &str = r#"
[[device.topology]]
station = "plc-ifc"
port = "port-001"
[interface]
station_name = "plc-ifc"
name_by_program = true
address_by_program = true
check_link = true
"#;

#[test]
#[ignore = "needs root: network namespaces, veth, AF_PACKET"]
fn a_program_reads_the_interface_hears_its_alarms_and_sets_its_name_and_address() {
    let net = TestNet::new("ifc", true);
    net.address(0, "10.47.0.1/24");
    let dir = procimg_testkit::files::temp_dir("controller-interface");
    let pcap = dir.path().join("wire.pcapng");
    let capture = LiveCapture::start(&net.ns[1], &net.ifs[1], &pcap);
    let controller = Launch::config(
        "ifcc",
        &(CONTROLLER_TOML.replace("IFACE", &net.ifs[0]) + INTERFACE),
    )
    .netns(&net.ns[0])
    .until_cycling()
    .start();
    let own = controller
        .status()
        .controller
        .expect("the controller's station");
    assert_eq!((own.interface_address, own.port_address), (16382, 16381));

    let src = crate_dir().join("tests/c/iobase_interface.c");
    let program = scratch("iobase_interface").join("interface");
    compile(&[src], &program, Link::Shared, sanitize_from_env());
    let mut child = Command::new(&program)
        .env_remove("LD_LIBRARY_PATH")
        .env("PROCIMG_INSTANCE", &controller.instance)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start the interface program");
    let mut stdin = child.stdin.take().expect("its input");
    let mut out = BufReader::new(child.stdout.take().expect("its output"));
    let mut device = None;
    let mut line = String::new();
    let mut steps = Vec::new();
    loop {
        line.clear();
        if out.read_line(&mut line).expect("its output") == 0 {
            break;
        }
        let step = line.trim().to_owned();
        match step.as_str() {
            // The configured neighbour comes.
            "ready" => {
                device = Some(
                    Launch::config(
                        "ifcd",
                        &DEVICE_TOML
                            .replace("IFACE", &net.ifs[1])
                            .replace(
                                "STATE",
                                &dir.path().join("station.toml").display().to_string(),
                            )
                            .replace("fresh-device", "pc-device"),
                    )
                    .netns(&net.ns[1])
                    .start(),
                );
            }
            "peer" => {
                ip(&["-n", &net.ns[1], "link", "set", "dev", &net.ifs[1], "down"]);
            }
            "down" => {
                ip(&["-n", &net.ns[1], "link", "set", "dev", &net.ifs[1], "up"]);
            }
            // The tool finds the program's name.
            "named" => {
                let (ok, scan) = procimg(
                    &net.ns[1],
                    &["dcp", "--iface", &net.ifs[1], "scan", "--name", "plc-ifc-2"],
                );
                assert!(ok && scan.contains(&own.mac), "{scan}");
                writeln!(stdin, "go").expect("tell the program");
            }
            // The interface carries the program's address; the tool renames the station.
            "addressed" => {
                let addresses = ip(&["-n", &net.ns[0], "-4", "addr", "show", "dev", &net.ifs[0]]);
                assert!(
                    addresses.contains("10.47.0.2/24") && !addresses.contains("10.47.0.1/"),
                    "{addresses}"
                );
                let (ok, scan) = procimg(
                    &net.ns[1],
                    &["dcp", "--iface", &net.ifs[1], "scan", "--name", "plc-ifc-2"],
                );
                assert!(ok && scan.contains("10.47.0.2"), "{scan}");
                let (ok, set) = procimg(
                    &net.ns[1],
                    &[
                        "dcp",
                        "--iface",
                        &net.ifs[1],
                        "set-name",
                        &own.mac,
                        "plc-ifc-3",
                    ],
                );
                assert!(ok, "{set}");
            }
            _ => {}
        }
        steps.push(step);
    }
    let status = child.wait().expect("wait for it");
    let mut err = String::new();
    if let Some(mut e) = child.stderr.take() {
        let _ = std::io::Read::read_to_string(&mut e, &mut err);
    }
    assert!(
        status.success()
            && steps
                .last()
                .is_some_and(|s| s == "interface: all checks held"),
        "{status:?}\nsteps: {steps:?}\n{err}"
    );
    let now = controller.status().controller.expect("the station");
    assert_eq!(
        (now.station_name.as_str(), now.ip.as_str()),
        ("plc-ifc-3", "10.47.0.2")
    );

    std::thread::sleep(Duration::from_millis(200));
    drop((controller, device));
    let pcap = capture.stop();
    let bad = flagged(&pcap);
    assert!(bad.is_empty(), "tshark flags frames on the wire:\n{bad}");
    drop((net, dir));
}
