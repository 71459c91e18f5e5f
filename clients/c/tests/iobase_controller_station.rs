// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller's own station on a real interface, as an engineering tool meets it over a
//! veth pair: `procimg dcp scan` finds it (its name, IP suite and type of station), and a
//! DCP Signal to it reaches a C program (`tests/c/iobase_led.c`, built with strict warnings)
//! as PNIO_CBE_START_LED_FLASH and, three seconds later, PNIO_CBE_STOP_LED_FLASH. Every
//! frame on the wire is tshark-clean.

use procimg_testkit::Launch;
use procimg_testkit::c::{Link, compile, crate_dir, sanitize_from_env, scratch};
use procimg_testkit::netns::TestNet;
use procimg_testkit::procimg_in_netns as procimg;
use procimg_testkit::tshark::{LiveCapture, flagged};
use procimg_testkit::veth_station::CONTROLLER_TOML;
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::Duration;

#[test]
#[ignore = "needs root: network namespaces, veth, AF_PACKET"]
fn engineering_tools_find_the_controllers_station_and_make_it_flash() {
    let net = TestNet::new("cs", true);
    net.address(0, "10.47.0.1/24");
    net.address(1, "10.47.0.9/24");
    let dir = procimg_testkit::files::temp_dir("controller-station");
    let pcap = dir.path().join("wire.pcapng");
    let capture = LiveCapture::start(&net.ns[1], &net.ifs[1], &pcap);
    let controller = Launch::config("csc", &CONTROLLER_TOML.replace("IFACE", &net.ifs[0]))
        .netns(&net.ns[0])
        .until_cycling()
        .start();
    let own = controller
        .status()
        .controller
        .expect("the controller's station");
    // The station joined the multicast groups it is addressed by, as a real NIC needs it.
    let groups = Command::new("ip")
        .args(["-n", &net.ns[0], "maddr", "show", "dev", &net.ifs[0]])
        .output()
        .expect("ip maddr");
    let groups = String::from_utf8_lossy(&groups.stdout);
    for group in [
        "01:0e:cf:00:00:00",
        "01:0e:cf:00:00:01",
        "01:80:c2:00:00:0e",
    ] {
        assert!(groups.contains(group), "{group} not joined:\n{groups}");
    }

    // The tool finds the controller's station.
    let (ok, scan) = procimg(&net.ns[1], &["dcp", "--iface", &net.ifs[1], "scan"]);
    assert!(ok, "{scan}");
    let line = scan
        .lines()
        .find(|l| l.contains(&own.station_name))
        .unwrap_or_else(|| panic!("the scan did not find \"{}\":\n{scan}", own.station_name));
    for part in [
        own.mac.as_str(),
        "10.47.0.1",
        "255.255.255.0",
        "procimg controller",
    ] {
        assert!(line.contains(part), "no {part} in {line}");
    }

    // A program waits for the LED events; the tool's Signal makes them come.
    let src = crate_dir().join("tests/c/iobase_led.c");
    let program = scratch("iobase_led").join("led");
    compile(&[src], &program, Link::Shared, sanitize_from_env());
    let mut child = Command::new(&program)
        .env_remove("LD_LIBRARY_PATH")
        .env("PROCIMG_INSTANCE", &controller.instance)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start the LED program");
    let mut out = BufReader::new(child.stdout.take().expect("its output"));
    let mut line = String::new();
    out.read_line(&mut line).expect("its first line");
    assert_eq!(line.trim(), "ready");
    let (ok, blink) = procimg(
        &net.ns[1],
        &["dcp", "--iface", &net.ifs[1], "blink", &own.mac],
    );
    assert!(ok, "{blink}");
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut out, &mut rest).expect("the rest of its output");
    let status = child.wait().expect("wait for it");
    let mut err = String::new();
    if let Some(mut e) = child.stderr.take() {
        let _ = std::io::Read::read_to_string(&mut e, &mut err);
    }
    assert!(
        status.success() && rest.contains("led: all checks held"),
        "{status:?}\n{rest}\n{err}"
    );

    std::thread::sleep(Duration::from_millis(200));
    let pcap = capture.stop();
    let bad = flagged(&pcap);
    assert!(bad.is_empty(), "tshark flags frames on the wire:\n{bad}");
}
