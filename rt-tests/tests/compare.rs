// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-compare --quick` runs every tool it can find, prints the table and writes
//! table.md and latency.svg. Rows whose tool is missing or fails (no real cyclictest, no
//! procimgd beside procimg-handshake, no root) must come out "not measured" with a reason,
//! never as a failure of the run. Timing is not judged here.

use std::process::Command;

mod support;
use support::refusal;

#[test]
fn a_quick_comparison_prints_the_table_and_writes_its_files() {
    let dir = std::env::temp_dir().join(format!("procimg-compare-test-{}", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_procimg-compare"))
        .args(["--quick", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{}\n{stdout}\n{stderr}", out.status);

    assert!(stdout.contains("| figure"), "{stdout}");
    assert!(stdout.contains("machine: "), "{stdout}");
    // Every row is there, measured or with its reason.
    for row in [
        "wake-up, procimg-cyclictest [p99]",
        "busy round trip, 1 cl., 64 B [p99]",
        "sleeping round trip, 1 cl., 64 B [p99]",
        "sleeping STARTOP one way",
        "sleeping OPDONE one way",
        "sweep: sleeping round trip, 1 cl., 4 KiB [p99]",
        "sweep: sleeping round trip, 4 cl., 64 B [p99]",
        "sweep: sleeping round trip, 1 cl., 64 KiB [p99]",
    ] {
        assert!(stdout.contains(row), "{row} missing:\n{stdout}");
    }
    // The goal table comes last, every goal measured or with its reason.
    let goals = stdout
        .split("## Goals")
        .nth(1)
        .unwrap_or_else(|| panic!("no goal table:\n{stdout}"));
    for goal in [
        "busy-poll round trip / spin round trip, p50",
        "busy-poll round trip / spin round trip, p99",
        "sleeping round trip / futex round trip, p50 (1 cl., 64 B)",
        "sleeping round trip / futex round trip one per cycle, p99 (1 cl., 64 B)",
        "sleeping round trip / futex round trip one per cycle, p99 (4 cl., 64 B)",
        "(futex one per cycle + copy 64 KiB)",
        "server copies per image byte, inputs",
        "server copies per image byte, outputs",
        "steady-state allocations in the cycle, server",
        "steady-state allocations in the cycle, clients",
        "locked memory of procimgd",
        "procimgd start to first cycle",
        "client attach (release, synchronous), 359.5 KiB image",
        "client attach (release, synchronous), 64 B image",
        "overruns while clients attach / idle as long",
    ] {
        assert!(goals.contains(goal), "{goal} missing:\n{goals}");
    }
    // The baselines need nothing but this crate: they are always measured.
    for baseline in [
        "futex round trip",
        "eventfd round trip",
        "socket round trip",
    ] {
        let line = stdout
            .lines()
            .find(|l| l.contains(&format!("| {baseline} ")))
            .unwrap_or_else(|| panic!("no row against {baseline}:\n{stdout}"));
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        assert!(!cells[4].starts_with("not measured"), "{line}");
    }
    // A row that could not be measured points to a footnote that says why.
    if stdout.contains("not measured [1]") {
        assert!(stdout.contains("\n[1] "), "{stdout}");
    }

    let table = std::fs::read_to_string(dir.join("table.md")).unwrap();
    assert!(table.contains("| figure"));
    let svg = std::fs::read_to_string(dir.join("latency.svg")).unwrap();
    assert!(
        svg.trim_start().starts_with("<svg"),
        "{}",
        &svg[..svg.len().min(200)]
    );
    assert!(svg.trim_end().ends_with("</svg>"));
    assert!(
        svg.contains("futex baseline"),
        "the legend names the series"
    );
    assert!(dir.join("round-1").join("futex.json").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_bad_option_is_refused_with_a_reason() {
    let err = refusal(env!("CARGO_BIN_EXE_procimg-compare"), &["--sizes", "lots"]);
    assert!(err.contains("not a size"), "{err}");
}

#[test]
fn a_cycle_time_procimgd_cannot_run_is_refused_with_the_ones_it_can() {
    let err = refusal(
        env!("CARGO_BIN_EXE_procimg-compare"),
        &["--shortest-cycle", "250,200"],
    );
    assert!(err.contains("31.25") && err.contains("187.5"), "{err}");
}
