// SPDX-License-Identifier: MIT OR Apache-2.0
//! The goal table: the goals of the acceptance (issue 34's, and issue 16's where the later
//! one says nothing else; the bounds are in [`super::acceptance`]), each with today's value
//! and whether it is met. The latency goals are ratios to the machine's limits (from the
//! comparison's own runs); the others are counts, memory and times from procimg-handshake's
//! runs and its `startup` and `attach-load` jobs, and two properties of the code
//! ([`SERVER_COPIES_PER_INPUT_BYTE`], [`SERVER_COPIES_PER_OUTPUT_BYTE`]).

use super::acceptance;
use super::figures::{Results, Stats};
use super::plan::{self, Handshake, Settings};
use super::table::{self, Notes};
use procimg_rt_tests::names;

/// Copies the server makes of each input byte on its way from the wire to the clients, per
/// cycle. A property of the server's cycle, not measured, and not reported by procimgd: the
/// cycle thread writes a device's input data from its frame straight into the sample it then
/// publishes; the inputs of a device that sent nothing in the cycle are carried over from
/// the last image, once. Update it here, and only here, when the cycle changes
/// (docs/PERFORMANCE.md, "Copies").
pub const SERVER_COPIES_PER_INPUT_BYTE: u32 = 1;

/// Copies the server makes of each output byte on its way from a client to the wire: the
/// client's sample straight into the next input sample, whose mirror of the outputs holds
/// each device's output frame (and shows the clients the outputs as last sent); the frame
/// is sent from there. The controller role's; in the device role, whose frames the PLC lays
/// out at Connect, the frame is written from the mirror: 2.
pub const SERVER_COPIES_PER_OUTPUT_BYTE: u32 = 1;

/// The unit a goal's value is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    /// A ratio to a limit: "4.50×".
    Ratio,
    /// A count: "2".
    Count,
    /// Bytes: "21.6 MiB".
    Bytes,
    /// Nanoseconds: "312 ms", "4.10 ms".
    Ns,
}

/// What a value must be to meet its goal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bound {
    /// At most this.
    AtMost(f64),
    /// Less than this.
    Below(f64),
}

impl Bound {
    /// Whether `value` meets the bound.
    pub fn met(self, value: f64) -> bool {
        match self {
            Bound::AtMost(b) => value <= b,
            Bound::Below(b) => value < b,
        }
    }
}

/// One goal with today's value.
#[derive(Clone, Debug)]
pub struct Goal {
    /// The goal's quantity.
    pub name: String,
    /// What went into the value (the figures of a ratio, the method), or why nothing was
    /// measured.
    pub measured: Result<String, String>,
    /// Today's value.
    pub value: Option<f64>,
    /// Its unit (also the bound's).
    pub unit: Unit,
    /// The goal.
    pub bound: Bound,
    /// A latency statistic, judged only in full runs (a quick run's few loops say nothing
    /// about percentiles).
    pub statistical: bool,
}

/// `value / limit`, when the limit is a positive number.
pub fn ratio(value: f64, limit: f64) -> Option<f64> {
    (limit > 0.0 && value.is_finite()).then(|| value / limit)
}

/// A value written in its unit.
pub fn format_value(v: f64, unit: Unit) -> String {
    match unit {
        Unit::Ratio => format!("{v:.2}×"),
        Unit::Count => format!("{v:.0}"),
        Unit::Bytes => format!("{:.1} MiB", v / f64::from(1 << 20)),
        Unit::Ns if v >= 1e9 => format!("{:.2} s", v / 1e9),
        Unit::Ns if v >= 1e8 => format!("{:.0} ms", v / 1e6),
        Unit::Ns => format!("{:.2} ms", v / 1e6),
    }
}

