// SPDX-License-Identifier: MIT OR Apache-2.0
//! The native C API from C: `tests/c/native_api.c` and `examples/native_cycle.c`, built with
//! strict warnings against `include/procimg.h`, linked static and shared (and with ASan and
//! UBSan when `PROCIMG_C_SANITIZE=1`), run against a real `procimgd --demo`.

use procimg_testkit::c::{
    Link, assert_success, compile, crate_dir, run, sanitize_from_env, scratch,
};
use procimg_testkit::{Procimgd, unique_instance};
use std::path::PathBuf;
use std::time::Duration;

const RUN_TIMEOUT: Duration = Duration::from_secs(20);

/// Builds `source` (relative to the crate) linked as `link`, into a directory of the test
/// `tag` (tests run in parallel: each builds its own copy).
fn build(source: &str, link: Link, tag: &str) -> PathBuf {
    let src = crate_dir().join(source);
    let stem = src.file_stem().unwrap().to_string_lossy().into_owned();
    let out = scratch(&format!("{stem}-{tag}")).join(format!("{stem}-{link:?}").to_lowercase());
    compile(&[src], &out, link, sanitize_from_env());
    out
}

/// Runs one part of `native_api.c` against `instance`, static and shared.
fn native_api(part: &str, instance: &str) {
    for link in [Link::Static, Link::Shared] {
        let program = build("tests/c/native_api.c", link, part);
        let o = run(&program, &[part], instance, RUN_TIMEOUT);
        assert_success(&o, &format!("native_api {part} ({link:?})"));
        // What the program measured (gaps, OPFAULTs), for --nocapture.
        eprint!("{}", String::from_utf8_lossy(&o.stderr));
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(
            stdout.contains(&format!("{part}: all checks held")),
            "native_api {part} ({link:?}) said:\n{stdout}"
        );
    }
}

/// Without a server: NULL arguments, bad options, error texts, a missing instance.
#[test]
fn error_paths_without_a_server() {
    native_api("errors", &unique_instance("missing"));
}

/// A synchronous client: 300 cycles through the echo device in place, the window's errors,
/// a second client refused with the holder named, a second thread refused as busy.
#[test]
fn synchronous_cycles_through_the_echo_device() {
    let server = Procimgd::demo("nsync");
    native_api("sync", &server.instance);
}

/// An asynchronous client: data_write/data_read through the echo device, the caches.
#[test]
fn asynchronous_access_by_address_and_the_caches() {
    let server = Procimgd::demo("nasync");
    native_api("async", &server.instance);
}

/// OFFLINE and back to OPERATE, each step confirmed by a MODE event.
#[test]
fn mode_changes_come_as_mode_events() {
    let server = Procimgd::demo("nmodes");
    native_api("modes", &server.instance);
}

/// The example compiles with -std=c11 -Wall -Wextra -Werror -pedantic and runs its cycles;
/// in OFFLINE, where nothing is echoed, it fails and says how to get OPERATE.
#[test]
fn the_native_cycle_example_runs() {
    let server = Procimgd::demo("nexample");
    let program = build("examples/native_cycle.c", Link::Shared, "example");
    let o = run(&program, &[&server.instance, "200"], "", RUN_TIMEOUT);
    assert_success(&o, "examples/native_cycle.c");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("200 cycles") && stdout.contains(&server.instance),
        "the example's summary:\n{stdout}"
    );
    assert!(!stdout.contains(" 0 echoed"), "{stdout}");

    server.set_mode(procimg_client::Mode::Offline);
    let o = run(&program, &[&server.instance, "50"], "", RUN_TIMEOUT);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "in OFFLINE:\n{stderr}");
    for part in [
        "no echo in 50 cycles",
        "is in mode OFFLINE",
        "`procimg mode operate --instance",
    ] {
        assert!(stderr.contains(part), "no \"{part}\" in:\n{stderr}");
    }
}
