// SPDX-License-Identifier: MIT OR Apache-2.0
//! `--json`: the final results with the keys and layout of cyclictest's `--json` file
//! (including its `"cmdline:"` and `"rt_test_version:"` keys, colons and all, so a script
//! that reads one reads the other). The version field names this tool, not rt-tests.
//!
//! Written by hand rather than through serde so the key order and the thread map ("0", "1",
//! … "10" in numeric order) come out as cyclictest writes them.

use crate::stats::ThreadStats;
use std::fmt::Write as _;
use std::path::Path;
use std::time::SystemTime;

/// Why the JSON file could not be written.
#[derive(Debug, thiserror::Error)]
#[error(
    "cannot write the --json file {path}: {source}; check that its directory exists and is writable"
)]
pub struct JsonError {
    /// The file.
    pub path: String,
    /// The OS error.
    pub source: std::io::Error,
}

/// When the run started and ended.
#[derive(Clone, Copy, Debug)]
pub struct RunTimes {
    /// Start.
    pub start: SystemTime,
    /// End.
    pub end: SystemTime,
}

fn kernel(name: &str) -> String {
    std::fs::read_to_string(format!("/proc/sys/kernel/{name}"))
        .map(|s| s.trim_end().to_string())
        .unwrap_or_default()
}

fn quoted(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_else(|_| "\"\"".into())
}

/// The NUMA node of `cpu` (0 when the machine has no NUMA information).
fn numa_node(cpu: usize) -> usize {
    std::fs::read_dir(format!("/sys/devices/system/cpu/cpu{cpu}"))
        .ok()
        .and_then(|dir| {
            dir.flatten().find_map(|e| {
                e.file_name()
                    .to_str()?
                    .strip_prefix("node")?
                    .parse::<usize>()
                    .ok()
            })
        })
        .unwrap_or(0)
}

