// SPDX-License-Identifier: MIT OR Apache-2.0
//! What one comparison runs: every tool invocation, grouped in pairs of a figure and its
//! limit that run back to back, one pair after the other, never two at once.

use super::run::Program;
use std::time::Duration;

/// The tools.
pub const CYCLICTEST: Program = Program::InPath {
    name: "cyclictest",
    install: "apt-get install rt-tests",
};
/// procimg's cyclictest.
pub const PROCIMG_CYCLICTEST: Program = Program::Sibling("procimg-cyclictest");
/// The handshake between procimgd and its clients.
pub const HANDSHAKE: Program = Program::Sibling("procimg-handshake");
/// The limits.
pub const BASELINE: Program = Program::Sibling("procimg-baseline");

/// The handshake measurements (as procimg-handshake names them).
pub const STARTOP: &str = "startop one way";
/// See [`STARTOP`].
pub const OPDONE: &str = "opdone one way";
/// See [`STARTOP`]; also the baselines' only measurement.
pub const ROUND_TRIP: &str = "round trip";
/// procimg-cyclictest's measurement (thread 0), and the name given to cyclictest's.
pub const WAKE_UP: &str = "wake-up";

/// How much to measure.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Cycles of the wake-up and handshake runs; the ping-pongs and copies do ten times as
    /// many, being that much shorter.
    pub loops: u64,
    /// Cycle time, µs.
    pub interval_us: u64,
    /// Image sizes of the sweep, bytes; the first is the size of the main handshake rows.
    pub sizes: Vec<usize>,
    /// Client counts of the sweep; the first is the count of the main handshake rows.
    pub clients: Vec<usize>,
    /// Image sizes of the start-up jobs (some of [`STARTUP_SIZES`]).
    pub startup_sizes: Vec<usize>,
    /// Clients that attach and detach beside the running demo in the attach-load job
    /// (0: no such job).
    pub attach_load: u32,
}

impl Settings {
    /// Image size of the main handshake rows.
    pub fn main_bytes(&self) -> usize {
        self.sizes.first().copied().unwrap_or(64)
    }

    /// Client count of the main handshake rows.
    pub fn main_clients(&self) -> usize {
        self.clients.first().copied().unwrap_or(1)
    }
}

/// How a handshake run is set up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Handshake {
    /// Busy-polling (else sleeping).
    pub busy: bool,
    /// Client processes.
    pub clients: usize,
    /// Image bytes each way.
    pub bytes: usize,
}

impl Handshake {
    /// The job key.
    pub fn key(&self) -> String {
        format!(
            "handshake-{}-{}c-{}B",
            if self.busy { "busy" } else { "sleep" },
            self.clients,
            self.bytes
        )
    }
}

/// What a job writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// A procimg report (`--report FILE`).
    Report,
    /// cyclictest's own JSON (`--json=FILE`).
    CyclictestJson,
}

/// One invocation, without its output file (added per round).
#[derive(Clone, Debug)]
pub struct Job {
    /// Unique name; also the name of its files.
    pub key: String,
    /// The tool.
    pub program: Program,
    /// Its arguments.
    pub args: Vec<String>,
    /// What it writes.
    pub output: Output,
    /// About how long it runs.
    pub expected: Duration,
}

impl Job {
    /// The arguments with the output file.
    pub fn args_with_output(&self, file: &std::path::Path) -> Vec<String> {
        let mut args = self.args.clone();
        match self.output {
            Output::Report => {
                args.push("--report".into());
                args.push(file.display().to_string());
            }
            Output::CyclictestJson => args.push(format!("--json={}", file.display())),
        }
        args
    }

    /// Longest it may take: generous, since a debug build on a busy machine is slow; the
    /// limit only catches a hung tool.
    pub fn limit(&self) -> Duration {
        self.expected * 5 + Duration::from_secs(120)
    }
}

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

/// The memcpy job's measurement for `bytes` (as procimg-baseline names it).
pub fn copy_name(bytes: usize) -> String {
    format!("copy {bytes} B")
}

/// Key of the memcpy job.
pub const MEMCPY: &str = "memcpy";

/// Image sizes the start-up job runs with: the largest image (what the memory and start
/// goals are about) and the smallest.
pub const STARTUP_SIZES: [usize; 2] = [368_128, 64];
/// Why a quick run leaves the largest image's start-up out.
pub const QUICK_LEAVES_OUT_LARGE: &str = "--quick leaves the largest image's start-up out \
     (procimgd locks some 40 MiB for it, and a quick run stays small); run without --quick";