/// The goal written out: "≤ 1.5×", "0", "< 1 s".
pub fn format_bound(b: Bound, unit: Unit) -> String {
    let plain = |v: f64| match unit {
        Unit::Ratio => format!("{v}×"),
        Unit::Ns if v >= 1e9 => format!("{} s", v / 1e9),
        Unit::Ns => format!("{} ms", v / 1e6),
        _ => format_value(v, unit),
    };
    match b {
        Bound::AtMost(v) => format!("≤ {}", plain(v)),
        Bound::Below(v) => format!("< {}", plain(v)),
    }
}

/// "yes"/"NO", in parentheses for a latency goal of a run too short to judge; "—" without a
/// value.
pub fn met_text(g: &Goal, judged: bool) -> String {
    match g.value {
        None => "—".into(),
        Some(v) => {
            let met = g.bound.met(v);
            match (judged || !g.statistical, met) {
                (true, true) => "yes".into(),
                (true, false) => "NO".into(),
                (false, true) => "(yes)".into(),
                (false, false) => "(no)".into(),
            }
        }
    }
}

fn us(ns: f64) -> String {
    format!("{:.1} µs", ns / 1000.0)
}

/// A latency ratio goal: `value`'s statistic over `limit`'s.
fn ratio_goal(
    name: String,
    value: Result<Stats, String>,
    limit: Result<Stats, String>,
    p50: bool,
    goal: f64,
) -> Goal {
    let pick = |s: &Stats| if p50 { s.p50 } else { s.p99 };
    let (measured, v) = match (value, limit) {
        (Ok(v), Ok(l)) => (
            Ok(format!("{} / {}", us(pick(&v)), us(pick(&l)))),
            ratio(pick(&v), pick(&l)),
        ),
        (Err(e), _) | (_, Err(e)) => (Err(e), None),
    };
    Goal {
        name,
        measured,
        value: v,
        unit: Unit::Ratio,
        bound: Bound::AtMost(goal),
        statistical: true,
    }
}

/// Every goal, from the comparison's results.
pub fn goals(res: &Results, s: &Settings) -> Vec<Goal> {
    let fig = |key: &str, name: &str| res.figure(key, name).map(|f| f.stats);
    let run_hint = |key: String, hint: &'static str| {
        move |e: String| {
            if e == format!("{key} was not run") {
                format!("{e} ({hint})")
            } else {
                e
            }
        }
    };
    let bytes = s.main_bytes();
    let size = table::human_bytes(bytes);
    let sleep = |clients, bytes| Handshake {
        busy: false,
        clients,
        bytes,
    };
    let main = sleep(s.main_clients(), bytes).key();
    let futex = fig("futex", plan::ROUND_TRIP);
    let every_cycle = fig(plan::FUTEX_EVERY_CYCLE, plan::ROUND_TRIP);
    let four = sleep(4, bytes).key();
    let big = sleep(s.main_clients(), 65_536).key();
    let busy = Handshake {
        busy: true,
        ..sleep(s.main_clients(), bytes)
    }
    .key();
    let spin = fig("spin", plan::ROUND_TRIP);
    let copy = fig(plan::MEMCPY, &plan::copy_name(65_536));
    let every_cycle_copy = match (&every_cycle, &copy) {
        (Ok(f), Ok(c)) => Ok(f.plus(*c)),
        (Err(e), _) | (_, Err(e)) => Err(e.clone()),
    };
    let cl = s.main_clients();
    let mut goals = vec![
        ratio_goal(
            format!("busy-poll round trip / spin round trip, p50 ({cl} cl., {size})"),
            fig(&busy, plan::ROUND_TRIP),
            spin.clone(),
            true,
            acceptance::BUSY_P50,
        ),
        ratio_goal(
            format!("busy-poll round trip / spin round trip, p99 ({cl} cl., {size})"),
            fig(&busy, plan::ROUND_TRIP),
            spin,
            false,
            acceptance::BUSY_P99,
        ),
        ratio_goal(
            format!("sleeping round trip / futex round trip, p50 ({cl} cl., {size})"),
            fig(&main, plan::ROUND_TRIP),
            futex.clone(),
            true,
            acceptance::SLEEPING_P50,
        ),
        ratio_goal(
            format!("sleeping round trip / futex round trip one per cycle, p99 ({cl} cl., {size})"),
            fig(&main, plan::ROUND_TRIP),
            every_cycle.clone(),
            false,
            acceptance::SLEEPING_P99,
        ),
        ratio_goal(
            format!("sleeping round trip / futex round trip one per cycle, p99 (4 cl., {size})"),
            fig(&four, plan::ROUND_TRIP).map_err(run_hint(four.clone(), "add 4 to --clients")),
            every_cycle,
            false,
            acceptance::FOUR_CLIENTS_P99,
        ),
        ratio_goal(
            format!(
                "sleeping round trip / (futex one per cycle + copy 64 KiB), p99 ({cl} cl., \
                 64 KiB)"
            ),
            fig(&big, plan::ROUND_TRIP).map_err(run_hint(big.clone(), "add 64KiB to --sizes")),
            every_cycle_copy,
            false,
            acceptance::BIG_IMAGE_P99,
        ),
        copies_goal(
            "inputs",
            "SERVER_COPIES_PER_INPUT_BYTE",
            SERVER_COPIES_PER_INPUT_BYTE,
        ),
        copies_goal(
            "outputs",
            "SERVER_COPIES_PER_OUTPUT_BYTE",
            SERVER_COPIES_PER_OUTPUT_BYTE,
        ),
    ];
    goals.extend(allocation_goals(res));
    goals.extend(startup_goals(res, s));
    goals.push(attach_load_goal(res, s));
    goals
}