/// `t` as cyclictest writes it ("Sat, 21 Nov 2026 19:15:07 +0000"), in UTC.
pub fn rfc2822_utc(t: SystemTime) -> String {
    let secs = t
        .duration_since(SystemTime::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let days = (secs / 86400) as i64;
    let rem = secs % 86400;
    // Days since 1970-01-01 to a civil date (proleptic Gregorian calendar), by 400-year eras.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    const WEEKDAYS: [&str; 7] = ["Thu", "Fri", "Sat", "Sun", "Mon", "Tue", "Wed"];
    const MONTHS: [&str; 12] = [
        "Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec",
    ];
    format!(
        "{}, {day:02} {} {year} {:02}:{:02}:{:02} +0000",
        WEEKDAYS[days.rem_euclid(7) as usize],
        MONTHS[(month - 1) as usize],
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// The document, as cyclictest lays it out.
pub fn render(threads: &[ThreadStats], times: RunTimes, return_code: i32) -> String {
    let cmdline = std::env::args().collect::<Vec<_>>().join(" ");
    let realtime = std::fs::read_to_string("/sys/kernel/realtime").is_ok_and(|s| s.trim() == "1");
    let machine = match kernel("arch") {
        a if a.is_empty() => std::env::consts::ARCH.to_string(),
        a => a,
    };
    let mut o = String::new();
    let _ = writeln!(o, "{{");
    let _ = writeln!(o, "  \"file_version\": 1,");
    let _ = writeln!(o, "  \"cmdline:\": {},", quoted(&cmdline));
    let _ = writeln!(
        o,
        "  \"rt_test_version:\": {},",
        quoted(&format!("procimg-cyclictest {}", env!("CARGO_PKG_VERSION")))
    );
    let _ = writeln!(o, "  \"tool\": \"procimg-cyclictest\",");
    let _ = writeln!(
        o,
        "  \"tool_version\": {},",
        quoted(env!("CARGO_PKG_VERSION"))
    );
    let _ = writeln!(
        o,
        "  \"start_time\": {},",
        quoted(&rfc2822_utc(times.start))
    );
    let _ = writeln!(o, "  \"end_time\": {},", quoted(&rfc2822_utc(times.end)));
    let _ = writeln!(o, "  \"return_code\": {return_code},");
    let _ = writeln!(o, "  \"sysinfo\": {{");
    let _ = writeln!(o, "    \"sysname\": {},", quoted(&kernel("ostype")));
    let _ = writeln!(o, "    \"nodename\": {},", quoted(&kernel("hostname")));
    let _ = writeln!(o, "    \"release\": {},", quoted(&kernel("osrelease")));
    let _ = writeln!(o, "    \"version\": {},", quoted(&kernel("version")));
    let _ = writeln!(o, "    \"machine\": {},", quoted(&machine));
    let _ = writeln!(o, "    \"realtime\": {}", u8::from(realtime));
    let _ = writeln!(o, "  }},");
    let _ = writeln!(o, "  \"num_threads\": {},", threads.len());
    let _ = writeln!(o, "  \"resolution_in_ns\": 0,");
    let _ = writeln!(o, "  \"thread\": {{");
    for (i, t) in threads.iter().enumerate() {
        let _ = writeln!(o, "    \"{}\": {{", t.index);
        let filled: Vec<(usize, u64)> = t
            .us_buckets
            .iter()
            .enumerate()
            .filter(|(_, n)| **n > 0)
            .map(|(us, n)| (us, *n))
            .collect();
        if filled.is_empty() {
            let _ = writeln!(o, "      \"histogram\": {{      }},");
        } else {
            let _ = writeln!(o, "      \"histogram\": {{");
            for (j, (us, n)) in filled.iter().enumerate() {
                let comma = if j + 1 < filled.len() { "," } else { "" };
                let _ = writeln!(o, "        \"{us}\": {n}{comma}");
            }
            let _ = writeln!(o, "      }},");
        }
        let _ = writeln!(o, "      \"cycles\": {},", t.cycles);
        let _ = writeln!(o, "      \"min\": {},", t.min_us);
        let _ = writeln!(o, "      \"max\": {},", t.max_us);
        let _ = writeln!(o, "      \"avg\": {:.2},", t.avg_us());
        let cpu = t.cpu.unwrap_or(0);
        let _ = writeln!(o, "      \"cpu\": {cpu},");
        let _ = writeln!(o, "      \"node\": {}", numa_node(cpu));
        let comma = if i + 1 < threads.len() { "," } else { "" };
        let _ = writeln!(o, "    }}{comma}");
    }
    let _ = writeln!(o, "  }}");
    let _ = writeln!(o, "}}");
    o
}

/// Writes [`render`] to `path`.
pub fn write(
    path: &Path,
    threads: &[ThreadStats],
    times: RunTimes,
    return_code: i32,
) -> Result<(), JsonError> {
    std::fs::write(path, render(threads, times, return_code)).map_err(|source| JsonError {
        path: path.display().to_string(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_rt_tests::cyclictest_json::TOP_LEVEL_KEYS;
    use std::time::Duration;

    #[test]
    fn dates_come_out_as_cyclictest_writes_them() {
        let t = SystemTime::UNIX_EPOCH + Duration::from_secs(1_795_288_507);
        assert_eq!(rfc2822_utc(t), "Sat, 21 Nov 2026 19:15:07 +0000");
        assert_eq!(
            rfc2822_utc(SystemTime::UNIX_EPOCH),
            "Thu, 01 Jan 1970 00:00:00 +0000"
        );
        let leap = SystemTime::UNIX_EPOCH + Duration::from_secs(951_782_400);
        assert_eq!(rfc2822_utc(leap), "Tue, 29 Feb 2000 00:00:00 +0000");
    }

    #[test]
    fn the_document_is_json_with_cyclictests_keys() {
        let mut a = ThreadStats::new(0, 80, 1000, 20);
        a.record(13_200);
        a.record(19_000);
        let b = ThreadStats::new(1, 80, 1500, 0);
        let now = SystemTime::now();
        let text = render(
            &[a, b],
            RunTimes {
                start: now,
                end: now,
            },
            0,
        );
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        for key in TOP_LEVEL_KEYS {
            assert!(v.get(key).is_some(), "{key} missing in {text}");
        }
        assert_eq!(v["thread"]["0"]["histogram"]["13"], 1);
        assert_eq!(v["thread"]["0"]["avg"], 16.0);
        assert!(text.contains("\"histogram\": {      },"), "{text}");
    }
}
