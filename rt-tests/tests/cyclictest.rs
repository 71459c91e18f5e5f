// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimg-cyclictest as scripts written for cyclictest see it: the summary line, the
//! histogram file, the --json keys; procimg's own --report; and the --procimgd mode against
//! a real server (which the test kit builds up to date and starts).
//!
//! Runs without root: SCHED_FIFO, mlockall and /dev/cpu_dma_latency then fail with warnings
//! and the threads measure at normal priority.

use procimg_rt_tests::cyclictest_json::TOP_LEVEL_KEYS;
use procimg_rt_tests::report::Report;
use std::path::PathBuf;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

mod support;
use support::refusal;

const TOOL: &str = env!("CARGO_BIN_EXE_procimg-cyclictest");

/// Runs the tool with `args`; fails the test if it runs longer than `limit` or fails.
fn run(args: &[&str], limit: Duration) -> Output {
    let mut child = Command::new(TOOL)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start procimg-cyclictest");
    let until = Instant::now() + limit;
    while child.try_wait().expect("wait").is_none() {
        if Instant::now() > until {
            let _ = child.kill();
            let out = child.wait_with_output().expect("collect output");
            panic!(
                "procimg-cyclictest {args:?} ran longer than {limit:?}; stderr: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().expect("collect output");
    assert!(
        out.status.success(),
        "procimg-cyclictest {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !stderr.contains("allocated"),
        "the measuring loop allocated: {stderr}"
    );
    out
}

fn stdout(out: &Output) -> String {
    String::from_utf8(out.stdout.clone()).expect("stdout is UTF-8")
}

/// A scratch directory for one test, removed at the end.
struct Scratch(PathBuf);

impl Scratch {
    fn new(tag: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("procimg-ct-{}-{tag}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("create the scratch directory");
        Scratch(dir)
    }

    fn file(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// One `T:` line, taken apart by its labels (no regex), with cyclictest's field widths.
#[derive(Debug, PartialEq)]
struct Summary {
    thread: u64,
    tid: u64,
    priority: u64,
    interval: u64,
    cycles: u64,
    min: u64,
    act: u64,
    avg: u64,
    max: u64,
}

/// `text` as a number, which must be `width` wide (padded with spaces) unless its value has
/// more digits.
fn number(text: &str, width: usize, label: &str) -> Result<u64, String> {
    let value: u64 = text
        .trim_start()
        .parse()
        .map_err(|_| format!("{text:?} at {label:?} is not a number"))?;
    if text.len() != width && value.to_string().len() < width {
        return Err(format!("{text:?} at {label:?} is not {width} wide"));
    }
    Ok(value)
}

/// Cuts `rest` at `label`: the field before it as a number (see [`number`]) and what
/// follows the label.
fn field<'a>(rest: &'a str, label: &str, width: usize) -> Result<(u64, &'a str), String> {
    let (text, after) = rest
        .split_once(label)
        .ok_or_else(|| format!("no {label:?} in {rest:?}"))?;
    Ok((number(text, width, label)?, after))
}

fn parse_summary(line: &str) -> Result<Summary, String> {
    let rest = line
        .strip_prefix("T:")
        .ok_or_else(|| format!("{line:?} does not start with T:"))?;
    let (thread, rest) = field(rest, " (", 2)?;
    let (tid, rest) = field(rest, ") P:", 5)?;
    let (priority, rest) = field(rest, " I:", 2)?;
    let (interval, rest) = field(rest, " C:", 0)?;
    let (cycles, rest) = field(rest, " Min:", 7)?;
    let (min, rest) = field(rest, " Act:", 7)?;
    let (act, rest) = field(rest, " Avg:", 5)?;
    let (avg, rest) = field(rest, " Max:", 5)?;
    let max = number(rest, 8, "Max:")?;
    Ok(Summary {
        thread,
        tid,
        priority,
        interval,
        cycles,
        min,
        act,
        avg,
        max,
    })
}

#[test]
fn the_parser_reads_a_real_cyclictest_line() {
    let s = parse_summary(
        "T: 0 ( 1804) P:80 I:1000 C:   2000 Min:     12 Act:   32 Avg:   49 Max:   35150",
    )
    .unwrap();
    assert_eq!(
        s,
        Summary {
            thread: 0,
            tid: 1804,
            priority: 80,
            interval: 1000,
            cycles: 2000,
            min: 12,
            act: 32,
            avg: 49,
            max: 35150
        }
    );
    assert!(
        parse_summary("T: 0 (1804) P:80 I:1000 C:2000 Min:12 Act:32 Avg:49 Max:35150").is_err()
    );
}

#[test]
fn quiet_prints_one_summary_line_in_cyclictests_format() {
    let out = run(&["-q", "-l", "200", "-i", "1000"], Duration::from_secs(60));
    let text = stdout(&out);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 1, "{text}");
    let s = parse_summary(lines[0]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((s.thread, s.interval, s.cycles), (0, 1000, 200));
    // 0 when SCHED_FIFO was refused (not root): the tool then warns and goes on.
    assert!(s.priority == 80 || s.priority == 0, "{s:?}");
    assert!(s.tid > 0);
    assert!(s.min <= s.avg && s.avg <= s.max && s.act <= s.max, "{s:?}");
}

#[test]
fn two_threads_print_two_lines_at_their_intervals() {
    let out = run(
        &["-q", "-l", "200", "-i", "1000", "-t", "2"],
        Duration::from_secs(60),
    );
    let text = stdout(&out);
    let lines: Vec<Summary> = text
        .lines()
        .map(|l| parse_summary(l).unwrap_or_else(|e| panic!("{e}")))
        .collect();
    assert_eq!(lines.len(), 2, "{text}");
    assert_eq!((lines[0].thread, lines[0].interval), (0, 1000));
    assert_eq!((lines[1].thread, lines[1].interval), (1, 1500));
    // As cyclictest: the run ends when the first thread has done its loops. Periods lost to
    // an overrun are skipped, as procimgd's cycle skips them, so on a loaded machine the
    // first thread measures fewer than its 200 periods, never more.
    assert!((1..=200).contains(&lines[0].cycles), "{text}");
    assert!(lines[1].cycles < 200, "{text}");
    assert_ne!(lines[0].tid, lines[1].tid);
}

#[test]
fn the_histogram_file_has_cyclictests_structure() {
    let dir = Scratch::new("hist");
    let path = dir.file("hist.txt");
    let out = run(
        &[
            "-q",
            "-l",
            "200",
            "-i",
            "1000",
            "-h",
            "100",
            "--histfile",
            path.to_str().unwrap(),
        ],
        Duration::from_secs(60),
    );
    // With a histogram, -q prints nothing else on stdout (as cyclictest).
    assert_eq!(stdout(&out), "");
    let text = std::fs::read_to_string(&path).expect("histogram file written");
    let lines: Vec<&str> = text.split('\n').collect();
    assert_eq!(lines[0], "# Histogram");
    let mut counted = 0;
    for (us, line) in lines[1..101].iter().enumerate() {
        let (bucket, count) = line.split_once(' ').expect("two columns");
        assert_eq!(bucket, format!("{us:06}"));
        assert_eq!(count.len(), 6, "{line:?}");
        counted += count.parse::<u64>().unwrap();
    }
    let total = lines[101].strip_prefix("# Total: ").expect("# Total:");
    assert_eq!(total.len(), 9);
    assert_eq!(total.parse::<u64>().unwrap(), counted);
    for (line, label) in lines[102..106].iter().zip([
        "# Min Latencies: ",
        "# Avg Latencies: ",
        "# Max Latencies: ",
        "# Histogram Overflows: ",
    ]) {
        let value = line
            .strip_prefix(label)
            .unwrap_or_else(|| panic!("{line:?}"));
        assert!(value.len() >= 5 && value.parse::<u64>().is_ok(), "{line:?}");
    }
    let overflows: u64 = lines[105].rsplit(' ').next().unwrap().parse().unwrap();
    assert_eq!(counted + overflows, 200);
    assert_eq!(lines[106], "# Histogram Overflow at cycle number:");
    assert!(lines[107].starts_with("# Thread 0:"));
    assert_eq!(&lines[108..], ["", ""], "ends with an empty line");
}

#[test]
fn json_has_the_keys_cyclictest_writes() {
    let dir = Scratch::new("json");
    let path = dir.file("ct.json");
    let arg = format!("--json={}", path.display());
    run(
        &["-q", "-l", "100", "-t", "2", "-h", "400", &arg],
        Duration::from_secs(60),
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).expect("valid JSON");
    for key in TOP_LEVEL_KEYS {
        assert!(v.get(key).is_some(), "{key} missing: {v}");
    }
    for key in [
        "sysname", "nodename", "release", "version", "machine", "realtime",
    ] {
        assert!(
            v["sysinfo"].get(key).is_some(),
            "sysinfo.{key} missing: {v}"
        );
    }
    assert_eq!(v["num_threads"], 2);
    for t in ["0", "1"] {
        let thread = &v["thread"][t];
        for key in ["histogram", "cycles", "min", "max", "avg", "cpu", "node"] {
            assert!(thread.get(key).is_some(), "thread.{t}.{key} missing: {v}");
        }
    }
    // Both threads run at the same interval with -h; the first to finish its 100 loops ends
    // the run, whatever share the scheduler gave the other (which may have run none).
    let cycles = |t: &str| v["thread"][t]["cycles"].as_u64().unwrap();
    assert_eq!(cycles("0").max(cycles("1")), 100, "{v}");
    for t in ["0", "1"] {
        let in_histogram: u64 = v["thread"][t]["histogram"]
            .as_object()
            .unwrap()
            .values()
            .map(|n| n.as_u64().unwrap())
            .sum();
        assert!(in_histogram <= cycles(t), "thread {t}: {v}");
    }
    assert!(
        v["rt_test_version:"]
            .as_str()
            .unwrap()
            .starts_with("procimg-cyclictest ")
    );
}

#[test]
fn the_report_reads_back() {
    let dir = Scratch::new("report");
    let json = dir.file("r.json");
    let hlog = dir.file("r.hlog");
    run(
        &[
            "-q",
            "-l",
            "100",
            "--report",
            json.to_str().unwrap(),
            "--hdr-log",
            hlog.to_str().unwrap(),
        ],
        Duration::from_secs(60),
    );
    let r = Report::read_json(&json).expect("report reads back");
    assert_eq!(r.tool, "procimg-cyclictest");
    let all = r.get("wake-up").expect("wake-up");
    let t0 = r.get("wake-up T:0").expect("wake-up T:0");
    assert_eq!(all.count, 100);
    assert_eq!(
        all,
        &procimg_rt_tests::report::Measurement {
            name: "wake-up".into(),
            ..t0.clone()
        }
    );
    assert!(t0.min_ns <= t0.p50_ns && t0.p50_ns <= t0.max_ns);
    let log = std::fs::read_to_string(&hlog).unwrap();
    assert!(log.contains("Tag=wake_up_T_0,"), "{log}");
}

#[test]
fn bad_options_are_refused_with_a_hint() {
    let err = refusal(TOOL, &["-D", "10w"]);
    assert!(err.contains("s, m, h or d"), "{err}");
}

#[test]
fn procimgd_mode_reads_the_servers_cycle_thread() {
    // The demo cycling is all this needs; its devices may come up meanwhile.
    let server = procimg_testkit::Launch::demo("ct").until_cycling().start();
    let instance = server.instance.clone();
    let dir = Scratch::new("procimgd");
    let report = dir.file("r.json");
    let out = run(
        &[
            "--procimgd",
            &instance,
            "-l",
            "300",
            "-q",
            "--report",
            report.to_str().unwrap(),
        ],
        Duration::from_secs(60),
    );
    let text = stdout(&out);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 1, "{text}");
    let s = parse_summary(lines[0]).unwrap_or_else(|e| panic!("{e}"));
    assert!(s.cycles >= 300, "{s:?}");
    assert_eq!(s.interval, 1000, "the demo's cycle time");
    assert!(s.min <= s.max);
    let r = Report::read_json(&report).unwrap();
    assert_eq!(r.get("wake-up").unwrap().count, s.cycles);
}
