// SPDX-License-Identifier: MIT OR Apache-2.0
//! The application's check of a new AR (GOAL's NEW_AR and CONNECT_FINISH, IO-Base's
//! `PNIO_CBF_AR_CHECK_IND`): with [`Device::check_connects`] on, a Connect the device would
//! accept waits for [`Device::answer_connect`], which accepts it or refuses it with a PNIO
//! error of the application's choice. The application sees the AR's parameters and the
//! submodules the controller expects, with what is plugged at each place, and answers
//! within [`AR_CHECK_TIMEOUT_NS`]; without an answer by then the AR is accepted, as it would
//! be without a check. Retransmissions of the Connect are dropped meanwhile and pings are
//! answered "working"; a second Connect while one waits is refused (out of AR resources).

use super::connect::{self, CMRPC, refuse};
use super::diagnosis::SubslotAddr;
use super::{Application, Device, DeviceAction, PluggedSubmodule};
use crate::wire::connect as wire_connect;
use crate::wire::rpc::Header;
use crate::wire::{MacAddress, PnioStatus, Uuid};
use std::net::{Ipv4Addr, SocketAddrV4};

/// How long a Connect waits for the application's check. A controller repeats its Connect
/// after about a second and gives up after a few.
pub const AR_CHECK_TIMEOUT_NS: u64 = 2_000_000_000;

/// A new AR for the application to accept or refuse.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ArCheck {
    /// The check, named in the answer.
    pub job: u64,
    /// ARUUID.
    pub ar_uuid: Uuid,
    /// ARType (1 IOCAR single, …).
    pub ar_type: u16,
    /// SessionKey.
    pub session_key: u16,
    /// The controller's MAC address.
    pub controller_mac: MacAddress,
    /// The controller's station name.
    pub controller_name: String,
    /// The controller's IP address (where its Connect came from).
    pub controller_ip: Ipv4Addr,
    /// ARProperties of the Connect's ARBlockReq.
    pub ar_properties: u32,
    /// CMInitiatorObjectUUID of the Connect's ARBlockReq.
    pub cmi_object_uuid: Uuid,
    /// Every submodule the controller expects, with what is plugged there.
    pub expected: Vec<ExpectedAt>,
    /// The AR's IO CRs: the input CR first, then the output CR.
    pub crs: Vec<CrInfo>,
}

/// An IO CR of the AR a Connect asks for (IO-Base's `PNIO_IOCR_TYPE`): its timing as the
/// Connect gives it, its FrameID as the AR will use it, and where each submodule's data
/// object sits in its frames.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CrInfo {
    /// An input CR (the device sends) or an output CR (the device receives).
    pub input: bool,
    /// RTClass (IOCRProperties bits 0–3: 1 and 2 RT, 3 IRT, 4 RT over UDP).
    pub rt_class: u8,
    /// The FrameID of its frames: the device's choice for a CR whose FrameID the
    /// controller left open.
    pub frame_id: u16,
    /// SendClockFactor (× 31.25 µs).
    pub send_clock_factor: u16,
    /// ReductionRatio: a frame every so many send clocks.
    pub reduction_ratio: u16,
    /// Phase.
    pub phase: u16,
    /// DataHoldFactor.
    pub data_hold_factor: u16,
    /// C_SDU bytes.
    pub data_length: u16,
    /// Each submodule's data object (its data, then its IOPS) and where it starts in the
    /// C_SDU, in the Connect's order.
    pub data_objects: Vec<(SubslotAddr, u16)>,
}

impl CrInfo {
    /// The CR `c` of a Connect, whose frames carry `frame_id`.
    pub(super) fn new(c: &wire_connect::IocrBlockReq, frame_id: u16) -> CrInfo {
        CrInfo {
            input: c.iocr_type == wire_connect::iocr_type::INPUT,
            rt_class: (c.iocr_properties & wire_connect::iocr_properties::RT_CLASS_MASK) as u8,
            frame_id,
            send_clock_factor: c.send_clock_factor,
            reduction_ratio: c.reduction_ratio,
            phase: c.phase,
            data_hold_factor: c.data_hold_factor,
            data_length: c.data_length,
            data_objects: c
                .apis
                .iter()
                .flat_map(|a| {
                    a.data_objects
                        .iter()
                        .map(move |o| (SubslotAddr::new(a.api, o.slot, o.subslot), o.frame_offset))
                })
                .collect(),
        }
    }
}

/// One submodule the controller expects (GOAL's EXP_SUBMOD), and the real one at its place.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExpectedAt {
    /// Where.
    pub at: SubslotAddr,
    /// The expected ModuleIdentNumber.
    pub module_ident: u32,
    /// The expected SubmoduleIdentNumber.
    pub submodule_ident: u32,
    /// Expected input bytes.
    pub input_length: u16,
    /// Expected output bytes.
    pub output_length: u16,
    /// What is plugged there, if anything.
    pub plugged: Option<PluggedSubmodule>,
}

/// The answer to a check names no waiting Connect.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "AR check {0} is not waiting for an answer: it was answered already, it timed out (after \
     {timeout} ms the AR is accepted), or it was never given out",
    timeout = AR_CHECK_TIMEOUT_NS / 1_000_000
)]
pub struct UnknownArCheck(pub u64);