/// Attaches timed per start-up job.
pub const STARTUP_ATTACHES: u32 = 20;
pub use procimg_rt_tests::names::{ATTACH, FIRST_CYCLE, LOCKED_KIB, VMLCK_KIB, VMRSS_KIB};
/// procimg-handshake's settings: allocations in the measured cycles.
pub const SERVER_ALLOCATIONS: &str = "server_cycle_allocations";
/// See [`SERVER_ALLOCATIONS`].
pub const CLIENT_ALLOCATIONS: &str = "client_cycle_allocations";

/// Key of the start-up job for an image of `bytes`.
pub fn startup_key(bytes: usize) -> String {
    format!("startup-{bytes}B")
}

/// Key of the attach-load job: procimgd's demo, clients attaching and detaching one after the
/// other, then as long idle (`procimg-handshake attach-load`).
pub const ATTACH_LOAD: &str = "attach-load";

/// The job key of the futex ping-pong that starts one round trip per cycle
/// (`procimg-baseline futex --period-us INTERVAL`): the limit of a handshake whose two sides
/// sleep through most of a cycle, as procimgd's cycle thread and a sleeping client do.
pub const FUTEX_EVERY_CYCLE: &str = "futex-every-cycle";

/// The job key of the spin ping-pong that starts one round trip per cycle
/// (`procimg-baseline spin --period-us INTERVAL`): its first side sleeps through the cycle
/// as procimgd's cycle thread does, its second spins as a busy client does, and the run is
/// as long as the handshake's, so it meets the machine's rarer stalls as often.
pub const SPIN_EVERY_CYCLE: &str = "spin-every-cycle";

/// The groups, in order; each group runs back to back.
pub fn groups(s: &Settings) -> Vec<Vec<Job>> {
    let cycles = Duration::from_micros(s.loops * s.interval_us);
    let l = s.loops.to_string();
    let i = s.interval_us.to_string();
    // cyclictest's options exactly as its users give them; procimg-cyclictest takes the same.
    let wake_args = strings(&["-m", "-p", "80", "-i", &i, "-l", &l, "-q", "-h", "2000"]);
    let wake = |key: &str, program: Program, output| Job {
        key: key.to_string(),
        program,
        args: wake_args.clone(),
        output,
        expected: cycles,
    };
    let baseline_loops = (s.loops * 10).to_string();
    let baseline = |what: &str, extra: &[&str]| {
        let mut args = strings(&[what, "-l", &baseline_loops]);
        args.extend(strings(extra));
        Job {
            key: what.to_string(),
            program: BASELINE,
            args,
            output: Output::Report,
            expected: Duration::from_micros(s.loops * 10 * 100),
        }
    };
    let handshake = |h: Handshake| Job {
        key: h.key(),
        program: HANDSHAKE,
        args: strings(&[
            "--clients",
            &h.clients.to_string(),
            "--wait",
            if h.busy { "busy" } else { "sleep" },
            "--image-bytes",
            &h.bytes.to_string(),
            "-l",
            &l,
            "-i",
            &i,
            "-q",
        ]),
        output: Output::Report,
        // Plus procimg-handshake's warm-up of up to 3000 cycles.
        expected: cycles + Duration::from_micros(3000 * s.interval_us),
    };
    let every_cycle = |key: &str, what: &str| Job {
        key: key.to_string(),
        program: BASELINE,
        args: strings(&[what, "-l", &l, "--period-us", &i]),
        output: Output::Report,
        // Plus procimg-baseline's warm-up of 1000 round trips, one per cycle too.
        expected: cycles + Duration::from_micros(1000 * s.interval_us),
    };
    let main = |busy| Handshake {
        busy,
        clients: s.main_clients(),
        bytes: s.main_bytes(),
    };
    let sizes: Vec<String> = s.sizes.iter().map(|b| b.to_string()).collect();
    let mut groups = vec![
        vec![
            wake("cyclictest", CYCLICTEST, Output::CyclictestJson),
            wake("procimg-cyclictest", PROCIMG_CYCLICTEST, Output::Report),
        ],
        vec![
            baseline("spin", &[]),
            every_cycle(SPIN_EVERY_CYCLE, "spin"),
            handshake(main(true)),
        ],
        vec![
            baseline("futex", &[]),
            every_cycle(FUTEX_EVERY_CYCLE, "futex"),
            handshake(main(false)),
        ],
        vec![baseline("eventfd", &[]), baseline("socket", &[])],
        vec![baseline(MEMCPY, &["--bytes", &sizes.join(",")])],
    ];
    for h in sweep(s) {
        groups.push(vec![handshake(h)]);
    }
    groups.push(
        s.startup_sizes
            .iter()
            .map(|&bytes| Job {
                key: startup_key(bytes),
                program: HANDSHAKE,
                args: strings(&[
                    "startup",
                    "-b",
                    &bytes.to_string(),
                    "-n",
                    &STARTUP_ATTACHES.to_string(),
                ]),
                output: Output::Report,
                expected: Duration::from_secs(5),
            })
            .collect(),
    );
    if s.attach_load > 0 {
        groups.push(vec![Job {
            key: ATTACH_LOAD.to_string(),
            program: HANDSHAKE,
            args: strings(&["attach-load", "-n", &s.attach_load.to_string(), "-r", "1"]),
            output: Output::Report,
            // procimgd's start and its 2 s to settle, then each attach (some 10 ms at the
            // demo's size) and the 5 ms pause after it, twice: attaching, then idle.
            expected: Duration::from_secs(3)
                + Duration::from_millis(2 * 15 * u64::from(s.attach_load)),
        }]);
    }
    groups
}

