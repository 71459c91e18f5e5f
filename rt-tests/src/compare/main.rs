// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-compare`: every procimg latency figure beside the limit it should be a small
//! multiple of, measured on this machine in one run, one tool at a time.
//!
//! It runs, as child processes and in pairs that alternate (a figure, then its limit, the
//! order swapped every other round so neither always goes first):
//!
//! - the real `cyclictest` and `procimg-cyclictest` with the same options (wake-up);
//! - `procimg-baseline spin`, the same ping-pong with one round trip per cycle, and a
//!   busy-polling `procimg-handshake`;
//! - `procimg-baseline futex`, the same ping-pong with one round trip per cycle
//!   (`--period-us`: both sides wake from a cycle's sleep, as the handshake's do), and a
//!   sleeping `procimg-handshake`;
//! - `procimg-baseline eventfd` and `socket` (what iceoryx2's events cost);
//! - `procimg-baseline memcpy` for the image sizes of the sweep, then the sweep of sleeping
//!   handshakes over image sizes and client counts;
//! - `procimg-handshake startup` for the largest and the smallest image (procimgd's start,
//!   its locked memory, a client's attach);
//! - `procimg-handshake attach-load`: clients attaching and detaching beside procimgd's
//!   demo, its overruns against as long idle;
//!
//! reads their JSON back, prints one table and the goal table (also `DIR/table.md`) and
//! draws `DIR/latency.svg`. With `--shortest-cycle` it runs instead, for each cycle time
//! given, procimgd's demo beside the real cyclictest and reports the cycles each lost.
//! A tool that is missing or fails leaves its rows "not measured" with the reason; the run
//! goes on.

mod acceptance;
mod figures;
mod goals;
mod plan;
mod plot;
mod run;
mod shortest;
mod table;

use anyhow::{Context, Result};
use clap::Parser;
use figures::Results;
use plan::{Handshake, Job, Output, Settings};
use procimg_rt_tests::report::{Machine, Report};
use std::path::{Path, PathBuf};

/// Runs all latency tools alternately and prints each procimg figure beside the machine's limit
/// for it, as a table and latency.svg.
#[derive(Parser)]
#[command(version)]
struct Args {
    /// Seconds in all: few loops, one round, a small sweep. Proves the tools work together;
    /// too short to judge timing (the table puts met? in parentheses).
    #[arg(long)]
    quick: bool,
    /// Times every pair is run, alternately; the table shows each statistic's median over
    /// the rounds [default: 3, --quick: 1].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100))]
    rounds: Option<u32>,
    /// Cycles per wake-up and handshake run; ping-pongs and copies run ten times as many
    /// [default: 10000, --quick: 300].
    #[arg(short = 'l', long, value_parser = clap::value_parser!(u64).range(1..))]
    loops: Option<u64>,
    /// Cycle time in µs of the wake-up and handshake runs.
    #[arg(short = 'i', long = "interval", default_value_t = 1000, value_parser = clap::value_parser!(u64).range(50..=1_000_000))]
    interval_us: u64,
    /// Image sizes of the handshake sweep (the first is the main rows' size); procimgd's
    /// image holds at most 368128 bytes each way [default: 64,4KiB,64KiB,368128; --quick:
    /// 64,4KiB,64KiB].
    #[arg(long, value_delimiter = ',', value_parser = parse_size)]
    sizes: Option<Vec<usize>>,
    /// Client counts of the handshake sweep (the first is the main rows' count)
    /// [default: 1,4; --quick: 1,4].
    #[arg(long, value_delimiter = ',', value_parser = clap::value_parser!(usize))]
    clients: Option<Vec<usize>>,
    /// Run directory for every tool's report and log, the table and the plot
    /// [default: a directory under target/procimg-compare named by the UTC time].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Do not draw latency.svg.
    #[arg(long)]
    no_plots: bool,
    /// Instead of the comparison: for each cycle time (µs, multiples of 31.25, e.g.
    /// 250,187.5,125,93.75), procimgd's demo with a synchronous client beside the real
    /// cyclictest at that interval, each for --duration; reports procimgd's overruns and
    /// OPFAULTs beside cyclictest's late wake-ups.
    #[arg(long, value_name = "µs,…", value_delimiter = ',', value_parser = shortest::parse_interval)]
    shortest_cycle: Option<Vec<u64>>,
    /// Clients that attach and detach one after the other beside procimgd's demo, its
    /// overruns then against as long idle; 0 leaves the job out [default: 1000, --quick: 20].
    #[arg(long, value_name = "N")]
    attach_load: Option<u32>,
    /// How long each side of a --shortest-cycle pair runs [default: 60s, --quick: 5s].
    #[arg(long, value_parser = humantime::parse_duration)]
    duration: Option<std::time::Duration>,
}

