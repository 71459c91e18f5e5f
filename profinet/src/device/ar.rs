// SPDX-License-Identifier: MIT OR Apache-2.0
//! One application relation of the device: its submodules and where their data
//! and status bytes sit in the two CRs, the provider and consumer, the alarm channels and the
//! ApplicationReady call.

use super::connect::{DEVICE_ALARM_REFERENCE, Expected, Fit, MAX_ALARM_DATA_LENGTH, Plan};
use super::cyclic::Provider;
use super::diagnosis::SubslotAddr;
use super::rpc::ClientCall;
use super::{Application, ArState, DeviceAction, ethernet_frame};
use crate::cyclic::Consumer;
use crate::cyclic::{CrMap, CrTiming, DataMap, IocsMap};
use crate::rta::{RtaChannel, RtaEvent};
use crate::wire::alarm::{AlarmAck, AlarmBlock, Priority};
use crate::wire::connect::{IocrBlockReq, IocrEntry};
use crate::wire::rt::data_status;
use crate::wire::rta_pdu::{AbortCode, RtaBody, RtaPdu};
use crate::wire::{MacAddress, Uuid};
use std::net::SocketAddrV4;

/// (API, slot, subslot, index) of a record.
pub(super) type RecordKey = (u32, u16, u16, u16);

/// The records written during an AR.
pub(super) type WrittenRecords = std::collections::HashMap<RecordKey, Vec<u8>>;

/// IOxS GOOD.
pub(super) const IOXS_GOOD: u8 = 0x80;
/// IOxS BAD (detected by the subslot).
pub(super) const IOXS_BAD: u8 = 0x00;

/// One expected submodule of the AR.
pub(super) struct ArSubmodule {
    /// What the controller expects.
    pub(super) expected: Expected,
    /// Whether the real submodule is the expected one (data exchange) or not (BAD status).
    pub(super) proper: bool,
    /// Offset of its input data (then IOPS) in the input CR.
    in_data: Option<usize>,
    /// Offset of our IOCS for its outputs in the input CR.
    in_iocs: Option<usize>,
    /// Offset of its output data (then IOPS) in the output CR.
    out_data: Option<usize>,
    /// Offset of the controller's IOCS for its inputs in the output CR.
    out_iocs: Option<usize>,
    /// The inputs last produced.
    pub(super) inputs: Vec<u8>,
    /// The outputs last received.
    pub(super) outputs: Vec<u8>,
    /// Whether those outputs may be used: provider in RUN and IOPS GOOD.
    pub(super) outputs_valid: bool,
    /// The controller's IOCS for our inputs.
    pub(super) controller_iocs: u8,
    /// The AlarmSequenceNumber of the plug alarm whose sub-cycle (records, PlugPrmEnd,
    /// PlugApplicationReady) this submodule is in; it exchanges data again at its end.
    pub(super) plugging: Option<u16>,
}

/// Where `e`'s data object and IOCS sit in CR `c`, if it has them.
fn offsets(c: &IocrBlockReq, e: &Expected) -> (Option<usize>, Option<usize>) {
    let at = |entries: &[IocrEntry]| {
        entries
            .iter()
            .find(|o| (o.slot, o.subslot) == (e.slot, e.subslot))
            .map(|o| usize::from(o.frame_offset))
    };
    let mut apis = c.apis.iter().filter(|a| a.api == e.api);
    let data = apis.clone().find_map(|a| at(&a.data_objects));
    (data, apis.find_map(|a| at(&a.iocs)))
}

