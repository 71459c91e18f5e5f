// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFIenergy commands of the controller's clients, as IO-Base's PNIOLib carries them: the
//! PE request written to record 0x80A0 of the submodule, then its answer read from the same
//! record; a read the device refuses as not ready yet (PNIORW "resource busy" 0xC2 or
//! "resource unavailable" 0xC3, which the Siemens controllers retry on) is made again after
//! [`POLL_START`], doubling up to [`POLL_MAX`], until the answer comes or
//! [`PE_LIFETIME_MS`] passed. Any other failure ends the command with the record job's
//! status; an answer that is not the request's (another service or reference) is read
//! again, as a device still holding an older answer gives it.

use procimg_control::pe::{
    PE_LIFETIME_MS, PeAnswer, PeCommand, PeMeasurementInfo, PeMeasurementValue, PeModeInfo,
    PePemStatus,
};
use procimg_control::services::{RecordStatus, RecordTarget};
use procimg_profinet::controller::{RecordFailure, RecordRequest, RecordResult};
use procimg_profinet::wire::record::pe::{self as wire, INDEX_PE_SERVICE, PeRequest, PeResponse};
use std::collections::HashMap;
use std::time::{Duration, Instant};

/// The first wait before a read is made again.
const POLL_START: Duration = Duration::from_millis(20);
/// The longest wait between two reads (PNIOLib's period).
const POLL_MAX: Duration = Duration::from_millis(1000);
/// The most bytes of an answer read.
const MAX_ANSWER: u32 = 4096;
/// How long after its lifetime a command whose record job never ended is given up (the
/// controller confirms every record job; this is for one that went nowhere).
const LOST_GRACE: Duration = Duration::from_secs(30);

/// A command on its way.
struct PeJob {
    reply_to: u64,
    reference: u64,
    target: RecordTarget,
    device: usize,
    command: PeCommand,
    request: PeRequest,
    deadline: Instant,
    /// When the next read goes (`None`: a record job is under way).
    next_read: Option<Instant>,
    wait: Duration,
}

/// How a command ended.
pub(super) struct PeOutcome {
    pub reply_to: u64,
    pub reference: u64,
    pub target: RecordTarget,
    pub command: PeCommand,
    pub result: Result<PeAnswer, (RecordStatus, String)>,
}

/// What the commands ask of the controller and tell the clients.
#[derive(Default)]
pub(super) struct PeSteps {
    /// Record jobs to send, with their ids.
    pub records: Vec<RecordRequest>,
    /// Commands that ended.
    pub done: Vec<PeOutcome>,
}

/// The commands on their way, by the id of their record job.
#[derive(Default)]
pub(super) struct PeJobs {
    jobs: HashMap<u64, PeJob>,
    /// Request_Reference of the next command (1..=255).
    next_reference: u8,
}

