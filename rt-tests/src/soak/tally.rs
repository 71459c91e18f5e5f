// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the soak counted, and the one table it prints at the end.

use crate::capture::Verdict;
use serde::Serialize;
use std::fmt::Write as _;
use std::time::Duration;

/// Times until things worked again, in ms.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Reconnects {
    /// From the device's restart to procimgd reporting it running.
    pub device: Vec<f64>,
    /// From procimgd's restart to the device running.
    pub procimgd: Vec<f64>,
    /// From procimgd's restart to the running client's first answered output.
    pub client_after_procimgd: Vec<f64>,
    /// From a new client's start to its first answered output.
    pub client: Vec<f64>,
}

/// Record jobs asked while everything ran.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Records {
    /// Asked.
    pub asked: u64,
    /// Answered with the record.
    pub answered: u64,
    /// Answered with an error.
    pub refused: u64,
    /// Not answered within the timeout.
    pub lost: u64,
}

/// Diagnosis alarms the device raised while everything ran.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Alarms {
    /// Diagnoses raised or cleared at the device.
    pub raised: u64,
    /// Received (and acknowledged) by the services client.
    pub delivered: u64,
    /// Not received within the timeout.
    pub lost: u64,
    /// AlarmAcks the device received over the run.
    pub acked_at_device: u64,
}

/// Faults the soak caused.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Kills {
    /// Client SIGKILLed.
    pub client: u64,
    /// Device SIGKILLed.
    pub device: u64,
    /// procimgd SIGKILLed.
    pub procimgd_killed: u64,
    /// procimgd stopped with SIGTERM.
    pub procimgd_terminated: u64,
}

/// cyclictest's wake-ups in the same run.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Cyclictest {
    /// Wake-ups measured.
    pub samples: u64,
    /// Wake-ups one cycle or more late (a cycle thread that late overruns).
    pub late: u64,
    /// 99th percentile, µs.
    pub p99_us: f64,
    /// Largest, µs.
    pub max_us: f64,
}

/// Everything the soak counted.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Tally {
    /// The seed of the fault schedule.
    pub seed: u64,
    /// How long it ran, s.
    pub seconds: f64,
    /// procimgd's cycle, µs.
    pub cycle_us: u64,
    /// Cycles procimgd ran, over all its runs.
    pub cycles: u64,
    /// Cycles whose work did not end within the cycle.
    pub overruns: u64,
    /// OPFAULTs procimgd gave.
    pub opfaults: u64,
    /// procimgd's consumer watchdog expiries.
    pub watchdog_expiries: u64,
    /// Frames or datagrams procimgd received and dropped as malformed.
    pub malformed_received: u64,
    /// Allocations of procimgd's cycle thread in its cycles.
    pub rt_heap_allocations: u64,
    /// Cycles the synchronous client handled.
    pub client_cycles: u64,
    /// Valid inputs that answered no value the client wrote (torn or foreign data).
    pub data_errors: u64,
    /// Valid inputs that answered a value more than 64 handled cycles old (outputs held while
    /// OPDONE came late, or the device's application lagging).
    pub stale_echoes: u64,
    /// The oldest answer seen, in handled cycles.
    pub oldest_echo: u64,
    /// Faults.
    pub kills: Kills,
    /// Times until it worked again.
    pub reconnect_ms: Reconnects,
    /// Restarts after which the soak waited in vain.
    pub recoveries_failed: u64,
    /// Record jobs.
    pub records: Records,
    /// Diagnosis alarms.
    pub alarms: Alarms,
    /// What tshark found (`None`: not checked).
    pub frames: Option<FrameCheck>,
    /// cyclictest beside it (`None`: not run).
    pub cyclictest: Option<Cyclictest>,
}

/// tshark's verdict, serialisable.
#[derive(Clone, Debug, Default, Serialize)]
pub struct FrameCheck {
    /// Frames read.
    pub frames: u64,
    /// Malformed or in error, sent by procimgd.
    pub bad_from_procimgd: u64,
    /// Malformed or in error, sent by the device.
    pub bad_from_device: u64,
}

impl From<Verdict> for FrameCheck {
    fn from(v: Verdict) -> FrameCheck {
        FrameCheck {
            frames: v.frames,
            bad_from_procimgd: v.bad_from_procimgd,
            bad_from_device: v.bad_from_device,
        }
    }
}

