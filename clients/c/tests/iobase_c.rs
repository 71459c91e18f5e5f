// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO-Base controller API from C and C++ programs against a real procimgd: the manual's
//! example tables, the error paths, and the PnioEasy and isochronous examples, built with
//! `-Wall -Wextra -Werror -pedantic` (and ASan/UBSan with `PROCIMG_C_SANITIZE=1`).

use procimg_client::Mode;
use procimg_testkit::c::{
    Link, assert_success, compile, crate_dir, run, sanitize_from_env, scratch,
};
use procimg_testkit::{Procimgd, unique_instance};
use std::path::PathBuf;
use std::time::Duration;

/// The manual's example modules (shared with runtime/tests/iobase.rs): inputs 2 bytes at
/// I 0..1 and 4 bytes at I 2..5; outputs 2 bytes at Q 0..1, 4 bytes at Q 2..5 and 4 bytes
/// at Q 10..13.
const MANUAL_LAYOUT: &str =
    include_str!("../../../runtime/tests/fixtures/iobase_manual_layout.toml");

const TIMEOUT: Duration = Duration::from_secs(60);

fn test_source(name: &str) -> PathBuf {
    crate_dir().join("tests/c").join(name)
}

fn example(name: &str) -> PathBuf {
    crate_dir().join("examples").join(name)
}

/// Builds `sources` into the test's scratch directory.
fn build(tag: &str, sources: &[PathBuf], link: Link) -> PathBuf {
    let exe = scratch(tag).join(tag);
    compile(sources, &exe, link, sanitize_from_env());
    exe
}

fn output(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn manual_tables_with_and_without_slice_access() {
    let exe = build(
        "iobase-tables",
        &[test_source("iobase_tables.c")],
        Link::Static,
    );
    let server = Procimgd::with_config("iotables", MANUAL_LAYOUT);
    let o = run(&exe, &["slice"], &server.instance, TIMEOUT);
    assert_success(&o, "the manual's tables with PNIO_CEP_SLICE_ACCESS");
    let text = output(&o);
    // Every row of both tables was run.
    assert_eq!(text.matches("read  I").count(), 8, "{text}");
    assert_eq!(text.matches("write Q").count(), 11, "{text}");
    assert!(text.contains("0 rows wrong"), "{text}");

    let o = run(&exe, &["exact"], &server.instance, TIMEOUT);
    assert_success(&o, "whole submodules only without PNIO_CEP_SLICE_ACCESS");
    assert!(output(&o).contains("0 rows wrong"), "{}", output(&o));
}

#[test]
fn error_paths_give_the_manuals_codes() {
    let exe = build(
        "iobase-errors",
        &[test_source("iobase_errors.c")],
        Link::Shared,
    );
    let server = Procimgd::demo("ioerrors");
    let o = run(&exe, &[], &server.instance, TIMEOUT);
    assert_success(&o, "the error paths");
    let text = output(&o);
    assert!(text.contains("0 checks wrong"), "{text}");
    assert!(!text.contains("WRONG"), "{text}");
}

/// Both run the manual's flow (which ends in OFFLINE) and then give the server back the mode
/// it had before: OPERATE, so that the next program finds data exchanged.
#[test]
fn pnio_easy_in_c_and_cpp() {
    let c = build("pnio-easy", &[example("pnio_easy.c")], Link::Shared);
    let cpp = build("pnio-easy-cpp", &[example("pnio_easy.cpp")], Link::Static);
    let server = Procimgd::demo("ioeasy");
    for (exe, what) in [(&c, "pnio_easy.c"), (&cpp, "pnio_easy.cpp")] {
        let o = run(exe, &["20"], &server.instance, TIMEOUT);
        assert_success(&o, what);
        let text = output(&o);
        for step in [
            "mode OPERATE",
            "inputs echo the outputs",
            "mode OFFLINE",
            "controller closed",
            "back in mode OPERATE, as before the controller opened",
        ] {
            assert!(
                text.contains(step),
                "{what} did not print \"{step}\":\n{text}"
            );
        }
        assert_eq!(server.mode(), Mode::Operate, "{what} left the server so");
        server.wait_ready(TIMEOUT);
    }
    // A server that was OFFLINE before stays OFFLINE, as the manual's flow leaves it.
    server.set_mode(Mode::Offline);
    let o = run(&c, &["5"], &server.instance, TIMEOUT);
    assert_success(&o, "pnio_easy.c from OFFLINE");
    assert!(!output(&o).contains("back in mode"), "{}", output(&o));
    assert_eq!(server.mode(), Mode::Offline);
}

/// Without a server the failure names the code and says what to do.
#[test]
fn pnio_easy_without_a_server_says_what_to_do() {
    let c = build(
        "pnio-easy-no-server",
        &[example("pnio_easy.c")],
        Link::Shared,
    );
    let o = run(&c, &["5"], &unique_instance("noserver"), TIMEOUT);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    for part in [
        "PNIO_controller_open failed with 0x304",
        "(PNIO_ERR_NO_CONFIG)",
        "procimgd --demo",
    ] {
        assert!(err.contains(part), "no \"{part}\" in:\n{err}");
    }
}

#[test]
fn pnio_isochronous_runs_the_cycle() {
    let exe = build(
        "pnio-isochronous",
        &[example("pnio_isochronous.c")],
        Link::Static,
    );
    let server = Procimgd::demo("ioiso");
    let o = run(&exe, &["600"], &server.instance, TIMEOUT);
    assert_success(&o, "pnio_isochronous.c");
    let text = output(&o);
    for line in [
        "isochronous controller",
        "with PNIO_WARN_IRT_INCONSISTENT",
        "RT reads outside the window:",
        "cycles in OPERATE",
        "a second PNIO_CP_set_opdone in one cycle: 0x309",
        "back in mode OPERATE",
    ] {
        assert!(text.contains(line), "no \"{line}\" in:\n{text}");
    }
    assert_eq!(server.mode(), Mode::Operate);
    // The example opens from a SCHED_FIFO thread: the callback threads take its priority.
    if !text.contains("no permission for SCHED_FIFO") {
        assert!(
            text.contains("STARTOP callbacks at SCHED_FIFO 70"),
            "the STARTOP callback did not run at the opening thread's priority:\n{text}"
        );
    }
}