/// Parses `64`, `4K`, `4KiB`, `1M`, `1MiB` (the sizes the tools take).
fn parse_size(s: &str) -> Result<usize, String> {
    let t = s.trim();
    let (num, unit) = t.split_at(t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len()));
    let factor: usize = match unit {
        "" | "B" => 1,
        "K" | "KiB" => 1 << 10,
        "M" | "MiB" => 1 << 20,
        _ => return Err(format!("{s:?} is not a size such as 64, 4KiB or 1MiB")),
    };
    num.parse::<usize>()
        .ok()
        .and_then(|n| n.checked_mul(factor))
        .filter(|&b| b > 0)
        .ok_or_else(|| format!("{s:?} is not a size such as 64, 4KiB or 1MiB"))
}

fn main() {
    let args = Args::parse();
    if let Err(e) = compare(&args) {
        eprintln!("procimg-compare: {e:#}");
        std::process::exit(1);
    }
}

fn settings(args: &Args) -> Settings {
    let (loops, sizes, clients) = if args.quick {
        // Every size and client count a goal is about, with few loops.
        (300, vec![64, 4096, 65536], vec![1, 4])
    } else {
        (10_000, vec![64, 4096, 65536, 368_128], vec![1, 4])
    };
    // The largest image's start-up locks some 40 MiB: not in a quick run, which stays small.
    let startup_sizes = if args.quick {
        plan::STARTUP_SIZES[1..].to_vec()
    } else {
        plan::STARTUP_SIZES.to_vec()
    };
    Settings {
        loops: args.loops.unwrap_or(loops),
        interval_us: args.interval_us,
        sizes: args.sizes.clone().unwrap_or(sizes),
        clients: args.clients.clone().unwrap_or(clients),
        startup_sizes,
        attach_load: args.attach_load.unwrap_or(if args.quick {
            20
        } else {
            acceptance::ATTACH_LOAD_ATTACHES
        }),
    }
}

fn compare(args: &Args) -> Result<()> {
    let s = settings(args);
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("target/procimg-compare").join(utc_stamp()));
    std::fs::create_dir_all(&dir)
        .with_context(|| format!("cannot create the run directory {}", dir.display()))?;
    if let Some(intervals) = &args.shortest_cycle {
        return shortest_cycle(args, intervals, &dir);
    }
    let rounds = args.rounds.unwrap_or(if args.quick { 1 } else { 3 });
    let groups = plan::groups(&s);
    let results = run_groups(&groups, rounds, &dir)?;

    let rows = table::rows(&results, &s);
    let mut text = header(&s, rounds, &dir, args.quick);
    text += &table::render(&rows, !args.quick);
    text += &footer(&results, &s);
    text += "\n## Goals\n\n";
    text += &goals::render(&goals::goals(&results, &s), !args.quick);
    print!("{text}");
    let table_path = dir.join("table.md");
    std::fs::write(&table_path, &text)
        .with_context(|| format!("cannot write {}", table_path.display()))?;
    if !args.no_plots {
        let svg = dir.join("latency.svg");
        let title = format!(
            "procimg latency beside its limits: {}",
            Machine::this().cpu.trim()
        );
        plot::latency_svg(&svg, &title, &panels(&results, &s))?;
        println!("plot: {}", svg.display());
    }
    println!("table: {}", table_path.display());
    Ok(())
}

