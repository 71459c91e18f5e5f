// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg io watch` against `procimgd --demo`: JSON lines with the time, the cycle, the
//! bytes, IOPS/IOCS and the device's state, and a line when only the status changes (the
//! server going OFFLINE turns the inputs BAD; the bytes may stay as they were).

use procimg_client::Mode;
use procimg_testkit::Procimgd;
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{Receiver, channel};
use std::time::{Duration, Instant};

/// The watch command, killed (by its own pid) when the test ends, also on a failure.
struct Watching(Child);

impl Drop for Watching {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// The next line that `want` accepts, within 30 s.
fn next_line(
    lines: &Receiver<serde_json::Value>,
    what: &str,
    want: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    let until = Instant::now() + Duration::from_secs(30);
    while let Some(left) = until.checked_duration_since(Instant::now()) {
        match lines.recv_timeout(left) {
            Ok(v) if want(&v) => return v,
            Ok(_) => {}
            Err(e) => panic!("no line with {what}: {e}"),
        }
    }
    panic!("no line with {what} within 30 s");
}

#[test]
fn watch_prints_status_and_state_changes_with_time_and_cycle() {
    let server = Procimgd::demo("io-watch");
    let _ = server.control(Duration::from_secs(30));
    let mut child = Command::new(env!("CARGO_BIN_EXE_procimg"))
        .args([
            "--instance",
            &server.instance,
            "io",
            "watch",
            "16",
            "--json",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("start procimg io watch");
    let stdout = child.stdout.take().expect("its output");
    let _watching = Watching(child);
    let (tx, lines) = channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            let v: serde_json::Value =
                serde_json::from_str(&line).unwrap_or_else(|e| panic!("{e}: {line}"));
            if tx.send(v).is_err() {
                return;
            }
        }
    });

    let first = next_line(&lines, "GOOD inputs", |v| v["iops"] == "GOOD");
    for key in [
        "time", "cycle", "space", "address", "data", "iocs", "device", "state",
    ] {
        assert!(first.get(key).is_some(), "no {key:?} in {first}");
    }
    assert_eq!(first["space"], "input");
    assert_eq!(first["address"], 16);
    assert!(first["cycle"].as_u64().is_some_and(|c| c > 0), "{first}");
    let state = first["state"].as_str().unwrap_or_default().to_owned();
    assert!(!state.is_empty(), "{first}");

    // OFFLINE: the devices' ARs end, their inputs turn BAD; a line says so whatever the bytes.
    server.set_mode(Mode::Offline);
    let bad = next_line(&lines, "BAD inputs", |v| v["iops"] == "BAD");
    // The device's new state comes with a notification, which may arrive before the image
    // with the BAD inputs (one line tells both) or after it (a line of its own).
    let gone = if bad["state"] != state.as_str() {
        bad.clone()
    } else {
        next_line(&lines, "the device's new state", |v| {
            v["state"] != state.as_str()
        })
    };
    assert!(
        bad["cycle"].as_u64() >= first["cycle"].as_u64(),
        "{first}\n{bad}"
    );
    assert_ne!(gone["state"], first["state"]);
}
