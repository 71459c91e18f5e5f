// SPDX-License-Identifier: MIT OR Apache-2.0
//! A device's record reads and writes: the parameter records before PrmEnd and the
//! clients' record jobs in data exchange, one call at a time on the AR's activity.

use super::*;
use crate::controller::plan::PlannedRecord;
use crate::wire::record::IodKind;

impl DeviceAr {
    /// Fails every queued record job with `why`.
    pub(super) fn fail_records(&mut self, why: &str, out: &mut Vec<ControllerAction>) {
        // Plug sub-cycles end with the AR: the next Connect sees the tree as it is.
        self.plugs.clear();
        while let Some(r) = self.records.pop_front() {
            out.push(ControllerAction::Event(DeviceEvent::Record(RecordResult {
                request: r,
                result: Err(RecordFailure::no_connection(why)),
            })));
        }
    }

    /// Queues a record read or write; it runs while the AR is in data exchange.
    pub fn record(&mut self, r: RecordRequest, out: &mut Vec<ControllerAction>) {
        if self.state != DeviceState::Running {
            out.push(ControllerAction::Event(DeviceEvent::Record(RecordResult {
                request: r,
                result: Err(RecordFailure::no_connection(format!(
                    "device {:?} is {}, not in data exchange; retry when it is",
                    self.plan.name, self.state
                ))),
            })));
            return;
        }
        self.records.push_back(r);
    }

    /// Writes the parameter records on the just connected `ar` (PrmEnd at once when there
    /// are none); not those of submodules the device lacks.
    pub(super) fn write_records(&mut self, ar: Box<Ar>, now: u64, out: &mut Vec<ControllerAction>) {
        let records: Vec<PlannedRecord> = self
            .plan
            .records
            .iter()
            .filter(|r| !ar.absent.contains(&(r.api, r.slot, r.subslot)))
            .cloned()
            .collect();
        if let Err(ar) = self.write_planned(ar, &records, now, out, Phase::Write) {
            self.prm_end(ar, now, out);
        }
    }

    /// Starts the plug sub-cycle of a submodule the device announced with the plug alarm
    /// numbered `seq`: its parameter records, then PlugPrmEnd (at once when it has none).
    pub(super) fn write_plug_records(
        &mut self,
        mut ar: Box<Ar>,
        plug: Plug,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        let at = (plug.api, plug.slot, plug.subslot);
        ar.absent.retain(|a| *a != at);
        let records: Vec<PlannedRecord> = self
            .plan
            .records
            .iter()
            .filter(|r| (r.api, r.slot, r.subslot) == at)
            .cloned()
            .collect();
        let phase = |call| Phase::PlugWrite { call, plug };
        if let Err(ar) = self.write_planned(ar, &records, now, out, phase) {
            self.plug_prm_end(ar, plug, now, out);
        }
    }

    /// Writes `records` on `ar`, the call going on in the phase `phase` makes of it;
    /// `Err` gives the AR back when there is nothing to write.
    fn write_planned(
        &mut self,
        mut ar: Box<Ar>,
        records: &[PlannedRecord],
        now: u64,
        out: &mut Vec<ControllerAction>,
        phase: impl FnOnce(RpcCall) -> Phase,
    ) -> Result<(), Box<Ar>> {
        if records.is_empty() {
            return Err(ar);
        }
        match write_body(&mut ar, records) {
            Ok(body) => self.call(ar, opnum::WRITE, &body, now, out, phase),
            Err(_) => self.fail_accepted(
                ar,
                FailureCause::Internal,
                "the parameter records do not fit a Write request",
                None,
                now,
                out,
            ),
        }
        Ok(())
    }

    /// Starts the next queued record job when the AR is in data exchange with none running.
    pub(super) fn next_record(&mut self, now: u64, out: &mut Vec<ControllerAction>) {
        let Step::Ar {
            ar,
            phase: phase @ Phase::Running,
        } = &mut self.step
        else {
            return;
        };
        if let Some(plug) = self.plugs.pop_front() {
            let Step::Ar { ar, .. } = core::mem::replace(&mut self.step, Step::Idle) else {
                return;
            };
            return self.write_plug_records(ar, plug, now, out);
        }
        let Some(request) = self.records.pop_front() else {
            return;
        };
        ar.record_seq = ar.record_seq.wrapping_add(1);
        // A write's length is its data's (longer than RecordDataLength holds: the call below
        // refuses it as too long); a read's the most it takes.
        let (kind, op, len) = match &request.write {
            Some(data) => (
                IodKind::WriteReq,
                opnum::WRITE,
                record_data_length(data).unwrap_or(u32::MAX),
            ),
            None => (IodKind::ReadReq, opnum::READ, request.max_len),
        };
        let h = IodHeader::request(
            kind,
            ar.record_seq,
            ar.uuid,
            request.api,
            request.slot,
            request.subslot,
            request.index,
            len,
        );
        let (body, more) = match &request.write {
            Some(data) => (with_data(&h, data), 0),
            None => (h.to_bytes().to_vec(), request.max_len),
        };
        match ar.next_call(self.plan.object_uuid(), op, &body, more, now) {
            Some(call) => {
                call.send(ar.rpc_server(), out);
                *phase = Phase::Record { call, request };
            }
            None => out.push(ControllerAction::Event(DeviceEvent::Record(RecordResult {
                request,
                result: Err(RecordFailure {
                    status: PnioStatus {
                        error_code: 0xDF,
                        error_decode: 0x80,
                        error_code1: 0xB1,
                        error_code2: 0,
                    },
                    add_value1: 0,
                    add_value2: 0,
                    reason: "the record is longer than an RPC call can carry".into(),
                }),
            }))),
        }
    }
}

