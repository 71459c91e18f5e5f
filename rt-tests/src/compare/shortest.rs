// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-compare --shortest-cycle 250,187.5,125`: how short a cycle procimgd holds on
//! this machine. For each cycle time, as a pair like every other (one after the other,
//! never at once, the order swapped every other round): procimgd's built-in demo (its
//! simulated devices answer, so the cycle carries their PROFINET work) with one sleeping
//! synchronous client (`procimg-handshake --demo`), and the real cyclictest at the same
//! interval and priority (`-m -p 80`), each for the same duration. It reports procimgd's
//! overruns and OPFAULTs, and its cycle thread's wake-ups later than the cycle, beside
//! cyclictest's late wake-ups: wake-ups at least one interval late, the cycles a thread with
//! no work at all would already have lost.

use super::figures::Results;
use super::plan::{CYCLICTEST, HANDSHAKE, Job, Output, WAKE_UP};
use super::table::{self, Notes};
use procimg_control::Bucket;
use std::time::Duration;

/// procimgd's cycle unit, ns: every cycle time is a multiple.
pub const CYCLE_UNIT_NS: u64 = procimg_shm_layout::CYCLE_COUNT_UNIT_NS;
/// procimg-handshake's measurement of the cycle thread's wake-ups.
pub const SERVER_WAKE_UP: &str = "server wake-up";

/// Parses a cycle time in µs ("250", "187.5") into ns; procimgd takes multiples of
/// 31.25 µs only.
pub fn parse_interval(s: &str) -> Result<u64, String> {
    let us: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a cycle time in µs such as 250 or 187.5"))?;
    let ns = (us * 1000.0).round();
    if ns < CYCLE_UNIT_NS as f64 || ns > 1e9 || ns % CYCLE_UNIT_NS as f64 != 0.0 {
        return Err(format!(
            "{s} µs: procimgd's cycle is a multiple of 31.25 µs (up to 1 s here), e.g. 250, \
             218.75, 187.5, 156.25, 125 or 93.75"
        ));
    }
    Ok(ns as u64)
}

/// "250", "187.5".
pub fn us_text(ns: u64) -> String {
    let us = ns as f64 / 1000.0;
    if us.fract() == 0.0 {
        format!("{us:.0}")
    } else {
        format!("{us}")
    }
}

/// cyclictest's interval for a cycle of `ns`: whole µs, the nearest.
pub fn cyclictest_us(ns: u64) -> u64 {
    (ns + 500) / 1000
}

/// The job keys of the pair for `ns`.
pub fn keys(ns: u64) -> (String, String) {
    let us = us_text(ns);
    (format!("demo-{us}us"), format!("cyclictest-{us}us"))
}

/// The pair for a cycle of `ns`, each running for `duration`.
pub fn pair(ns: u64, duration: Duration) -> Vec<Job> {
    let cycles = (duration.as_nanos() / u128::from(ns)).max(1).to_string();
    let (demo, ct) = keys(ns);
    let strings = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    vec![
        Job {
            key: demo,
            program: HANDSHAKE,
            args: strings(&["--demo", "-i", &us_text(ns), "-l", &cycles, "-q"]),
            output: Output::Report,
            // Plus procimg-handshake's warm-up of up to 3000 cycles and procimgd's start.
            expected: duration + Duration::from_nanos(3000 * ns) + Duration::from_secs(5),
        },
        Job {
            key: ct,
            program: CYCLICTEST,
            args: strings(&[
                "-m",
                "-p",
                "80",
                "-i",
                &cyclictest_us(ns).to_string(),
                "-l",
                &cycles,
                "-q",
                "-h",
                "2000",
            ]),
            output: Output::CyclictestJson,
            expected: duration,
        },
    ]
}

/// Values in buckets above `ns` (each bucket's `ns` is its highest value).
pub fn count_above(buckets: &[Bucket], ns: u64) -> u64 {
    buckets.iter().filter(|b| b.ns > ns).map(|b| b.count).sum()
}

