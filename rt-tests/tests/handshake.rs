// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-handshake` against the real procimgd (built beside it by `cargo test
//! --workspace`): it measures every figure it promises, for sleeping and busy-polling
//! clients, and its report reads back. Timing is not judged here.

use procimg_rt_tests::report::Report;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;

mod support;
use support::{refusal, stdout_of_success};

fn tool() -> &'static str {
    env!("CARGO_BIN_EXE_procimg-handshake")
}

/// procimgd is another package's binary; `cargo test --workspace` builds it into the same
/// directory.
fn procimgd_built() -> bool {
    Path::new(tool()).with_file_name("procimgd").exists()
}

/// One measurement at a time: a busy-polling run keeps a whole CPU at SCHED_FIFO, and on a
/// two-CPU machine a second run beside it leaves procimgd's control thread (normal
/// priority) too little time to answer within its timeout.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

fn run(args: &[&str], report: &Path) -> Report {
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let stdout = stdout_of_success(
        Command::new(tool()).args(args).arg("--report").arg(report),
        &args,
    );
    assert!(stdout.contains("round trip"), "{stdout}");
    Report::read_json(report).unwrap()
}

fn temp(name: &str) -> PathBuf {
    support::temp("procimg-handshake", name)
}

#[test]
fn sleeping_clients_are_measured_in_both_directions() {
    if !procimgd_built() {
        eprintln!("skipped: procimgd is not built (run cargo test --workspace)");
        return;
    }
    let path = temp("sleep.json");
    let r = run(&["-c", "2", "-b", "4KiB", "-l", "300", "-q"], &path);
    let _ = std::fs::remove_file(&path);
    assert_eq!(r.settings["clients"], "2");
    assert_eq!(r.settings["devices"], "3");
    assert_eq!(r.get("startop one way").unwrap().count, 600);
    // The allocations of the measured cycles are counted on both sides (values not judged).
    for key in ["server_cycle_allocations", "client_cycle_allocations"] {
        assert!(
            r.settings[key].parse::<u64>().is_ok(),
            "{key}: {:?}",
            r.settings
        );
    }
    // Server side: every OPDONE between the two snapshots, at least the measured ones.
    for name in ["opdone one way", "round trip"] {
        let m = r.get(name).unwrap();
        assert!(m.count >= 600, "{name}: {m:?}");
        assert!(m.min_ns > 0 && m.p50_ns <= m.p99_ns && m.p99_ns <= m.max_ns);
    }
}

#[test]
fn a_busy_polling_client_is_measured() {
    if !procimgd_built() {
        eprintln!("skipped: procimgd is not built (run cargo test --workspace)");
        return;
    }
    if std::thread::available_parallelism().map_or(1, |n| n.get()) < 2 {
        eprintln!("skipped: busy-polling needs two CPUs");
        return;
    }
    let path = temp("busy.json");
    let r = run(&["-w", "busy", "-l", "300", "-q"], &path);
    let _ = std::fs::remove_file(&path);
    assert_eq!(r.settings["wait"], "busy");
    assert_eq!(r.get("startop one way").unwrap().count, 300);
    assert!(r.get("round trip").unwrap().count >= 300);
}

#[test]
fn too_many_busy_clients_are_refused_with_the_reason() {
    let err = refusal(tool(), &["-w", "busy", "-c", "64", "-l", "10"]);
    assert!(err.contains("need 65 CPUs"), "{err}");
}

#[test]
fn the_demo_runs_at_the_cycle_asked_for() {
    if !procimgd_built() {
        eprintln!("skipped: procimgd is not built (run cargo test --workspace)");
        return;
    }
    let path = temp("demo.json");
    let r = run(&["--demo", "-i", "500", "-l", "300", "-q"], &path);
    let _ = std::fs::remove_file(&path);
    assert_eq!(r.settings["plant"], "demo");
    assert_eq!(r.settings["interval_us"], "500");
    assert_eq!(r.get("startop one way").unwrap().count, 300);
    for key in ["cycles", "overruns", "opfaults"] {
        assert!(
            r.settings[key].parse::<u64>().is_ok(),
            "{key}: {:?}",
            r.settings
        );
    }
    assert!(r.get("server wake-up").unwrap().count > 0);
}

#[test]
fn a_cycle_time_procimgd_cannot_run_is_refused_with_the_ones_it_can() {
    let err = refusal(tool(), &["--demo", "-i", "200", "-l", "10"]);
    assert!(err.contains("31.25") && err.contains("187.5"), "{err}");
}

#[test]
fn startup_times_the_start_and_the_attaches_and_reads_the_memory() {
    if !procimgd_built() {
        eprintln!("skipped: procimgd is not built (run cargo test --workspace)");
        return;
    }
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let path = temp("startup.json");
    let args = ["startup", "-b", "4KiB", "-n", "3", "--report"];
    stdout_of_success(Command::new(tool()).args(args).arg(&path), &args);
    let r = Report::read_json(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    assert_eq!(r.get("client attach").unwrap().count, 3);
    assert_eq!(r.get("start to first cycle").unwrap().count, 1);
    assert_eq!(r.settings["max_clients"], "64");
    for key in ["procimgd_vmlck_kib", "procimgd_vmrss_kib"] {
        assert!(
            r.settings[key].parse::<u64>().is_ok(),
            "{key}: {:?}",
            r.settings
        );
    }
}
