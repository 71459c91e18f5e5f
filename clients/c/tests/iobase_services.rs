// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO-Base services from C: `tests/c/iobase_services_demo.c` built with strict warnings
//! against `pniousrx.h`, linked static and shared (with ASan and UBSan when
//! `PROCIMG_C_SANITIZE=1`), run against a real `procimgd --demo`: record jobs and their
//! confirmations, alarms, device activation and diagnosis through the `PNIO_*` functions.

use procimg_testkit::Procimgd;
use procimg_testkit::c::{
    Link, assert_success, compile, crate_dir, run, sanitize_from_env, scratch,
};
use std::path::PathBuf;
use std::time::Duration;

const RUN_TIMEOUT: Duration = Duration::from_secs(60);

/// Builds the test program for `part` (each part its own file: tests build in parallel).
fn build(part: &str, link: Link) -> PathBuf {
    let src = crate_dir().join("tests/c/iobase_services_demo.c");
    let out = scratch("iobase_services").join(format!("{part}-{link:?}").to_lowercase());
    compile(&[src], &out, link, sanitize_from_env());
    out
}

/// Runs one part of the program against its own demo server, static and shared.
fn part(part: &str) {
    for link in [Link::Static, Link::Shared] {
        let server = Procimgd::demo(&format!("svc-{part}"));
        let program = build(part, link);
        let o = run(&program, &[part], &server.instance, RUN_TIMEOUT);
        assert_success(&o, &format!("iobase_services_demo {part} ({link:?})"));
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(
            stdout.contains(&format!("{part}: all checks held")),
            "iobase_services_demo {part} ({link:?}) said:\n{stdout}"
        );
    }
}

/// I&M0 read with its REC_READ_CONF (ReqRef, pAddr, RecordIndex, Err, the data), a record
/// written and read back, a missing record's PNIORW status; PRM_ADD, PRM_REC_INDEX and
/// VALUE_LEN at the call; CONFIG_SUBMODULE_LIST equal to the demo's layout; DEVICE_STATE in
/// data exchange; a diagnosis without its callback refused.
#[test]
fn record_jobs_and_the_configuration_from_c() {
    part("records");
}

/// A process alarm raised by a simulated device reaches ALARM_IND with its data;
/// deactivation and activation bring DEV_ACT_CONF and the DEV_FAILURE / DEV_RETURN alarms;
/// DEVICE_STATE follows; OFFLINE reports a station failure per device.
#[test]
fn alarms_and_device_activation_from_c() {
    part("alarms");
}
