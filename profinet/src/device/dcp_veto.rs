// SPDX-License-Identifier: MIT OR Apache-2.0
//! The application's veto on DCP's changes of the station (GOAL's STATION_NAME_VERIFY and
//! NET_IP_SET_VERIFY), its state and the device's calls for it: with [`Device::verify_dcp_sets`] on, a DCP Set that gives the station
//! a name or an IP suite, or resets it to factory, waits for [`Device::answer_dcp_set`]. A
//! refusal answers those blocks with BlockError "SET not possible" (0x05) and leaves the
//! station as it is; the request's other blocks (Signal, start/stop) are carried out either
//! way. Without an answer within [`DCP_SET_CHECK_TIMEOUT_NS`] the Set is carried out: a DCP
//! client waits about a second for its response. A repetition of the waiting request (same
//! Xid from the same client) is dropped; another Set while one waits is answered at once
//! with "resource error" for its blocks.

use super::dcp::{self, Changes};
use super::{Application, Device, DeviceAction};
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

/// The device's side of the checks.
#[derive(Default)]
pub(super) struct DcpChecks {
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

impl DcpChecks {
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

impl<A: Application> Device<A> {
    /// Has every DCP Set of the station's name or address (and reset to factory) wait for
    /// the application's [`answer_dcp_set`](Self::answer_dcp_set) (a
    /// [`DeviceAction::DcpSetCheck`]), or not. Off from the start.
    pub fn verify_dcp_sets(&mut self, on: bool) {
        self.dcp.checks.on = on;
    }

    /// The application's verdict on DCP Set check `job`: carry it out (`true`) or refuse
    /// its name, address and reset blocks.
    pub fn answer_dcp_set(
        &mut self,
        job: u64,
        allow: bool,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Result<(), UnknownDcpSetCheck> {
        let held = self
            .dcp
            .checks
            .held
            .take_if(|h| h.job == job)
            .ok_or(UnknownDcpSetCheck(job))?;
        self.carry_out_set(&held, allow, out);
        self.sync_handover(now_ns, out);
        Ok(())
    }

    /// DCP Set checks the application did not answer in time (the Sets were carried out).
    pub fn dcp_set_check_timeouts(&self) -> u64 {
        self.dcp.checks.timeouts
    }

    /// Carries out a held Set whose time is up.
    pub(super) fn expire_dcp_check(&mut self, now_ns: u64, out: &mut Vec<DeviceAction>) {
        if let Some(h) = self.dcp.checks.held.take_if(|h| now_ns >= h.deadline) {
            self.dcp.checks.timeouts += 1;
            self.carry_out_set(&h, true, out);
        }
    }

    fn carry_out_set(&mut self, held: &HeldSet, allow: bool, out: &mut Vec<DeviceAction>) {
        let changes: Changes =
            dcp::answer_set(&mut self.station.id, held.src, &held.req, allow, out);
        self.after_dcp(changes, out);
    }
}
