// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg gsdml`: the device demo's GSDML file to standard output, to a file and into a
//! directory under its standard name, the same as the writer's, also where the configured
//! interface does not exist; a controller configuration and a broken one refused with what
//! to do.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use procimg_config::gsdml::Gsdml;
use procimg_config::gsdml::export::{GsdmlDate, station_gsdml};
use procimg_config::{Config, DEMO_DEVICE_TOML, DEMO_TOML};

/// A fresh directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("procimg-gsdml-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn procimg(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_procimg"))
        .current_dir(dir)
        .arg("gsdml")
        .args(args)
        .env_remove("PROCIMG_INSTANCE")
        .output()
        .unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The demo's file as the writer makes it, dated 2025-01-31.
fn expected() -> (String, String) {
    let demo = Config::demo_device();
    let date = GsdmlDate::new(2025, 1, 31).unwrap();
    let g = station_gsdml(demo.station.as_ref().unwrap(), demo.cycle_ns, date).unwrap();
    (g.file_name, g.xml)
}

#[test]
fn the_device_demo_goes_to_stdout_a_file_and_a_directory() {
    let dir = scratch("demo");
    std::fs::write(dir.join("device.toml"), DEMO_DEVICE_TOML).unwrap();
    let (name, xml) = expected();
    assert_eq!(name, "GSDML-V2.4-procimg-procimg_device-20250131.xml");

    let out = procimg(&dir, &["-c", "device.toml", "--date", "20250131"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), xml);

    std::fs::create_dir(dir.join("gsd")).unwrap();
    let out = procimg(
        &dir,
        &["-c", "device.toml", "-d", "gsd", "--date", "2025-01-31"],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let path = Path::new("gsd").join(&name);
    assert_eq!(text(&out.stdout), format!("{}\n", path.display()));
    assert_eq!(std::fs::read_to_string(dir.join(&path)).unwrap(), xml);
    let g = Gsdml::load(&dir.join(&path)).unwrap();
    assert_eq!((g.vendor_id, g.device_id), (0x0493, 0x0100));

    // -o replaces an existing file, leaving no temporary file behind.
    std::fs::write(dir.join("gsd/mine.xml"), "old").unwrap();
    let out = procimg(
        &dir,
        &[
            "-c",
            "device.toml",
            "-o",
            "gsd/mine.xml",
            "--date",
            "20250131",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(
        std::fs::read_to_string(dir.join("gsd/mine.xml")).unwrap(),
        xml
    );
    let mut files: Vec<String> = std::fs::read_dir(dir.join("gsd"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(files, [name.clone(), "mine.xml".to_owned()]);

    // Without --date, today's date is in the name.
    let out = procimg(&dir, &["-c", "device.toml", "-d", "gsd"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let shown = text(&out.stdout);
    assert!(
        shown.starts_with("gsd/GSDML-V2.4-procimg-procimg_device-2") && shown.ends_with(".xml\n"),
        "{shown}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_interface_this_machine_lacks_makes_the_same_file() {
    // The engineering PC that makes the GSDML is not the one the station runs on.
    let dir = scratch("elsewhere");
    let toml = DEMO_DEVICE_TOML.replace(
        "network = \"sim\"",
        "network = \"enp99s0\" # the station's PC, not this one",
    );
    assert_ne!(toml, DEMO_DEVICE_TOML, "the demo names its network");
    std::fs::write(dir.join("device.toml"), toml).unwrap();
    let out = procimg(&dir, &["-c", "device.toml", "--date", "20250131"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), expected().1);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_controller_configuration_is_refused_with_what_to_do() {
    let dir = scratch("controller");
    std::fs::write(dir.join("plant.toml"), DEMO_TOML).unwrap();
    let out = procimg(&dir, &["-c", "plant.toml", "-d", "."]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    let e = text(&out.stderr);
    assert!(
        e.starts_with("procimg: plant.toml: this is a configuration of the controller role"),
        "{e}"
    );
    assert!(
        e.contains("Give a configuration with role = \"device\""),
        "{e}"
    );

    // A configuration error reads as procimgd reports it: file, line, key.
    std::fs::write(
        dir.join("broken.toml"),
        "role = \"device\"\n[station]\nname = \"Bad Name\"\nvendor_id = 1\ndevice_id = 1\n",
    )
    .unwrap();
    let out = procimg(&dir, &["-c", "broken.toml"]);
    assert_eq!(out.status.code(), Some(1));
    let e = text(&out.stderr);
    assert!(
        e.starts_with("procimg: broken.toml:3: station.name: "),
        "{e}"
    );
    let files = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(files, 2, "nothing written");
    let _ = std::fs::remove_dir_all(&dir);
}
