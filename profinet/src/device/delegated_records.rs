// SPDX-License-Identifier: MIT OR Apache-2.0
//! The user records (indices 0x0000–0x7FFF) the device hands to its application (GOAL's
//! record callbacks, IO-Base's `PNIO_CBF_REC_READ` / `PNIO_CBF_REC_WRITE`; which ones:
//! [`super::params`]).
//!
//! A Write or Read of an application's record does not complete at once: the device gives
//! each record to the application as a [`RecordJob`] with a job number and answers the
//! controller's call when the application answered every job of it
//! ([`Device::answer_record`]), or when [`RECORD_ANSWER_TIMEOUT_NS`] passed: the jobs left
//! unanswered end with PNIORW "resource busy" (0xC2), which tells the PLC's program to try
//! again later. A late answer finds its job gone and is refused ([`UnknownRecordJob`]).
//! Meanwhile the RPC server drops the controller's retransmissions of the call and answers
//! its pings with "working".

use super::served_records::{Pending, read_response, write_response};
use super::{Application, Device, DeviceAction};
use crate::wire::record::{IodHeader, RecordError, RecordErrorCode};
use crate::wire::rpc::Header;
use crate::wire::{PnioStatus, Uuid};
use std::net::SocketAddrV4;

/// How long the device waits for the application's answer to a record job. A controller
/// repeats its call after about a second and gives up after a few: the answer must come
/// before that.
pub const RECORD_ANSWER_TIMEOUT_NS: u64 = 2_000_000_000;
/// Calls that may wait for the application at the same time (the AR's and implicit reads);
/// more get "resource busy" at once.
pub const MAX_WAITING_CALLS: usize = 4;

/// A record the device hands to its application.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RecordJob {
    /// The job, named again in the answer.
    pub job: u64,
    /// A write (`true`) or a read.
    pub write: bool,
    /// The AR the request came in (nil: a ReadImplicit outside any AR).
    pub ar_uuid: Uuid,
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// Record index.
    pub index: u16,
    /// What the controller wrote (empty for a read).
    pub data: Vec<u8>,
    /// For a read, the most bytes the controller takes.
    pub max_len: u32,
}

/// The answer to a record job that was refused: [`Device::answer_record`] names no job of
/// the device.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "record job {0} is not waiting for an answer: it was answered already, it timed out \
     (after {timeout} ms the device answers the controller itself), or it was never given out",
    timeout = RECORD_ANSWER_TIMEOUT_NS / 1_000_000
)]
pub struct UnknownRecordJob(pub u64);

/// One record of a waiting call.
#[derive(Clone, Copy, Debug)]
enum Part {
    /// The device answered it.
    Done(PnioStatus),
    /// Job `0` waits for the application.
    Waiting(u64),
}

/// What a waiting call asked.
enum Asked {
    Write {
        outer: IodHeader,
        parts: Vec<(IodHeader, Part)>,
    },
    Read {
        header: IodHeader,
        job: u64,
    },
}

/// A Write or Read call waiting for the application.
struct WaitingCall {
    request: Header,
    from: SocketAddrV4,
    args_maximum: u32,
    deadline: u64,
    asked: Asked,
}

/// A call the device can answer now: to whom, and what.
pub(super) struct Finished {
    pub(super) request: Header,
    pub(super) from: SocketAddrV4,
    pub(super) args_maximum: u32,
    pub(super) status: PnioStatus,
    pub(super) blocks: Vec<u8>,
}

/// The calls waiting for the application.
#[derive(Default)]
pub(super) struct Waiting {
    calls: Vec<WaitingCall>,
    next_job: u64,
    /// Jobs that timed out.
    pub(super) timeouts: u64,
}

impl WaitingCall {
    /// Whether job `job` belongs to it.
    fn has(&self, job: u64) -> bool {
        match &self.asked {
            Asked::Write { parts, .. } => parts
                .iter()
                .any(|(_, p)| matches!(p, Part::Waiting(j) if *j == job)),
            Asked::Read { job: j, .. } => *j == job,
        }
    }

