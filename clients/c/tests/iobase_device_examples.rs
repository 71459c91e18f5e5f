// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO-Base device examples against a real `procimgd --demo-device-program` (the device
//! demo whose station its program defines: the examples' plugs are the station's tree):
//! DevEasy in C (shared library) and C++17 (static library), and the isochronous device loop, built with
//! `-Wall -Wextra -Werror -pedantic` (and ASan/UBSan with `PROCIMG_C_SANITIZE=1`). Each run
//! gets a procimgd of its own, since a run leaves the station OFFLINE with its modules
//! pulled. The checks are on the exit status and the milestones the programs print, in
//! their order, with counts; never on timing.

use procimg_client::Mode;
use procimg_testkit::Launch;
use procimg_testkit::c::{
    Link, assert_success, compile, crate_dir, run, sanitize_from_env, scratch,
};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

const TIMEOUT: Duration = Duration::from_secs(120);

fn example(name: &str) -> PathBuf {
    crate_dir().join("examples").join(name)
}

/// Builds example `name` into the test's scratch directory.
fn build(tag: &str, name: &str, link: Link) -> PathBuf {
    let exe = scratch(tag).join(tag);
    compile(&[example(name)], &exe, link, sanitize_from_env());
    exe
}

/// Runs `exe` with `args` against a fresh device demo whose station its program defines;
/// its stdout, after asserting success.
fn run_against_demo_device(tag: &str, exe: &Path, args: &[&str], what: &str) -> String {
    let server = Launch::demo_device_program(tag).start();
    let o = run(exe, args, &server.instance, TIMEOUT);
    assert_success(&o, what);
    // The program's close takes its station off the wire: it waits for the next program.
    let after = server.wait_status("the station waiting again", |s| {
        s.station
            .as_ref()
            .and_then(|s| s.program.as_ref())
            .is_some_and(|p| p.defined_by.is_none())
    });
    assert_eq!(after.mode, Mode::Offline, "{what} left the server so");
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The line numbers of `steps`, each of which must be printed exactly once, in this order.
fn in_order(text: &str, what: &str, steps: &[&str]) {
    let lines: Vec<&str> = text.lines().collect();
    let mut last = None;
    for step in steps {
        let at: Vec<usize> = (0..lines.len())
            .filter(|&i| lines[i].contains(step))
            .collect();
        assert_eq!(
            at.len(),
            1,
            "{what}: \"{step}\" printed {} times, not once:\n{text}",
            at.len()
        );
        assert!(
            last.is_none_or(|l| l < at[0]),
            "{what}: \"{step}\" out of order:\n{text}"
        );
        last = Some(at[0]);
    }
}

/// The number before `after` on the line that has it.
fn number_before(text: &str, after: &str) -> u64 {
    let line = text
        .lines()
        .find(|l| l.contains(after))
        .unwrap_or_else(|| panic!("no \"{after}\" in:\n{text}"));
    let head = &line[..line.find(after).unwrap()];
    head.split_whitespace()
        .last()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no number before \"{after}\" in \"{line}\""))
}

