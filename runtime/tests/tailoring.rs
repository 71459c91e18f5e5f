// SPDX-License-Identifier: MIT OR Apache-2.0
//! Configuration control of the IO system ("tailoring") through the real procimgd, on the
//! simulated network: optional devices wait deactivated; a tailoring brings up the optional
//! device the machine has and leaves the one it lacks (absent from the network) down, and
//! writes the joined ports' expected neighbours, which the devices hold as their
//! PDPortDataCheck; a tailoring naming a mandatory device or a fixed port is refused,
//! changing nothing; DEACT takes every device down.

use procimg_client::{
    DeviceState, Notification, PortRef, RecordTarget, ServiceOptions, Services, Tailoring,
    TailoringRefusal,
};
use procimg_profinet::wire::record::{INDEX_PD_PORT_DATA_CHECK, PdPortDataCheck};
use procimg_testkit::Launch;
use std::time::{Duration, Instant};

const WAIT: Duration = Duration::from_secs(10);

/// A simulated device with its access point, two ports and 4 bytes each way; optional or
/// not, its port 2 (and for optional ones port 1 too) with a programmable peer.
fn device(name: &str, ip: &str, sim: &str, optional: bool) -> String {
    let mut t = format!(
        "[[device]]\nname = \"{name}\"\nip = \"{ip}\"\nvendor_id = 0x0493\ndevice_id = 0x0001\n\
         sim = \"{sim}\"\nwatchdog_factor = 100\noptional = {optional}\n"
    );
    for (subslot, ident) in [(1, 1), (0x8000, 0x8000), (0x8001, 0x8001), (0x8002, 0x8002)] {
        t += &format!(
            "[[device.submodule]]\nslot = 0\nsubslot = {subslot:#x}\nmodule_ident = 1\n\
             submodule_ident = {ident:#x}\n"
        );
    }
    t += "[[device.submodule]]\nslot = 1\nsubslot = 1\nmodule_ident = 0x20\n\
          submodule_ident = 1\ninput_length = 4\noutput_length = 4\n";
    t += "[[device.topology]]\nsubslot = 0x8002\nprogrammable = true\n";
    if optional {
        t += "[[device.topology]]\nsubslot = 0x8001\nprogrammable = true\n";
    } else {
        t += "[[device.topology]]\nsubslot = 0x8001\nstation = \"plc\"\nport = \"port-001\"\n";
    }
    t
}

fn states(s: &Services) -> Vec<DeviceState> {
    s.control()
        .status()
        .expect("status")
        .devices
        .iter()
        .map(|d| d.state)
        .collect()
}

