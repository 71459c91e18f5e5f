// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimg's own report (`--report`, `--hdr-log`): one measurement `wake-up T:<i>` per
//! thread, and `wake-up` (thread 0, the one at the base interval) so other tools find the
//! figure under the same name in every report.

use crate::stats::ThreadStats;
use procimg_rt_tests::report::{Measurement, Report};

/// The tool's name in reports.
pub const TOOL: &str = "procimg-cyclictest";

/// The report of a run; `mode` says what was measured (`"threads"` or `"procimgd <instance>"`).
pub fn report(threads: &[ThreadStats], mode: &str, mlock: bool) -> Report {
    let mut r = Report::new(TOOL);
    r.setting("mode", mode)
        .setting("threads", threads.len())
        .setting("mlockall", mlock);
    if let Some(t) = threads.first() {
        r.setting("priority", t.priority)
            .setting("interval_us", t.interval_us);
        r.measurements
            .push(Measurement::from_histogram("wake-up", &t.ns));
    }
    for t in threads {
        r.setting(&format!("overruns T:{}", t.index), t.overruns);
        r.measurements.push(Measurement::from_histogram(
            &format!("wake-up T:{}", t.index),
            &t.ns,
        ));
    }
    r
}