    /// The response, once nothing waits any more.
    fn finished(self) -> Option<Finished> {
        let (status, blocks) = match &self.asked {
            Asked::Write { outer, parts } => {
                let mut done = Vec::with_capacity(parts.len());
                for (h, p) in parts {
                    match p {
                        Part::Done(s) => done.push((*h, *s)),
                        Part::Waiting(_) => return None,
                    }
                }
                write_response(outer, &done)
            }
            Asked::Read { .. } => return None,
        };
        Some(self.answered(status, blocks))
    }

    fn answered(self, status: PnioStatus, blocks: Vec<u8>) -> Finished {
        Finished {
            request: self.request,
            from: self.from,
            args_maximum: self.args_maximum,
            status,
            blocks,
        }
    }

    /// Ends every job still waiting with `code`.
    fn give_up(self, code: RecordErrorCode) -> Finished {
        let (status, blocks) = match &self.asked {
            Asked::Write { outer, parts } => {
                let failed = RecordError::write(code, 0).status();
                let done: Vec<(IodHeader, PnioStatus)> = parts
                    .iter()
                    .map(|(h, p)| match p {
                        Part::Done(s) => (*h, *s),
                        Part::Waiting(_) => (*h, failed),
                    })
                    .collect();
                write_response(outer, &done)
            }
            Asked::Read { header, .. } => {
                read_response(header, Err(RecordError::read(code, 0).status()))
            }
        };
        self.answered(status, blocks)
    }
}

