// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device's side of the application's veto on DCP's changes (see [`super::dcp_check`]):
//! turning the checks on, the verdict, and the Set carried out when nobody answers.

use super::dcp::{self, Changes};
use super::dcp_check::{HeldSet, UnknownDcpSetCheck};
use super::{Application, Device, DeviceAction};

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
        let changes: Changes = dcp::answer_set(&mut self.id, held.src, &held.req, allow, out);
        self.after_dcp(changes, out);
    }
}