/// The state of an AR.
pub(super) struct Ar {
    pub(super) ar_uuid: Uuid,
    pub(super) session_key: u16,
    pub(super) initiator_object: Uuid,
    /// The PLC's NameOfStation (the Connect's CMInitiatorStationName).
    pub(super) controller_name: String,
    /// Where the ApplicationReady goes: the Connect's IP, the controller's RPC server port.
    pub(super) controller: SocketAddrV4,
    pub(super) state: ArState,
    pub(super) submodules: Vec<ArSubmodule>,
    pub(super) provider: Provider,
    pub(super) consumer: Consumer,
    pub(super) alarms: Alarms,
    /// When the ApplicationReady is to be sent (after PrmEnd).
    pub(super) app_ready_due: Option<u64>,
    /// Until when the application holds the ApplicationReady after PrmEnd.
    pub(super) app_ready_held: Option<u64>,
    /// Submodules the application is not ready for: its ApplicationReady's ModuleDiffBlock
    /// gives them ARInfo "application ready pending" until their Return of Submodule.
    pub(super) app_ready_pending: Vec<SubslotAddr>,
    /// The outstanding ApplicationReady.
    pub(super) app_ready: Option<ClientCall>,
    /// The AR ends unless it reaches data exchange before this: the CM initiator's activity
    /// timeout, from the Connect or the AR's last record call.
    pub(super) cmi_deadline: Option<u64>,
    /// CMInitiatorActivityTimeoutFactor × 100 ms.
    cmi_timeout_ns: u64,
    /// Records written in this AR.
    pub(super) records: WrittenRecords,
    /// Grows whenever a submodule starts or stops exchanging data in the AR (pull, the end
    /// of a plug sub-cycle), so that a handed-over exchange is handed out again.
    pub(super) exchange_generation: u32,
    /// PlugApplicationReadys to send (the submodule and its plug alarm's sequence number),
    /// one at a time, each when due.
    pub(super) plug_ready: std::collections::VecDeque<(SubslotAddr, u16, u64)>,
    /// The outstanding PlugApplicationReady and its submodule.
    pub(super) plug_call: Option<(ClientCall, SubslotAddr)>,
    /// Send clock, reduction ratio and data hold factor of the output CR (the input CR's are
    /// the same for RT class 1/2); `every_cycles` is left at 1 for the caller to set.
    pub(super) timing: CrTiming,
    /// The outputs of all submodules as the behaviour sees them (zeros where invalid).
    device_outputs: Vec<u8>,
    c_sdu: Vec<u8>,
    /// The AR as ARData reports it (its CRs' APDU status filled in when read).
    pub(super) described: crate::wire::record::ArDataEntry,
}

impl Ar {
    /// The AR of an accepted Connect.
    pub(super) fn new(
        plan: &Plan,
        fits: &[Fit],
        (input_frame_id, output_frame_id): (u16, u16),
        controller: SocketAddrV4,
        now_ns: u64,
    ) -> Ar {
        let submodules = plan
            .expected
            .iter()
            .zip(fits)
            .map(|(e, fit)| {
                let (in_data, in_iocs) = offsets(&plan.input, e);
                let (out_data, out_iocs) = offsets(&plan.output, e);
                ArSubmodule {
                    expected: *e,
                    proper: *fit == Fit::Proper,
                    in_data,
                    in_iocs,
                    out_data,
                    out_iocs,
                    inputs: vec![0; usize::from(e.input_length)],
                    outputs: vec![0; usize::from(e.output_length)],
                    outputs_valid: false,
                    controller_iocs: IOXS_BAD,
                    plugging: None,
                }
            })
            .collect();
        let controller_mac = plan.ar.initiator_mac;
        let a = &plan.alarm_cr;
        let cmi_timeout_ns = u64::from(plan.ar.activity_timeout_factor) * 100_000_000;
        let timing = CrTiming {
            send_clock_factor: plan.output.send_clock_factor,
            reduction_ratio: plan.output.reduction_ratio,
            every_cycles: 1,
            data_hold_factor: plan.output.data_hold_factor,
        };
        let mut apis: Vec<u32> = plan.expected.iter().map(|e| e.api).collect();
        apis.sort_unstable();
        apis.dedup();
        let described = super::connect::described(
            &plan.ar,
            Some(&plan.alarm_cr),
            &[
                (&plan.input, input_frame_id),
                (&plan.output, output_frame_id),
            ],
            apis,
        );
        Ar {
            described,
            ar_uuid: plan.ar.ar_uuid,
            session_key: plan.ar.session_key,
            initiator_object: plan.ar.initiator_object_uuid,
            controller_name: plan.ar.station_name.clone(),
            controller,
            state: ArState::Connected,
            submodules,
            provider: Provider::new(&plan.input, input_frame_id, controller_mac),
            // The watchdog: DataHoldFactor frame periods of the output CR.
            consumer: Consumer::new(
                output_frame_id,
                usize::from(plan.output.data_length),
                controller_mac,
                timing.watchdog_ns(),
            ),
            alarms: Alarms {
                high: RtaChannel::new(
                    Priority::High,
                    DEVICE_ALARM_REFERENCE,
                    a.local_alarm_reference,
                    a.rta_timeout_factor,
                    a.rta_retries,
                ),
                low: RtaChannel::new(
                    Priority::Low,
                    DEVICE_ALARM_REFERENCE,
                    a.local_alarm_reference,
                    a.rta_timeout_factor,
                    a.rta_retries,
                ),
                tci: [a.tag_header_high, a.tag_header_low],
                controller_mac,
                controller_reference: a.local_alarm_reference,
                timeout_ns: u64::from(a.rta_timeout_factor.max(1)) * 100_000_000,
                busy_since: [None, None],
                sequence: 0,
                acks: Vec::new(),
                max_data_length: a.max_alarm_data_length.min(MAX_ALARM_DATA_LENGTH),
            },
            app_ready_due: None,
            app_ready_held: None,
            app_ready_pending: Vec::new(),
            app_ready: None,
            cmi_deadline: Some(now_ns.saturating_add(cmi_timeout_ns)),
            cmi_timeout_ns,
            records: WrittenRecords::new(),
            exchange_generation: 0,
            plug_ready: std::collections::VecDeque::new(),
            plug_call: None,
            timing,
            device_outputs: Vec::new(),
            c_sdu: Vec::new(),
        }
    }

