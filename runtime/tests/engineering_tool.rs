// SPDX-License-Identifier: MIT OR Apache-2.0
//! As root: procimgd in the device role on one end of a veth pair, procimg's controller as
//! its PLC and an engineering tool — profinet-py (PyPI), an independent implementation — on
//! the other. The tool opens a device access AR beside the PLC's AR and reads the physical
//! device (the interface, the port and the controller as its LLDP neighbour), ARData and
//! I&M0, writes I&M1 and releases its AR; the PLC's AR runs on untouched.
//!
//! profinet-py lives in a virtual environment: `PROFINET_PY` names its interpreter, by
//! default `target/profinet-py-venv/bin/python`, which CI makes with
//! `python3 -m venv target/profinet-py-venv && target/profinet-py-venv/bin/pip install
//! profinet-py==0.6.6`.

use procimg_client::{ArState, Notification, ServiceOptions, Services};
use procimg_testkit::Launch;
use procimg_testkit::netns::TestNet;
use procimg_testkit::veth_station::{CONTROLLER_TOML, DEVICE_TOML};
use std::path::PathBuf;
use std::process::Command;
use std::time::Duration;

fn profinet_py() -> PathBuf {
    procimg_testkit::pypi::venv_python("PROFINET_PY", "profinet-py-venv", "profinet-py==0.6.6")
}

fn in_data(s: &procimg_client::StatusReport) -> bool {
    s.station
        .as_ref()
        .and_then(|st| st.ar.as_ref())
        .is_some_and(|ar| ar.state == ArState::Data)
}

#[test]
#[ignore = "needs root: network namespaces, veth, AF_PACKET"]
fn an_engineering_tool_reads_the_station_beside_the_plcs_ar() {
    let python = profinet_py();
    let net = TestNet::new("et", true);
    net.address(0, "10.47.0.1/24");
    let dir = procimg_testkit::files::temp_dir("engineering-tool");
    let device_toml = DEVICE_TOML
        .replace("IFACE", &net.ifs[1])
        .replace(
            "STATE",
            &dir.path().join("station.toml").display().to_string(),
        )
        .replace("fresh-device", "pc-device");
    let device = Launch::config("etd", &device_toml)
        .netns(&net.ns[1])
        .until_cycling()
        .start();
    // The station's program hears of its neighbour (GOAL's LLDP_UPDATE).
    let mut events = Services::open(&device.instance, ServiceOptions::new("et-events"))
        .expect("the station's services");
    let plc = Launch::config("etc", &CONTROLLER_TOML.replace("IFACE", &net.ifs[0]))
        .netns(&net.ns[0])
        .until_cycling()
        .start();
    plc.wait_devices_running(Duration::from_secs(30));
    let running = device.wait_status("the PLC's AR in data exchange", in_data);
    let plc_ar = running
        .station
        .as_ref()
        .unwrap()
        .ar
        .clone()
        .unwrap()
        .ar_uuid;
    device.wait_status("the controller as the port's neighbour", |s| {
        s.station
            .as_ref()
            .is_some_and(|st| st.neighbours.len() == 1)
    });
    let station = running.station.unwrap();
    let controller_name = format!("procimgd-{}", plc.instance.to_ascii_lowercase());
    let told = std::iter::from_fn(|| events.next(Duration::from_secs(10))).find_map(|n| match n {
        Notification::StationNeighbours {
            port, neighbours, ..
        } => Some((port, neighbours)),
        _ => None,
    });
    let (port, neighbours) = told.expect("a neighbour notification");
    assert_eq!(port, 1);
    assert_eq!(neighbours.len(), 1, "{neighbours:?}");
    assert_eq!(
        neighbours[0].station.as_deref(),
        Some(controller_name.as_str())
    );

    let script = procimg_testkit::workspace_dir().join("interop/profinet-py/engineering_tool.py");
    let out = Command::new("ip")
        .args(["netns", "exec", &net.ns[0]])
        .arg(&python)
        .arg(&script)
        .args([
            "--ip",
            "10.47.0.50",
            "--mac",
            &station.mac,
            "--name",
            "pc-device",
        ])
        .args(["--vendor", "0x0493", "--device", "0x0100"])
        .args(["--src-mac", "02:00:00:00:00:77"])
        .output()
        .expect("run profinet-py");
    assert!(
        out.status.success(),
        "profinet-py failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let got: serde_json::Value = serde_json::from_slice(&out.stdout).expect("profinet-py's JSON");

    // PDRealData: the interface, and the port with the controller as its one neighbour.
    let interface = &got["interface"];
    assert_eq!(interface["chassis_id"], "pc-device", "{got}");
    assert_eq!(interface["mac"], station.mac.to_lowercase(), "{got}");
    assert_eq!(interface["ip"], "10.47.0.50", "{got}");
    assert_eq!(
        got["slots"],
        serde_json::json!([
            [0, 0, 0x8000, ["PDInterfaceDataReal", "PDPortStatistic"]],
            [0, 0, 0x8001, ["PDPortDataReal", "PDPortStatistic"]]
        ]),
        "{got}"
    );
    assert_eq!(
        got["ports"],
        serde_json::json!([{"slot": 0, "subslot": 0x8001, "port_id": "port-001", "peers": 1}]),
        "{got}"
    );
    assert_eq!(
        got["topology_ports"],
        serde_json::json!([[0, 0x8001, "port-001"]])
    );
    assert_eq!(got["port_info"], serde_json::json!([0, 0x8001, "port-001"]));
    // ARData: the PLC's IO AR first (profinet-py reads its ARUUID; the rest of ARData
    // version 1.1 it takes for version 1.0's layout).
    let ar_uuid = plc_ar.replace('-', "");
    let told = got["ar_info"]["ar_uuid"]
        .as_str()
        .unwrap_or("")
        .replace(':', "");
    assert_eq!(told, ar_uuid, "{got}");
    // I&M0 read, I&M1 written and read back.
    assert_eq!(got["im0"]["vendor_id"], 0x0493, "{got}");
    assert_eq!(got["im0"]["order_id"], "PC-DEVICE-TEST", "{got}");
    assert_eq!(got["im1_location"], "hall-3 line-2", "{got}");

    // The PLC's AR ran on: the same AR, nothing aborted; the tool's AR is gone.
    let after = device.status().station.unwrap();
    assert_eq!(after.ar.map(|a| a.ar_uuid), Some(plc_ar));
    assert_eq!(after.aborted_ars, 0);
    assert!(after.access_ar.is_none(), "{:?}", after.access_ar);
    drop((plc, device, net, dir));
}
