// SPDX-License-Identifier: MIT OR Apache-2.0
//! cyclictest beside the soak, for the whole run: its wake-ups a cycle or more late say what
//! the machine did to any real-time thread meanwhile, the figure procimgd's overruns are
//! read against.

use crate::process::Running;
use crate::tally::Cyclictest;
use anyhow::Context as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

/// Priority of cyclictest's thread: just below procimgd's cycle thread (80).
const PRIORITY: u8 = 79;

/// cyclictest, running.
pub struct Baseline {
    run: Running,
    json: PathBuf,
    cycle: Duration,
}

impl Drop for Baseline {
    /// Also when the soak ends early: SIGINT lets cyclictest remove its file in /dev/shm.
    fn drop(&mut self) {
        self.run.stop(libc::SIGINT, Duration::from_secs(10));
    }
}

/// cyclictest in PATH (rt-tests), else procimg's own beside this program.
fn program() -> Option<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .map(|dir| dir.join("cyclictest"))
        .find(|p| p.is_file())
        .or_else(|| {
            let me = std::env::current_exe().ok()?;
            let ours = me.with_file_name("procimg-cyclictest");
            ours.is_file().then_some(ours)
        })
}

impl Baseline {
    /// Starts cyclictest at `cycle` for at most `longest`; `None` when there is none.
    pub fn start(
        cycle: Duration,
        longest: Duration,
        out: &Path,
    ) -> anyhow::Result<Option<Baseline>> {
        let Some(program) = program() else {
            eprintln!(
                "procimg-soak: no cyclictest (apt-get install rt-tests): its row says not run"
            );
            return Ok(None);
        };
        let json = out.join("cyclictest.json");
        let _ = std::fs::remove_file(&json);
        let interval_us = cycle.as_micros().max(1);
        let mut cmd = Command::new(program);
        cmd.args(["-m", "-q", "-p", &PRIORITY.to_string()])
            .args(["-i", &interval_us.to_string()])
            // Buckets up to two cycles: every late wake-up lands in one, or beyond as an
            // overflow at the maximum.
            .args(["-h", &(interval_us * 2).to_string()])
            .args(["-D", &format!("{}s", longest.as_secs().max(1))])
            .arg(format!("--json={}", json.display()));
        let run =
            Running::spawn(cmd, &out.join("cyclictest.log")).context("starting cyclictest")?;
        Ok(Some(Baseline { run, json, cycle }))
    }

    /// Stops it (SIGINT: it writes its results) and reads them.
    pub fn finish(mut self) -> anyhow::Result<Cyclictest> {
        self.run.stop(libc::SIGINT, Duration::from_secs(10));
        let m = procimg_rt_tests::cyclictest_json::read(&self.json, "wake-up")?;
        let h = m.histogram();
        let cycle_ns = self.cycle.as_nanos() as u64;
        let late = h
            .iter_recorded()
            .filter(|v| v.value_iterated_to() >= cycle_ns)
            .map(|v| v.count_at_value())
            .sum();
        Ok(Cyclictest {
            samples: m.count,
            late,
            p99_us: m.p99_ns as f64 / 1000.0,
            max_us: m.max_ns as f64 / 1000.0,
        })
    }
}
