// SPDX-License-Identifier: MIT OR Apache-2.0
//! The command line, with cyclictest's option names and meanings, and what it resolves to:
//! one [`ThreadPlan`] per measuring thread.

use clap::Parser;
use std::path::PathBuf;
use std::time::Duration;

/// Wake-up latency of a thread set up exactly like procimgd's cycle thread, in cyclictest's
/// conventions (options, summary line, histogram and --json formats).
///
/// Each measuring thread is pinned, made SCHED_FIFO and stack-prefaulted by procimgd's own
/// set-up functions, then sleeps with procimgd's absolute clock_nanosleep on CLOCK_MONOTONIC
/// and skips to the next period still ahead after an overrun, as procimgd's cycle loop does.
/// Latencies are in µs: the time a thread woke minus the time it asked to wake.
#[derive(Parser, Debug)]
#[command(version, about, long_about, disable_help_flag = true)]
pub struct Args {
    /// SCHED_FIFO priority of every measuring thread (cyclictest with -t gives all threads
    /// the same priority, and so does this tool). 0: normal scheduling (SCHED_OTHER), which
    /// is cyclictest's default; this tool's default is procimgd's.
    #[arg(short = 'p', long = "priority", default_value_t = 80, value_parser = clap::value_parser!(u8).range(0..=99))]
    pub priority: u8,
    /// Base interval of thread 0 in µs; thread i runs at INTERVAL + i·DIST.
    #[arg(short = 'i', long = "interval", default_value_t = 1000, value_parser = clap::value_parser!(u64).range(1..))]
    pub interval_us: u64,
    /// Distance of the thread intervals in µs (0 with -h/-H, as cyclictest does).
    #[arg(short = 'd', long = "distance", default_value_t = 500)]
    pub distance_us: u64,
    /// Loops: the run ends when the first thread has woken this often (0: until -D or Ctrl-C).
    /// With --procimgd: when the server recorded this many more wake-ups.
    #[arg(short = 'l', long = "loops", default_value_t = 0)]
    pub loops: u64,
    /// Run time: a number of seconds, or with a suffix s, m, h or d (e.g. 90s, 10m, 2h).
    #[arg(short = 'D', long = "duration", value_parser = parse_duration)]
    pub duration: Option<Duration>,
    /// CPUs to pin the threads to, round robin: a list like 3-5,0. Without it (or with -a
    /// and no list), thread i runs on the i-th CPU this process may use, as cyclictest 2.x
    /// does.
    #[arg(short = 'a', long = "affinity", num_args = 0..=1, default_missing_value = "", value_parser = parse_cpu_list)]
    pub affinity: Option<CpuList>,
    /// Measuring threads; -t without a number: one per CPU this process may use.
    #[arg(short = 't', long = "threads", num_args = 0..=1, default_missing_value = "0")]
    pub threads: Option<usize>,
    /// Lock current and future memory (mlockall), as procimgd does.
    #[arg(short = 'm', long = "mlockall")]
    pub mlock: bool,
    /// Print only the summary on exit (no live lines). With -h/-H: only the histogram.
    #[arg(short = 'q', long = "quiet")]
    pub quiet: bool,
    /// Dump a latency histogram after the run: one line per µs 0..US-1, one column per thread,
    /// then cyclictest's "# Total:", "# Min Latencies:" … lines.
    #[arg(short = 'h', long = "histogram", value_name = "US", value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub histogram: Option<u32>,
    /// As -h, with an extra column summing all threads.
    #[arg(short = 'H', long = "histofall", value_name = "US", value_parser = clap::value_parser!(u32).range(1..=1_000_000), conflicts_with = "histogram")]
    pub histofall: Option<u32>,
    /// Write the histogram of -h/-H to this file instead of stdout.
    #[arg(long = "histfile", value_name = "PATH")]
    pub histfile: Option<PathBuf>,
    /// Write the final results to FILE as JSON, with the keys cyclictest's --json writes.
    #[arg(long = "json", value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Write procimg's own latency report (JSON, read by procimg-compare): one measurement
    /// `"wake-up T:<i>"` per thread, and "wake-up" (thread 0).
    #[arg(long = "report", value_name = "FILE")]
    pub report: Option<PathBuf>,
    /// Write the same measurements as an HdrHistogram interval log.
    #[arg(long = "hdr-log", value_name = "FILE")]
    pub hdr_log: Option<PathBuf>,
    /// Measure nothing itself: read the wake-up histogram of the cycle thread of the running
    /// procimgd INSTANCE at the start and at the end (-l: its wake-ups, -D: time), and print
    /// the difference. "Act:" is then the largest wake-up latency of the last 100 ms.
    #[arg(long = "procimgd", value_name = "INSTANCE", conflicts_with_all = ["threads", "affinity", "mlock"])]
    pub procimgd: Option<String>,
    /// Print help.
    #[arg(long = "help", action = clap::ArgAction::Help)]
    pub help: Option<bool>,
}

impl Args {
    /// The histogram size in µs, from -h or -H.
    pub fn histogram_us(&self) -> Option<u32> {
        self.histogram.or(self.histofall)
    }
}

/// Why a -D value was refused.
#[derive(Debug, thiserror::Error)]
pub enum DurationError {
    /// Not a number with an optional unit.
    #[error(
        "{0:?} is not a duration: write seconds, or a number with s, m, h or d (e.g. 90s, 10m)"
    )]
    Syntax(String),
    /// Too long to count in nanoseconds.
    #[error("{0:?} is too long: at most about 500 years")]
    TooLong(String),
}

