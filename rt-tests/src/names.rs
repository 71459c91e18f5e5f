// SPDX-License-Identifier: MIT OR Apache-2.0
//! The names under which `procimg-handshake`'s jobs write their figures and settings, and
//! under which `procimg-compare` reads them back, and the one figure both derive from them
//! ([`overrun_ratio`]): one place, so that the two cannot drift apart.

/// `procimg-handshake startup`: from spawning procimgd to its first cycle.
pub const FIRST_CYCLE: &str = "start to first cycle";
/// `procimg-handshake startup`: one synchronous client's attach.
pub const ATTACH: &str = "client attach";
/// `procimg-handshake startup`: a status request and its answer.
pub const REQUEST: &str = "control request";
/// `procimg-handshake startup`, KiB: procimgd's memory locked and resident (`Locked` of
/// `/proc/<pid>/smaps_rollup`).
pub const LOCKED_KIB: &str = "procimgd_locked_kib";
/// `procimg-handshake startup`, KiB: procimgd's mappings flagged locked (`VmLck`).
pub const VMLCK_KIB: &str = "procimgd_vmlck_kib";
/// `procimg-handshake startup`, KiB: procimgd's resident memory (`VmRSS`).
pub const VMRSS_KIB: &str = "procimgd_vmrss_kib";

/// `procimg-handshake attach-load`: procimgd's overruns in all attaching windows.
pub const OVERRUNS_ATTACHING: &str = "overruns_attaching";
/// `procimg-handshake attach-load`: procimgd's overruns in all idle windows, as long as the
/// attaching ones.
pub const OVERRUNS_IDLE: &str = "overruns_idle";
/// `procimg-handshake attach-load`: the attaches of all rounds.
pub const ATTACHES: &str = "attaches";

/// The attach-load figure: overruns while attaching over overruns idle as long. None in
/// either window is 1 (attaching cost nothing measurable); some while attaching and none
/// idle is infinite.
pub fn overrun_ratio(attaching: u64, idle: u64) -> f64 {
    match (attaching, idle) {
        (0, 0) => 1.0,
        (_, 0) => f64::INFINITY,
        _ => attaching as f64 / idle as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_overrun_ratio_is_defined_for_every_count() {
        assert_eq!(overrun_ratio(0, 0), 1.0);
        assert_eq!(overrun_ratio(0, 4), 0.0);
        assert_eq!(overrun_ratio(3, 0), f64::INFINITY);
        assert_eq!(overrun_ratio(6, 4), 1.5);
    }
}
