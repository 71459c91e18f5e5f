// SPDX-License-Identifier: MIT OR Apache-2.0
//! The application's veto on DCP's changes of the station (GOAL's STATION_NAME_VERIFY and
//! NET_IP_SET_VERIFY), the state the DCP responder keeps of it (the device's calls for it
//! are the responder's, in [`super::dcp`]): with [`Device::verify_dcp_sets`] on, a DCP Set that gives the station
//! a name or an IP suite, or resets it to factory, waits for [`Device::answer_dcp_set`]. A
//! refusal answers those blocks with BlockError "SET not possible" (0x05) and leaves the
//! station as it is; the request's other blocks (Signal, start/stop) are carried out either
//! way. Without an answer within [`DCP_SET_CHECK_TIMEOUT_NS`] the Set is carried out: a DCP
//! client waits about a second for its response. A repetition of the waiting request (same
//! Xid from the same client) is dropped; another Set while one waits is answered at once
//! with "resource error" for its blocks.

use crate::wire::MacAddress;
use crate::wire::dcp::{BlockRepr, Repr};

/// How long a DCP Set waits for the application's verdict.
pub const DCP_SET_CHECK_TIMEOUT_NS: u64 = 500_000_000;

/// A DCP Set of the station's name or address, for the application to allow or veto.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DcpSetCheck {
    /// The check, named in the answer.
    pub job: u64,
    /// The DCP client's MAC address.
    pub from: MacAddress,
    /// The new NameOfStation, if the Set gives one.
    pub name: Option<String>,
    /// The new IP address, subnet mask and gateway, if the Set gives them.
    pub ip_suite: Option<[[u8; 4]; 3]>,
    /// To be kept across a restart.
    pub permanent: bool,
    /// A reset to factory (no name, no address).
    pub reset: bool,
}

/// The answer to a check names no waiting Set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "DCP Set check {0} is not waiting for an answer: it was answered already, it timed out \
     (after {timeout} ms the Set is carried out), or it was never given out",
    timeout = DCP_SET_CHECK_TIMEOUT_NS / 1_000_000
)]
pub struct UnknownDcpSetCheck(pub u64);

/// A Set waiting for the application.
pub(super) struct HeldSet {
    pub(super) job: u64,
    pub(super) src: MacAddress,
    pub(super) req: Repr,
    pub(super) deadline: u64,
}

/// The device's side of the checks: whether they are on, the Set that waits, and how many
/// timed out ([`Device::dcp_set_checks`](super::Device::dcp_set_checks)).
#[derive(Default)]
pub struct DcpSetChecks {
    pub(super) on: bool,
    pub(super) held: Option<HeldSet>,
    next_job: u64,
    /// Checks that timed out.
    pub(super) timeouts: u64,
}

/// What becomes of a Set request.
pub(super) enum Hold {
    /// Carry it out now.
    GoAhead,
    /// It waits: the check for the application.
    Wait(DcpSetCheck),
    /// A repetition of the waiting request: no answer.
    Repeat,
    /// Another Set waits: answer this one with "resource error".
    Busy,
}

impl DcpSetChecks {
    /// DCP Set checks the application did not answer in time (the Sets were carried out).
    pub fn timeouts(&self) -> u64 {
        self.timeouts
    }

    /// What becomes of Set `req` from `src`: it waits when it changes the station and checks
    /// are on.
    pub(super) fn hold(&mut self, src: MacAddress, req: &Repr, now_ns: u64) -> Hold {
        if !self.on {
            return Hold::GoAhead;
        }
        let mut check = DcpSetCheck {
            job: 0,
            from: src,
            name: None,
            ip_suite: None,
            permanent: false,
            reset: false,
        };
        for b in &req.blocks {
            let permanent = b.prefix & 1 == 1;
            match &b.value {
                BlockRepr::NameOfStation(n) => {
                    check.name = Some(n.clone());
                    check.permanent |= permanent;
                }
                BlockRepr::IpParameter { ip, mask, gateway }
                | BlockRepr::FullIpSuite {
                    ip, mask, gateway, ..
                } => {
                    check.ip_suite = Some([*ip, *mask, *gateway]);
                    check.permanent |= permanent;
                }
                BlockRepr::ResetToFactory(_) | BlockRepr::FactoryReset(_) => {
                    check.reset = true;
                    check.permanent = true;
                }
                _ => {}
            }
        }
        if check.name.is_none() && check.ip_suite.is_none() && !check.reset {
            return Hold::GoAhead;
        }
        if let Some(h) = &self.held {
            return if h.src == src && h.req.xid == req.xid {
                Hold::Repeat
            } else {
                Hold::Busy
            };
        }
        self.next_job = self.next_job.wrapping_add(1);
        check.job = self.next_job;
        self.held = Some(HeldSet {
            job: check.job,
            src,
            req: req.clone(),
            deadline: now_ns.saturating_add(DCP_SET_CHECK_TIMEOUT_NS),
        });
        Hold::Wait(check)
    }
}
