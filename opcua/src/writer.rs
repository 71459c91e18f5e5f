// SPDX-License-Identifier: MIT OR Apache-2.0
//! Writes of outputs from OPC UA sessions, as `procimg io write` makes them: the submodule
//! is claimed (all its outputs are the session's until the session ends), the bytes go in,
//! marked GOOD. A submodule another procimg client holds, or another session, is refused
//! with the holder's name. One thread owns the writing client: its calls block.

use procimg_client::{Client, ControlError, Ioxs, Refusal};
use std::collections::HashMap;
use std::sync::mpsc;
use std::time::Duration;
use tokio::sync::oneshot;

/// How often sessions are looked at, to release the claims of those that ended.
const LOOK_EVERY: Duration = Duration::from_millis(200);

/// Whether a session lives.
pub type Alive = Box<dyn Fn() -> bool + Send>;

/// Why a write was not made.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum WriteRefusal {
    /// Another client or session holds the submodule's outputs.
    Held(String),
    /// The write was resolved against a layout procimgd no longer has.
    Gone,
    /// The server refused or did not answer.
    Failed(String),
}

/// A write of `bytes` at output address `address` (within submodule `submodule`) by session
/// `session`.
pub struct Write {
    /// The session's id.
    pub session: u32,
    /// Whether the session still lives (checked to release its claims).
    pub alive: Alive,
    /// The hash of the layout the write was resolved against.
    pub layout: u64,
    /// The submodule.
    pub submodule: usize,
    /// The first byte's logical address.
    pub address: u32,
    /// The bytes.
    pub bytes: Vec<u8>,
    /// The outcome.
    pub reply: oneshot::Sender<Result<(), WriteRefusal>>,
}

/// Runs the writer over `client` (attached with slice access) until `jobs` ends. A write
/// resolved against another layout than the client's (procimgd started anew) makes it
/// attach again with `attach`; the claims of the old server went with it.
pub fn run(mut client: Client, jobs: mpsc::Receiver<Write>, attach: impl Fn() -> Option<Client>) {
    // Submodule → the session holding it, and how to tell that session lives.
    let mut held: HashMap<usize, (u32, Alive)> = HashMap::new();
    // The layout `held` counts submodules in: the client may have attached again by itself.
    let mut known = client.layout().hash();
    loop {
        match jobs.recv_timeout(LOOK_EVERY) {
            Ok(w) => {
                if w.layout != client.layout().hash() || known != client.layout().hash() {
                    if let Some(again) = attach() {
                        client = again;
                    }
                    held.clear();
                    known = client.layout().hash();
                    if w.layout != client.layout().hash() {
                        let _ = w.reply.send(Err(WriteRefusal::Gone));
                        continue;
                    }
                }
                let outcome = write(
                    &mut client,
                    &mut held,
                    w.session,
                    w.alive,
                    w.submodule,
                    w.address,
                    &w.bytes,
                );
                let _ = w.reply.send(outcome);
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => return,
        }
        release_ended(&mut client, &mut held);
    }
}

fn write(
    client: &mut Client,
    held: &mut HashMap<usize, (u32, Alive)>,
    session: u32,
    alive: Alive,
    s: usize,
    address: u32,
    bytes: &[u8],
) -> Result<(), WriteRefusal> {
    match held.get(&s) {
        Some((owner, _)) if *owner != session => {
            return Err(WriteRefusal::Held(format!(
                "OPC UA session {owner} of procimg-opcua"
            )));
        }
        Some(_) => {}
        None => {
            match client.claim(&[s]) {
                Ok(()) => {}
                Err(ControlError::Refused(Refusal::ClaimHeld {
                    holder, holder_pid, ..
                })) => {
                    return Err(WriteRefusal::Held(format!("{holder} (pid {holder_pid})")));
                }
                Err(e) => return Err(WriteRefusal::Failed(e.to_string())),
            }
            held.insert(s, (session, alive));
        }
    }
    client
        .data_write(address, bytes, Ioxs::Good)
        .map(|_| ())
        .map_err(|e| WriteRefusal::Failed(e.to_string()))
}

/// Releases the claims of sessions that ended: their outputs go out invalid again, as a
/// program's do when it lets them go.
fn release_ended(client: &mut Client, held: &mut HashMap<usize, (u32, Alive)>) {
    let ended: Vec<usize> = held
        .iter()
        .filter(|(_, (_, alive))| !alive())
        .map(|(s, _)| *s)
        .collect();
    if ended.is_empty() {
        return;
    }
    if let Err(e) = client.release(&ended) {
        tracing::warn!("cannot release the outputs of an ended session: {e}");
    }
    for s in ended {
        held.remove(&s);
    }
}