/// procimgd's overruns while clients attach and detach, over its overruns idle as long:
/// summed over the rounds before the ratio (a round has a few tens of overruns at most, and
/// a median of such small counts says less than their sum).
fn attach_load_goal(res: &Results, s: &Settings) -> Goal {
    let name = "overruns while clients attach / idle as long, the demo".to_string();
    let sum = |setting: &str| -> Option<u64> {
        let values = res.settings_of(plan::ATTACH_LOAD, setting);
        (!values.is_empty()).then(|| values.iter().filter_map(|v| v.parse::<u64>().ok()).sum())
    };
    let attaches = sum(names::ATTACHES);
    let (measured, value) = match (
        sum(names::OVERRUNS_ATTACHING),
        sum(names::OVERRUNS_IDLE),
        attaches,
    ) {
        (Some(with), Some(idle), Some(n)) => (
            Ok(format!(
                "{with} overruns over {n} attaches and detaches, {idle} idle as long"
            )),
            Some(names::overrun_ratio(with, idle)),
        ),
        _ if s.attach_load == 0 => (
            Err("--attach-load 0 leaves the attach-load job out".to_string()),
            None,
        ),
        _ => (Err(res.failure(plan::ATTACH_LOAD)), None),
    };
    Goal {
        name,
        measured,
        value,
        unit: Unit::Ratio,
        bound: Bound::AtMost(acceptance::ATTACH_OVERRUNS),
        statistical: true,
    }
}

/// The goal of one copy per image byte in one direction: a property of the cycle.
fn copies_goal(direction: &str, constant: &str, copies: u32) -> Goal {
    Goal {
        name: format!("server copies per image byte, {direction}"),
        measured: Ok(format!(
            "property of the cycle ({constant}, rt-tests/src/compare/goals.rs)"
        )),
        value: Some(f64::from(copies)),
        unit: Unit::Count,
        bound: Bound::AtMost(1.0),
        statistical: false,
    }
}