/// A Write of `records` on `ar`: one Write, or a WriteMultiple for several.
fn write_body(ar: &mut Ar, records: &[PlannedRecord]) -> Result<Vec<u8>, EmitError> {
    let mut headers = Vec::with_capacity(records.len());
    for r in records {
        ar.record_seq = ar.record_seq.wrapping_add(1);
        headers.push(IodHeader::write_request(
            ar.record_seq,
            ar.uuid,
            r.api,
            r.slot,
            r.subslot,
            r.index,
            record_data_length(&r.data)?,
        ));
    }
    if let ([h], [r]) = (&headers[..], records) {
        return Ok(with_data(h, &r.data));
    }
    let writes: Vec<(IodHeader, &[u8])> = headers
        .iter()
        .zip(records)
        .map(|(h, r)| (*h, &r.data[..]))
        .collect();
    let data = record::join_write_multiple_to_vec(&writes)?;
    let outer = IodHeader::write_multiple(0, ar.uuid, record_data_length(&data)?);
    Ok(with_data(&outer, &data))
}

/// The RecordDataLength of `data`; [`EmitError::TooLong`] above `u32::MAX` bytes.
fn record_data_length(data: &[u8]) -> Result<u32, EmitError> {
    u32::try_from(data.len()).map_err(|_| EmitError::TooLong {
        field: "RecordDataLength",
        value: data.len(),
        max: u32::MAX as usize,
    })
}

/// An IOD header followed by its record data.
pub(super) fn with_data(header: &IodHeader, data: &[u8]) -> Vec<u8> {
    let mut b = header.to_bytes().to_vec();
    b.extend_from_slice(data);
    b
}

/// Why a Write (single or multiple) failed, or `None` when every record was taken.
pub(super) fn write_failure(
    status: PnioStatus,
    blocks: &[u8],
) -> Option<(String, Option<PnioStatus>)> {
    if !status.is_ok() {
        return Some((
            format!(
                "writing the parameter records failed: {}",
                rpc::describe(status)
            ),
            Some(status),
        ));
    }
    let Ok((outer, _, rest)) = IodHeader::split(blocks) else {
        return Some(("the Write response is malformed".into(), None));
    };
    if outer.is_write_multiple() {
        let Ok((_, inner)) = record::split_write_multiple_response(blocks) else {
            return Some(("the WriteMultiple response is malformed".into(), None));
        };
        for h in inner {
            if !h.status.is_ok() {
                return Some((
                    format!(
                        "the device refused parameter record {:#06x} of slot {} subslot \
                         {:#06x}: {}",
                        h.index,
                        h.slot,
                        h.subslot,
                        rpc::describe(h.status)
                    ),
                    Some(h.status),
                ));
            }
        }
    } else if !outer.status.is_ok() {
        return Some((
            format!(
                "the device refused parameter record {:#06x}: {}",
                outer.index,
                rpc::describe(outer.status)
            ),
            Some(outer.status),
        ));
    }
    let _ = rest;
    None
}

pub(super) fn record_result(
    request: &RecordRequest,
    status: PnioStatus,
    blocks: &[u8],
) -> Result<RecordData, RecordFailure> {
    let header = IodHeader::split(blocks);
    let (add_value1, add_value2) = header
        .as_ref()
        .map_or((0, 0), |(h, _, _)| (h.add_value1, h.add_value2));
    let failure = |status: PnioStatus| RecordFailure {
        status,
        add_value1,
        add_value2,
        reason: rpc::describe(status),
    };
    if !status.is_ok() {
        return Err(failure(status));
    }
    let Ok((h, data, _)) = header else {
        return Err(RecordFailure {
            reason: "the record response is malformed".into(),
            ..RecordFailure::no_connection("")
        });
    };
    if request.write.is_some() {
        if !h.status.is_ok() {
            return Err(failure(h.status));
        }
        return Ok(RecordData {
            data: Vec::new(),
            add_value1,
            add_value2,
        });
    }
    Ok(RecordData {
        data: data.to_vec(),
        add_value1,
        add_value2,
    })
}
