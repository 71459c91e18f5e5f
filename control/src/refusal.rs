// SPDX-License-Identifier: MIT OR Apache-2.0
//! Why the server refused a request, each reason with what to do about it.

use crate::Space;
use procimg_shm_layout::Mode;
use serde::{Deserialize, Serialize};

/// Why a plug, pull or return of a station submodule was refused
/// ([`Refusal::StationPlug`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlugRefusal {
    /// The station's configuration has no submodule at the position.
    NotConfigured,
    /// Something is plugged there already.
    AlreadyPlugged,
    /// Nothing is plugged there.
    NotPlugged,
    /// The PLC's AR is between its Connect and data exchange.
    ArStartingUp,
    /// No AR in data exchange holds the submodule (a return needs one).
    NotInDataExchange,
}

/// Why an alarm did not go out ([`Refusal::StationAlarm`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AlarmRefusal {
    /// No AR is in data exchange.
    NotInDataExchange,
    /// The AR holds no proper submodule at the address.
    NotInAr,
    /// The USI does not fit the alarm.
    InvalidUsi,
    /// The alarm is longer than the AR takes.
    TooLong,
}

/// Why the server refused a request.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum Refusal {
    /// Every client slot is taken.
    TooManyClients {
        /// The limit.
        max: u32,
    },
    /// The slot/token pair is not a current registration.
    UnknownClient,
    /// A submodule index is outside the table.
    NoSuchSubmodule {
        /// The index.
        submodule: u32,
    },
    /// The submodule has no outputs to claim.
    NoOutputs {
        /// The index.
        submodule: u32,
    },
    /// Another client holds the claim.
    ClaimHeld {
        /// The index.
        submodule: u32,
        /// The holder's name.
        holder: String,
        /// The holder's process id.
        holder_pid: u32,
        /// The holder's slot.
        holder_slot: u32,
    },
    /// The previous mode change has not been confirmed yet.
    ModeChangePending {
        /// The mode being reached.
        pending: Mode,
    },
    /// The cycle thread's command queue is full (the cycle is stalled); try again.
    ServerBusy,
    /// There is no device with this index in the layout.
    NoSuchDevice {
        /// The index.
        device: u32,
    },
    /// The requester has as many record jobs open as it may.
    TooManyJobs {
        /// The limit.
        max: u32,
    },
    /// The record is longer than a job may carry.
    RecordTooLong {
        /// Its length.
        len: u32,
        /// The limit.
        max: u32,
    },
    /// The request needs the controller online (CLEAR or OPERATE).
    Offline,
    /// No subscriber with this id is announced.
    UnknownSubscriber,
    /// No alarm with this id waits for this subscriber's acknowledgement.
    UnknownAlarm {
        /// The alarm's id.
        alarm: u64,
    },
    /// The server could not subscribe to a client's output service.
    OutputsNotConnected {
        /// iceoryx2's error, naming the service.
        detail: String,
    },
    /// The request could not be decoded.
    BadRequest {
        /// What was wrong.
        message: String,
    },
    /// An alarm of the station was not sent.
    StationAlarm {
        /// Why, for a program to act on.
        refused: AlarmRefusal,
        /// Why, in words that name the submodule.
        message: String,
    },
    /// A plug, pull or return of a station submodule was refused.
    StationPlug {
        /// Why, for a program to act on.
        refused: PlugRefusal,
        /// Why, in words that name the position.
        message: String,
    },
    /// No submodule has IO data at this address.
    NoSuchAddress {
        /// I or Q.
        space: Space,
        /// The address.
        address: u32,
    },
    /// The bytes run past the end of the submodule at the address.
    PastSubmoduleEnd {
        /// I or Q.
        space: Space,
        /// The address.
        address: u32,
        /// Bytes asked for.
        length: u32,
        /// Bytes from the address to the end of its submodule.
        room: u32,
    },
    /// The force table is full.
    TooManyForces {
        /// The most forced bytes.
        max: u32,
    },
    /// The request is a service of the other PROFINET role than the server plays (an IO
    /// controller's record job asked of a server in the device role, say).
    WrongRole {
        /// The role the server plays: `"controller"` or `"device"`.
        role: String,
        /// The service asked for.
        service: String,
    },
    /// Another subscriber took the records of this submodule of the station.
    RecordsTaken {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
        /// The name of the subscriber that took them.
        by: String,
    },
    /// The station has no such submodule.
    NoSuchStationSubmodule {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
    },
    /// Another subscriber checks the station's new ARs.
    ArChecksTaken {
        /// The name of the subscriber that checks them.
        by: String,
    },
    /// Another subscriber checks DCP's changes of the station.
    DcpChecksTaken {
        /// The name of the subscriber that checks them.
        by: String,
    },
    /// No DCP Set check of this number waits for this subscriber's answer.
    StaleDcpCheck {
        /// The check.
        job: u64,
    },
    /// The AR named is not the station's current one.
    ArGone {
        /// The ARUUID named.
        ar_uuid: String,
    },
    /// No AR check of this number waits for this subscriber's answer.
    StaleArCheck {
        /// The check.
        job: u64,
    },
    /// No record job of this number waits for this subscriber's answer.
    StaleRecordJob {
        /// The job.
        job: u64,
    },
    /// A configuration to restart with does not check.
    BadConfiguration {
        /// Why, with the line and key.
        message: String,
    },
    /// Programs are attached: a SAFE restart waits for none.
    ClientsAttached {
        /// Their names.
        clients: Vec<String>,
    },
    /// A restart is under way already.
    RestartPending,
    /// The answer could not be handed over (the control service had no room for it).
    AnswerLost {
        /// Bytes of the answer.
        bytes: u64,
        /// What the shared-memory layer said.
        detail: String,
    },
}