impl PeJobs {
    /// Starts `command` for `reply_to`: its write goes as record job `id`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn start(
        &mut self,
        id: u64,
        reply_to: u64,
        reference: u64,
        target: RecordTarget,
        device: usize,
        command: PeCommand,
        now: Instant,
    ) -> RecordRequest {
        self.next_reference = self.next_reference.wrapping_add(1).max(1);
        let request = PeRequest {
            reference: self.next_reference,
            command: to_wire(&command),
        };
        let write = RecordRequest {
            reference: id,
            device,
            api: target.api,
            slot: target.slot,
            subslot: target.subslot,
            index: INDEX_PE_SERVICE,
            max_len: 0,
            // A command of this crate's own always emits.
            write: Some(request.to_vec().unwrap_or_default()),
        };
        self.jobs.insert(
            id,
            PeJob {
                reply_to,
                reference,
                target,
                device,
                command,
                request,
                deadline: now + Duration::from_millis(PE_LIFETIME_MS),
                next_read: None,
                wait: POLL_START,
            },
        );
        write
    }

    /// Whether record job `id` is a command's.
    pub(super) fn owns(&self, id: u64) -> bool {
        self.jobs.contains_key(&id)
    }

    /// Forgets the command of record job `id` (its write could not be sent).
    pub(super) fn forget(&mut self, id: u64) {
        self.jobs.remove(&id);
    }

    /// Commands of `reply_to` on their way.
    pub(super) fn open_of(&self, reply_to: u64) -> usize {
        self.jobs
            .values()
            .filter(|j| j.reply_to == reply_to)
            .count()
    }

    /// A command's record job ended.
    pub(super) fn on_record(&mut self, r: RecordResult, now: Instant, steps: &mut PeSteps) {
        let Some(mut job) = self.jobs.remove(&r.request.reference) else {
            return;
        };
        let id = r.request.reference;
        match r.result {
            // The write went: read the answer at once.
            Ok(_) if r.request.write.is_some() => {
                job.next_read = Some(now);
                self.jobs.insert(id, job);
            }
            Ok(read) => match PeResponse::parse(&read.data) {
                Ok(res)
                    if res.reference == job.request.reference
                        && res.service == job.request.command.codes().0 =>
                {
                    steps.done.push(outcome(job, Ok(from_wire(res.answer))));
                }
                Ok(_) => self.again(id, job, now, steps),
                Err(_) => {
                    let why = format!(
                        "the device's answer in record 0x80A0 is no PE response block ({} bytes)",
                        read.data.len()
                    );
                    steps
                        .done
                        .push(outcome(job, Err((RecordStatus::default(), why))));
                }
            },
            Err(f) if busy(&f) && r.request.write.is_none() => self.again(id, job, now, steps),
            Err(f) => {
                let status = status_of(&f);
                steps.done.push(outcome(job, Err((status, f.reason))));
            }
        }
    }

    /// The answer is not there yet: read again after the wait, unless the lifetime is over.
    fn again(&mut self, id: u64, mut job: PeJob, now: Instant, steps: &mut PeSteps) {
        if now >= job.deadline {
            steps.done.push(timeout(job));
            return;
        }
        job.next_read = Some(now + job.wait);
        job.wait = (job.wait * 2).min(POLL_MAX);
        self.jobs.insert(id, job);
    }

    /// The reads that are due, each under a new id from `ids`, and the commands whose
    /// lifetime ended.
    pub(super) fn poll(&mut self, now: Instant, mut ids: impl FnMut() -> u64, steps: &mut PeSteps) {
        let lost: Vec<u64> = self
            .jobs
            .iter()
            .filter(|(_, j)| j.next_read.is_none() && now >= j.deadline + LOST_GRACE)
            .map(|(id, _)| *id)
            .collect();
        for id in lost {
            if let Some(job) = self.jobs.remove(&id) {
                steps.done.push(timeout(job));
            }
        }
        let due: Vec<u64> = self
            .jobs
            .iter()
            .filter(|(_, j)| j.next_read.is_some_and(|t| t <= now))
            .map(|(id, _)| *id)
            .collect();
        for old in due {
            let Some(mut job) = self.jobs.remove(&old) else {
                continue;
            };
            if now >= job.deadline {
                steps.done.push(timeout(job));
                continue;
            }
            job.next_read = None;
            let id = ids();
            steps.records.push(RecordRequest {
                reference: id,
                device: job.device,
                api: job.target.api,
                slot: job.target.slot,
                subslot: job.target.subslot,
                index: INDEX_PE_SERVICE,
                max_len: MAX_ANSWER,
                write: None,
            });
            self.jobs.insert(id, job);
        }
    }
}

/// Whether a read was refused as "not ready yet".
fn busy(f: &RecordFailure) -> bool {
    f.status.error_code == 0xde
        && f.status.error_decode == 0x80
        && matches!(f.status.error_code1, 0xc2 | 0xc3)
}

fn status_of(f: &RecordFailure) -> RecordStatus {
    RecordStatus {
        error_code: f.status.error_code,
        error_decode: f.status.error_decode,
        error_code1: f.status.error_code1,
        error_code2: f.status.error_code2,
        add_value1: f.add_value1,
        add_value2: f.add_value2,
    }
}

