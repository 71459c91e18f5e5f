// SPDX-License-Identifier: MIT OR Apache-2.0
//! The real cyclictest's `--json` file, turned into a procimg [`Measurement`] so it sits in
//! the same table and plot as ours.
//!
//! cyclictest keeps whole µs: a latency of 12.7 µs is counted in bucket 12, and `min`/`max`
//! are truncated the same way. Each bucket is therefore taken at its middle (k + 0.5 µs),
//! which is the unbiased estimate; latencies beyond the `-h` range (its "overflows") are
//! taken at `max` + 0.5 µs. Its percentiles are thus good to ±0.5 µs.

use crate::report::{HIGHEST_NS, Measurement, new_histogram};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// The top-level keys of cyclictest's `--json` file, which procimg-cyclictest writes as well
/// (colons and all) so that scripts written for cyclictest read its file.
pub const TOP_LEVEL_KEYS: [&str; 10] = [
    "file_version",
    "cmdline:",
    "rt_test_version:",
    "start_time",
    "end_time",
    "return_code",
    "sysinfo",
    "num_threads",
    "resolution_in_ns",
    "thread",
];

#[derive(Deserialize)]
struct File {
    thread: BTreeMap<String, Thread>,
}

#[derive(Deserialize)]
struct Thread {
    #[serde(default)]
    histogram: BTreeMap<String, u64>,
    cycles: u64,
    max: u64,
    avg: f64,
}

/// Why the file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum CyclictestJsonError {
    /// Not readable.
    #[error("cannot read {path} ({source})")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// Not cyclictest's format.
    #[error(
        "{path} is not a cyclictest --json file ({detail}); procimg-compare reads the format \
         of rt-tests 2.x"
    )]
    Format {
        /// The file.
        path: String,
        /// What did not fit.
        detail: String,
    },
}

/// Reads thread 0 of the file at `path` as a measurement called `name`.
pub fn read(path: &Path, name: &str) -> Result<Measurement, CyclictestJsonError> {
    let text = std::fs::read_to_string(path).map_err(|source| CyclictestJsonError::Io {
        path: path.display().to_string(),
        source,
    })?;
    parse(&text, name).map_err(|detail| CyclictestJsonError::Format {
        path: path.display().to_string(),
        detail,
    })
}

/// Parses the file's text; `Err` says what did not fit.
pub fn parse(text: &str, name: &str) -> Result<Measurement, String> {
    let file: File = serde_json::from_str(text).map_err(|e| e.to_string())?;
    let t = file
        .thread
        .get("0")
        .ok_or("it has no thread 0 (was it run with -h?)")?;
    let mid = |us: u64| (us * 1000 + 500).min(HIGHEST_NS);
    let mut h = new_histogram();
    let mut counted = 0u64;
    for (us, &count) in &t.histogram {
        let us: u64 = us
            .parse()
            .map_err(|_| format!("histogram bucket {us:?} is not a number of µs"))?;
        if count > 0 {
            h.saturating_record_n(mid(us), count);
            counted += count;
        }
    }
    let overflows = t.cycles.saturating_sub(counted);
    if overflows > 0 {
        h.saturating_record_n(mid(t.max), overflows);
    }
    let mut m = Measurement::from_histogram(name, &h);
    // cyclictest's own mean is exact; the one of the midpoints is not.
    m.mean_ns = t.avg * 1000.0;
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buckets_are_taken_at_their_middle_and_overflows_at_the_max() {
        let text = r#"{"file_version": 1, "num_threads": 1, "thread": {"0": {
            "histogram": {"12": 50, "13": 48, "20": 1}, "cycles": 100, "min": 12,
            "max": 2500, "avg": 13.1, "cpu": 0, "node": 0}}}"#;
        let m = parse(text, "wake-up").unwrap();
        assert_eq!(m.count, 100);
        // HdrHistogram keeps 3 significant digits.
        assert!((12_500..=12_510).contains(&m.p50_ns), "{}", m.p50_ns);
        assert!((20_500..=20_520).contains(&m.p99_ns), "{}", m.p99_ns);
        assert!((2_499_000..=2_502_000).contains(&m.max_ns), "{}", m.max_ns);
        assert!((m.mean_ns - 13_100.0).abs() < 1.0);
    }

    #[test]
    fn other_files_are_refused_with_a_reason() {
        assert!(parse(r#"{"tool": "x"}"#, "w").is_err());
        assert!(
            parse(r#"{"thread": {}}"#, "w")
                .unwrap_err()
                .contains("thread 0")
        );
    }
}
