// SPDX-License-Identifier: MIT OR Apache-2.0
//! An IO-Base device program that defines its station: `tests/c/iobase_device_program.c`,
//! built with `-Wall -Wextra -Werror -pedantic` (ASan and UBSan with
//! `PROCIMG_C_SANITIZE=1`), against a procimgd whose configuration names only the station's
//! GSDML file. The file (made with `procimg gsdml`, as a device maker makes it) describes a
//! module 0x4242 with 40 bytes each way that no procimgd configuration holds; the program
//! plugs it, and the demo PLC connects the program's tree. Before the program the station
//! waits off the wire with its device access point only; after its close it waits again.

use procimg_client::{AttachOptions, Client, StatusReport};
use procimg_testkit::Launch;
use procimg_testkit::build::workspace_bin;
use procimg_testkit::c::{
    Link, assert_success, compile, crate_dir, run, sanitize_from_env, scratch,
};
use std::path::Path;
use std::process::Command;
use std::time::Duration;

const RUN_TIMEOUT: Duration = Duration::from_secs(120);

/// The station the device maker describes: the DAP, module 0x4242 in slot 1 (40 bytes each
/// way), module 0x20 in slot 2; VendorID 0x0493 is procimg's demo's (a product needs its own
/// from PROFIBUS & PROFINET International).
const MAKER_STATION: &str = r#"
role = "device"
cycle_time = "1ms"
network = "sim"

[station]
name = "program-station"
vendor_id = 0x0493
device_id = 0x0100
device_type = "procimg test"
order_number = "PROCIMG-TEST"

[station.dap]
module_ident = 0x00000001
submodule_ident = 0x00000001
interface_ident = 0x00008000
port_ident = 0x00008001

[[station.submodule]]
slot = 1
module_ident = 0x00004242
submodule_ident = 0x00000001
input_length = 40
output_length = 40

[[station.submodule]]
slot = 2
module_ident = 0x00000020
submodule_ident = 0x00000001
input_length = 4
"#;

/// Writes the maker's station's GSDML file into `dir` with `procimg gsdml`; its path.
fn maker_gsdml(dir: &Path) -> std::path::PathBuf {
    let toml = dir.join("maker.toml");
    std::fs::write(&toml, MAKER_STATION).unwrap();
    let procimg = workspace_bin("procimg", "PROCIMG_BIN", "procimg-tools");
    let out = Command::new(procimg)
        .args(["gsdml", "-c"])
        .arg(&toml)
        .arg("-d")
        .arg(dir)
        .args(["--date", "20261128"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "procimg gsdml: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::path::PathBuf::from(String::from_utf8_lossy(&out.stdout).trim())
}

fn defined_by(s: &StatusReport) -> Option<String> {
    s.station.as_ref()?.program.as_ref()?.defined_by.clone()
}

#[test]
fn a_device_program_defines_its_station_from_the_gsdml_in_the_manuals_order() {
    let dir = procimg_testkit::files::temp_dir("iobase-program-station");
    let gsdml = maker_gsdml(dir.path());
    let toml = format!(
        "role = \"device\"\ncycle_time = \"1ms\"\nnetwork = \"sim\"\n[station]\n\
         name = \"program-station\"\nip = \"192.168.0.50\"\ngsdml = \"{}\"\n",
        gsdml.display()
    );
    let server = Launch::config("iobase-program", &toml)
        .debug_log()
        .until_cycling()
        .start();
    // Before the program: the device access point only, off the wire.
    let waiting = server.status();
    assert_eq!(defined_by(&waiting), None);
    let mut watcher =
        Client::attach(&server.instance, AttachOptions::asynchronous("watcher")).unwrap();
    assert_eq!(watcher.layout().submodules.len(), 3, "slot 0 only");

    let src = crate_dir().join("tests/c/iobase_device_program.c");
    let program = scratch("iobase_device_program").join("program");
    compile(&[src], &program, Link::Shared, sanitize_from_env());
    let o = run(
        &program,
        &["0x0493", "0x0100"],
        &server.instance,
        RUN_TIMEOUT,
    );
    assert_success(&o, "iobase_device_program");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("all checks held"),
        "the program said:\n{stdout}"
    );

    // The PLC got the first I data with the ApplicationReady: its log says what it read.
    let seen = server.log_lines("I data at the ApplicationReady");
    assert!(
        seen.first()
            .is_some_and(|l| l.contains("[30, 31, 32, 33, 34,")),
        "the demo PLC at the ApplicationReady: {seen:?}\n{}",
        server.log()
    );
    // After the program's close the station waits again, and a client attached before the
    // program follows each station it ran (its generation changes).
    let after = server.wait_status("the station waiting again", |s| {
        defined_by(s).is_none() && s.layout_hash == waiting.layout_hash
    });
    assert!(after.station.unwrap().ar.is_none());
    let until = std::time::Instant::now() + Duration::from_secs(30);
    while watcher.generation() != after.generation {
        assert!(
            std::time::Instant::now() < until,
            "the watcher did not follow"
        );
        let _ = watcher.wait_startop(Duration::from_millis(20));
        watcher.events();
    }
    assert_eq!(watcher.layout().hash(), waiting.layout_hash);
}
