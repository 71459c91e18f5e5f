// SPDX-License-Identifier: MIT OR Apache-2.0
//! The names under which `procimg-handshake`'s jobs write their figures and settings, and
//! under which `procimg-compare` reads them back: one place, so that the two cannot drift
//! apart.

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
