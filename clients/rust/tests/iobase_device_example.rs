// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO-Base device semantics from Rust, without the C library: `examples/iobase_device.rs`
//! against `procimgd --demo-device`, whose simulated PLC connects again after each AR ends.
//! The program sees two ARs through the manual's indications with ArNumbers 1 and 2, makes
//! each one's ApplicationReady go (the PLC reaches data exchange), has a second
//! ApplicationReady and a call naming the ended AR refused, keeps a diagnosis under a
//! DiagTag, and aborts the first AR itself.

use procimg_testkit::Launch;
use procimg_testkit::build::{cargo_build_once, profile_dir};
use procimg_testkit::c::run;
use std::time::Duration;

#[test]
fn a_rust_program_follows_two_ars_with_io_base_semantics() {
    let server = Launch::demo_device("iobase-rs").start();
    cargo_build_once(&["-p", "procimg-client", "--example", "iobase_device"]);
    let program = profile_dir().join("examples/iobase_device");
    let o = run(
        &program,
        &["--ars", "2", "--hold", "200", "--timeout", "90"],
        &server.instance,
        Duration::from_secs(120),
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    let said = format!(
        "{stdout}\nstderr:\n{}\nprocimgd:\n{}",
        String::from_utf8_lossy(&o.stderr),
        server.log()
    );
    assert!(o.status.success(), "iobase_device failed:\n{said}");
    let lines: Vec<&str> = stdout.lines().collect();
    let at = |prefix: &str| {
        lines
            .iter()
            .position(|l| l.starts_with(prefix))
            .unwrap_or_else(|| panic!("no line \"{prefix}…\":\n{said}"))
    };
    // The manual's order, per AR, ArNumbers counting from 1.
    let order = [
        at("AR_CHECK_IND ar 1 "),
        at("AR_INFO_IND ar 1:"),
        at("PRM_END_IND ar 1 None"),
        at("application ready for ar 1"),
        at("AR_INDATA_IND ar 1"),
        at("wire break on slot 1 under DiagTag 7"),
        at("DiagTag 7 removed"),
        at("aborting ar 1"),
        // The program's abort: AbortRequest, IO-Base's PNIO_AR_REASON_ABORT.
        at("AR_OFFLINE_IND ar 1 reason 13"),
        at("AR_CHECK_IND ar 2 "),
        at("PRM_END_IND ar 2 None"),
        at("AR_INDATA_IND ar 2"),
    ];
    assert!(
        order.windows(2).all(|w| w[0] < w[1]),
        "out of the manual's order:\n{said}"
    );
    // AR_INFO_IND has the CRs of the demo PLC's Connect: a frame each way every 1 ms.
    let info = lines[order[1]];
    assert!(
        info.contains("input CR frame 0x") && info.contains("output CR frame 0x"),
        "{info}"
    );
    assert_eq!(info.matches("every 1000 µs").count(), 2, "{info}");
    assert!(
        stdout.contains("a second application ready is refused: not now for AR 1: it was called for this AR already"),
        "{said}"
    );
    assert!(
        stdout.contains("ar 1 named again is refused: AR 1 has ended"),
        "{said}"
    );
    assert!(stdout.contains("ARs in data exchange 2 "), "{said}");
    assert_eq!(
        lines
            .iter()
            .filter(|l| l.starts_with("AR_INDATA_IND"))
            .count(),
        2,
        "one AR_INDATA_IND per AR:\n{said}"
    );
}
