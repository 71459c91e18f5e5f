// SPDX-License-Identifier: MIT OR Apache-2.0
//! Connection management over RPC: the calls of the PNIO device interface (Connect, Release,
//! Read, Write, Control) executed against the device's state, and the answer to its own
//! ApplicationReady call.

use super::access_ar::AccessAr;
use super::ar::Ar;
use super::connect::{self, CMDEV, CMDEV_STATE_CONFLICT, CMRPC, refuse};
use super::diagnosis::SubslotAddr;
use super::{
    Application, ArState, Device, DeviceAction, SIM_ALARM_INDEX, SIM_ALARM_USI, log_book, physical,
    rpc, served_records,
};
use crate::wire::control::{self, ControlBlock};
use crate::wire::record::{ERROR_CODE_READ, ERROR_CODE_WRITE, IodHeader};
use crate::wire::rpc::{self as wire_rpc, Header, Ndr, PacketType, opnum};
use crate::wire::rta_pdu::AbortCode;
use crate::wire::{BlockType, PnioStatus, Uuid};
use std::net::SocketAddrV4;

/// ErrorCodes of the RPC services.
const ERROR_CODE_RELEASE: u8 = 0xdc;
const ERROR_CODE_CONTROL: u8 = 0xdd;
/// ErrorCode1 of a faulty IODControlReq (PrmEnd), PrmBegin, and IODReleaseReq; ErrorCode2
/// is the index of the field (5 ARUUID, 6 SessionKey, 8 ControlCommand, 9 properties).
const FAULTY_PRM_END: u8 = 0x14;
const FAULTY_PRM_BEGIN: u8 = 0x18;
const FAULTY_RELEASE: u8 = 0x28;
/// The DCE status of a reject for a request too short to carry the NDR header.
const NCA_PROTO_ERROR: u32 = 0x1c01_000b;

/// A status `Dx 81 c1 c2` of an RPC service.
pub(super) const fn pnio(error_code: u8, c1: u8, c2: u8) -> PnioStatus {
    PnioStatus {
        error_code,
        error_decode: 0x81,
        error_code1: c1,
        error_code2: c2,
    }
}

impl<A: Application> Device<A> {
    /// Whether the device takes part: when it stops (its application goes away, say) the AR
    /// ends with an ERR-RTA and Connects are refused (CMDEV state conflict) until it takes
    /// part again. It does from the start.
    pub fn set_accepting(&mut self, accepting: bool, now_ns: u64, out: &mut Vec<DeviceAction>) {
        self.ar.accepting = accepting;
        if !accepting {
            self.abort_ar(AbortCode::AbortRequest, out);
            self.sync_handover(now_ns, out);
        }
    }

