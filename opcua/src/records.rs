// SPDX-License-Identifier: MIT OR Apache-2.0
//! Record jobs of OPC UA sessions (`EDS<addr>,DATA<index>,<len>` items): read or written
//! through procimgd's client services, by the submodule a logical address names, on a thread
//! of their own (a job waits for the device's answer).

use procimg_client::{Layout, RecordError, RecordTarget, ServiceOptions, Services};
use std::sync::mpsc;
use std::time::Duration;
use tokio::sync::oneshot;

/// How long a device may take to answer a record job.
pub const RECORD_TIMEOUT: Duration = Duration::from_secs(10);

/// A record job.
pub enum Job {
    /// Read up to `max_len` bytes.
    Read {
        /// The record.
        target: RecordTarget,
        /// The most bytes wanted.
        max_len: u32,
        /// The data, or why not.
        reply: oneshot::Sender<Result<Vec<u8>, String>>,
    },
    /// Write `data`.
    Write {
        /// The record.
        target: RecordTarget,
        /// The record's data.
        data: Vec<u8>,
        /// Done, or why not.
        reply: oneshot::Sender<Result<(), String>>,
    },
}

/// The record of submodule `submodule` of `layout` with index `index`.
pub fn target(layout: &Layout, submodule: usize, index: u16) -> Option<RecordTarget> {
    let e = layout.submodules.get(submodule)?;
    Some(RecordTarget {
        device: u32::from(e.device),
        api: e.api,
        slot: e.slot,
        subslot: e.subslot,
        index,
    })
}

/// Sends `job` to the record thread behind `jobs` and waits, blocking, for its answer: for
/// callers outside async code (a method's callback).
pub fn blocking<T>(
    jobs: &std::sync::Mutex<mpsc::Sender<Job>>,
    job: impl FnOnce(oneshot::Sender<Result<T, String>>) -> Job,
) -> Result<T, String> {
    let (reply, answer) = oneshot::channel();
    jobs.lock()
        .unwrap_or_else(|e| e.into_inner())
        .send(job(reply))
        .map_err(|_| "the record thread has ended".to_owned())?;
    let got = blocking_call(|| answer.blocking_recv());
    got.map_err(|_| "the record thread has ended".to_owned())?
}

/// Runs `call`, which blocks (a wait for procimgd), from a method's callback: inside the
/// server's runtime it must not hold up the runtime's other tasks.
pub fn blocking_call<T>(call: impl FnOnce() -> T) -> T {
    match tokio::runtime::Handle::try_current() {
        Ok(_) => tokio::task::block_in_place(call),
        Err(_) => call(),
    }
}

/// Runs record jobs for `instance` until `jobs` ends.
pub fn run(instance: &str, jobs: mpsc::Receiver<Job>) {
    let mut services: Option<Services> = None;
    for job in jobs {
        if services.is_none() {
            services = Services::open(instance, ServiceOptions::new("procimg-opcua records"))
                .map_err(|e| tracing::warn!("no record services of instance {instance:?}: {e}"))
                .ok();
        }
        let Some(s) = services.as_mut() else {
            let why = format!("procimgd instance {instance:?} takes no record jobs now");
            match job {
                Job::Read { reply, .. } => drop(reply.send(Err(why))),
                Job::Write { reply, .. } => drop(reply.send(Err(why))),
            }
            continue;
        };
        let words = |e: RecordError| e.to_string();
        match job {
            Job::Read {
                target,
                max_len,
                reply,
            } => {
                let _ = reply.send(
                    s.read_record(target, max_len, RECORD_TIMEOUT)
                        .map_err(words),
                );
            }
            Job::Write {
                target,
                data,
                reply,
            } => {
                let _ = reply.send(s.write_record(target, &data, RECORD_TIMEOUT).map_err(words));
            }
        }
    }
}