/// The sleeping handshake runs of the sweep beyond the main one: every size with the main
/// client count, every client count with the main size.
pub fn sweep(s: &Settings) -> Vec<Handshake> {
    let main = Handshake {
        busy: false,
        clients: s.main_clients(),
        bytes: s.main_bytes(),
    };
    let by_size = s.sizes.iter().map(|&bytes| Handshake { bytes, ..main });
    let by_clients = s
        .clients
        .iter()
        .map(|&clients| Handshake { clients, ..main });
    let mut all: Vec<Handshake> = Vec::new();
    for h in by_size.chain(by_clients) {
        if h != main && !all.contains(&h) {
            all.push(h);
        }
    }
    all
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings() -> Settings {
        Settings {
            loops: 100,
            interval_us: 1000,
            sizes: vec![64, 4096],
            clients: vec![1, 4],
            startup_sizes: STARTUP_SIZES.to_vec(),
            attach_load: 20,
        }
    }

    #[test]
    fn the_sweep_leaves_out_the_main_run_and_repeats_nothing() {
        let keys: Vec<String> = sweep(&settings()).iter().map(|h| h.key()).collect();
        assert_eq!(keys, ["handshake-sleep-1c-4096B", "handshake-sleep-4c-64B"]);
    }

    #[test]
    fn every_job_key_is_unique_and_outputs_are_passed_the_tools_way() {
        let groups = groups(&settings());
        let groups_of = |s: Settings| super::groups(&s);
        let mut keys: Vec<&str> = groups.iter().flatten().map(|j| j.key.as_str()).collect();
        let n = keys.len();
        keys.sort();
        keys.dedup();
        assert_eq!(keys.len(), n);
        let ct = &groups[0][0];
        let args = ct.args_with_output(std::path::Path::new("/x/c.json"));
        assert_eq!(args.last().unwrap(), "--json=/x/c.json");
        let ours = groups[0][1].args_with_output(std::path::Path::new("/x/p.json"));
        assert_eq!(&ours[ours.len() - 2..], ["--report", "/x/p.json"]);
        for (key, what) in [(FUTEX_EVERY_CYCLE, "futex"), (SPIN_EVERY_CYCLE, "spin")] {
            let job = groups.iter().flatten().find(|j| j.key == key).unwrap();
            assert_eq!(job.args, [what, "-l", "100", "--period-us", "1000"]);
        }
        let attach_load = groups.last().unwrap();
        assert_eq!(attach_load[0].key, ATTACH_LOAD);
        assert_eq!(attach_load[0].args, ["attach-load", "-n", "20", "-r", "1"]);
        let without = groups_of(Settings {
            attach_load: 0,
            ..settings()
        });
        assert!(!without.iter().flatten().any(|j| j.key == ATTACH_LOAD));
    }
}