/// "12 (0.005 %)".
pub fn count_and_percent(n: u64, of: u64) -> String {
    if of == 0 {
        return format!("{n}");
    }
    let pct = n as f64 * 100.0 / of as f64;
    let digits = if pct == 0.0 || pct >= 0.1 { 2 } else { 4 };
    format!("{n} ({pct:.digits$} %)")
}

/// One cycle time's outcome, summed over the rounds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Row {
    /// Cycle time, ns.
    pub ns: u64,
    /// procimgd's counts, or why there are none.
    pub procimgd: Result<Counts, String>,
    /// cyclictest's, or why there are none.
    pub cyclictest: Result<Counts, String>,
}

/// Counts of one side.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Cycles (procimgd: run while measured; cyclictest: its loops).
    pub cycles: u64,
    /// Wake-ups at least one cycle late.
    pub late: u64,
    /// procimgd's overruns (0 for cyclictest).
    pub overruns: u64,
    /// procimgd's OPFAULTs (0 for cyclictest).
    pub opfaults: u64,
}

impl Row {
    /// procimgd holds the cycle when it loses no more cycles (overruns and OPFAULTs) than
    /// cyclictest has late wake-ups: no more than the machine itself loses. `None` when a
    /// side was not measured.
    pub fn holds(&self) -> Option<bool> {
        let (p, c) = (self.procimgd.as_ref().ok()?, self.cyclictest.as_ref().ok()?);
        Some(p.overruns + p.opfaults <= c.late)
    }
}

/// The rows, from the rounds' results.
pub fn rows(res: &Results, intervals: &[u64]) -> Vec<Row> {
    intervals
        .iter()
        .map(|&ns| {
            let (demo, ct) = keys(ns);
            let procimgd = res.figure(&demo, SERVER_WAKE_UP).and_then(|f| {
                let sum = |name: &str| -> Result<u64, String> {
                    let v = res.settings_of(&demo, name);
                    if v.is_empty() {
                        return Err(format!("{demo}: its reports have no {name:?}"));
                    }
                    Ok(v.iter().filter_map(|s| s.parse::<u64>().ok()).sum())
                };
                Ok(Counts {
                    cycles: sum("cycles")?,
                    late: count_above(&f.buckets, ns),
                    overruns: sum("overruns")?,
                    opfaults: sum("opfaults")?,
                })
            });
            let cyclictest = res.figure(&ct, WAKE_UP).map(|f| Counts {
                cycles: f.buckets.iter().map(|b| b.count).sum(),
                late: count_above(&f.buckets, cyclictest_us(ns) * 1000),
                ..Counts::default()
            });
            Row {
                ns,
                procimgd,
                cyclictest,
            }
        })
        .collect()
}

