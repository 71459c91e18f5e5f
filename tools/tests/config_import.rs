// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg config import`: TIA Portal's PN Driver configuration printed as procimgd's own,
//! which procimgd's checks take as it is; without `--network` the interface is left for
//! procimgd's `--adapter`; a project procimgd cannot run refused with the XML's line.

use std::process::{Command, Output};

const PC_DEVICE: &str = "../config/tests/data/pn-driver/pc-device.xml";

fn procimg(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_procimg"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(["config", "import"])
        .args(args)
        .env_remove("PROCIMG_INSTANCE")
        .output()
        .unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn the_project_prints_as_a_configuration_procimgd_takes() {
    let out = procimg(&[PC_DEVICE, "--network", "eth3"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let toml = text(&out.stdout);
    let config = procimg_config::parse(&toml, "imported").unwrap();
    assert_eq!(
        config.network,
        procimg_config::Network::Interface("eth3".into())
    );
    assert_eq!(config.devices.len(), 1);
    assert_eq!(config.devices[0].name, "pc-device");
    assert!(
        toml.contains("# \"IO 8/8_1\", line "),
        "the tables name the project's objects:\n{toml}"
    );

    let out = procimg(&[PC_DEVICE]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("network = \"pnd-adapter\""));
}

#[test]
fn a_project_procimgd_cannot_run_is_refused_with_its_line() {
    let dir = std::env::temp_dir().join(format!("procimg-import-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let xml =
        std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(PC_DEVICE))
            .unwrap();
    // The device's identity block lost.
    let cut = xml.replace("<Field Key=\"12384\"", "<Field Key=\"12385\"");
    let path = dir.join("cut.xml");
    std::fs::write(&path, cut).unwrap();
    let out = procimg(&[path.to_str().unwrap()]);
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("cut.xml:") && err.contains("PNIOD_PROPERTIES"),
        "{err}"
    );
}