/// p50 and max of `ms`, as text.
fn spread(ms: &[f64]) -> String {
    if ms.is_empty() {
        return "none".into();
    }
    let mut sorted = ms.to_vec();
    sorted.sort_by(f64::total_cmp);
    let p50 = sorted[(sorted.len() - 1) / 2];
    let max = sorted[sorted.len() - 1];
    format!("p50 {p50:.0} ms, max {max:.0} ms (n = {})", sorted.len())
}

impl Tally {
    /// What must be 0 and is not.
    pub fn failures(&self) -> Vec<String> {
        let mut f = Vec::new();
        let mut check = |what: &str, n: u64| {
            if n > 0 {
                f.push(format!("{what}: {n}"));
            }
        };
        check("records lost", self.records.lost);
        check("alarms lost", self.alarms.lost);
        check("data errors at the client", self.data_errors);
        check("recoveries failed", self.recoveries_failed);
        check(
            "malformed frames received by procimgd",
            self.malformed_received,
        );
        check("allocations in the cycle", self.rt_heap_allocations);
        if let Some(frames) = &self.frames {
            check(
                "frames of procimgd malformed in tshark",
                frames.bad_from_procimgd,
            );
        }
        f
    }

    /// The table, in Markdown.
    pub fn table(&self) -> String {
        let mut t = String::new();
        let mut row = |figure: &str, value: String| {
            let _ = writeln!(t, "| {figure} | {value} |");
        };
        row("figure", "value".into());
        row("---", "---".into());
        let run = Duration::from_secs_f64(self.seconds);
        row(
            "run",
            format!(
                "{} s at a cycle of {} µs, seed {}",
                run.as_secs(),
                self.cycle_us,
                self.seed
            ),
        );
        let k = &self.kills;
        row(
            "faults",
            format!(
                "client SIGKILL {}, device SIGKILL {}, procimgd SIGKILL {}, procimgd SIGTERM {}",
                k.client, k.device, k.procimgd_killed, k.procimgd_terminated
            ),
        );
        row("cycles (procimgd, all runs)", self.cycles.to_string());
        row("overruns", self.overruns.to_string());
        row(
            "OPFAULTs",
            format!(
                "{} (the client handled {} cycles)",
                self.opfaults, self.client_cycles
            ),
        );
        row(
            "watchdog expiries",
            format!(
                "{} ({} devices killed)",
                self.watchdog_expiries, self.kills.device
            ),
        );
        let r = &self.reconnect_ms;
        row("reconnect after a device restart", spread(&r.device));
        row("reconnect after a procimgd restart", spread(&r.procimgd));
        row(
            "client back after a procimgd restart",
            spread(&r.client_after_procimgd),
        );
        row("new client's first answer", spread(&r.client));
        row("recoveries failed", self.recoveries_failed.to_string());
        match &self.frames {
            Some(f) => row(
                "frames malformed (tshark)",
                format!(
                    "{} of procimgd, {} of the device, in {} frames",
                    f.bad_from_procimgd, f.bad_from_device, f.frames
                ),
            ),
            None => row("frames malformed (tshark)", "not checked".into()),
        }
        row(
            "frames malformed (received by procimgd)",
            self.malformed_received.to_string(),
        );
        row("data errors at the client", self.data_errors.to_string());
        row(
            "stale answers at the client (older than 64 cycles)",
            format!(
                "{} (the oldest {} cycles)",
                self.stale_echoes, self.oldest_echo
            ),
        );
        let rec = &self.records;
        row(
            "records lost",
            format!(
                "{} of {} (answered {}, refused {})",
                rec.lost, rec.asked, rec.answered, rec.refused
            ),
        );
        let a = &self.alarms;
        row(
            "alarms lost",
            format!(
                "{} of {} (delivered {}, acknowledged at the device {})",
                a.lost, a.raised, a.delivered, a.acked_at_device
            ),
        );
        row(
            "allocations in the cycle",
            self.rt_heap_allocations.to_string(),
        );
        match &self.cyclictest {
            Some(c) => row(
                "cyclictest wake-ups a cycle or more late",
                format!(
                    "{} of {} (p99 {:.0} µs, max {:.0} µs)",
                    c.late, c.samples, c.p99_us, c.max_us
                ),
            ),
            None => row("cyclictest wake-ups a cycle or more late", "not run".into()),
        }
        t
    }
}