/// The shortest-cycle runs: a pair per cycle time, their table printed and in table.md.
fn shortest_cycle(args: &Args, intervals: &[u64], dir: &Path) -> Result<()> {
    let rounds = args.rounds.unwrap_or(1);
    let duration = args
        .duration
        .unwrap_or(std::time::Duration::from_secs(if args.quick {
            5
        } else {
            60
        }));
    let groups: Vec<Vec<Job>> = intervals
        .iter()
        .map(|&ns| shortest::pair(ns, duration))
        .collect();
    let results = run_groups(&groups, rounds, dir)?;
    let m = Machine::this();
    let list: Vec<String> = intervals.iter().map(|&ns| shortest::us_text(ns)).collect();
    let mut text = format!(
        "# procimg-compare --shortest-cycle {}\n\n\
         machine: {}, {} CPUs, kernel {}, PREEMPT_RT {}\n\
         settings: {rounds} round(s) (counts summed), pairs alternated; each side {} per \
         round: procimgd --demo (SCHED_FIFO 80, OPDONE deadline half the cycle) with one \
         sleeping synchronous client (FIFO 70), and cyclictest -m -p 80 -h 2000\n\
         run directory: {}\n\n",
        list.join(","),
        m.cpu,
        m.cpus,
        m.kernel,
        if m.preempt_rt { "yes" } else { "no" },
        humantime::format_duration(duration),
        dir.display(),
    );
    text += &shortest::render(&shortest::rows(&results, intervals));
    print!("{text}");
    let table_path = dir.join("table.md");
    std::fs::write(&table_path, &text)
        .with_context(|| format!("cannot write {}", table_path.display()))?;
    println!("table: {}", table_path.display());
    Ok(())
}

/// Runs every group `rounds` times into `dir/round-N`, the pairs' order swapped every other
/// round.
fn run_groups(groups: &[Vec<Job>], rounds: u32, dir: &Path) -> Result<Results> {
    let mut results = Results::default();
    for round in 1..=rounds {
        let round_dir = dir.join(format!("round-{round}"));
        std::fs::create_dir_all(&round_dir)
            .with_context(|| format!("cannot create {}", round_dir.display()))?;
        for group in groups {
            // Swap each pair every other round, so that neither side always runs first
            // (right after the other has warmed or disturbed the caches and the CPU clock).
            let order: Vec<&Job> = if round % 2 == 0 {
                group.iter().rev().collect()
            } else {
                group.iter().collect()
            };
            for job in order {
                eprint!("procimg-compare: round {round}/{rounds}: {} … ", job.key);
                let outcome = run_job(job, &round_dir);
                match &outcome {
                    Ok(_) => eprintln!("done"),
                    Err(e) => eprintln!("not measured: {e}"),
                }
                results.add(&job.key, outcome);
            }
        }
    }
    Ok(results)
}

/// Runs `job` once into `dir` and reads what it wrote.
fn run_job(job: &Job, dir: &Path) -> Result<Report, String> {
    let file = dir.join(format!("{}.json", job.key));
    let inv = run::Invocation {
        program: job.program.clone(),
        args: job.args_with_output(&file),
        log: dir.join(format!("{}.log", job.key)),
        limit: job.limit(),
    };
    run::run(&inv)?;
    match job.output {
        Output::Report => Report::read_json(&file).map_err(|e| e.to_string()),
        Output::CyclictestJson => {
            let m = procimg_rt_tests::cyclictest_json::read(&file, plan::WAKE_UP)
                .map_err(|e| e.to_string())?;
            let mut r = Report::new("cyclictest");
            r.command = format!("cyclictest {}", inv.args.join(" "));
            r.measurements.push(m);
            Ok(r)
        }
    }
}

fn header(s: &Settings, rounds: u32, dir: &Path, quick: bool) -> String {
    let m = Machine::this();
    let list = |v: &[String]| v.join(", ");
    let sizes: Vec<String> = s.sizes.iter().map(|&b| table::human_bytes(b)).collect();
    let clients: Vec<String> = s.clients.iter().map(|c| c.to_string()).collect();
    format!(
        "# procimg-compare{}\n\n\
         machine: {}, {} CPUs, kernel {}, PREEMPT_RT {}\n\
         settings: {rounds} round(s), pairs alternated (table: median of the rounds' values; \
         plot: all rounds pooled); {} cycles per wake-up and handshake run at {} µs, {} round \
         trips per ping-pong; SCHED_FIFO 80; main handshake rows: {} client(s), {}; sweep: \
         sizes {}, clients {}; attach-load: {} attaches per round beside the demo\n\
         run directory: {} (each tool's report and log in round-N/)\n\n",
        if quick {
            " (quick: timing not judged)"
        } else {
            ""
        },
        m.cpu,
        m.cpus,
        m.kernel,
        if m.preempt_rt { "yes" } else { "no" },
        s.loops,
        s.interval_us,
        s.loops * 10,
        s.main_clients(),
        table::human_bytes(s.main_bytes()),
        list(&sizes),
        list(&clients),
        s.attach_load,
        dir.display(),
    )
}