/// The table with its footnotes.
pub fn render(rows: &[Row]) -> String {
    let mut notes = Notes::default();
    let header = [
        "cycle (µs)",
        "procimgd cycles",
        "overruns",
        "OPFAULTs",
        "procimgd wake-ups ≥ 1 cycle late",
        "cyclictest cycles",
        "cyclictest wake-ups ≥ 1 cycle late",
        "holds?",
    ]
    .map(String::from);
    let mut cells = vec![header];
    for r in rows {
        let (p, c) = (r.procimgd.as_ref(), r.cyclictest.as_ref());
        let pcell = |f: fn(&Counts) -> u64, notes: &mut Notes| match p {
            Ok(k) => count_and_percent(f(k), k.cycles),
            Err(e) => notes.not_measured(e),
        };
        let cycle = if cyclictest_us(r.ns) * 1000 == r.ns {
            us_text(r.ns)
        } else {
            format!("{} (cyclictest {})", us_text(r.ns), cyclictest_us(r.ns))
        };
        cells.push([
            cycle,
            p.map_or_else(|e| notes.not_measured(e), |k| k.cycles.to_string()),
            pcell(|k| k.overruns, &mut notes),
            pcell(|k| k.opfaults, &mut notes),
            pcell(|k| k.late, &mut notes),
            c.map_or_else(|e| notes.not_measured(e), |k| k.cycles.to_string()),
            c.map_or_else(
                |e| notes.not_measured(e),
                |k| count_and_percent(k.late, k.cycles),
            ),
            match r.holds() {
                Some(true) => "yes".into(),
                Some(false) => "no".into(),
                None => "—".into(),
            },
        ]);
    }
    let mut out = table::grid(&cells);
    out += &table::footnotes(&notes.0);
    out += "\nholds: procimgd lost no more cycles (overruns + OPFAULTs) than cyclictest had \
            wake-ups at least one cycle late, the machine's own losses. Late wake-ups are \
            counted to the histograms' resolution (cyclictest: 1 µs; procimgd: 1 %).\n";
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cycle_times_are_multiples_of_the_cycle_unit() {
        assert_eq!(parse_interval("250"), Ok(250_000));
        assert_eq!(parse_interval("187.5"), Ok(187_500));
        assert_eq!(parse_interval("93.75"), Ok(93_750));
        assert!(parse_interval("200").unwrap_err().contains("31.25"));
        assert!(parse_interval("0").is_err());
        assert!(parse_interval("fast").is_err());
        assert_eq!(us_text(187_500), "187.5");
        assert_eq!(us_text(250_000), "250");
        assert_eq!(cyclictest_us(187_500), 188);
        assert_eq!(cyclictest_us(93_750), 94);
    }

    #[test]
    fn the_pair_runs_the_same_cycles_at_the_same_interval() {
        let jobs = pair(250_000, Duration::from_secs(60));
        assert_eq!(jobs[0].key, "demo-250us");
        assert!(jobs[0].args.windows(2).any(|w| w == ["-l", "240000"]));
        assert!(jobs[0].args.contains(&"--demo".to_string()));
        assert!(jobs[1].args.windows(2).any(|w| w == ["-l", "240000"]));
        assert!(jobs[1].args.windows(2).any(|w| w == ["-i", "250"]));
        assert!(jobs[1].args.windows(2).any(|w| w == ["-p", "80"]));
    }

    #[test]
    fn late_wake_ups_are_those_above_the_cycle() {
        let b = |ns, count| Bucket { ns, count };
        let buckets = [
            b(20_000, 900),
            b(250_000, 5),
            b(251_000, 3),
            b(2_000_000, 2),
        ];
        assert_eq!(count_above(&buckets, 250_000), 5);
        assert_eq!(count_and_percent(12, 240_000), "12 (0.0050 %)");
        assert_eq!(count_and_percent(0, 240_000), "0 (0.00 %)");
        assert_eq!(count_and_percent(3, 100), "3 (3.00 %)");
        assert_eq!(count_and_percent(3, 0), "3");
    }

    #[test]
    fn a_cycle_holds_when_procimgd_loses_no_more_than_the_machine() {
        let row = |overruns, opfaults, late| Row {
            ns: 250_000,
            procimgd: Ok(Counts {
                cycles: 1000,
                late: 0,
                overruns,
                opfaults,
            }),
            cyclictest: Ok(Counts {
                cycles: 1000,
                late,
                ..Counts::default()
            }),
        };
        assert_eq!(row(0, 0, 0).holds(), Some(true));
        assert_eq!(row(1, 1, 2).holds(), Some(true));
        assert_eq!(row(2, 1, 2).holds(), Some(false));
        let unmeasured = Row {
            cyclictest: Err("cyclictest is not installed".into()),
            ..row(0, 0, 0)
        };
        assert_eq!(unmeasured.holds(), None);
        let text = render(&[row(2, 1, 2), unmeasured]);
        assert!(text.contains("| no "), "{text}");
        assert!(text.contains("2 (0.20 %)"), "{text}");
        assert!(text.contains("[1] cyclictest is not installed"), "{text}");
        crate::table::assert_rows_equally_wide(&text);
    }
}
