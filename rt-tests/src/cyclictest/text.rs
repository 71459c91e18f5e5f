// SPDX-License-Identifier: MIT OR Apache-2.0
//! cyclictest's text formats: the `T:` summary line, the live block, and the histogram dump
//! of -h/-H (field widths and separators as cyclictest 2.x prints them, so scripts written
//! for it — the gnuplot recipe that greps the histogram lines, the sed that picks Min/Avg/Max
//! — read this tool's output unchanged).

use crate::stats::ThreadStats;
use std::fmt::Write as _;

/// The figures of one `T:` line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Line {
    /// Thread number.
    pub index: usize,
    /// Kernel thread id.
    pub tid: u32,
    /// Priority.
    pub priority: u8,
    /// Interval, µs.
    pub interval_us: u64,
    /// Wake-ups.
    pub cycles: u64,
    /// µs.
    pub min_us: u64,
    /// µs.
    pub act_us: u64,
    /// µs, truncated.
    pub avg_us: u64,
    /// µs.
    pub max_us: u64,
}

impl Line {
    /// The line of a finished thread.
    pub fn of(s: &ThreadStats) -> Line {
        Line {
            index: s.index,
            tid: s.tid,
            priority: s.priority,
            interval_us: s.interval_us,
            cycles: s.cycles,
            min_us: s.min_us,
            act_us: s.act_us,
            avg_us: s.avg_us() as u64,
            max_us: s.max_us,
        }
    }
}

/// `T: 0 ( 1234) P:80 I:1000 C:   5000 Min:     19 Act:   22 Avg:   30 Max:     663`
pub fn summary_line(l: &Line) -> String {
    format!(
        "T:{:>2} ({:>5}) P:{:>2} I:{} C:{:>7} Min:{:>7} Act:{:>5} Avg:{:>5} Max:{:>8}",
        l.index, l.tid, l.priority, l.interval_us, l.cycles, l.min_us, l.act_us, l.avg_us, l.max_us
    )
}

/// The live block: the policy and load line, a blank line and one `T:` line per thread.
/// Every block but the first starts by moving the cursor up over the previous one, so a
/// terminal shows it in place.
pub fn live_block(policy: &str, lines: &[Line], first: bool) -> String {
    let mut out = String::new();
    if !first {
        let _ = write!(out, "\x1b[{}A", lines.len() + 2);
    }
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    // The trailing spaces erase what a longer previous line left on the terminal.
    let _ = writeln!(
        out,
        "policy: {policy}: loadavg: {}          \n",
        load.trim_end()
    );
    for l in lines {
        out.push_str(&summary_line(l));
        out.push('\n');
    }
    out
}

/// The histogram dump of -h (`with_sum`: -H, an extra column summing the threads).
pub fn histogram_dump(threads: &[ThreadStats], with_sum: bool) -> String {
    let size = threads
        .iter()
        .map(|t| t.us_buckets.len())
        .max()
        .unwrap_or(0);
    let mut out = String::from("# Histogram\n");
    for us in 0..size {
        let _ = write!(out, "{us:06}");
        let mut sum = 0;
        for (j, t) in threads.iter().enumerate() {
            let n = t.us_buckets.get(us).copied().unwrap_or(0);
            sum += n;
            out.push(if j == 0 { ' ' } else { '\t' });
            let _ = write!(out, "{n:06}");
        }
        if with_sum {
            let _ = write!(out, "\t{sum:06}");
        }
        out.push('\n');
    }
    let totals: Vec<u64> = threads.iter().map(|t| t.us_buckets.iter().sum()).collect();
    out.push_str("# Total:");
    for n in &totals {
        let _ = write!(out, " {n:09}");
    }
    if with_sum {
        let _ = write!(out, " {:09}", totals.iter().sum::<u64>());
    }
    out.push_str("\n# Min Latencies:");
    for t in threads {
        let _ = write!(out, " {:05}", t.min_us);
    }
    out.push_str("\n# Avg Latencies:");
    for t in threads {
        let _ = write!(out, " {:05}", t.avg_us() as u64);
    }
    out.push_str("\n# Max Latencies:");
    for t in threads {
        let _ = write!(out, " {:05}", t.max_us);
    }
    if with_sum {
        let max = threads.iter().map(|t| t.max_us).max().unwrap_or(0);
        let _ = write!(out, " {max:05}");
    }
    out.push_str("\n# Histogram Overflows:");
    for t in threads {
        let _ = write!(out, " {:05}", t.overflows);
    }
    if with_sum {
        let _ = write!(
            out,
            " {:05}",
            threads.iter().map(|t| t.overflows).sum::<u64>()
        );
    }
    out.push_str("\n# Histogram Overflow at cycle number:\n");
    for t in threads {
        let _ = write!(out, "# Thread {}:", t.index);
        for c in &t.overflow_cycles {
            let _ = write!(out, " {c:05}");
        }
        let others = t.overflows - t.overflow_cycles.len() as u64;
        if others > 0 {
            let _ = write!(out, " # {others:05} others");
        }
        out.push('\n');
    }
    out.push('\n');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_summary_line_has_cyclictests_widths() {
        let l = Line {
            index: 0,
            tid: 1804,
            priority: 80,
            interval_us: 1000,
            cycles: 2000,
            min_us: 12,
            act_us: 32,
            avg_us: 49,
            max_us: 35150,
        };
        assert_eq!(
            summary_line(&l),
            "T: 0 ( 1804) P:80 I:1000 C:   2000 Min:     12 Act:   32 Avg:   49 Max:   35150"
        );
        let l = Line {
            priority: 5,
            interval_us: 200,
            ..l
        };
        assert!(summary_line(&l).contains(" P: 5 I:200 "));
    }

    #[test]
    fn the_histogram_has_cyclictests_layout() {
        let mut a = ThreadStats::new(0, 80, 1000, 3);
        let mut b = ThreadStats::new(1, 80, 1000, 3);
        for ns in [1_200, 2_000, 9_000, 9_500] {
            a.record(ns);
        }
        b.record(0);
        let text = histogram_dump(&[a, b], false);
        assert_eq!(
            text,
            "# Histogram\n\
             000000 000000\t000001\n\
             000001 000001\t000000\n\
             000002 000001\t000000\n\
             # Total: 000000002 000000001\n\
             # Min Latencies: 00001 00000\n\
             # Avg Latencies: 00005 00000\n\
             # Max Latencies: 00009 00000\n\
             # Histogram Overflows: 00002 00000\n\
             # Histogram Overflow at cycle number:\n\
             # Thread 0: 00002 00003\n\
             # Thread 1:\n\n"
        );
    }

    #[test]
    fn overflows_beyond_the_list_are_others() {
        let mut a = ThreadStats::new(0, 80, 1000, 1);
        for _ in 0..3 {
            a.record(5_000);
        }
        let text = histogram_dump(&[a], true);
        assert!(
            text.contains("# Thread 0: 00000 # 00002 others\n"),
            "{text}"
        );
        assert!(text.contains("000000 000000\t000000\n"), "{text}");
        assert!(text.contains("# Total: 000000000 000000000\n"), "{text}");
    }
}