/// The cycle allocations of every handshake run and round, server and clients.
fn allocation_goals(res: &Results) -> Vec<Goal> {
    let mut out = Vec::new();
    // (who, setting, where the cycles are counted, how)
    for (who, setting, cycles, how) in [
        (
            "server",
            plan::SERVER_ALLOCATIONS,
            Cycles::Setting("cycles"),
            "procimgd's rt_heap_allocations",
        ),
        (
            "clients",
            plan::CLIENT_ALLOCATIONS,
            Cycles::Measurement(plan::STARTOP),
            "the clients' cycle loops on procimg's real-time allocator",
        ),
    ] {
        let reports = res.reports_with(setting);
        let number = |v: Option<&String>| v.and_then(|v| v.parse::<u64>().ok()).unwrap_or(0);
        let total: u64 = reports
            .iter()
            .map(|r| number(r.settings.get(setting)))
            .sum();
        let cycles: u64 = reports
            .iter()
            .map(|r| match cycles {
                Cycles::Setting(name) => number(r.settings.get(name)),
                Cycles::Measurement(name) => r.get(name).map_or(0, |m| m.count),
            })
            .sum();
        let (measured, value) = if reports.is_empty() {
            (
                Err("no procimg-handshake run reported its cycle allocations".to_string()),
                None,
            )
        } else {
            (
                Ok(format!(
                    "Σ over {} handshake runs: {} per cycle over {cycles} cycles ({how})",
                    reports.len(),
                    per_cycle(total, cycles)
                )),
                Some(total as f64),
            )
        };
        out.push(Goal {
            name: format!("steady-state allocations in the cycle, {who}"),
            measured,
            value,
            unit: Unit::Count,
            bound: Bound::AtMost(0.0),
            statistical: false,
        });
    }
    out
}

