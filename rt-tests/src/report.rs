// SPDX-License-Identifier: MIT OR Apache-2.0
//! The tools' common output: a [`Report`] of named [`Measurement`]s (percentiles plus the
//! histogram's buckets, so a plot can be drawn from the file alone), written as JSON, and
//! HdrHistogram interval logs for HdrHistogram's own tools.

use hdrhistogram::Histogram;
use hdrhistogram::serialization::V2DeflateSerializer;
use hdrhistogram::serialization::interval_log::{IntervalLogWriterBuilder, Tag};
use procimg_control::Bucket;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The histograms of every tool are procimgd's own: 1 ns … 10 s (larger values clamped),
/// 3 significant digits, so their figures and buckets compare one to one.
pub use procimg_runtime::stats::{HIGHEST_NS, buckets, latency_histogram as new_histogram};

/// Rebuilds a histogram from buckets (procimgd's `Histograms` answer, or a report's).
pub fn histogram_from_buckets(buckets: &[Bucket]) -> Histogram<u64> {
    let mut h = new_histogram();
    for b in buckets {
        let _ = h.record_n(b.ns.clamp(1, HIGHEST_NS), b.count);
    }
    h
}

/// `later − earlier`, bucket by bucket: what was recorded between two snapshots of the
/// same growing histogram.
pub fn buckets_between(earlier: &[Bucket], later: &[Bucket]) -> Vec<Bucket> {
    let before: BTreeMap<u64, u64> = earlier.iter().map(|b| (b.ns, b.count)).collect();
    later
        .iter()
        .filter_map(|b| {
            let count = b
                .count
                .saturating_sub(before.get(&b.ns).copied().unwrap_or(0));
            (count > 0).then_some(Bucket { ns: b.ns, count })
        })
        .collect()
}

/// One measured quantity: its percentiles in ns and its histogram.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Measurement {
    /// What was measured, e.g. `"round trip"`; unique within a report.
    pub name: String,
    /// Number of values.
    pub count: u64,
    /// Smallest, ns.
    pub min_ns: u64,
    /// Mean, ns.
    pub mean_ns: f64,
    /// Median, ns.
    pub p50_ns: u64,
    /// 99th percentile, ns.
    pub p99_ns: u64,
    /// 99.9th percentile, ns.
    pub p999_ns: u64,
    /// Largest, ns.
    pub max_ns: u64,
    /// The histogram's buckets that hold values.
    pub buckets: Vec<Bucket>,
}

impl Measurement {
    /// The percentiles and buckets of `h` under `name`.
    pub fn from_histogram(name: &str, h: &Histogram<u64>) -> Measurement {
        if h.is_empty() {
            return Measurement {
                name: name.to_string(),
                ..Measurement::default()
            };
        }
        Measurement {
            name: name.to_string(),
            count: h.len(),
            min_ns: h.min(),
            mean_ns: h.mean(),
            p50_ns: h.value_at_quantile(0.50),
            p99_ns: h.value_at_quantile(0.99),
            p999_ns: h.value_at_quantile(0.999),
            max_ns: h.max(),
            buckets: buckets(h),
        }
    }

    /// The histogram again, from the buckets.
    pub fn histogram(&self) -> Histogram<u64> {
        histogram_from_buckets(&self.buckets)
    }

    /// The row of this measurement in a tool's µs table (see [`table_header`]): the name in
    /// `name_width` columns, then count, min, p50, p99, p99.9 and max.
    pub fn table_row(&self, name_width: usize) -> String {
        let us = |ns: u64| ns as f64 / 1000.0;
        format!(
            "{:<name_width$} {:>8} {:>9.1} {:>9.1} {:>9.1} {:>9.1} {:>9.1}",
            self.name,
            self.count,
            us(self.min_ns),
            us(self.p50_ns),
            us(self.p99_ns),
            us(self.p999_ns),
            us(self.max_ns)
        )
    }
}

/// The header of the µs table the tools print after a run, one
/// [`Measurement::table_row`] a measurement.
pub fn table_header(name_width: usize) -> String {
    format!(
        "{:<name_width$} {:>8} {:>9} {:>9} {:>9} {:>9} {:>9}",
        "µs", "count", "min", "p50", "p99", "p99.9", "max"
    )
}

/// The machine a report was measured on.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Machine {
    /// CPU model name from /proc/cpuinfo.
    pub cpu: String,
    /// Online CPUs.
    pub cpus: usize,
    /// Kernel release (uname -r).
    pub kernel: String,
    /// The kernel is PREEMPT_RT (/sys/kernel/realtime).
    pub preempt_rt: bool,
}

impl Machine {
    /// This machine.
    pub fn this() -> Machine {
        let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
        let cpu = cpuinfo
            .lines()
            .find(|l| l.starts_with("model name"))
            .and_then(|l| l.split_once(':'))
            .map(|(_, v)| v.trim().to_string())
            .unwrap_or_default();
        let kernel = std::fs::read_to_string("/proc/sys/kernel/osrelease")
            .unwrap_or_default()
            .trim()
            .to_string();
        let preempt_rt =
            std::fs::read_to_string("/sys/kernel/realtime").is_ok_and(|s| s.trim() == "1");
        Machine {
            cpu,
            cpus: std::thread::available_parallelism().map_or(1, |n| n.get()),
            kernel,
            preempt_rt,
        }
    }
}

/// What one run of one tool measured.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// The tool, e.g. `"procimg-handshake"`.
    pub tool: String,
    /// The command line it ran with.
    pub command: String,
    /// Where.
    pub machine: Machine,
    /// The settings that matter for reading the figures, e.g. `clients = "4"`.
    pub settings: BTreeMap<String, String>,
    /// The figures.
    pub measurements: Vec<Measurement>,
}