    /// The controller was active in the AR's start-up (a record call of the AR): its CMI
    /// timeout starts again, so that a long parameterization (records its application
    /// answers slowly, one call after another) is not taken for a controller gone silent.
    /// Nothing in data exchange, where the timeout is off.
    pub(super) fn restart_cmi_timeout(&mut self, now_ns: u64) {
        if let Some(d) = self.cmi_deadline.as_mut() {
            *d = now_ns.saturating_add(self.cmi_timeout_ns);
        }
    }

    /// The expected submodules, in the Connect's order.
    pub(super) fn expected(&self) -> Vec<Expected> {
        self.submodules.iter().map(|s| s.expected).collect()
    }

    /// Where the submodules this AR owns (the proper ones) are.
    pub(super) fn owned(&self) -> impl Iterator<Item = SubslotAddr> + '_ {
        self.submodules
            .iter()
            .filter(|s| s.proper)
            .map(|s| s.expected.addr())
    }

    /// The controller's MAC.
    pub(super) fn controller_mac(&self) -> MacAddress {
        self.alarms.controller_mac
    }

    /// Whether the AR is in data exchange (ApplicationReady confirmed): only then are our
    /// IOPS and IOCS GOOD.
    pub(super) fn in_data(&self) -> bool {
        self.state == ArState::Data
    }

    /// Takes the C_SDU of an accepted output frame: each submodule's outputs and IOPS, and
    /// the controller's IOCS for our inputs.
    pub(super) fn consume(&mut self, c_sdu: &[u8]) {
        let run = self.consumer.data_status() & data_status::PROVIDER_RUN != 0;
        for s in &mut self.submodules {
            if let Some(at) = s.out_data {
                let n = s.outputs.len();
                if let (Some(d), Some(&iops)) = (c_sdu.get(at..at + n), c_sdu.get(at + n)) {
                    s.outputs.copy_from_slice(d);
                    s.outputs_valid = s.proper && run && iops & IOXS_GOOD != 0;
                }
            }
            if let Some(&iocs) = s.out_iocs.and_then(|at| c_sdu.get(at)) {
                s.controller_iocs = iocs;
            }
        }
    }

    /// Produces the inputs for count `k` and the next input CR frame; `station_ok` is the
    /// DataStatus StationProblemIndicator (false while a fault is pending).
    pub(super) fn produce(
        &mut self,
        app: &mut impl Application,
        k: u64,
        src: MacAddress,
        cycle_counter: u16,
        station_ok: bool,
    ) -> Option<Vec<u8>> {
        // The outputs as the behaviour sees them: invalid ones read as substitute value 0.
        self.device_outputs.clear();
        for s in &self.submodules {
            if s.outputs_valid {
                self.device_outputs.extend_from_slice(&s.outputs);
            } else {
                self.device_outputs
                    .extend(std::iter::repeat_n(0, s.outputs.len()));
            }
        }
        let sensor = self
            .submodules
            .iter()
            .rposition(|s| s.proper && !s.inputs.is_empty());
        let mut at = 0;
        for (i, s) in self.submodules.iter_mut().enumerate() {
            let own = &self.device_outputs[at..at + s.outputs.len()];
            at += s.outputs.len();
            if s.proper {
                app.fill_inputs(
                    k,
                    &mut s.inputs,
                    own,
                    &self.device_outputs,
                    Some(i) == sensor,
                );
            }
        }
        let ready = self.in_data();
        self.c_sdu.clear();
        self.c_sdu.resize(self.provider.data_length, 0);
        for s in &self.submodules {
            let status = if ready && s.proper {
                IOXS_GOOD
            } else {
                IOXS_BAD
            };
            if let Some(at) = s.in_data {
                let n = s.inputs.len();
                if let Some(d) = self.c_sdu.get_mut(at..at + n) {
                    d.copy_from_slice(&s.inputs);
                }
                if let Some(b) = self.c_sdu.get_mut(at + n) {
                    *b = status;
                }
            }
            if let Some(b) = s.in_iocs.and_then(|at| self.c_sdu.get_mut(at)) {
                *b = status;
            }
        }
        let status = if station_ok {
            data_status::OPERATE
        } else {
            data_status::OPERATE & !data_status::STATION_OK
        };
        self.provider.frame(src, cycle_counter, status, &self.c_sdu)
    }

    /// Where the submodules' data and status sit in the two CRs, for a cycle thread that
    /// runs the exchange over a submodule table: the CR consumed (the output CR: data, the
    /// controller's IOPS, its IOCS for our inputs) and the CR produced (the input CR).
    /// `table` gives a submodule's index in that table; submodules that are not the
    /// expected ones, or not in the table, are left out, so their status bytes stay 0 (BAD).
    pub(super) fn cr_maps(&self, table: impl Fn(&Expected) -> Option<usize>) -> (CrMap, CrMap) {
        let mut consumed = CrMap {
            frame_id: self.consumer.frame_id(),
            data_length: self.consumer.data_length(),
            objects: Vec::new(),
            iocs: Vec::new(),
        };
        let mut produced = CrMap {
            frame_id: self.provider.frame_id,
            data_length: self.provider.data_length,
            objects: Vec::new(),
            iocs: Vec::new(),
        };
        for s in self.submodules.iter().filter(|s| s.proper) {
            let Some(index) = table(&s.expected) else {
                continue;
            };
            let data = |at: usize, len: usize| DataMap {
                submodule: index,
                data: at,
                len,
                iops: at + len,
            };
            let iocs = |offset: usize| IocsMap {
                submodule: index,
                offset,
            };
            consumed
                .objects
                .extend(s.out_data.map(|at| data(at, s.outputs.len())));
            consumed.iocs.extend(s.out_iocs.map(iocs));
            produced
                .objects
                .extend(s.in_data.map(|at| data(at, s.inputs.len())));
            produced.iocs.extend(s.in_iocs.map(iocs));
        }
        (consumed, produced)
    }

    /// When [`Ar`] needs a poll next.
    pub(super) fn deadline(&self) -> Option<u64> {
        [
            self.provider.next_due(),
            self.consumer.deadline_ns(),
            self.cmi_deadline,
            self.app_ready_due,
            self.app_ready_held,
            self.app_ready.as_ref().map(ClientCall::deadline),
            self.plug_call.as_ref().map(|(c, _)| c.deadline()),
            self.plug_ready
                .front()
                .filter(|_| self.plug_call.is_none())
                .map(|(_, _, due)| *due),
            self.alarms.deadline(),
        ]
        .into_iter()
        .flatten()
        .min()
    }
}