fn outcome(job: PeJob, result: Result<PeAnswer, (RecordStatus, String)>) -> PeOutcome {
    PeOutcome {
        reply_to: job.reply_to,
        reference: job.reference,
        target: job.target,
        command: job.command,
        result,
    }
}

/// The lifetime ended without an answer: IO-Base's "no connection" status.
fn timeout(job: PeJob) -> PeOutcome {
    let status = RecordStatus {
        error_code: 0xc0,
        error_decode: 0x80,
        error_code1: 0xa3,
        ..RecordStatus::default()
    };
    let why = format!(
        "no PE answer within {} s: the device kept answering the read of record 0x80A0 as not \
         ready",
        PE_LIFETIME_MS / 1000
    );
    outcome(job, Err((status, why)))
}

fn to_wire(c: &PeCommand) -> wire::PeCommand {
    match c {
        PeCommand::StartPause { pause_ms } => wire::PeCommand::StartPause {
            pause_ms: *pause_ms,
        },
        PeCommand::EndPause => wire::PeCommand::EndPause,
        PeCommand::ListModes => wire::PeCommand::ListModes,
        PeCommand::GetMode { mode } => wire::PeCommand::GetMode { mode: *mode },
        PeCommand::PemStatus => wire::PeCommand::PemStatus,
        PeCommand::Identify => wire::PeCommand::Identify,
        PeCommand::QueryVersion => wire::PeCommand::QueryVersion,
        PeCommand::MeasurementList => wire::PeCommand::MeasurementList,
        PeCommand::MeasurementValues { ids } => {
            wire::PeCommand::MeasurementValues { ids: ids.clone() }
        }
    }
}