/// Why a report could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// The file could not be written or read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// The file is not a report.
    #[error("{path}: not a procimg latency report ({source}); write it with a tool's --json")]
    Format {
        /// The file.
        path: String,
        /// The parse error.
        source: serde_json::Error,
    },
    /// A histogram could not be encoded for the HdrHistogram log.
    #[error("{path}: cannot encode histogram {name:?} for the HdrHistogram log: {detail}")]
    Encode {
        /// The file.
        path: String,
        /// The measurement.
        name: String,
        /// What failed.
        detail: String,
    },
}

impl Report {
    /// A report of `tool`, for the command line this process runs with, on this machine.
    pub fn new(tool: &str) -> Report {
        Report {
            tool: tool.to_string(),
            command: std::env::args().collect::<Vec<_>>().join(" "),
            machine: Machine::this(),
            settings: BTreeMap::new(),
            measurements: Vec::new(),
        }
    }

    /// Adds a setting.
    pub fn setting(&mut self, key: &str, value: impl ToString) -> &mut Report {
        self.settings.insert(key.to_string(), value.to_string());
        self
    }

    /// The measurement called `name`.
    pub fn get(&self, name: &str) -> Option<&Measurement> {
        self.measurements.iter().find(|m| m.name == name)
    }

    /// Writes the files a tool's `--report` and `--hdr-log` options asked for.
    pub fn save(&self, json: Option<&Path>, hdr_log: Option<&Path>) -> Result<(), ReportError> {
        if let Some(path) = json {
            self.write_json(path)?;
        }
        if let Some(path) = hdr_log {
            self.write_hdr_log(path)?;
        }
        Ok(())
    }

    /// Writes the report as pretty JSON.
    pub fn write_json(&self, path: &Path) -> Result<(), ReportError> {
        let text = serde_json::to_string_pretty(self).map_err(|e| ReportError::Format {
            path: path.display().to_string(),
            source: e,
        })?;
        std::fs::write(path, text + "\n").map_err(|source| ReportError::Io {
            path: path.display().to_string(),
            source,
        })
    }

    /// Reads a report written by [`Report::write_json`].
    pub fn read_json(path: &Path) -> Result<Report, ReportError> {
        let text = std::fs::read_to_string(path).map_err(|source| ReportError::Io {
            path: path.display().to_string(),
            source,
        })?;
        serde_json::from_str(&text).map_err(|source| ReportError::Format {
            path: path.display().to_string(),
            source,
        })
    }

    /// Writes every measurement as one tagged interval of an HdrHistogram log (V2, deflated),
    /// readable by HdrHistogram's `HistogramLogProcessor` and plotters of `.hlog` files.
    pub fn write_hdr_log(&self, path: &Path) -> Result<(), ReportError> {
        let io = |source| ReportError::Io {
            path: path.display().to_string(),
            source,
        };
        let mut file = std::io::BufWriter::new(std::fs::File::create(path).map_err(io)?);
        let mut serializer = V2DeflateSerializer::new();
        let mut log = IntervalLogWriterBuilder::new()
            .add_comment(&format!("{} on {}", self.command, self.machine.cpu))
            .with_max_value_divisor(1000.0)
            .begin_log_with(&mut file, &mut serializer)
            .map_err(io)?;
        for m in &self.measurements {
            let encode = |detail: String| ReportError::Encode {
                path: path.display().to_string(),
                name: m.name.clone(),
                detail,
            };
            // HdrHistogram tags may not hold spaces, commas or colons.
            let tag: String = m
                .name
                .chars()
                .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
                .collect();
            let tag = Tag::new(&tag).ok_or_else(|| encode(format!("bad tag {tag:?}")))?;
            log.write_histogram(
                &m.histogram(),
                std::time::Duration::ZERO,
                std::time::Duration::from_secs(1),
                Some(tag),
            )
            .map_err(|e| encode(format!("{e:?}")))?;
        }
        drop(log);
        use std::io::Write as _;
        file.flush().map_err(io)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buckets_round_trip_through_a_histogram() {
        let mut h = new_histogram();
        for v in [1_000, 1_500, 20_000, 20_000, 3_000_000] {
            h.record(v).unwrap();
        }
        let m = Measurement::from_histogram("x", &h);
        let again = m.histogram();
        assert_eq!(again.len(), 5);
        assert_eq!(again.max(), h.max());
        assert_eq!(again.value_at_quantile(0.5), h.value_at_quantile(0.5));
    }

    #[test]
    fn the_difference_of_two_snapshots_is_what_came_between() {
        let a = vec![Bucket { ns: 10, count: 2 }, Bucket { ns: 20, count: 1 }];
        let b = vec![
            Bucket { ns: 10, count: 5 },
            Bucket { ns: 20, count: 1 },
            Bucket { ns: 30, count: 4 },
        ];
        assert_eq!(
            buckets_between(&a, &b),
            vec![Bucket { ns: 10, count: 3 }, Bucket { ns: 30, count: 4 }]
        );
    }

    #[test]
    fn a_report_survives_json_and_the_hdr_log_is_written() {
        let dir = std::env::temp_dir().join(format!("procimg-report-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut h = new_histogram();
        h.record(12_345).unwrap();
        let mut r = Report::new("test");
        r.setting("clients", 1);
        r.measurements
            .push(Measurement::from_histogram("round trip", &h));
        let json = dir.join("r.json");
        r.write_json(&json).unwrap();
        assert_eq!(Report::read_json(&json).unwrap(), r);
        let log = dir.join("r.hlog");
        r.write_hdr_log(&log).unwrap();
        let text = std::fs::read_to_string(&log).unwrap();
        assert!(text.contains("Tag=round_trip,"), "{text}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