/// The two alarm channels of the AR.
pub(super) struct Alarms {
    high: RtaChannel,
    low: RtaChannel,
    /// Tag control information of the high and low priority frames (from the AlarmCR).
    tci: [u16; 2],
    controller_mac: MacAddress,
    controller_reference: u16,
    timeout_ns: u64,
    /// When each channel's outstanding DATA-RTA went out, to know when to poll it.
    busy_since: [Option<u64>; 2],
    /// AlarmSpecifier sequence number of our next alarm.
    pub(super) sequence: u16,
    /// The AlarmAcks the controller sent for our alarms.
    pub(super) acks: Vec<AlarmAck>,
    /// MaxAlarmDataLength of the AR (the smaller of the controller's and ours, as the
    /// AlarmCRBlockRes says): the most bytes of alarm data one DATA-RTA may carry.
    pub(super) max_data_length: u16,
}

/// How an alarm channel ended the AR.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct ChannelAbort {
    pub(super) code: AbortCode,
    /// We sent the ERR-RTA (true) or the controller did (false).
    pub(super) local: bool,
}

const fn index(p: Priority) -> usize {
    match p {
        Priority::High => 0,
        Priority::Low => 1,
    }
}

impl Alarms {
    fn channel(&mut self, p: Priority) -> &mut RtaChannel {
        match p {
            Priority::High => &mut self.high,
            Priority::Low => &mut self.low,
        }
    }

