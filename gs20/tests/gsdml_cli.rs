// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-gs20 gsdml`: the item catalogue's GSDML file to a file, into a directory under
//! its standard name and to standard output, the library's file each time, read back by
//! procimg and well-formed for xmllint (where installed); the identity and the cycle as
//! given; what cannot be written refused with what to do, and nothing written.

use std::path::Path;
use std::process::{Command, Output};

use procimg_config::gsdml::Gsdml;
use procimg_gs20::catalogue::{CatalogueIdentity, GsdmlDate, StationGsdml, catalogue_gsdml};

fn gs20(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_procimg-gs20"))
        .current_dir(dir)
        .arg("gsdml")
        .args(args)
        .output()
        .unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The library's file of `identity`, for a cycle of `cycle_ns`, dated 2025-01-31.
fn expected(identity: CatalogueIdentity, cycle_ns: u64) -> StationGsdml {
    catalogue_gsdml(&identity, cycle_ns, GsdmlDate::new(2025, 1, 31).unwrap()).unwrap()
}

/// `xmllint --noout` on `path`, if xmllint is installed: well-formed XML, nothing said.
fn well_formed(path: &Path) {
    let Ok(out) = Command::new("xmllint").arg("--noout").arg(path).output() else {
        eprintln!("xmllint is not installed: well-formedness left to procimg's reader");
        return;
    };
    assert!(
        out.status.success() && out.stderr.is_empty(),
        "xmllint: {}",
        text(&out.stderr)
    );
}

#[test]
fn the_catalogue_goes_to_a_file_a_directory_and_stdout() {
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    let file = expected(CatalogueIdentity::default(), 1_000_000);
    assert_eq!(file.file_name, "GSDML-V2.4-procimg-GS20_PN-20250131.xml");

    let out = gs20(dir, &["-o", "items.xml", "--date", "20250131"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), "items.xml\n");
    let path = dir.join("items.xml");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), file.xml);
    let read = Gsdml::load(&path).unwrap();
    assert_eq!((read.vendor_id, read.device_id), (0x0493, 0x0200));
    assert_eq!(read.modules.len(), 27);
    well_formed(&path);

    // -d: the standard name; an existing file is replaced, no temporary file stays.
    std::fs::create_dir(dir.join("gsd")).unwrap();
    std::fs::write(dir.join("gsd").join(&file.file_name), "old").unwrap();
    let out = gs20(dir, &["-d", "gsd", "--date", "2025-01-31"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let written = Path::new("gsd").join(&file.file_name);
    assert_eq!(text(&out.stdout), format!("{}\n", written.display()));
    assert_eq!(
        std::fs::read_to_string(dir.join(&written)).unwrap(),
        file.xml
    );
    assert_eq!(std::fs::read_dir(dir.join("gsd")).unwrap().count(), 1);

    // Neither: standard output, with the identity and cycle given.
    let out = gs20(
        dir,
        &[
            "--vendor-id",
            "0x1234",
            "--device-id",
            "43981",
            "--cycle-time",
            "2ms",
            "--date",
            "20250131",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let mine = CatalogueIdentity {
        vendor_id: 0x1234,
        device_id: 0xABCD,
    };
    assert_eq!(text(&out.stdout), expected(mine, 2_000_000).xml);

    // Without --date, today's date is in the name.
    let out = gs20(dir, &["-d", "gsd"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let shown = text(&out.stdout);
    assert!(
        shown.starts_with("gsd/GSDML-V2.4-procimg-GS20_PN-2") && shown.ends_with(".xml\n"),
        "{shown}"
    );
}

#[test]
fn what_cannot_be_written_is_refused_with_what_to_do() {
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();

    let out = gs20(dir, &["--cycle-time", "3ms", "-d", "."]);
    assert_eq!(out.status.code(), Some(1));
    let e = text(&out.stderr);
    assert!(
        e.starts_with("procimg-gs20: a cycle time of 3ms cannot be described")
            && e.contains("give the cycle_time of procimgd's configuration"),
        "{e}"
    );

    let out = gs20(dir, &["-o", "missing/items.xml"]);
    assert_eq!(out.status.code(), Some(1));
    let e = text(&out.stderr);
    assert!(
        e.contains("cannot write missing/items.xml")
            && e.contains("check that the directory missing exists and is writable"),
        "{e}"
    );

    // The command line's own refusals (clap: exit code 2).
    for (args, phrase) in [
        (&["--vendor-id", "0x10000"][..], "from 0 to 0xFFFF"),
        (
            &["--device-id", "pump"][..],
            "in hex as 0x0493 or in decimal",
        ),
        (&["--date", "20250230"][..], "YYYYMMDD"),
        (&["--cycle-time", "1"][..], "has no unit"),
        (&["-o", "a.xml", "-d", "."][..], "cannot be used with"),
    ] {
        let out = gs20(dir, args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let e = text(&out.stderr);
        assert!(e.contains(phrase), "{args:?}: {e}");
    }
    assert_eq!(
        std::fs::read_dir(dir).unwrap().count(),
        0,
        "nothing written"
    );
}