    /// Ends the AR `ar_uuid` as the application asks (IO-Base's `PNIO_device_ar_abort`): an
    /// ERR-RTA with AbortRequest to the controller, the cyclic exchange stopped; the station
    /// stays on the wire and takes the controller's next Connect. Whether `ar_uuid` was the
    /// current AR.
    pub fn abort_ar_on_request(
        &mut self,
        ar_uuid: Uuid,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> bool {
        if self.ar.ar_uuid() != Some(ar_uuid) {
            return false;
        }
        self.abort_ar(AbortCode::AbortRequest, out);
        self.sync_handover(now_ns, out);
        true
    }

    /// Executes a whole request and answers it.
    pub(super) fn call(
        &mut self,
        h: &Header,
        body: &[u8],
        from: SocketAddrV4,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) {
        if h.interface != wire_rpc::DEVICE_INTERFACE {
            self.rpc.reject(h, from, rpc::NCA_UNKNOWN_INTERFACE, out);
            return;
        }
        let error_code = match h.opnum {
            opnum::CONNECT => connect::ERROR_CODE_CONNECT,
            opnum::RELEASE => ERROR_CODE_RELEASE,
            opnum::READ | opnum::READ_IMPLICIT => ERROR_CODE_READ,
            opnum::WRITE => ERROR_CODE_WRITE,
            opnum::CONTROL => ERROR_CODE_CONTROL,
            _ => {
                self.rpc.reject(h, from, rpc::NCA_OP_RANGE_ERROR, out);
                return;
            }
        };
        let Ok((Ndr::Request(ndr), blocks)) =
            wire_rpc::parse_body(PacketType::Request, h.little_endian, body)
        else {
            self.rpc.reject(h, from, NCA_PROTO_ERROR, out);
            return;
        };
        let args = usize::try_from(ndr.args_length).unwrap_or(usize::MAX);
        let blocks = match blocks.get(..args) {
            Some(b) if ndr.actual_count == ndr.args_length && ndr.offset == 0 => b,
            _ => {
                let s = pnio(error_code, CMRPC, connect::CMRPC_ARGS_LENGTH);
                self.rpc.respond(h, from, s, ndr.args_maximum, &[], out);
                return;
            }
        };
        if let Some(access) = self.access_call(h, blocks, from, now_ns) {
            let (status, res) = access;
            self.rpc
                .respond(h, from, status, ndr.args_maximum, &res, out);
            return;
        }
        let (status, res) = match h.opnum {
            opnum::CONNECT if self.ar_checks.on => match self.admit(blocks, out) {
                Err(s) => (s, Vec::new()),
                Ok(plan) => {
                    let call = (*h, from, ndr.args_maximum);
                    match self.check_connect(&plan, call, blocks, now_ns, out) {
                        Some(s) => (s, Vec::new()),
                        None => return,
                    }
                }
            },
            opnum::CONNECT => self.establish(blocks, from, now_ns, out),
            opnum::RELEASE => self.release(blocks),
            opnum::READ | opnum::READ_IMPLICIT | opnum::WRITE => {
                self.cm_initiator_active(blocks, now_ns);
                let outcome = if h.opnum == opnum::WRITE {
                    served_records::write(
                        self.ar.current.as_mut().map(|a| served_records::ArRecords {
                            ar_uuid: a.ar_uuid,
                            records: &mut a.records,
                        }),
                        served_records::DeviceWrite {
                            real: self.plugging.plugged(),
                            im: &mut self.station.im,
                            im_writes: &mut self.station.im_writes,
                            params: &self.records.params,
                        },
                        blocks,
                    )
                } else {
                    served_records::read(
                        h.opnum == opnum::READ_IMPLICIT,
                        self.ar.current.as_ref().map(|a| served_records::ArView {
                            ar_uuid: a.ar_uuid,
                            records: &a.records,
                            submodules: &a.submodules,
                            app_ready_pending: &a.app_ready_pending,
                        }),
                        &self.device_read(),
                        blocks,
                    )
                };
                match outcome {
                    served_records::Outcome::Done(s, b) => (s, b),
                    served_records::Outcome::Pending(p) => {
                        self.wait_for_application(p, (*h, from, ndr.args_maximum), now_ns, out);
                        return;
                    }
                }
            }
            _ => self.control(blocks, now_ns),
        };
        self.rpc
            .respond(h, from, status, ndr.args_maximum, &res, out);
        if h.opnum == opnum::WRITE && status.is_ok() {
            self.alarm_on_request(blocks, now_ns, out);
            self.adjust_lldp();
            self.adjust_ports();
            self.check_topology(now_ns, out);
        }
    }

    /// A record call that names the AR is its controller's activity (an implicit read names
    /// none): the AR's CMI timeout starts again.
    fn cm_initiator_active(&mut self, blocks: &[u8], now_ns: u64) {
        let Ok(h) = IodHeader::parse(blocks) else {
            return;
        };
        if let Some(ar) = self.ar.current.as_mut().filter(|a| a.ar_uuid == h.ar_uuid) {
            ar.restart_cmi_timeout(now_ns);
        }
    }

    /// Hands a call's records to the application; answers it at once if it cannot wait.
    fn wait_for_application(
        &mut self,
        pending: served_records::Pending,
        call: (Header, SocketAddrV4, u32),
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) {
        if let Some(f) = self.records.waiting.start(pending, call, now_ns, out) {
            self.respond_finished(f, out);
        }
    }

    /// A write of [`SIM_ALARM_INDEX`] makes the device raise a process alarm on that
    /// submodule with the written bytes, so that alarms can be tried without hardware.
    fn alarm_on_request(&mut self, blocks: &[u8], now_ns: u64, out: &mut Vec<DeviceAction>) {
        let Ok((h, data, _)) = IodHeader::split(blocks) else {
            return;
        };
        if h.index == SIM_ALARM_INDEX && !h.is_write_multiple() {
            let data = data.to_vec();
            self.raise_process_alarm(h.api, h.slot, h.subslot, SIM_ALARM_USI, &data, now_ns, out);
        }
    }

    /// The checks of a Connect before an AR is made: its plan, or the refusal.
    fn admit(
        &mut self,
        blocks: &[u8],
        out: &mut Vec<DeviceAction>,
    ) -> Result<connect::Plan, PnioStatus> {
        let plan = connect::validate(blocks)?;
        if !self.ar.accepting {
            return Err(refuse(CMDEV, CMDEV_STATE_CONFLICT));
        }
        if let Some(h) = &self.handover {
            connect::check_period(&plan, |period| h.fits(period))?;
        }
        if let Some(existing) = &self.ar.current {
            if existing.ar_uuid == plan.ar.ar_uuid {
                // A re-run of the AR the device still holds: it ends, and this Connect is
                // refused; the controller's next attempt finds the device free (p-net).
                self.abort_ar(AbortCode::RerunAbortsExisting, out);
                return Err(refuse(CMDEV, CMDEV_STATE_CONFLICT));
            }
            return Err(refuse(CMRPC, connect::CMRPC_NO_AR_RESOURCES));
        }
        Ok(plan)
    }

    /// Runs a Connect: the AR, or the refusal.
    pub(super) fn establish(
        &mut self,
        blocks: &[u8],
        from: SocketAddrV4,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> (PnioStatus, Vec<u8>) {
        let plan = match self.admit(blocks, out) {
            Ok(p) => p,
            Err(s) => {
                self.ar
                    .note(Uuid([0; 16]), s, log_book::detail::CONNECT_REFUSED);
                return (s, Vec::new());
            }
        };
        let diagnosis = &self.diagnosis;
        let state =
            |api, slot, subslot| diagnosis.submodule_state(SubslotAddr::new(api, slot, subslot));
        let (fits, diff) = connect::module_diff(&plan.expected, self.plugging.plugged(), state);
        let ids = connect::frame_ids(&plan);
        let Ok(res) = connect::response_blocks(
            &plan,
            self.station.id.mac,
            &self.station.id.name,
            ids.0,
            ids.1,
            diff.as_ref(),
        ) else {
            return (refuse(CMRPC, connect::CMRPC_NO_AR_RESOURCES), Vec::new());
        };
        let controller = SocketAddrV4::new(*from.ip(), plan.rpc_port.unwrap_or(wire_rpc::RPC_PORT));
        self.ar.current = Some(Ar::new(&plan, &fits, ids, controller, now_ns));
        self.ar.note(
            plan.ar.ar_uuid,
            PnioStatus::OK,
            log_book::detail::AR_ESTABLISHED,
        );
        (PnioStatus::OK, res)
    }

    /// PrmEnd (and PrmBegin) from the controller.
    fn control(&mut self, blocks: &[u8], now_ns: u64) -> (PnioStatus, Vec<u8>) {
        let fail = |c1, c2| (pnio(ERROR_CODE_CONTROL, c1, c2), Vec::new());
        let Ok(c) = ControlBlock::parse(blocks) else {
            return fail(CMRPC, connect::CMRPC_UNKNOWN_BLOCKS);
        };
        if blocks.len() != control::BLOCK_LEN {
            return fail(CMRPC, connect::CMRPC_ARGS_LENGTH);
        }
        let (faulty, command) = match c.block_type {
            BlockType::PrmEndReq | BlockType::PlugPrmEndReq => {
                (FAULTY_PRM_END, control::command::PRM_END)
            }
            BlockType::PrmBeginReq => (FAULTY_PRM_BEGIN, control::command::PRM_BEGIN),
            _ => return fail(CMRPC, connect::CMRPC_UNKNOWN_BLOCKS),
        };
        // With the exchange handed over, the caller's cycle produces and supervises.
        let own_cyclic = self.handover.is_none();
        let Some(ar) = self.ar.current.as_mut().filter(|a| a.ar_uuid == c.ar_uuid) else {
            return fail(CMRPC, connect::CMRPC_AR_UUID_UNKNOWN);
        };
        if c.session_key != ar.session_key {
            return fail(faulty, 6);
        }
        if c.command != command {
            return fail(faulty, 8);
        }
        if c.properties != 0 {
            return fail(faulty, 9);
        }
        match (c.block_type, ar.state) {
            (BlockType::PrmEndReq, ArState::Connected) => {
                ar.state = ArState::Parameterized;
                if own_cyclic {
                    ar.provider.start(now_ns);
                }
                self.schedule_app_ready(now_ns);
            }
            (BlockType::PlugPrmEndReq, ArState::Data) => {
                if let Err(code) = self.plug_prm_end(&c, now_ns) {
                    return fail(CMDEV, code);
                }
            }
            (BlockType::PrmBeginReq, ArState::Data) => {
                // Re-parameterization: records may be written again until the next PrmEnd;
                // the CRs keep running.
                ar.state = ArState::Connected;
            }
            _ => return fail(CMDEV, CMDEV_STATE_CONFLICT),
        }
        match ControlBlock::done_response_for(&c) {
            Some(r) => (PnioStatus::OK, r.to_bytes().to_vec()),
            None => fail(CMRPC, connect::CMRPC_UNKNOWN_BLOCKS),
        }
    }

    fn release(&mut self, blocks: &[u8]) -> (PnioStatus, Vec<u8>) {
        let held = self.ar.current.as_ref().map(|a| (a.ar_uuid, a.session_key));
        let c = match release_request(blocks, held) {
            Ok(c) => c,
            Err(s) => return (s, Vec::new()),
        };
        self.ar.current = None;
        self.ar
            .note(c.ar_uuid, PnioStatus::OK, log_book::detail::AR_RELEASED);
        release_response(&c)
    }

    /// What of the device a Read may see.
    fn device_read(&self) -> served_records::DeviceRead<'_> {
        let id = &self.station.id;
        let own_port_id = self
            .station
            .lldp()
            .and_then(|l| l.station().port_id().local().map(str::to_owned))
            .unwrap_or_else(|| "port-001".to_owned());
        let mut ars: Vec<crate::wire::record::ArDataEntry> = Vec::new();
        if let Some(a) = &self.ar.current {
            let mut d = a.described.clone();
            // The CRs run: their frames are valid, the provider in RUN.
            if a.state == ArState::Data {
                for c in &mut d.iocrs {
                    c.data_status = 0x35;
                }
            }
            ars.push(d);
        }
        ars.extend(self.ar.access.as_ref().map(|a| a.described.clone()));
        served_records::DeviceRead {
            real: self.plugging.plugged(),
            im0: &self.station.im0,
            im: &self.station.im,
            diagnosis: &self.diagnosis,
            params: &self.records.params,
            physical: physical::PhysicalView {
                name: &id.name,
                mac: id.mac,
                ip_suite: [id.ip, id.mask, id.gateway],
                own_port_id,
                physical: &self.physical,
                neighbours: self.station.neighbours(),
            },
            ars,
            log: &self.ar.log,
            now_ns: self.ar.now_ns,
        }
    }

    /// A call of the device access AR: its Connect, its records, its Release. `None` for
    /// any other call.
    fn access_call(
        &mut self,
        h: &Header,
        blocks: &[u8],
        from: SocketAddrV4,
        now_ns: u64,
    ) -> Option<(PnioStatus, Vec<u8>)> {
        if h.opnum == opnum::CONNECT {
            let plan = connect::validate_device_access(blocks)?;
            return Some(self.establish_access(plan, from, now_ns));
        }
        let access = self.ar.access.as_mut()?;
        let named = match h.opnum {
            opnum::READ | opnum::WRITE => IodHeader::parse(blocks).ok()?.ar_uuid,
            opnum::RELEASE => ControlBlock::parse(blocks).ok()?.ar_uuid,
            _ => return None,
        };
        if named != access.ar_uuid {
            return None;
        }
        access.active(now_ns);
        Some(match h.opnum {
            opnum::READ => self.read_by_access(blocks),
            opnum::WRITE => served_records::write_by_access(
                access.ar_uuid,
                served_records::DeviceWrite {
                    real: self.plugging.plugged(),
                    im: &mut self.station.im,
                    im_writes: &mut self.station.im_writes,
                    params: &self.records.params,
                },
                blocks,
            ),
            _ => self.release_access(blocks),
        })
    }

    /// A device access Connect: the AR beside the IO AR, or the refusal.
    fn establish_access(
        &mut self,
        plan: Result<connect::AccessPlan, PnioStatus>,
        from: SocketAddrV4,
        now_ns: u64,
    ) -> (PnioStatus, Vec<u8>) {
        let plan = match plan {
            Ok(p) => p,
            Err(s) => {
                self.ar
                    .note(Uuid([0; 16]), s, log_book::detail::CONNECT_REFUSED);
                return (s, Vec::new());
            }
        };
        if let Some(held) = &self.ar.access
            && held.ar_uuid != plan.ar.ar_uuid
        {
            // One tool at a time; a tool that lost its AR connects with the same ARUUID
            // again only after it timed out.
            let s = refuse(CMRPC, connect::CMRPC_NO_AR_RESOURCES);
            self.ar
                .note(plan.ar.ar_uuid, s, log_book::detail::CONNECT_REFUSED);
            return (s, Vec::new());
        }
        let Ok(res) = connect::access_response_blocks(&plan, self.station.id.mac) else {
            return (refuse(CMRPC, connect::CMRPC_NO_AR_RESOURCES), Vec::new());
        };
        self.ar.access = Some(AccessAr::new(&plan, from, now_ns));
        self.ar.note(
            plan.ar.ar_uuid,
            PnioStatus::OK,
            log_book::detail::ACCESS_AR_ESTABLISHED,
        );
        (PnioStatus::OK, res)
    }

    /// A Read in the device access AR: what a Read Implicit may read, the IO AR's own
    /// records excepted.
    fn read_by_access(&mut self, blocks: &[u8]) -> (PnioStatus, Vec<u8>) {
        let view = self.device_read();
        match served_records::read_by_access(&view, blocks) {
            served_records::Outcome::Done(s, b) => (s, b),
            // The application's records are read in the IO AR only.
            served_records::Outcome::Pending(_) => (
                pnio(ERROR_CODE_READ, CMRPC, connect::CMRPC_AR_UUID_UNKNOWN),
                Vec::new(),
            ),
        }
    }

    /// The device access AR's Release.
    fn release_access(&mut self, blocks: &[u8]) -> (PnioStatus, Vec<u8>) {
        let held = self.ar.access.as_ref().map(|a| (a.ar_uuid, a.session_key));
        let c = match release_request(blocks, held) {
            Ok(c) => c,
            Err(s) => return (s, Vec::new()),
        };
        self.ar.access = None;
        self.ar
            .note(c.ar_uuid, PnioStatus::OK, log_book::detail::ACCESS_AR_ENDED);
        release_response(&c)
    }

    /// Ends the device access AR whose tool has been silent for its activity timeout.
    pub(super) fn expire_access_ar(&mut self, now_ns: u64) {
        if let Some(a) = self.ar.access.as_ref()
            && now_ns >= a.deadline_ns
        {
            let uuid = a.ar_uuid;
            self.ar.access = None;
            let status = crate::wire::rta_pdu::ErrRta::abort(AbortCode::CmiTimeout).status;
            self.ar
                .note(uuid, status, log_book::detail::ACCESS_AR_ENDED);
        }
    }

    /// A PDU that may answer our ApplicationReady.
    pub(super) fn client_pdu(
        &mut self,
        h: &Header,
        body: &[u8],
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) {
        if self.plug_ready_pdu(h, body, now_ns, out) {
            return;
        }
        let own_cyclic = self.handover.is_none();
        let Some(ar) = self.ar.current.as_mut() else {
            return;
        };
        let Some(call) = ar.app_ready.as_mut() else {
            return;
        };
        match call.on_pdu(h, body, now_ns, out) {
            rpc::CallOutcome::Confirmed => {
                ar.app_ready = None;
                ar.state = ArState::Data;
                ar.cmi_deadline = None;
                if own_cyclic {
                    ar.consumer.start(now_ns);
                }
            }
            rpc::CallOutcome::Failed => self.abort_ar(AbortCode::RpcClientCallNegative, out),
            rpc::CallOutcome::Pending | rpc::CallOutcome::NotOurs => {}
        }
    }
}

/// Checks a Release of the AR `held` (its ARUUID and SessionKey): the request, or the
/// negative status to answer.
fn release_request(blocks: &[u8], held: Option<(Uuid, u16)>) -> Result<ControlBlock, PnioStatus> {
    let fail = |c1, c2| pnio(ERROR_CODE_RELEASE, c1, c2);
    let c = ControlBlock::parse(blocks).map_err(|_| fail(CMRPC, connect::CMRPC_UNKNOWN_BLOCKS))?;
    if c.block_type != BlockType::ReleaseReq {
        return Err(fail(CMRPC, connect::CMRPC_UNKNOWN_BLOCKS));
    }
    if blocks.len() != control::BLOCK_LEN {
        return Err(fail(CMRPC, connect::CMRPC_ARGS_LENGTH));
    }
    let Some((_, session_key)) = held.filter(|(uuid, _)| *uuid == c.ar_uuid) else {
        return Err(fail(CMRPC, connect::CMRPC_AR_UUID_UNKNOWN));
    };
    if c.session_key != session_key {
        return Err(fail(FAULTY_RELEASE, 6));
    }
    if c.command != control::command::RELEASE {
        return Err(fail(FAULTY_RELEASE, 8));
    }
    Ok(c)
}

/// The positive answer to the Release `c`.
fn release_response(c: &ControlBlock) -> (PnioStatus, Vec<u8>) {
    match ControlBlock::done_response_for(c) {
        Some(r) => (PnioStatus::OK, r.to_bytes().to_vec()),
        None => (
            pnio(ERROR_CODE_RELEASE, CMRPC, connect::CMRPC_UNKNOWN_BLOCKS),
            Vec::new(),
        ),
    }
}
