// SPDX-License-Identifier: MIT OR Apache-2.0
//! A PN Driver program against procimg: `tests/c/pnd_startup.c`, built with strict warnings
//! against `servusrx.h` and `pniousrx.h`, linked static and shared (with ASan and UBSan when
//! `PROCIMG_C_SANITIZE=1`), starts its own stack (a procimgd with the demo's configuration,
//! a simulated plant: no root) and lives the whole PN Driver life; and when it dies, its
//! stack ends with it.

use procimg_client::iobase::{instance_serves, network_adapters};
use procimg_testkit::c::{
    Link, assert_success, compile, crate_dir, run_with_env, sanitize_from_env, scratch,
};
use procimg_testkit::{procimgd_bin, unique_instance};
use std::path::PathBuf;
use std::time::{Duration, Instant};

const RUN_TIMEOUT: Duration = Duration::from_secs(120);

fn build(link: Link) -> PathBuf {
    let src = crate_dir().join("tests/c/pnd_startup.c");
    let out = scratch("pn_driver").join(format!("pnd_startup-{link:?}").to_lowercase());
    compile(&[src], &out, link, sanitize_from_env());
    out
}

/// The demo's configuration in a file, as a PN Driver program reads its own, with the
/// controller's name settable by programs (and so by retentive data).
fn demo_config(tag: &str) -> PathBuf {
    let out = std::process::Command::new(procimgd_bin())
        .arg("--print-demo-config")
        .output()
        .expect("run procimgd --print-demo-config");
    assert!(out.status.success());
    let path = scratch("pn_driver").join(format!("{tag}.toml"));
    let mut text = out.stdout;
    text.extend_from_slice(b"\n[interface]\nname_by_program = true\n");
    std::fs::write(&path, text).unwrap();
    path
}

/// procimgd processes serving `instance` (their command line names it).
fn stacks_of(instance: &str) -> Vec<u32> {
    let Ok(dir) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    dir.filter_map(Result::ok)
        .filter_map(|e| e.file_name().to_str()?.parse::<u32>().ok())
        .filter(|pid| {
            std::fs::read(format!("/proc/{pid}/cmdline")).is_ok_and(|c| {
                let args: Vec<&[u8]> = c.split(|b| *b == 0).collect();
                args.first().is_some_and(|a| a.ends_with(b"procimgd"))
                    && args.contains(&instance.as_bytes())
            })
        })
        .collect()
}

/// SEQUENCE before init, between init and startup and after shutdown; the adapters listed;
/// startup refusing NrOfCp 2, NULL pointers, length 0, retentive data, XML that is no PN
/// Driver configuration, a configuration procimgd refuses (its line and key in the last
/// error), an adapter the machine lacks and an unknown CpSelection; then the stack: trace levels set and
/// confirmed, a controller in OPERATE whose echo device returns the outputs written,
/// shutdown refused while it is open, then closed, shut down and undone; procimgd's log
/// lines reached the trace callback.
#[test]
fn a_pn_driver_program_starts_uses_and_ends_its_own_stack() {
    let adapters = network_adapters().expect("read /sys/class/net");
    assert!(
        !adapters.is_empty(),
        "this machine has no Ethernet interface for the program to choose"
    );
    let procimgd = procimgd_bin();
    // CP 2: a station in the device role, whose firmware information the program asks too.
    let device = procimg_testkit::Launch::demo_device("pnd-dev")
        .until_cycling()
        .start();
    let station = device.status().station.expect("a station");
    let nobody = unique_instance("pnd-nobody");
    for link in [Link::Static, Link::Shared] {
        let instance = unique_instance("pnd");
        let config = demo_config(&instance);
        let program = build(link);
        let o = run_with_env(
            &program,
            &["run", config.to_str().unwrap()],
            &instance,
            &[
                ("PROCIMGD", procimgd.as_os_str()),
                ("PROCIMG_CP2", device.instance.as_ref()),
                ("PROCIMG_CP3", nobody.as_ref()),
            ],
            RUN_TIMEOUT,
        );
        assert_success(&o, &format!("pnd_startup run ({link:?})"));
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(
            stdout.contains("pnd: all checks held"),
            "pnd_startup ({link:?}) said:\n{stdout}"
        );
        // The adapters the program listed are the machine's, in its order.
        let listed: Vec<&str> = stdout
            .lines()
            .filter_map(|l| l.strip_prefix("adapter "))
            .filter_map(|l| l.split_whitespace().next())
            .collect();
        let names: Vec<&str> = adapters.iter().map(|a| a.name.as_str()).collect();
        assert_eq!(listed, names, "SERV_CP_get_network_adapters ({link:?})");
        // SERV_CP_get_fw_info of the stack (a controller) and of the station.
        let version = env!("CARGO_PKG_VERSION");
        let fw = |cp: u32| {
            stdout
                .lines()
                .find_map(|l| l.strip_prefix(&format!("fw {cp}: ")))
                .unwrap_or_else(|| panic!("no fw {cp} line in:\n{stdout}"))
                .to_owned()
        };
        // cp_ser_nr holds 15 characters and the NUL.
        let serial = |i: &str| i[..i.len().min(15)].to_owned();
        let controller = fw(1);
        assert!(
            controller.starts_with(&format!(
                "version {version} ser {} mlfb procimgd hw 0",
                serial(&instance)
            )) && controller.ends_with("name plc-from-rema type procimg controller"),
            "the stack's firmware information, its name the retentive data's: {controller}"
        );
        let want = format!(
            "version {version} ser {} mlfb {} hw {} mac {} ip {} name {} type {}",
            serial(&device.instance),
            station.order_number,
            station.hardware_revision,
            station.mac,
            station.ip,
            station.name,
            station.type_of_station
        );
        assert_eq!(fw(2), want, "the station's firmware information");
        assert!(!instance_serves(&instance));
        assert!(stacks_of(&instance).is_empty(), "no procimgd left behind");
    }
}

