// SPDX-License-Identifier: MIT OR Apache-2.0
//! As root: the station's SNMP through net-snmp's snmpd, started by the test in the
//! station's network namespace after procimgd (which waits for it and attaches when it
//! comes). procimg's controller is the PLC on the other end of the veth pair and the
//! port's LLDP neighbour. snmpwalk and snmpget read the system group (sysName the
//! NameOfStation, sysLocation the I&M1 location the PLC writes) and the LLDP-MIB (the
//! local system and port, the neighbour).

use procimg_client::{ArState, RecordTarget, ServiceOptions, Services};
use procimg_testkit::Launch;
use procimg_testkit::netns::TestNet;
use procimg_testkit::snmpd::Snmpd;
use procimg_testkit::veth_station::{CONTROLLER_TOML, DEVICE_TOML};
use std::time::{Duration, Instant};

const SYS_NAME: &str = "1.3.6.1.2.1.1.5.0";
const SYS_LOCATION: &str = "1.3.6.1.2.1.1.6.0";
const LLDP_MIB: &str = "1.0.8802.1.1.2";

fn in_data(s: &procimg_client::StatusReport) -> bool {
    s.station
        .as_ref()
        .and_then(|st| st.ar.as_ref())
        .is_some_and(|ar| ar.state == ArState::Data)
}

/// The value snmpget gives `oid` (`STRING: "…"` as `"…"`), or what it says instead.
fn get(snmpd: &Snmpd, oid: &str) -> String {
    let out = snmpd.tool("/usr/bin/snmpget", &[oid]);
    out.split_once(" = ")
        .map(|(_, v)| v.split_once(": ").map_or(v, |(_, v)| v).trim().to_owned())
        .unwrap_or(out)
}

/// Waits (30 s at most) until `oid` reads `want`.
fn until_reads(snmpd: &Snmpd, oid: &str, want: &str) {
    let until = Instant::now() + Duration::from_secs(30);
    loop {
        let got = get(snmpd, oid);
        if got == want {
            return;
        }
        assert!(
            Instant::now() < until,
            "{oid} reads {got} rather than {want} after 30 s; snmpd's log:\n{}",
            snmpd.log()
        );
        std::thread::sleep(Duration::from_millis(200));
    }
}

#[test]
#[ignore = "needs root: network namespaces, veth, AF_PACKET, snmpd"]
fn snmpd_serves_the_stations_system_group_and_lldp_mib_from_procimgd() {
    procimg_testkit::snmpd::require_net_snmp();
    let net = TestNet::new("sn", true);
    net.address(0, "10.47.0.1/24");
    let dir = procimg_testkit::files::temp_dir("snmp");
    let socket = dir.path().join("agentx");
    let state = dir.path().join("station.toml");
    let device_toml = DEVICE_TOML
        .replace("IFACE", &net.ifs[1])
        .replace(
            "state_file = \"STATE\"",
            &format!(
                "state_file = \"{}\"\nsnmp_agentx = \"{}\"",
                state.display(),
                socket.display()
            ),
        )
        .replace("fresh-device", "pc-device");
    let device = Launch::config("snd", &device_toml)
        .netns(&net.ns[1])
        .until_cycling()
        .start();
    let plc = Launch::config("snc", &CONTROLLER_TOML.replace("IFACE", &net.ifs[0]))
        .netns(&net.ns[0])
        .until_cycling()
        .start();
    plc.wait_devices_running(Duration::from_secs(30));
    device.wait_status("the AR in data exchange", in_data);
    device.wait_status("the controller as the port's neighbour", |s| {
        s.station
            .as_ref()
            .is_some_and(|st| st.neighbours.len() == 1)
    });
    let controller_name = format!("procimgd-{}", plc.instance.to_ascii_lowercase());

    // snmpd comes after procimgd: procimgd attaches when it does.
    let snmpd = Snmpd::start(dir.path(), &socket, Some(&net.ns[1]));
    until_reads(&snmpd, SYS_NAME, "\"pc-device\"");

    // The LLDP-MIB: the local system's name, its port, the controller as its neighbour.
    let walk = snmpd.tool("/usr/bin/snmpwalk", &[LLDP_MIB]);
    let value = |prefix: &str| {
        walk.lines()
            .filter(|l| l.starts_with(&format!(".{prefix}")))
            .filter_map(|l| l.split_once(" = ").map(|(_, v)| v.to_owned()))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        value("1.0.8802.1.1.2.1.3.3.0"),
        ["STRING: \"pc-device\""],
        "lldpLocSysName in:\n{walk}"
    );
    assert_eq!(
        value("1.0.8802.1.1.2.1.3.7.1.3.1"),
        ["STRING: \"port-001\""],
        "lldpLocPortId in:\n{walk}"
    );
    let remote_chassis = value("1.0.8802.1.1.2.1.4.1.1.5.");
    assert_eq!(
        remote_chassis,
        [format!("STRING: \"{controller_name}\"")],
        "lldpRemChassisId in:\n{walk}"
    );
    let remote_port = value("1.0.8802.1.1.2.1.4.1.1.7.");
    assert_eq!(
        remote_port,
        ["STRING: \"port-001\""],
        "lldpRemPortId in:\n{walk}"
    );

    // The PLC writes I&M1: its location tag is sysLocation.
    let mut services = Services::open(&plc.instance, ServiceOptions::new("sn-records"))
        .expect("the controller's services");
    let mut im1 = vec![0x00, 0x21, 0x00, 0x38, 0x01, 0x00];
    im1.extend_from_slice(&[b' '; 32]);
    im1.extend_from_slice(b"hall 7, line 2        ");
    services
        .write_record(
            RecordTarget {
                device: 0,
                api: 0,
                slot: 0,
                subslot: 1,
                index: 0xaff1,
            },
            &im1,
            Duration::from_secs(10),
        )
        .expect("write I&M1");
    until_reads(&snmpd, SYS_LOCATION, "\"hall 7, line 2\"");
    drop((services, snmpd, plc, device, net, dir));
}