fn footer(res: &Results, s: &Settings) -> String {
    let mut out = String::from(
        "\nnotes: cyclictest's percentiles come from its 1 µs histogram, each bucket taken at \
         its middle (±0.5 µs); ours from HdrHistogram (3 significant digits). One way is \
         compared with half the baseline's round trip.\n",
    );
    let main = Handshake {
        busy: false,
        clients: s.main_clients(),
        bytes: s.main_bytes(),
    };
    for h in [Handshake { busy: true, ..main }, main] {
        if let (Some(o), Some(f)) = (
            res.setting(&h.key(), "overruns"),
            res.setting(&h.key(), "opfaults"),
        ) {
            out += &format!("{}: {o} overruns, {f} OPFAULTs (round 1)\n", h.key());
        }
    }
    out
}

/// The plot's panels: each group's figures beside their limits.
fn panels(res: &Results, s: &Settings) -> Vec<plot::Panel> {
    let series = |key: &str, name: &str, label: &str, baseline: bool| {
        res.figure(key, name).ok().map(|f| plot::Series {
            label: label.to_string(),
            buckets: f.buckets,
            p999_ns: f.stats.p999 as u64,
            max_ns: f.stats.max as u64,
            baseline,
        })
    };
    let main = |busy| Handshake {
        busy,
        clients: s.main_clients(),
        bytes: s.main_bytes(),
    };
    let rt = plan::ROUND_TRIP;
    vec![
        plot::Panel {
            title: format!("wake-up, {} µs cycle", s.interval_us),
            min_bin_us: 1.0,
            series: [
                series(
                    "procimg-cyclictest",
                    plan::WAKE_UP,
                    "procimg-cyclictest",
                    false,
                ),
                series("cyclictest", plan::WAKE_UP, "cyclictest (rt-tests)", true),
            ]
            .into_iter()
            .flatten()
            .collect(),
        },
        plot::Panel {
            title: "busy-polling handshake round trip".into(),
            min_bin_us: 0.0,
            series: [
                series(&main(true).key(), rt, "procimg busy round trip", false),
                series("spin", rt, "spin baseline", true),
                series(
                    plan::SPIN_EVERY_CYCLE,
                    rt,
                    "spin baseline, one per cycle",
                    true,
                ),
            ]
            .into_iter()
            .flatten()
            .collect(),
        },
        plot::Panel {
            title: "sleeping handshake round trip".into(),
            min_bin_us: 0.0,
            series: [
                series(&main(false).key(), rt, "procimg sleeping round trip", false),
                series("futex", rt, "futex baseline", true),
                series(
                    plan::FUTEX_EVERY_CYCLE,
                    rt,
                    "futex baseline, one per cycle",
                    true,
                ),
                series("eventfd", rt, "eventfd baseline", true),
                series("socket", rt, "unix socket baseline", true),
            ]
            .into_iter()
            .flatten()
            .collect(),
        },
    ]
}

/// "20261121-192102": UTC, sortable, safe in a path.
fn utc_stamp() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let (days, rest) = (secs / 86_400, secs % 86_400);
    let (y, m, d) = civil_from_days(days as i64);
    format!(
        "{y:04}{m:02}{d:02}-{:02}{:02}{:02}",
        rest / 3600,
        rest / 60 % 60,
        rest % 60
    )
}

/// Gregorian date of a day count since 1970-01-01 (H. Hinnant's civil_from_days).
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_are_gregorian() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(19_723), (2024, 1, 1));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
    }

    #[test]
    fn sizes_parse_like_the_tools() {
        assert_eq!(parse_size("4KiB"), Ok(4096));
        assert_eq!(parse_size("368128"), Ok(368_128));
        assert!(parse_size("0").is_err());
        assert!(parse_size("4 GB").is_err());
    }
}