/// A Connect waiting for the application.
pub(super) struct WaitingConnect {
    job: u64,
    request: Header,
    from: SocketAddrV4,
    args_maximum: u32,
    blocks: Vec<u8>,
    deadline: u64,
}

/// The device's side of the checks: whether they are on, the Connect that waits, and how
/// many timed out ([`Device::ar_checks`]).
#[derive(Default)]
pub struct ArChecks {
    pub(super) on: bool,
    waiting: Option<WaitingConnect>,
    next_job: u64,
    /// Checks that timed out.
    pub(super) timeouts: u64,
}

impl ArChecks {
    /// AR checks the application did not answer in time (the ARs were accepted).
    pub fn timeouts(&self) -> u64 {
        self.timeouts
    }

    /// Whether the call waits for the application.
    pub(super) fn has_call(&self, request: &Header) -> bool {
        self.waiting.as_ref().is_some_and(|w| {
            w.request.activity == request.activity
                && w.request.sequence_number == request.sequence_number
        })
    }

    /// When the waiting Connect times out.
    pub(super) fn deadline(&self) -> Option<u64> {
        self.waiting.as_ref().map(|w| w.deadline)
    }
}

impl<A: Application> Device<A> {
    /// Has every Connect the device would accept wait for the application's
    /// [`answer_connect`](Self::answer_connect) (a [`DeviceAction::ArCheck`]), or not. Off
    /// from the start.
    pub fn check_connects(&mut self, on: bool) {
        self.ar_checks.on = on;
    }

    /// The application's answer to AR check `job`: accept (`Ok`), or refuse with the
    /// Connect's ErrorCode1 and ErrorCode2 (ErrorCode 0xDB, ErrorDecode PNIO).
    pub fn answer_connect(
        &mut self,
        job: u64,
        answer: Result<(), (u8, u8)>,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Result<(), UnknownArCheck> {
        let w = self
            .ar_checks
            .waiting
            .take_if(|w| w.job == job)
            .ok_or(UnknownArCheck(job))?;
        self.finish_connect(w, answer, now_ns, out);
        self.sync_handover(now_ns, out);
        Ok(())
    }

    /// The application's checks of new ARs: how many timed out.
    pub fn ar_checks(&self) -> &ArChecks {
        &self.ar_checks
    }

    /// A Connect that passed the device's checks: hands it to the application, or answers
    /// at once when another one waits. `None`: nothing to answer now.
    pub(super) fn check_connect(
        &mut self,
        plan: &connect::Plan,
        (request, from, args_maximum): (Header, SocketAddrV4, u32),
        blocks: &[u8],
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Option<PnioStatus> {
        if self.ar_checks.waiting.is_some() {
            return Some(refuse(CMRPC, connect::CMRPC_NO_AR_RESOURCES));
        }
        self.ar_checks.next_job = self.ar_checks.next_job.wrapping_add(1);
        let job = self.ar_checks.next_job;
        let expected = plan
            .expected
            .iter()
            .map(|e| ExpectedAt {
                at: e.addr(),
                module_ident: e.module_ident,
                submodule_ident: e.submodule_ident,
                input_length: e.input_length,
                output_length: e.output_length,
                plugged: self
                    .plugging
                    .plugged()
                    .iter()
                    .copied()
                    .find(|p| p.addr() == e.addr()),
            })
            .collect();
        out.push(DeviceAction::ArCheck(ArCheck {
            job,
            ar_uuid: plan.ar.ar_uuid,
            ar_type: plan.ar.ar_type,
            session_key: plan.ar.session_key,
            controller_mac: plan.ar.initiator_mac,
            controller_name: plan.ar.station_name.clone(),
            controller_ip: *from.ip(),
            ar_properties: plan.ar.ar_properties,
            cmi_object_uuid: plan.ar.initiator_object_uuid,
            expected,
            crs: {
                let (input, output) = connect::frame_ids(plan);
                vec![
                    CrInfo::new(&plan.input, input),
                    CrInfo::new(&plan.output, output),
                ]
            },
        }));
        self.ar_checks.waiting = Some(WaitingConnect {
            job,
            request,
            from,
            args_maximum,
            blocks: blocks.to_vec(),
            deadline: now_ns.saturating_add(AR_CHECK_TIMEOUT_NS),
        });
        None
    }

    /// Accepts a waiting Connect whose time is up.
    pub(super) fn expire_ar_check(&mut self, now_ns: u64, out: &mut Vec<DeviceAction>) {
        if let Some(w) = self.ar_checks.waiting.take_if(|w| now_ns >= w.deadline) {
            self.ar_checks.timeouts += 1;
            self.finish_connect(w, Ok(()), now_ns, out);
        }
    }

    /// Runs the Connect as the application decided and answers it.
    fn finish_connect(
        &mut self,
        w: WaitingConnect,
        answer: Result<(), (u8, u8)>,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) {
        let (status, blocks) = match answer {
            // The device's state may have changed meanwhile: the Connect is checked again.
            Ok(()) => self.establish(&w.blocks, w.from, now_ns, out),
            Err((c1, c2)) => (refuse(c1, c2), Vec::new()),
        };
        self.rpc
            .respond(&w.request, w.from, status, w.args_maximum, &blocks, out);
    }
}