/// Where a run's cycles are counted.
#[derive(Clone, Copy)]
enum Cycles {
    /// A setting of the report (procimgd's cycles).
    Setting(&'static str),
    /// The count of a measurement (the clients' measured cycles).
    Measurement(&'static str),
}

/// "1.00", "0": allocations per cycle ("?" when allocations were counted but no cycles).
pub fn per_cycle(total: u64, cycles: u64) -> String {
    if total == 0 {
        return "0".into();
    }
    if cycles == 0 {
        return "?".into();
    }
    format!("{:.2}", total as f64 / cycles as f64)
}

/// Locked memory, start and attach, from the start-up jobs.
fn startup_goals(res: &Results, s: &Settings) -> Vec<Goal> {
    let [big, small] = plan::STARTUP_SIZES;
    let big_key = plan::startup_key(big);
    let figure = |bytes: usize, name: &str| {
        res.figure(&plan::startup_key(bytes), name).map_err(|e| {
            if s.startup_sizes.contains(&bytes) {
                e
            } else {
                plan::QUICK_LEAVES_OUT_LARGE.to_string()
            }
        })
    };
    let kib = |name: &str| {
        res.setting(&big_key, name)
            .and_then(|v| v.parse::<f64>().ok())
            .map(|k| k * 1024.0)
    };
    let big_size = table::human_bytes(big);
    let lock_bound = 16.0 * big as f64 + f64::from(16 << 20);
    let (lck, vmlck, rss) = (
        kib(plan::LOCKED_KIB),
        kib(plan::VMLCK_KIB),
        kib(plan::VMRSS_KIB),
    );
    let mut out = vec![Goal {
        name: format!(
            "locked memory of procimgd, {big_size} image, {} clients allowed",
            procimg_shm_layout::MAX_CLIENTS
        ),
        measured: match (lck, vmlck, rss) {
            (Some(_), Some(v), Some(r)) => Ok(format!(
                "Locked, pages locked and resident (VmLck {}, VmRSS {}); goal 16 × {big_size} \
                 + 16 MiB",
                format_value(v, Unit::Bytes),
                format_value(r, Unit::Bytes)
            )),
            _ => Err(figure(big, plan::FIRST_CYCLE)
                .err()
                .unwrap_or_else(|| format!("{big_key} reported no Locked"))),
        },
        value: lck,
        unit: Unit::Bytes,
        bound: Bound::AtMost(lock_bound),
        statistical: false,
    }];
    let first = figure(big, plan::FIRST_CYCLE);
    out.push(Goal {
        name: format!("procimgd start to first cycle, {big_size} image"),
        measured: first
            .as_ref()
            .map(|_| "spawn → status shows a cycle (polled every 1 ms)".to_string())
            .map_err(Clone::clone),
        value: first.ok().map(|f| f.stats.p50),
        unit: Unit::Ns,
        bound: Bound::Below(1e9),
        statistical: false,
    });
    for bytes in [big, small] {
        let f = figure(bytes, plan::ATTACH);
        out.push(Goal {
            name: format!(
                "client attach (release, synchronous), {} image, max",
                table::human_bytes(bytes)
            ),
            measured: f
                .as_ref()
                .map(|f| {
                    format!(
                        "p50 {} over {} attaches",
                        format_value(f.stats.p50, Unit::Ns),
                        plan::STARTUP_ATTACHES
                    )
                })
                .map_err(Clone::clone),
            value: f.ok().map(|f| f.stats.max),
            unit: Unit::Ns,
            bound: Bound::Below(20e6),
            statistical: false,
        });
    }
    out
}

/// The goal table with its footnotes. `judged`: false for quick runs.
pub fn render(goals: &[Goal], judged: bool) -> String {
    let mut notes = Notes::default();
    let header = ["goal", "measured", "today", "goal", "met?"].map(String::from);
    let mut cells = vec![header];
    for g in goals {
        let measured = match &g.measured {
            Ok(m) => m.clone(),
            Err(e) => notes.not_measured(e),
        };
        cells.push([
            g.name.clone(),
            measured,
            g.value.map_or("—".into(), |v| format_value(v, g.unit)),
            format_bound(g.bound, g.unit),
            met_text(g, judged),
        ]);
    }
    let mut out = table::grid(&cells);
    out += &table::footnotes(&notes.0);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_rt_tests::report::Report;

    fn goal(value: Option<f64>, bound: Bound, statistical: bool) -> Goal {
        Goal {
            name: "g".into(),
            measured: Ok("m".into()),
            value,
            unit: Unit::Ratio,
            bound,
            statistical,
        }
    }

    #[test]
    fn allocations_are_given_per_cycle() {
        assert_eq!(per_cycle(0, 1000), "0");
        assert_eq!(per_cycle(2405, 2400), "1.00");
        assert_eq!(per_cycle(5, 0), "?");
    }

    #[test]
    fn ratios_need_a_positive_limit() {
        assert_eq!(ratio(30.0, 10.0), Some(3.0));
        assert_eq!(ratio(30.0, 0.0), None);
        assert_eq!(ratio(f64::NAN, 10.0), None);
    }

    #[test]
    fn bounds_are_inclusive_or_strict_as_written() {
        assert!(Bound::AtMost(1.5).met(1.5));
        assert!(!Bound::AtMost(1.5).met(1.51));
        assert!(!Bound::Below(1e9).met(1e9));
        assert!(Bound::Below(1e9).met(0.99e9));
        assert!(Bound::AtMost(0.0).met(0.0));
        assert!(!Bound::AtMost(0.0).met(1.0));
    }

    #[test]
    fn only_latency_goals_wait_for_a_full_run_to_be_judged() {
        assert_eq!(
            met_text(&goal(Some(2.0), Bound::AtMost(1.5), true), true),
            "NO"
        );
        assert_eq!(
            met_text(&goal(Some(2.0), Bound::AtMost(1.5), true), false),
            "(no)"
        );
        assert_eq!(
            met_text(&goal(Some(1.0), Bound::AtMost(1.5), true), false),
            "(yes)"
        );
        assert_eq!(
            met_text(&goal(Some(0.0), Bound::AtMost(0.0), false), false),
            "yes"
        );
        assert_eq!(met_text(&goal(None, Bound::AtMost(1.5), true), true), "—");
    }

    #[test]
    fn values_and_goals_are_written_in_their_units() {
        assert_eq!(format_value(4.5, Unit::Ratio), "4.50×");
        assert_eq!(format_bound(Bound::AtMost(1.5), Unit::Ratio), "≤ 1.5×");
        assert_eq!(format_value(2.0, Unit::Count), "2");
        assert_eq!(format_bound(Bound::AtMost(0.0), Unit::Count), "≤ 0");
        assert_eq!(format_value(22_642_688.0, Unit::Bytes), "21.6 MiB");
        assert_eq!(format_value(312e6, Unit::Ns), "312 ms");
        assert_eq!(format_value(4.1e6, Unit::Ns), "4.10 ms");
        assert_eq!(format_value(1.5e9, Unit::Ns), "1.50 s");
        assert_eq!(format_bound(Bound::Below(1e9), Unit::Ns), "< 1 s");
        assert_eq!(format_bound(Bound::Below(20e6), Unit::Ns), "< 20 ms");
    }

    #[test]
    fn the_table_has_every_goal_with_a_reason_when_unmeasured() {
        let res = Results::default();
        let s = crate::table::tests::settings();
        let goals = goals(&res, &s);
        assert_eq!(goals.len(), 15);
        let text = render(&goals, true);
        for name in [
            "busy-poll round trip / spin round trip, p50 (1 cl., 64 B)",
            "busy-poll round trip / spin round trip, p99 (1 cl., 64 B)",
            "sleeping round trip / futex round trip, p50 (1 cl., 64 B)",
            "sleeping round trip / futex round trip one per cycle, p99 (1 cl., 64 B)",
            "sleeping round trip / futex round trip one per cycle, p99 (4 cl., 64 B)",
            "sleeping round trip / (futex one per cycle + copy 64 KiB), p99 (1 cl., 64 KiB)",
            "server copies per image byte, inputs",
            "server copies per image byte, outputs",
            "steady-state allocations in the cycle, server",
            "steady-state allocations in the cycle, clients",
            "locked memory of procimgd, 359.5 KiB image, 64 clients allowed",
            "procimgd start to first cycle, 359.5 KiB image",
            "client attach (release, synchronous), 359.5 KiB image, max",
            "client attach (release, synchronous), 64 B image, max",
            "overruns while clients attach / idle as long, the demo",
        ] {
            assert!(text.contains(name), "{name} missing:\n{text}");
        }
        assert!(text.contains("--attach-load 0 leaves"), "{text}");
        // The copies are a property of the code: always there; inputs and outputs are copied
        // once (outputs: the controller role's).
        let copies = |d: &str| {
            text.lines()
                .find(|l| l.contains(&format!("copies per image byte, {d}")))
                .unwrap()
        };
        assert!(copies("inputs").contains("| yes "), "{}", copies("inputs"));
        assert!(
            copies("outputs").contains("| yes "),
            "{}",
            copies("outputs")
        );
        assert!(text.contains("add 4 to --clients"), "{text}");
        let quick = Settings {
            startup_sizes: vec![64],
            ..s
        };
        let text = render(&super::goals(&res, &quick), false);
        assert!(text.contains("--quick leaves the largest image"), "{text}");
        assert!(
            text.contains("not measured [1]") && text.contains("\n[1] "),
            "{text}"
        );
    }

    #[test]
    fn measured_goals_are_judged() {
        use procimg_rt_tests::report::{Measurement, new_histogram};
        let report = |name: &str, ns: u64, settings: &[(&str, &str)]| {
            let mut h = new_histogram();
            h.record(ns).unwrap();
            let mut r = Report::new("fake");
            r.measurements.push(Measurement::from_histogram(name, &h));
            for (k, v) in settings {
                r.setting(k, v);
            }
            r
        };
        let mut res = Results::default();
        res.add("futex", Ok(report(plan::ROUND_TRIP, 10_000, &[])));
        res.add(
            plan::FUTEX_EVERY_CYCLE,
            Ok(report(plan::ROUND_TRIP, 10_000, &[])),
        );
        res.add(
            "handshake-sleep-1c-64B",
            Ok(report(
                plan::ROUND_TRIP,
                14_000,
                &[
                    (plan::SERVER_ALLOCATIONS, "0"),
                    (plan::CLIENT_ALLOCATIONS, "3"),
                ],
            )),
        );
        let mut startup = report(plan::ATTACH, 5_000_000, &[(plan::LOCKED_KIB, "20480")]);
        startup.setting(plan::VMLCK_KIB, "90000");
        startup.setting(plan::VMRSS_KIB, "30720");
        startup
            .measurements
            .extend(report(plan::FIRST_CYCLE, 300_000_000, &[]).measurements);
        res.add(&plan::startup_key(368_128), Ok(startup));
        let s = crate::table::tests::settings();
        let goals = goals(&res, &s);
        let find = |start: &str| goals.iter().find(|g| g.name.starts_with(start)).unwrap();
        let p99 = find("sleeping round trip / futex round trip one per cycle, p99 (1");
        assert!((p99.value.unwrap() - 1.4).abs() < 0.01);
        assert_eq!(met_text(p99, true), "yes");
        let p50 = find("sleeping round trip / futex round trip, p50");
        assert_eq!(met_text(p50, true), "NO");
        assert_eq!(
            find("steady-state allocations in the cycle, server").value,
            Some(0.0)
        );
        assert_eq!(
            met_text(find("steady-state allocations in the cycle, clients"), true),
            "NO"
        );
        let lock = find("locked memory");
        assert_eq!(lock.value, Some(20.0 * 1024.0 * 1024.0));
        assert_eq!(met_text(lock, true), "yes");
        assert!(lock.measured.as_ref().unwrap().contains("VmRSS 30.0 MiB"));
        assert_eq!(met_text(find("procimgd start to first cycle"), true), "yes");
        let attach = find("client attach (release, synchronous), 359.5 KiB");
        assert_eq!(met_text(attach, true), "yes");
        assert_eq!(find("overruns while clients attach").value, None);

        // Attach-load rounds are summed before the ratio: (12 + 30) / (20 + 20) = 1.05.
        for (with, idle) in [("12", "20"), ("30", "20")] {
            let mut r = Report::new("fake");
            r.setting(names::ATTACHES, "1000")
                .setting(names::OVERRUNS_ATTACHING, with)
                .setting(names::OVERRUNS_IDLE, idle);
            res.add(plan::ATTACH_LOAD, Ok(r));
        }
        let goals = super::goals(&res, &s);
        let load = goals
            .iter()
            .find(|g| g.name.starts_with("overruns while clients attach"))
            .unwrap();
        assert!((load.value.unwrap() - 1.05).abs() < 0.001);
        assert_eq!(met_text(load, true), "yes");
        assert!(
            load.measured
                .as_ref()
                .unwrap()
                .contains("42 overruns over 2000")
        );
    }

    #[test]
    fn no_overruns_while_attaching_meet_the_goal_and_some_against_none_idle_do_not() {
        let judge = |with: &str, idle: &str| {
            let mut res = Results::default();
            let mut r = Report::new("fake");
            r.setting(names::ATTACHES, "20")
                .setting(names::OVERRUNS_ATTACHING, with)
                .setting(names::OVERRUNS_IDLE, idle);
            res.add(plan::ATTACH_LOAD, Ok(r));
            met_text(
                &attach_load_goal(&res, &crate::table::tests::settings()),
                true,
            )
        };
        assert_eq!(judge("0", "0"), "yes");
        assert_eq!(judge("0", "3"), "yes");
        assert_eq!(judge("2", "0"), "NO");
        assert_eq!(judge("5", "4"), "NO");
    }
}
