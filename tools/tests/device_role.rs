// SPDX-License-Identifier: MIT OR Apache-2.0
//! The command line in the device role, against `procimgd --demo-device` (whose PLC is
//! procimg's own controller), speaking as the PLC sees the station: `procimg status` shows the
//! station and its AR (the PLC's name and MAC), not an empty list of devices; `procimg
//! layout` puts a submodule's I data (what the PLC reads) in the I column; `procimg io`
//! calls the bytes Q data from the PLC and I data to it; `procimg diag` shows the station's
//! own diagnosis.

use procimg_client::{AttachOptions, Client, DiagnosisDirection, DiagnosisEntry};
use procimg_testkit::Launch;
use std::process::Command;
use std::time::{Duration, Instant};

fn procimg(instance: &str, args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_procimg"))
        .arg("--instance")
        .arg(instance)
        .args(args)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "procimg {args:?}: {text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

#[test]
fn status_layout_io_and_diag_speak_as_the_plc_sees_the_station() {
    // By default the launch waits until the AR is in data exchange.
    let server = Launch::demo_device("cli-device").start();
    let instance = server.instance.as_str();
    let text = procimg(instance, &["status"]);
    assert!(
        text.contains("station \"procimg-device\"  IP ")
            && text.contains("VendorID 0x0493  DeviceID 0x0100"),
        "{text}"
    );
    // The demo's PLC connects as "demo-plc".
    assert!(
        text.contains("AR in data exchange  with PLC \"demo-plc\" "),
        "{text}"
    );
    assert!(text.contains("ARs aborted "), "{text}");
    assert!(
        !text.contains("devices:"),
        "a device has no devices: {text}"
    );

    // The demo station: slot 1 has 8 bytes each way, slot 2 four bytes of I data only.
    let layout = procimg(instance, &["layout"]);
    assert!(
        layout.contains("bytes of I data (the PLC reads them"),
        "{layout}"
    );
    let row = |slot: &str| {
        layout
            .lines()
            .find(|l| l.split_whitespace().nth(2) == Some(slot))
            .map(|l| l.split_whitespace().collect::<Vec<_>>())
            .unwrap_or_else(|| panic!("slot {slot} in {layout}"))
    };
    let (slot1, slot2) = (row("1"), row("2"));
    assert_eq!(slot1[slot1.len() - 2..], ["0..7", "0..7"], "{layout}");
    assert_eq!(slot2[slot2.len() - 2..], ["8..11", "-"], "{layout}");

    // What the PLC writes, and what it reads, named so.
    let q = procimg(instance, &["io", "read", "0", "8"]);
    assert!(
        q.contains("(Q data from the PLC: the PLC's IOPS Good)"),
        "{q}"
    );
    let i = procimg(instance, &["io", "read", "--output", "8", "4"]);
    assert!(
        i.contains("(I data to the PLC: this station's IOPS "),
        "{i}"
    );
    let help = procimg(instance, &["io", "read", "--help"]);
    assert!(help.contains("the Q data the PLC writes"), "{help}");

    // No diagnosis yet; then a wire break on channel 1 of slot 1: the PLC is told, the
    // station problem indicator goes on, and `diag` shows it.
    let text = procimg(instance, &["diag"]);
    assert!(text.contains("no diagnosis pending"), "{text}");
    assert!(text.contains("station problem indicator off"), "{text}");
    let client = Client::attach(instance, AttachOptions::asynchronous("cli-diag")).unwrap();
    let wire_break = DiagnosisEntry {
        channel: 1,
        error_type: 6,
        direction: DiagnosisDirection::Input,
        ..DiagnosisEntry::default()
    };
    client.add_diagnosis((0, 1, 1), wire_break).unwrap();
    let until = Instant::now() + Duration::from_secs(10);
    let text = loop {
        let text = procimg(instance, &["diag"]);
        if text.contains("wire break") || Instant::now() >= until {
            break text;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    assert!(
        text.contains(
            "API 0 slot 1 subslot 0x0001: fault, channel 1 (input): wire break \
             (ChannelErrorType 0x0006)"
        ),
        "{text}"
    );
    assert!(text.contains("station problem indicator on"), "{text}");
    assert!(
        text.contains("AR in data exchange with PLC \"demo-plc\""),
        "{text}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&procimg(instance, &["diag", "--json"])).unwrap();
    assert_eq!(json["diagnosis"][0]["slot"], 1, "{json}");
    assert_eq!(json["diagnosis"][0]["entry"]["error_type"], 6, "{json}");
    assert_eq!(json["station_problem"], true, "{json}");
}
