// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-baseline`: every subcommand runs briefly (with or without root) and its report
//! reads back with the measurements procimg-compare looks up. Timing is not judged here.

use procimg_rt_tests::report::Report;
use std::process::Command;

mod support;
use support::{refusal, stdout_of_success, temp};

const TOOL: &str = env!("CARGO_BIN_EXE_procimg-baseline");

/// Runs the tool with `args` and `--report`, checks it succeeded and printed `expect`, and
/// returns the report.
fn run(args: &[&str], expect: &str) -> Report {
    let path = temp("procimg-baseline", &format!("{}.json", args[0]));
    let hlog = path.with_extension("hlog");
    let stdout = stdout_of_success(
        Command::new(TOOL)
            .args(args)
            .arg("--report")
            .arg(&path)
            .arg("--hdr-log")
            .arg(&hlog),
        &args,
    );
    assert!(stdout.contains(expect), "{stdout}");
    let report = Report::read_json(&path).unwrap();
    assert!(std::fs::metadata(&hlog).unwrap().len() > 0);
    let _ = std::fs::remove_file(&path);
    let _ = std::fs::remove_file(&hlog);
    assert_eq!(report.tool, "procimg-baseline");
    report
}

fn check_round_trip(mechanism: &str) {
    let r = run(&[mechanism, "-l", "300"], "round trip");
    assert_eq!(r.settings["mechanism"], mechanism);
    assert_eq!(r.measurements.len(), 1);
    let m = r.get("round trip").unwrap();
    assert_eq!(m.count, 300);
    assert!(m.min_ns > 0 && m.min_ns <= m.p50_ns && m.p50_ns <= m.p99_ns);
    assert!(m.p99_ns <= m.max_ns);
}

fn two_cpus() -> bool {
    std::thread::available_parallelism().map_or(1, |n| n.get()) >= 2
}

#[test]
fn spin_round_trips_are_measured() {
    if !two_cpus() {
        eprintln!("skipped: spin needs two CPUs");
        return;
    }
    check_round_trip("spin");
}

#[test]
fn futex_round_trips_are_measured() {
    check_round_trip("futex");
}

#[test]
fn eventfd_round_trips_are_measured() {
    check_round_trip("eventfd");
}

#[test]
fn socket_round_trips_are_measured() {
    check_round_trip("socket");
}

#[test]
fn a_periodic_ping_pong_measures_every_round_trip_and_says_its_period() {
    let r = run(&["futex", "-l", "200", "--period-us", "500"], "round trip");
    assert_eq!(r.settings["period_us"], "500");
    assert_eq!(r.get("round trip").unwrap().count, 200);
}

#[test]
fn every_copy_size_is_a_measurement() {
    let r = run(
        &["memcpy", "--bytes", "64,4KiB,64KiB,1MiB", "-l", "300"],
        "copy 1048576 B",
    );
    let names: Vec<&str> = r.measurements.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        names,
        ["copy 64 B", "copy 4096 B", "copy 65536 B", "copy 1048576 B"]
    );
    for m in &r.measurements {
        assert_eq!(m.count, 300, "{}", m.name);
    }
}

#[test]
fn every_page_count_is_a_measurement_of_every_write() {
    let r = run(
        &[
            "page-writes",
            "--pages",
            "1,16",
            "-l",
            "50",
            "--period-us",
            "200",
        ],
        "page write, 16 pages",
    );
    let names: Vec<&str> = r.measurements.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["page write, 1 pages", "page write, 16 pages"]);
    for m in &r.measurements {
        assert_eq!(m.count, 50, "{}", m.name);
    }
    assert_eq!(r.settings["period_us"], "200");
}

#[test]
fn spin_on_one_cpu_is_refused_with_a_reason() {
    let stderr = refusal(TOOL, &["spin", "-a", "0,0", "-l", "10"]);
    assert!(stderr.contains("different CPUs"), "{stderr}");
}

#[test]
fn a_bad_size_is_refused_with_a_reason() {
    let stderr = refusal(TOOL, &["memcpy", "--bytes", "lots"]);
    assert!(stderr.contains("not a size"), "{stderr}");
}