/// Parses cyclictest's -D: seconds, or a number with `s`, `m`, `h` or `d`.
pub fn parse_duration(s: &str) -> Result<Duration, DurationError> {
    let split = s.find(|c: char| !c.is_ascii_digit()).unwrap_or(s.len());
    let (num, unit) = s.split_at(split);
    let n: u64 = num
        .parse()
        .map_err(|_| DurationError::Syntax(s.to_string()))?;
    let factor = match unit {
        "" | "s" | "S" => 1,
        "m" | "M" => 60,
        "h" | "H" => 3600,
        "d" | "D" => 86400,
        _ => return Err(DurationError::Syntax(s.to_string())),
    };
    let secs = n
        .checked_mul(factor)
        .filter(|secs| secs.checked_mul(1_000_000_000).is_some())
        .ok_or_else(|| DurationError::TooLong(s.to_string()))?;
    Ok(Duration::from_secs(secs))
}

/// CPUs given with -a; empty means "the CPUs this process may use".
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CpuList(pub Vec<usize>);

/// Why a CPU list was refused.
#[derive(Debug, thiserror::Error)]
pub enum CpuListError {
    /// An element is neither a number nor a range.
    #[error("{0:?} is not a CPU list: write CPUs and ranges separated by commas, e.g. 1 or 2-3,0")]
    Syntax(String),
    /// A range runs backwards.
    #[error("{0:?}: a range must run upwards, e.g. 2-5")]
    Backwards(String),
}

/// Parses a CPU list such as `3-5,0` (the order is kept: threads go round robin over it).
pub fn parse_cpu_list(s: &str) -> Result<CpuList, CpuListError> {
    let mut cpus = Vec::new();
    if s.trim().is_empty() {
        return Ok(CpuList(cpus));
    }
    let num = |t: &str| {
        t.trim()
            .parse::<usize>()
            .map_err(|_| CpuListError::Syntax(s.to_string()))
    };
    for part in s.split(',') {
        match part.split_once('-') {
            Some((a, b)) => {
                let (a, b) = (num(a)?, num(b)?);
                if b < a {
                    return Err(CpuListError::Backwards(part.to_string()));
                }
                if b - a > 4096 {
                    return Err(CpuListError::Syntax(s.to_string()));
                }
                cpus.extend(a..=b);
            }
            None => cpus.push(num(part)?),
        }
    }
    Ok(CpuList(cpus))
}

/// The CPUs this process may run on (its affinity mask), from /proc/self/status, in rising
/// order; empty if it cannot be read.
pub fn allowed_cpus() -> Vec<usize> {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("Cpus_allowed_list:"))
                .and_then(|v| parse_cpu_list(v.trim()).ok())
        })
        .map(|l| l.0)
        .unwrap_or_default()
}

/// What one measuring thread does.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ThreadPlan {
    /// Thread number (the `T:` of its line).
    pub index: usize,
    /// CPU it is pinned to.
    pub cpu: Option<usize>,
    /// SCHED_FIFO priority (0: normal scheduling).
    pub priority: u8,
    /// Wake-up period in µs.
    pub interval_us: u64,
}

/// The measuring threads the options ask for: thread i at INTERVAL + i·DIST (DIST 0 with a
/// histogram), pinned round robin over the -a list or the CPUs this process may use.
pub fn thread_plans(args: &Args) -> Vec<ThreadPlan> {
    let allowed = allowed_cpus();
    let cpus = match &args.affinity {
        Some(CpuList(list)) if !list.is_empty() => list.clone(),
        _ => allowed.clone(),
    };
    let count = match args.threads {
        None => 1,
        Some(0) if allowed.is_empty() => {
            std::thread::available_parallelism().map_or(1, |n| n.get())
        }
        Some(0) => allowed.len(),
        Some(n) => n,
    };
    let distance = if args.histogram_us().is_some() {
        0
    } else {
        args.distance_us
    };
    (0..count)
        .map(|i| ThreadPlan {
            index: i,
            cpu: (!cpus.is_empty()).then(|| cpus[i % cpus.len()]),
            priority: args.priority,
            interval_us: args.interval_us + i as u64 * distance,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_take_cyclictests_suffixes() {
        assert_eq!(parse_duration("10").unwrap(), Duration::from_secs(10));
        assert_eq!(parse_duration("10s").unwrap(), Duration::from_secs(10));
        assert_eq!(parse_duration("2m").unwrap(), Duration::from_secs(120));
        assert_eq!(parse_duration("1h").unwrap(), Duration::from_secs(3600));
        assert_eq!(parse_duration("1d").unwrap(), Duration::from_secs(86400));
        assert!(parse_duration("1w").is_err());
        assert!(parse_duration("").is_err());
        assert!(parse_duration("99999999999999999d").is_err());
    }

    #[test]
    fn cpu_lists_keep_their_order() {
        assert_eq!(parse_cpu_list("3-5,0").unwrap().0, vec![3, 4, 5, 0]);
        assert_eq!(parse_cpu_list("1").unwrap().0, vec![1]);
        assert_eq!(parse_cpu_list("").unwrap().0, Vec::<usize>::new());
        assert!(parse_cpu_list("5-3").is_err());
        assert!(parse_cpu_list("x").is_err());
    }

    #[test]
    fn threads_get_the_distance_unless_a_histogram_is_asked_for() {
        let args = Args::parse_from(["t", "-t", "3", "-a", "1", "-i", "200"]);
        let plans = thread_plans(&args);
        assert_eq!(plans.len(), 3);
        assert_eq!(
            plans.iter().map(|p| p.interval_us).collect::<Vec<_>>(),
            [200, 700, 1200]
        );
        assert!(plans.iter().all(|p| p.cpu == Some(1) && p.priority == 80));
        let args = Args::parse_from(["t", "-t", "2", "-h", "50"]);
        assert!(thread_plans(&args).iter().all(|p| p.interval_us == 1000));
    }
}