fn from_wire(a: wire::PeAnswer) -> PeAnswer {
    match a {
        wire::PeAnswer::StartPause { mode } => PeAnswer::StartPause { mode },
        wire::PeAnswer::EndPause { time_to_operate } => PeAnswer::EndPause { time_to_operate },
        wire::PeAnswer::ModeList(modes) => PeAnswer::ModeList { modes },
        wire::PeAnswer::Mode(m) => PeAnswer::Mode(PeModeInfo {
            mode: m.mode,
            attributes: m.attributes,
            time_min_pause: m.time_min_pause,
            time_to_pause: m.time_to_pause,
            time_to_operate: m.time_to_operate,
            time_min_length_of_stay: m.time_min_length_of_stay,
            time_max_length_of_stay: m.time_max_length_of_stay,
            power_kw: m.power_kw,
            energy_to_pause_kwh: m.energy_to_pause_kwh,
            energy_to_operate_kwh: m.energy_to_operate_kwh,
        }),
        wire::PeAnswer::PemStatus(s) => PeAnswer::PemStatus(PePemStatus {
            source: s.source,
            destination: s.destination,
            time_to_operate: s.time_to_operate,
            remaining_time_to_destination: s.remaining_time_to_destination,
            power_kw: s.power_kw,
            energy_to_destination_kwh: s.energy_to_destination_kwh,
            energy_to_operate_kwh: s.energy_to_operate_kwh,
        }),
        wire::PeAnswer::Identify(services) => PeAnswer::Identify { services },
        wire::PeAnswer::Version { major, minor } => PeAnswer::Version { major, minor },
        wire::PeAnswer::MeasurementList(items) => PeAnswer::MeasurementList {
            items: items
                .into_iter()
                .map(|m| PeMeasurementInfo {
                    id: m.id,
                    accuracy_domain: m.accuracy_domain,
                    accuracy_class: m.accuracy_class,
                    range: m.range,
                })
                .collect(),
        },
        wire::PeAnswer::MeasurementValues(values) => PeAnswer::MeasurementValues {
            values: values
                .into_iter()
                .map(|v| PeMeasurementValue {
                    id: v.id,
                    status: v.status,
                    value: v.value,
                })
                .collect(),
        },
        wire::PeAnswer::Error(code) => PeAnswer::Error { code },
        wire::PeAnswer::Other {
            status,
            structure,
            data,
        } => PeAnswer::Other {
            status,
            structure,
            data,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_profinet::controller::RecordData;
    use procimg_profinet::wire::PnioStatus;

    const TARGET: RecordTarget = RecordTarget {
        device: 0,
        api: 0,
        slot: 0,
        subslot: 1,
        index: INDEX_PE_SERVICE,
    };

    fn failure(request: RecordRequest, c1: u8) -> RecordResult {
        RecordResult {
            request,
            result: Err(RecordFailure {
                status: PnioStatus::from_bytes([0xde, 0x80, c1, 0]),
                add_value1: 0,
                add_value2: 0,
                reason: String::new(),
            }),
        }
    }

    fn data(request: RecordRequest, bytes: Vec<u8>) -> RecordResult {
        RecordResult {
            request,
            result: Ok(RecordData {
                data: bytes,
                add_value1: 0,
                add_value2: 0,
            }),
        }
    }

    #[test]
    fn a_busy_answer_is_read_again_until_it_comes() {
        let mut jobs = PeJobs::default();
        let t0 = Instant::now();
        let write = jobs.start(1, 9, 77, TARGET, 0, PeCommand::EndPause, t0);
        let request = PeRequest::parse(write.write.as_deref().unwrap()).unwrap();
        let mut steps = PeSteps::default();
        // The write went: a read is due at once.
        jobs.on_record(data(write, Vec::new()), t0, &mut steps);
        let mut next = 10;
        jobs.poll(
            t0,
            || {
                next += 1;
                next
            },
            &mut steps,
        );
        let read = steps.records.pop().expect("a read");
        assert_eq!((read.index, read.write.is_none()), (INDEX_PE_SERVICE, true));
        // Not ready: read again after the wait, not before.
        jobs.on_record(failure(read, 0xc3), t0, &mut steps);
        jobs.poll(
            t0,
            || {
                next += 1;
                next
            },
            &mut steps,
        );
        assert!(steps.records.is_empty());
        jobs.poll(
            t0 + POLL_START,
            || {
                next += 1;
                next
            },
            &mut steps,
        );
        let read = steps.records.pop().expect("the read again");
        let answer = PeResponse {
            service: wire::service::END_PAUSE,
            reference: request.reference,
            answer: wire::PeAnswer::EndPause { time_to_operate: 5 },
        };
        jobs.on_record(data(read, answer.to_vec().unwrap()), t0, &mut steps);
        let done = steps.done.pop().expect("confirmed");
        assert_eq!((done.reply_to, done.reference), (9, 77));
        assert_eq!(
            done.result.unwrap(),
            PeAnswer::EndPause { time_to_operate: 5 }
        );
    }

    #[test]
    fn a_device_that_never_gets_ready_ends_the_command_after_its_lifetime() {
        let mut jobs = PeJobs::default();
        let t0 = Instant::now();
        let write = jobs.start(1, 9, 1, TARGET, 0, PeCommand::PemStatus, t0);
        let mut steps = PeSteps::default();
        jobs.on_record(data(write, Vec::new()), t0, &mut steps);
        let late = t0 + Duration::from_millis(PE_LIFETIME_MS);
        let mut next = 10;
        jobs.poll(
            t0,
            || {
                next += 1;
                next
            },
            &mut steps,
        );
        let read = steps.records.pop().unwrap();
        jobs.on_record(failure(read, 0xc2), late, &mut steps);
        let done = steps.done.pop().expect("given up");
        let (status, _) = done.result.unwrap_err();
        assert_eq!((status.error_code, status.error_code1), (0xc0, 0xa3));
        assert_eq!(jobs.open_of(9), 0);
    }

    #[test]
    fn another_failure_ends_the_command_with_its_status() {
        let mut jobs = PeJobs::default();
        let t0 = Instant::now();
        let write = jobs.start(1, 9, 1, TARGET, 0, PeCommand::Identify, t0);
        let mut steps = PeSteps::default();
        jobs.on_record(failure(write, 0xb0), t0, &mut steps);
        let (status, _) = steps.done.pop().unwrap().result.unwrap_err();
        assert_eq!(status.error_code1, 0xb0);
    }
}
