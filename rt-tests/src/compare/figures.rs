// SPDX-License-Identifier: MIT OR Apache-2.0
//! The reports of every round, and one figure per measurement across the rounds: each
//! statistic is the median of the rounds' values (so one disturbed round does not move the
//! table), while the histogram pools all rounds (for the plot).

use procimg_control::Bucket;
use procimg_rt_tests::report::{Measurement, Report, buckets, histogram_from_buckets};
use std::collections::BTreeMap;

/// The statistics a table row is made of, in ns.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Median.
    pub p50: f64,
    /// 99th percentile.
    pub p99: f64,
    /// 99.9th percentile.
    pub p999: f64,
    /// Largest.
    pub max: f64,
}

impl Stats {
    fn of(m: &Measurement) -> Stats {
        Stats {
            p50: m.p50_ns as f64,
            p99: m.p99_ns as f64,
            p999: m.p999_ns as f64,
            max: m.max_ns as f64,
        }
    }

    /// Every statistic times `k` (half a round trip: the one-way limit).
    pub fn scaled(self, k: f64) -> Stats {
        Stats {
            p50: self.p50 * k,
            p99: self.p99 * k,
            p999: self.p999 * k,
            max: self.max * k,
        }
    }

    /// Statistic by statistic sum (a wake-up limit plus a copy limit). Percentiles do not
    /// add exactly; for a limit the sum is the honest upper figure.
    pub fn plus(self, o: Stats) -> Stats {
        Stats {
            p50: self.p50 + o.p50,
            p99: self.p99 + o.p99,
            p999: self.p999 + o.p999,
            max: self.max + o.max,
        }
    }
}

/// One measurement over all rounds.
#[derive(Clone, Debug)]
pub struct Figure {
    /// Medians over the rounds.
    pub stats: Stats,
    /// All rounds' buckets, pooled.
    pub buckets: Vec<Bucket>,
}

/// Every job's outcome, round by round.
#[derive(Default)]
pub struct Results {
    runs: BTreeMap<String, Vec<Result<Report, String>>>,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => v[n / 2],
        _ => (v[n / 2 - 1] + v[n / 2]) / 2.0,
    }
}

impl Results {
    /// Adds one round's outcome of job `key`.
    pub fn add(&mut self, key: &str, outcome: Result<Report, String>) {
        self.runs.entry(key.to_string()).or_default().push(outcome);
    }

    /// The measurement `name` of job `key` over all rounds, or why there is none.
    pub fn figure(&self, key: &str, name: &str) -> Result<Figure, String> {
        let runs = self
            .runs
            .get(key)
            .ok_or_else(|| format!("{key} was not run"))?;
        let mut found = Vec::new();
        let mut why = None;
        for run in runs {
            match run {
                Ok(report) => match report.get(name) {
                    Some(m) if m.count > 0 => found.push(m),
                    Some(_) => why = Some(format!("{key}: {name:?} counted nothing")),
                    None => why = Some(format!("{key}: its report has no {name:?}")),
                },
                Err(e) => why = Some(e.clone()),
            }
        }
        if found.is_empty() {
            return Err(why.unwrap_or_else(|| format!("{key} was not run")));
        }
        let stats: Vec<Stats> = found.iter().map(|m| Stats::of(m)).collect();
        let med = |f: fn(&Stats) -> f64| median(stats.iter().map(f).collect());
        let mut pooled = histogram_from_buckets(&[]);
        for m in &found {
            let _ = pooled.add(m.histogram());
        }
        Ok(Figure {
            stats: Stats {
                p50: med(|s| s.p50),
                p99: med(|s| s.p99),
                p999: med(|s| s.p999),
                max: med(|s| s.max),
            },
            buckets: buckets(&pooled),
        })
    }

    /// Every report of every job and round that has the setting `name`.
    pub fn reports_with(&self, name: &str) -> Vec<&Report> {
        self.runs
            .values()
            .flatten()
            .flatten()
            .filter(|r| r.settings.contains_key(name))
            .collect()
    }

    /// The setting `name` of job `key`'s reports, round by round (rounds that failed or lack
    /// it left out).
    pub fn settings_of(&self, key: &str, name: &str) -> Vec<String> {
        self.runs
            .get(key)
            .into_iter()
            .flatten()
            .flatten()
            .filter_map(|r| r.settings.get(name).cloned())
            .collect()
    }

    /// Why job `key` has no report: "was not run", or the first failed round's reason.
    pub fn failure(&self, key: &str) -> String {
        let Some(runs) = self.runs.get(key) else {
            return format!("{key} was not run");
        };
        runs.iter()
            .find_map(|r| r.as_ref().err().cloned())
            .unwrap_or_else(|| format!("{key} reported nothing"))
    }

    /// A setting of job `key`'s first report, e.g. procimg-handshake's overruns.
    pub fn setting(&self, key: &str, name: &str) -> Option<String> {
        self.runs
            .get(key)?
            .iter()
            .flatten()
            .find_map(|r| r.settings.get(name).cloned())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_rt_tests::report::new_histogram;

    fn report(values: &[u64]) -> Report {
        let mut h = new_histogram();
        for &v in values {
            h.record(v).unwrap();
        }
        let mut r = Report::new("fake");
        r.measurements
            .push(Measurement::from_histogram("round trip", &h));
        r
    }

    #[test]
    fn statistics_are_medians_of_the_rounds_and_histograms_are_pooled() {
        let mut res = Results::default();
        res.add("futex", Ok(report(&[1000, 1000, 90_000])));
        res.add("futex", Err("round 2 broke".into()));
        res.add("futex", Ok(report(&[2000, 2000, 2000])));
        res.add("futex", Ok(report(&[3000, 3000, 3000])));
        let f = res.figure("futex", "round trip").unwrap();
        // HdrHistogram keeps 3 significant digits: compare to 0.1 %.
        let near = |a: f64, b: f64| (a - b).abs() <= b / 1000.0;
        assert!(near(f.stats.p50, 2000.0), "{:?}", f.stats);
        assert!(near(f.stats.max, 3000.0), "{:?}", f.stats);
        assert_eq!(f.buckets.iter().map(|b| b.count).sum::<u64>(), 9);
    }

    #[test]
    fn a_figure_that_never_ran_says_why() {
        let mut res = Results::default();
        res.add("spin", Err("spin needs two CPUs".into()));
        assert_eq!(
            res.figure("spin", "round trip").unwrap_err(),
            "spin needs two CPUs"
        );
        res.add("futex", Ok(report(&[1000])));
        assert!(res.figure("futex", "nothing").unwrap_err().contains("no"));
        assert!(res.figure("socket", "round trip").is_err());
    }

    #[test]
    fn an_even_number_of_rounds_takes_the_middle_two() {
        assert_eq!(median(vec![4.0, 1.0, 3.0, 2.0]), 2.5);
    }
}
