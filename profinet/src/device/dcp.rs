// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device's DCP responder: the station's DCP side ([`crate::port::dcp_station`]) with
//! the application's veto on the Sets that change the station (`dcp_veto.rs`).

use super::dcp_veto::{DcpSetChecks, HeldSet, Hold, UnknownDcpSetCheck};
use super::{Application, Device, DeviceAction};
use crate::port::dcp_station::{DcpAnswers, DcpRequest, busy_response};
pub(super) use crate::port::dcp_station::{
    DcpChanges as Changes, DcpIdentity as Identity, ROLE_IO_DEVICE, Settable, answer_set,
    hello_frame, is_request_frame_id,
};
use crate::wire::MacAddress;

/// The DCP side of the device: Identify responses waiting for their delay, and the
/// application's checks of Sets.
#[derive(Default)]
pub(super) struct Responder {
    answers: DcpAnswers,
    /// The application's checks of Sets that change the station.
    pub(super) checks: DcpSetChecks,
}

impl Responder {
    /// A DCP PDU (`pdu` from the FrameID on) in a frame from `src` to `dst`. Answers what is
    /// for us; returns what a Set changed.
    pub(super) fn on_pdu(
        &mut self,
        id: &mut Identity,
        dst: MacAddress,
        src: MacAddress,
        pdu: &[u8],
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Changes {
        let mut frames = Vec::new();
        let req = self.answers.on_pdu(id, dst, src, pdu, now_ns, &mut frames);
        let changes = match req {
            DcpRequest::Done => Changes::default(),
            DcpRequest::Set(req) => match self.checks.hold(src, &req, now_ns) {
                Hold::GoAhead => answer_set(id, src, &req, Settable::all(true), &mut frames),
                Hold::Wait(check) => {
                    out.push(DeviceAction::DcpSetCheck(check));
                    Changes::default()
                }
                Hold::Repeat => Changes::default(),
                Hold::Busy => {
                    frames.extend(busy_response(id, src, &req));
                    Changes::default()
                }
            },
        };
        out.extend(frames.into_iter().map(DeviceAction::Frame));
        changes
    }

    /// Sends the Identify responses whose delay is over.
    pub(super) fn poll(&mut self, now_ns: u64, out: &mut Vec<DeviceAction>) {
        let mut frames = Vec::new();
        self.answers.poll(now_ns, &mut frames);
        out.extend(frames.into_iter().map(DeviceAction::Frame));
    }

    /// When the next delayed response is due.
    pub(super) fn next_deadline_ns(&self) -> Option<u64> {
        self.answers.next_deadline_ns()
    }
}

/// The application's veto on DCP's changes (`dcp_veto.rs`): turning the checks on,
/// the verdict, and the Set carried out when nobody answers.
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

    /// The application's checks of DCP Sets: how many timed out.
    pub fn dcp_set_checks(&self) -> &DcpSetChecks {
        &self.dcp.checks
    }

    /// Carries out a held Set whose time is up.
    pub(super) fn expire_dcp_check(&mut self, now_ns: u64, out: &mut Vec<DeviceAction>) {
        if let Some(h) = self.dcp.checks.held.take_if(|h| now_ns >= h.deadline) {
            self.dcp.checks.timeouts += 1;
            self.carry_out_set(&h, true, out);
        }
    }

    fn carry_out_set(&mut self, held: &HeldSet, allow: bool, out: &mut Vec<DeviceAction>) {
        let mut frames = Vec::new();
        let changes = answer_set(
            &mut self.station.id,
            held.src,
            &held.req,
            Settable::all(allow),
            &mut frames,
        );
        out.extend(frames.into_iter().map(DeviceAction::Frame));
        self.after_dcp(changes, out);
    }
}