/// A program that dies (abort) with its stack serving and a controller open: the stack
/// stops by itself, and its shared memory is released.
#[test]
fn a_stack_ends_with_the_program_that_started_it() {
    let instance = unique_instance("pnd-crash");
    let config = demo_config(&instance);
    let program = build(Link::Shared);
    let procimgd = procimgd_bin();
    let o = run_with_env(
        &program,
        &["crash", config.to_str().unwrap()],
        &instance,
        &[("PROCIMGD", procimgd.as_os_str())],
        RUN_TIMEOUT,
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("stack serving") && !o.status.success(),
        "the program should have started its stack and died: {:?}\n{stdout}\n{}",
        o.status,
        String::from_utf8_lossy(&o.stderr)
    );
    let until = Instant::now() + Duration::from_secs(30);
    while !stacks_of(&instance).is_empty() && Instant::now() < until {
        std::thread::sleep(Duration::from_millis(50));
    }
    assert!(
        stacks_of(&instance).is_empty(),
        "procimgd of instance {instance} outlived its program"
    );
    assert!(!instance_serves(&instance));
    // It stopped as procimgd stops, though its standard error had gone with the program:
    // its shared memory is released (a dead client's handshake block goes at the next
    // start of the instance, as always).
    let leftovers: Vec<String> = std::fs::read_dir("/dev/shm")
        .map(|d| {
            d.filter_map(Result::ok)
                .filter_map(|e| e.file_name().to_str().map(str::to_owned))
                .filter(|n| n.contains(&instance.replace('-', "_")) && n.ends_with(".doorbell"))
                .collect()
        })
        .unwrap_or_default();
    assert!(leftovers.is_empty(), "left in /dev/shm: {leftovers:?}");
}

/// Over a real interface: the program in one network namespace chooses the veth end there
/// (its configuration names an interface this machine lacks, or none), its stack connects
/// procimg's device role in the other namespace, and the outputs it writes come back as the
/// station's inputs (the station's program echoes them). Once with procimg's configuration,
/// once with TIA Portal's PN Driver configuration of the same plant, whose controller name
/// the stack takes.
#[test]
#[ignore = "needs root: network namespaces, veth, AF_PACKET"]
fn a_pn_driver_program_drives_the_adapter_it_chose() {
    use procimg_testkit::netns::TestNet;
    use procimg_testkit::veth_station::{CONTROLLER_PN_DRIVER_XML, CONTROLLER_TOML, DEVICE_TOML};
    let net = TestNet::new("pd", true);
    net.address(0, "10.47.0.1/24");
    net.address(1, "10.47.0.50/24");
    let dir = procimg_testkit::files::temp_dir("pn-driver-veth");
    let state = dir.path().join("station.toml");
    let device_toml = DEVICE_TOML
        .replace("IFACE", &net.ifs[1])
        .replace("STATE", &state.display().to_string())
        .replace("fresh-device", "pc-device");
    let device = procimg_testkit::Launch::config("pdd", &device_toml)
        .netns(&net.ns[1])
        .until_cycling()
        .start();
    let echo = procimg_testkit::exchange::device_echo(device.instance.clone(), 60_000);

    let toml = dir.path().join("plant.toml");
    std::fs::write(&toml, CONTROLLER_TOML.replace("IFACE", "pnd0")).unwrap();
    let xml = dir
        .path()
        .join("Station_1.PN Driver_1.PNDriverConfiguration.xml");
    std::fs::write(&xml, CONTROLLER_PN_DRIVER_XML).unwrap();
    let program = build(Link::Shared);
    let procimgd = procimgd_bin();
    for (config, name) in [(&toml, None), (&xml, Some("plc-pn-driver"))] {
        let instance = unique_instance("pnd-veth");
        let o = run_with_env(
            std::path::Path::new("ip"),
            &[
                "netns",
                "exec",
                &net.ns[0],
                program.to_str().unwrap(),
                "veth",
                config.to_str().unwrap(),
                &net.ifs[0],
            ],
            &instance,
            &[("PROCIMGD", procimgd.as_os_str())],
            RUN_TIMEOUT,
        );
        let what = format!("pnd_startup veth {}", config.display());
        assert_success(&o, &what);
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(
            stdout.contains(&format!("echoed the outputs over {}", net.ifs[0]))
                && stdout.contains("veth: all checks held"),
            "{what} said:\n{stdout}"
        );
        if let Some(name) = name {
            let fw = stdout
                .lines()
                .find(|l| l.starts_with("fw 1: "))
                .unwrap_or_else(|| panic!("{what} printed no firmware information:\n{stdout}"));
            assert!(
                fw.contains(&format!(" ip 10.47.0.1 name {name} type ")),
                "the stack's station is the project's: {fw}"
            );
        }
        assert!(stacks_of(&instance).is_empty(), "no procimgd left behind");
    }
    drop(device);
    let _ = echo.join();
}