fn wait_states(s: &Services, want: &[DeviceState]) {
    let until = Instant::now() + WAIT;
    loop {
        let now = states(s);
        if now == want {
            return;
        }
        assert!(
            Instant::now() < until,
            "states {now:?}, waited for {want:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The confirmation of this subscriber's reconfiguration.
fn reconfigured(s: &mut Services) -> (bool, Option<TailoringRefusal>) {
    let until = Instant::now() + WAIT;
    while Instant::now() < until {
        if let Some(Notification::Reconfigured {
            active, refused, ..
        }) = s.next(Duration::from_millis(100))
        {
            return (active, refused);
        }
    }
    panic!("no Reconfigured notification");
}

fn port(device: u32, subslot: u16) -> PortRef {
    PortRef {
        device,
        slot: 0,
        subslot,
    }
}

/// The PDPortDataCheck the device holds for a port (read back from it).
fn port_check(s: &mut Services, device: u32, subslot: u16) -> Option<PdPortDataCheck> {
    let target = RecordTarget {
        device,
        api: 0,
        slot: 0,
        subslot,
        index: INDEX_PD_PORT_DATA_CHECK,
    };
    let data = s.read_record(target, 4096, WAIT).ok()?;
    PdPortDataCheck::parse(&data).ok()
}

#[test]
fn tailoring_brings_up_the_optional_devices_present_and_checks_the_ports_joined() {
    use DeviceState::{Deactivated, Running};
    let config = format!(
        "network = \"sim\"\n{}{}{}",
        device("mandatory", "10.0.0.2", "echo", false),
        device("opt-present", "10.0.0.3", "echo", true),
        device("opt-absent", "10.0.0.4", "absent", true)
    );
    let server = Launch::config("tailoring", &config).until_cycling().start();
    let mut s = Services::open(&server.instance, ServiceOptions::new("tailor")).expect("open");
    // The optional devices wait for the tailoring.
    wait_states(&s, &[Running, Deactivated, Deactivated]);

    // Refused, changing nothing: a mandatory device named as optional, a fixed port joined.
    s.reconfigure_io_system(Some(Tailoring {
        devices: vec![0],
        links: vec![],
    }))
    .expect("taken");
    let (_, refused) = reconfigured(&mut s);
    assert!(
        matches!(&refused, Some(TailoringRefusal::Station { device: 0, reason }) if reason.contains("not optional")),
        "{refused:?}"
    );
    s.reconfigure_io_system(Some(Tailoring {
        devices: vec![1],
        links: vec![[port(0, 0x8001), port(1, 0x8001)]],
    }))
    .expect("taken");
    let (_, refused) = reconfigured(&mut s);
    assert!(
        matches!(&refused, Some(TailoringRefusal::Port { port: p, .. }) if *p == port(0, 0x8001)),
        "{refused:?}"
    );
    assert_eq!(states(&s), [Running, Deactivated, Deactivated]);

    // The machine has opt-present, joined to the mandatory device's port 2.
    s.reconfigure_io_system(Some(Tailoring {
        devices: vec![1],
        links: vec![[port(0, 0x8002), port(1, 0x8001)]],
    }))
    .expect("taken");
    assert_eq!(reconfigured(&mut s), (true, None));
    wait_states(&s, &[Running, Running, Deactivated]);
    let check = port_check(&mut s, 0, 0x8002).expect("mandatory's port 2 holds a check");
    let peer = &check.peers().expect("CheckPeers")[0];
    assert_eq!(
        (peer.chassis_id.as_str(), peer.port_id.as_str()),
        ("opt-present", "port-001")
    );
    let check = port_check(&mut s, 1, 0x8001).expect("opt-present's port 1 holds a check");
    let peer = &check.peers().expect("CheckPeers")[0];
    assert_eq!(
        (peer.chassis_id.as_str(), peer.port_id.as_str()),
        ("mandatory", "port-002")
    );

    // DEACT: every device down.
    s.reconfigure_io_system(None).expect("taken");
    assert_eq!(reconfigured(&mut s), (false, None));
    wait_states(&s, &[Deactivated, Deactivated, Deactivated]);
}

/// `procimg device tailor` and `procimg device deactivate-all`, as an operator runs them.
#[test]
fn the_command_line_tailors_and_deactivates() {
    use DeviceState::{Deactivated, Running};
    let config = format!(
        "network = \"sim\"\n{}{}",
        device("conveyor", "10.0.0.2", "echo", false),
        device("labeller", "10.0.0.3", "echo", true),
    );
    let server = Launch::config("tailoring-cli", &config)
        .until_cycling()
        .start();
    let procimg = procimg_testkit::workspace_bin("procimg", "PROCIMG_BIN", "procimg-tools");
    let run = |args: &[&str]| {
        let out = std::process::Command::new(&procimg)
            .args(["--instance", &server.instance, "device"])
            .args(args)
            .output()
            .expect("run procimg");
        (
            out.status.success(),
            String::from_utf8_lossy(&out.stdout).into_owned()
                + &String::from_utf8_lossy(&out.stderr),
        )
    };
    let s = Services::open(&server.instance, ServiceOptions::new("cli-watch")).expect("open");
    wait_states(&s, &[Running, Deactivated]);

    let (ok, text) = run(&["tailor", "conveyor"]);
    assert!(!ok && text.contains("not optional"), "{text}");
    let (ok, text) = run(&[
        "tailor",
        "labeller",
        "--link",
        "conveyor:0x8001=labeller:0x8001",
    ]);
    assert!(!ok && text.contains("programmable"), "{text}");
    let (ok, text) = run(&[
        "tailor",
        "labeller",
        "--link",
        "conveyor:0x8002=labeller:0x8001",
    ]);
    assert!(ok && text.contains("IO system tailored"), "{text}");
    wait_states(&s, &[Running, Running]);
    let (ok, text) = run(&["deactivate-all"]);
    assert!(ok && text.contains("every device deactivated"), "{text}");
    wait_states(&s, &[Deactivated, Deactivated]);
}