impl Waiting {
    /// Gives the application the records of `pending`, a call `request` from `from`; what
    /// can be answered at once (too many calls waiting) comes back.
    pub(super) fn start(
        &mut self,
        pending: Pending,
        (request, from, args_maximum): (Header, SocketAddrV4, u32),
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Option<Finished> {
        let busy = self.calls.len() >= MAX_WAITING_CALLS;
        let mut job = || {
            self.next_job = self.next_job.wrapping_add(1);
            self.next_job
        };
        let asked = match pending {
            Pending::Write { outer, parts } => {
                let parts = parts
                    .into_iter()
                    .map(|(h, r)| match r {
                        Ok(s) => (h, Part::Done(s)),
                        Err(_) if busy => (
                            h,
                            Part::Done(
                                RecordError::write(RecordErrorCode::ResourceBusy, 0).status(),
                            ),
                        ),
                        Err(data) => {
                            let j = job();
                            out.push(DeviceAction::Record(RecordJob {
                                job: j,
                                write: true,
                                ar_uuid: h.ar_uuid,
                                api: h.api,
                                slot: h.slot,
                                subslot: h.subslot,
                                index: h.index,
                                data,
                                max_len: 0,
                            }));
                            (h, Part::Waiting(j))
                        }
                    })
                    .collect();
                Asked::Write { outer, parts }
            }
            Pending::Read { header, .. } if busy => {
                let s = RecordError::read(RecordErrorCode::ResourceBusy, 0).status();
                let (s, b) = read_response(&header, Err(s));
                return Some(Finished {
                    request,
                    from,
                    args_maximum,
                    status: s,
                    blocks: b,
                });
            }
            Pending::Read { header, ar_uuid } => {
                let j = job();
                out.push(DeviceAction::Record(RecordJob {
                    job: j,
                    write: false,
                    ar_uuid,
                    api: header.api,
                    slot: header.slot,
                    subslot: header.subslot,
                    index: header.index,
                    data: Vec::new(),
                    max_len: header.record_data_length,
                }));
                Asked::Read { header, job: j }
            }
        };
        let call = WaitingCall {
            request,
            from,
            args_maximum,
            deadline: now_ns.saturating_add(RECORD_ANSWER_TIMEOUT_NS),
            asked,
        };
        if busy {
            // Every record of it is answered already.
            return Some(call.give_up(RecordErrorCode::ResourceBusy));
        }
        self.calls.push(call);
        None
    }

    /// The application's answer to `job`: the data read (ignored for a write) or the
    /// PNIORW error (ErrorCode1, ErrorCode2). Gives the call's response once it is whole.
    pub(super) fn answer(
        &mut self,
        job: u64,
        answer: Result<Vec<u8>, (RecordErrorCode, u8)>,
    ) -> Result<Option<Finished>, UnknownRecordJob> {
        let i = self
            .calls
            .iter()
            .position(|c| c.has(job))
            .ok_or(UnknownRecordJob(job))?;
        let call = &mut self.calls[i];
        match &mut call.asked {
            Asked::Write { parts, .. } => {
                let s = match answer {
                    Ok(_) => PnioStatus::OK,
                    Err((code, c2)) => RecordError::write(code, c2).status(),
                };
                for (_, p) in parts.iter_mut() {
                    if matches!(p, Part::Waiting(j) if *j == job) {
                        *p = Part::Done(s);
                    }
                }
                if parts.iter().any(|(_, p)| matches!(p, Part::Waiting(_))) {
                    return Ok(None);
                }
                Ok(self.calls.remove(i).finished())
            }
            Asked::Read { header, .. } => {
                let header = *header;
                let result = answer.map_err(|(code, c2)| RecordError::read(code, c2).status());
                let (s, b) = read_response(&header, result);
                Ok(Some(self.calls.remove(i).answered(s, b)))
            }
        }
    }

    /// The calls whose time is up, answered for the application.
    pub(super) fn expire(&mut self, now_ns: u64) -> Vec<Finished> {
        let mut done = Vec::new();
        while let Some(i) = self.calls.iter().position(|c| now_ns >= c.deadline) {
            let call = self.calls.remove(i);
            self.timeouts += match &call.asked {
                Asked::Write { parts, .. } => parts
                    .iter()
                    .filter(|(_, p)| matches!(p, Part::Waiting(_)))
                    .count() as u64,
                Asked::Read { .. } => 1,
            };
            done.push(call.give_up(RecordErrorCode::ResourceBusy));
        }
        done
    }

    /// When the next call times out.
    pub(super) fn deadline(&self) -> Option<u64> {
        self.calls.iter().map(|c| c.deadline).min()
    }

    /// Whether the call (`activity`, `sequence`) waits for the application.
    pub(super) fn has_call(&self, request: &Header) -> bool {
        self.calls.iter().any(|c| {
            c.request.activity == request.activity
                && c.request.sequence_number == request.sequence_number
        })
    }
}

impl<A: Application> Device<A> {
    /// The application's answer to record job `job`: for a read the record (cut to what the
    /// controller takes), for a write anything; or the PNIORW error (ErrorCode1, ErrorCode2)
    /// the controller gets. Answers the controller's call once all its jobs are answered.
    pub fn answer_record(
        &mut self,
        job: u64,
        answer: Result<Vec<u8>, (RecordErrorCode, u8)>,
        out: &mut Vec<DeviceAction>,
    ) -> Result<(), UnknownRecordJob> {
        if let Some(f) = self.records.waiting.answer(job, answer)? {
            self.respond_finished(f, out);
        }
        Ok(())
    }

    /// Answers the calls whose application jobs timed out.
    pub(super) fn expire_record_jobs(&mut self, now_ns: u64, out: &mut Vec<DeviceAction>) {
        for f in self.records.waiting.expire(now_ns) {
            self.respond_finished(f, out);
        }
    }

    /// Sends a finished call's response.
    pub(super) fn respond_finished(&mut self, f: Finished, out: &mut Vec<DeviceAction>) {
        self.rpc
            .respond(&f.request, f.from, f.status, f.args_maximum, &f.blocks, out);
    }
}