/// What every compiler the examples meet says about them: C11 and C++17 with every warning
/// an error. Only compiled, not linked, so that this holds also while the library lacks
/// functions the examples call.
#[test]
fn device_examples_compile_with_strict_warnings() {
    let out = scratch("device-examples-compile");
    for (name, compiler, std) in [
        ("pnio_dev_easy.c", "gcc", "-std=c11"),
        ("pnio_dev_easy.cpp", "g++", "-std=c++17"),
        ("pnio_dev_isochronous.c", "gcc", "-std=c11"),
    ] {
        let o = Command::new(compiler)
            .arg(std)
            .args(["-Wall", "-Wextra", "-Werror", "-pedantic", "-O2", "-c"])
            .arg("-I")
            .arg(crate_dir().join("include"))
            .arg("-I")
            .arg(crate_dir().join("../../shm-layout/include"))
            .arg(example(name))
            .arg("-o")
            .arg(out.join(format!("{name}.o")))
            .output()
            .unwrap_or_else(|e| panic!("run {compiler}: {e} (install gcc and g++)"));
        assert!(
            o.status.success(),
            "{name} with {compiler} {std}:\n{}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

#[test]
fn dev_easy_in_c_and_cpp() {
    let c = build("pnio-dev-easy", "pnio_dev_easy.c", Link::Shared);
    let cpp = build("pnio-dev-easy-cpp", "pnio_dev_easy.cpp", Link::Static);
    for (exe, tag, what) in [
        (&c, "deveasy-c", "pnio_dev_easy.c"),
        (&cpp, "deveasy-cpp", "pnio_dev_easy.cpp"),
    ] {
        let text = run_against_demo_device(tag, exe, &["3"], what);
        in_order(
            &text,
            what,
            &[
                "device open: handle",
                "plugged the DAP: slot 0 subslot 1",
                "plugged the IO module: slot 1 subslot 1, module 0x10 submodule 0x1",
                "AR_CHECK_IND: AR 1,",
                "AR_INFO_IND: AR 1,",
                "PRM_END_IND: AR 1, subslot 0",
                "application ready for AR 1",
                "AR_INDATA_IND: AR 1 in data exchange",
                "cyclic data:",
                "process alarm acknowledged (REQ_DONE, handle 1)",
                "channel diagnosis added, diagnosis alarm (appears) acknowledged",
                "channel diagnosis removed, diagnosis alarm (disappears) acknowledged",
                "parameter record 1: written",
                "AR_OFFLINE_IND: AR 1,",
                "device stopped (AR_OFFLINE_IND first)",
                "device closed",
                "DevEasy: all steps done",
            ],
        );
        // The PLC may connect before PNIO_device_start has returned (the callbacks come on
        // threads of their own): "device started" is ordered against the program's own
        // steps only.
        in_order(
            &text,
            what,
            &[
                "plugged the IO module: slot 1 subslot 1",
                "device started",
                "device stopped (AR_OFFLINE_IND first)",
            ],
        );
        assert!(
            number_before(&text, "round trips through the PLC") > 0,
            "{what}: no round trip:\n{text}"
        );
        // The PLC writes the parameter record while it connects (and again now and then):
        // each write was kept, and the count says so.
        let writes = text.matches("REC_WRITE: record 1 = ").count() as u64;
        assert!(writes >= 1, "{what}: no REC_WRITE of record 1:\n{text}");
        assert_eq!(
            number_before(&text, "times, read"),
            writes,
            "{what}: the writes counted:\n{text}"
        );
        assert!(!text.contains("refused"), "{what}:\n{text}");
        assert!(!text.contains("out of order"), "{what}:\n{text}");
        assert!(!text.contains("AR_ABORT_IND"), "{what}:\n{text}");
    }
}

#[test]
fn dev_isochronous_runs_the_cycle() {
    let exe = build(
        "pnio-dev-isochronous",
        "pnio_dev_isochronous.c",
        Link::Static,
    );
    let what = "pnio_dev_isochronous.c";
    let text = run_against_demo_device("deviso", &exe, &["500"], what);
    in_order(
        &text,
        what,
        &[
            "isochronous device open: handle",
            "plugged the DAP and the IO module",
            "registered OPFAULT_IND, then STARTOP_IND",
            "AR 1 in data exchange",
            "device stopped",
            "STARTOP cycles:",
            "isochronous device: all steps done",
        ],
    );
    // The callbacks come on threads of their own: "device started" (printed when
    // PNIO_device_start returned) is ordered against the program's own steps only.
    in_order(
        &text,
        what,
        &[
            "registered OPFAULT_IND, then STARTOP_IND",
            "device started",
            "device stopped",
        ],
    );
    assert!(
        number_before(&text, "with data exchanged") >= 500,
        "{what}: fewer cycles than asked for:\n{text}"
    );
    assert!(
        number_before(&text, "round trips through the PLC") > 0,
        "{what}: no round trip:\n{text}"
    );
    assert_eq!(
        number_before(&text, "(first"),
        0,
        "{what}: failed calls in the cycle:\n{text}"
    );
}