impl core::fmt::Display for Refusal {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Refusal::TooManyClients { max } => write!(
                f,
                "the server already has {max} clients attached; detach one and try again"
            ),
            Refusal::UnknownClient => f.write_str(
                "the server does not know this client (it restarted or dropped it); attach again",
            ),
            Refusal::NoSuchSubmodule { submodule } => write!(
                f,
                "submodule #{submodule} is not in the server's layout; check the configuration"
            ),
            Refusal::NoOutputs { submodule } => {
                write!(f, "submodule #{submodule} has no outputs to claim")
            }
            Refusal::ClaimHeld {
                submodule,
                holder,
                holder_pid,
                holder_slot,
            } => write!(
                f,
                "the outputs of submodule #{submodule} are claimed by client \"{holder}\" \
                 (pid {holder_pid}, slot {holder_slot}); release them there first"
            ),
            Refusal::ModeChangePending { pending } => write!(
                f,
                "the change to {pending} is not confirmed yet; wait for its MODE event"
            ),
            Refusal::ServerBusy => f.write_str(
                "the server's cycle is not taking commands at the moment (stalled?); try again",
            ),
            Refusal::NoSuchDevice { device } => write!(
                f,
                "there is no device #{device} in the server's layout; `procimg status` lists them"
            ),
            Refusal::TooManyJobs { max } => write!(
                f,
                "{max} record jobs of this requester are still open; wait for their confirmations"
            ),
            Refusal::RecordTooLong { len, max } => write!(
                f,
                "a record of {len} bytes is longer than the {max} bytes a job carries"
            ),
            Refusal::BadConfiguration { message } => {
                write!(f, "the configuration is refused: {message}")
            }
            Refusal::ClientsAttached { clients } => write!(
                f,
                "programs are attached ({}): close them first, or restart asking them to stop",
                clients.join(", ")
            ),
            Refusal::RestartPending => f.write_str(
                "the server is restarting already; wait for its new start (ServerStarted)",
            ),
            Refusal::Offline => {
                f.write_str("the controller is OFFLINE; set the mode to CLEAR or OPERATE first")
            }
            Refusal::UnknownSubscriber => f.write_str(
                "the server does not know this subscriber (it restarted or dropped it); \
                 subscribe again",
            ),
            Refusal::UnknownAlarm { alarm } => write!(
                f,
                "alarm #{alarm} is not waiting for this subscriber's acknowledgement \
                 (already acknowledged, or timed out)"
            ),
            Refusal::NoSuchAddress { space, address } => write!(
                f,
                "no submodule has IO data at {space} {address}; `procimg layout` lists the \
                 addresses"
            ),
            Refusal::PastSubmoduleEnd {
                space,
                address,
                length,
                room,
            } => write!(
                f,
                "{length} bytes at {space} {address} run past the end of its submodule: {room} \
                 bytes remain there; force each submodule on its own"
            ),
            Refusal::TooManyForces { max } => write!(
                f,
                "the force table holds at most {max} bytes; unforce some first \
                 (`procimg io unforce --all` clears it)"
            ),
            Refusal::BadRequest { message } => write!(f, "bad request: {message}"),
            Refusal::OutputsNotConnected { detail } => write!(
                f,
                "procimgd could not connect to this client's outputs ({detail}); attach again, \
                 and check that procimgd may open the client's files in its iceoryx2 directory \
                 ([access] group)"
            ),
            Refusal::StationPlug { message, .. } | Refusal::StationAlarm { message, .. } => {
                f.write_str(message)
            }
            Refusal::WrongRole { role, service } => write!(
                f,
                "this server plays the IO {role} role, and {service} is a service of the other \
                 role; use the {role} role's services, or run procimgd with the other `role`"
            ),
            Refusal::RecordsTaken {
                api,
                slot,
                subslot,
                by,
            } => write!(
                f,
                "the records of API {api} slot {slot} subslot {subslot:#06x} are taken by \
                 subscriber \"{by}\"; it gives them back when it unsubscribes or ends"
            ),
            Refusal::NoSuchStationSubmodule { api, slot, subslot } => write!(
                f,
                "the station has no submodule at API {api} slot {slot} subslot \
                 {subslot:#06x}; `procimgd --check` lists what is plugged"
            ),
            Refusal::ArChecksTaken { by } => write!(
                f,
                "subscriber \"{by}\" checks the station's new ARs; it stops when it unsubscribes \
                 or ends"
            ),
            Refusal::DcpChecksTaken { by } => write!(
                f,
                "subscriber \"{by}\" checks DCP's changes of the station; it stops when it \
                 unsubscribes or ends"
            ),
            Refusal::StaleDcpCheck { job } => write!(
                f,
                "DCP Set check {job} waits for no answer from this subscriber: it was answered, \
                 it timed out (the Set was then carried out) or it is another's"
            ),
            Refusal::ArGone { ar_uuid } => write!(
                f,
                "AR {ar_uuid} is not the station's current AR (it ended, or another PLC's \
                 replaced it): there is nothing of it to abort"
            ),
            Refusal::StaleArCheck { job } => write!(
                f,
                "AR check {job} waits for no answer from this subscriber: it was answered, it \
                 timed out (the AR was then accepted) or it is another's"
            ),
            Refusal::StaleRecordJob { job } => write!(
                f,
                "record job {job} waits for no answer from this subscriber: it was answered, \
                 it timed out (the station then answered the PLC itself) or it is another's"
            ),
            Refusal::AnswerLost { bytes, detail } => write!(
                f,
                "the server could not hand over its {bytes}-byte answer ({detail}); ask again, \
                 and see procimgd's log if it keeps happening"
            ),
        }
    }
}
