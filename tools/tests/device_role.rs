// SPDX-License-Identifier: MIT OR Apache-2.0
//! The command line in the device role, against `procimgd --demo-device` (whose PLC is
//! procimg's own controller): `procimg status` shows the station and its AR as the PLC sees
//! them, not an empty list of devices; `procimg layout` puts a submodule's I data (what the
//! PLC reads) in the I column.

use procimg_testkit::Launch;
use std::process::Command;

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
fn status_and_layout_speak_as_the_plc_sees_the_station() {
    // By default the launch waits until the AR is in data exchange.
    let server = Launch::demo_device("cli-device").start();
    let text = procimg(&server.instance, &["status"]);
    assert!(
        text.contains("station \"procimg-device\"  IP ")
            && text.contains("VendorID 0x0493  DeviceID 0x0100"),
        "{text}"
    );
    assert!(text.contains("AR in data exchange  with PLC "), "{text}");
    assert!(text.contains("ARs aborted "), "{text}");
    assert!(
        !text.contains("devices:"),
        "a device has no devices: {text}"
    );
}