    /// Puts the channel's events on the wire; the abort among them, if any.
    fn handle(
        &mut self,
        p: Priority,
        events: Vec<RtaEvent>,
        src: MacAddress,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Option<ChannelAbort> {
        let mut abort = None;
        for e in events {
            match e {
                RtaEvent::Send(pdu) => {
                    if matches!(pdu.body, RtaBody::Data(_)) {
                        self.busy_since[index(p)] = Some(now_ns);
                    }
                    if let Ok(bytes) = pdu.to_vec() {
                        let tci = self.tci[index(pdu.priority)];
                        out.push(DeviceAction::Frame(ethernet_frame(
                            self.controller_mac,
                            src,
                            Some(tci),
                            &bytes,
                        )));
                    }
                }
                RtaEvent::Deliver(blocks) => {
                    self.acks.extend(blocks.into_iter().filter_map(|b| match b {
                        AlarmBlock::Ack(a) => Some(a),
                        _ => None,
                    }));
                }
                RtaEvent::Confirmed => {}
                RtaEvent::Abort { code, local } => abort = Some(ChannelAbort { code, local }),
            }
        }
        if !self.channel(p).is_busy() {
            self.busy_since[index(p)] = None;
        }
        abort
    }

    /// An RTA PDU from the controller.
    pub(super) fn on_pdu(
        &mut self,
        pdu: &RtaPdu,
        src: MacAddress,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Option<ChannelAbort> {
        if pdu.header.dst_endpoint != DEVICE_ALARM_REFERENCE
            || pdu.header.src_endpoint != self.controller_reference
        {
            return None;
        }
        let mut events = Vec::new();
        self.channel(pdu.priority).receive(pdu, now_ns, &mut events);
        self.handle(pdu.priority, events, src, now_ns, out)
    }

    /// Sends alarm blocks on a channel.
    pub(super) fn send(
        &mut self,
        p: Priority,
        blocks: Vec<AlarmBlock>,
        src: MacAddress,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Option<ChannelAbort> {
        let mut events = Vec::new();
        self.channel(p).send(blocks, now_ns, &mut events);
        self.handle(p, events, src, now_ns, out)
    }

    /// Retransmissions due at `now_ns`.
    pub(super) fn poll(
        &mut self,
        src: MacAddress,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Option<ChannelAbort> {
        let mut abort = None;
        for p in [Priority::High, Priority::Low] {
            let mut events = Vec::new();
            self.channel(p).poll(now_ns, &mut events);
            abort = abort.or(self.handle(p, events, src, now_ns, out));
        }
        abort
    }

    /// Ends the AR from our side: an ERR-RTA with `code` on the low-priority channel (where
    /// p-net sends its aborts).
    pub(super) fn abort(&mut self, code: AbortCode, src: MacAddress, out: &mut Vec<DeviceAction>) {
        let mut events = Vec::new();
        self.low.abort(code, &mut events);
        // The channel reports the abort back; the caller is already ending the AR.
        let _ = self.handle(Priority::Low, events, src, 0, out);
    }

    /// When an outstanding DATA-RTA may need retransmitting.
    fn deadline(&self) -> Option<u64> {
        self.busy_since
            .iter()
            .flatten()
            .map(|t| t.saturating_add(self.timeout_ns))
            .min()
    }
}
