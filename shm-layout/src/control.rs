// SPDX-License-Identifier: MIT OR Apache-2.0
//! The control protocol: what clients ask the server over the request-response service
//! `procimg/<instance>/control`, and what it answers. Requests and responses travel as JSON in
//! byte-slice payloads, so both sides can add optional fields without breaking the other.

use crate::Mode;
pub use crate::states::{ArState, DeviceState};
use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use serde::{Deserialize, Serialize};

/// Largest encoded request or response.
pub const MAX_MESSAGE_LEN: usize = 256 * 1024;

/// The request-response service of an instance: the one name that survives server restarts.
pub fn control_service(instance: &str) -> String {
    format!("procimg/{instance}/control")
}

/// The input-image publish-subscribe service of one server generation.
pub fn input_service(instance: &str, generation: u64) -> String {
    format!("procimg/{instance}/{generation:016x}/inputs")
}

/// The layout publish-subscribe service of one server generation.
pub fn layout_service(instance: &str, generation: u64) -> String {
    format!("procimg/{instance}/{generation:016x}/layout")
}

/// The output publish-subscribe service (clients publish, the server subscribes).
pub fn output_service(instance: &str, generation: u64) -> String {
    format!("procimg/{instance}/{generation:016x}/outputs")
}

/// The event service on which the server signals NEWCYCLE, MODE, OPFAULT and shutdown, and
/// STARTOP to clients that wait on its descriptor (the others sleep on the handshake block's
/// futex word, see [`crate::handshake`]).
pub fn cycle_event_service(instance: &str, generation: u64) -> String {
    format!("procimg/{instance}/{generation:016x}/cycle-events")
}

/// The iceoryx2 node name of the server of an instance.
pub fn server_node_name(instance: &str) -> String {
    format!("procimgd/{instance}")
}

/// How a client takes part in the cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ClientRole {
    /// Takes part in the STARTOP/OPDONE handshake: the server waits for its OPDONE each cycle.
    Synchronous,
    /// Reads and writes at any time; not waited for.
    Asynchronous,
}

/// A request from a client.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "request", rename_all = "snake_case")]
pub enum Request {
    /// Join the instance; answered with [`Response::Registered`].
    Register {
        /// A name for status displays.
        name: String,
        /// The client's process id.
        pid: u32,
        /// Synchronous or asynchronous.
        role: ClientRole,
        /// Wants NEWCYCLE events (IO-Base registers PNIO_CP_CBE_NEWCYCLE_IND only on request).
        #[serde(default)]
        newcycle: bool,
        /// The iceoryx2 node id of the client, so the server notices when the process dies.
        node_id: String,
    },
    /// Leave the instance; claims are released.
    Unregister {
        /// Slot from the registration.
        slot: u32,
        /// Token from the registration.
        token: u64,
    },
    /// Claim the outputs of these submodules (indices in the submodule table).
    Claim {
        /// Slot from the registration.
        slot: u32,
        /// Token from the registration.
        token: u64,
        /// Submodule table indices.
        submodules: Vec<u32>,
    },
    /// Release claimed outputs.
    Release {
        /// Slot from the registration.
        slot: u32,
        /// Token from the registration.
        token: u64,
        /// Submodule table indices.
        submodules: Vec<u32>,
    },
    /// Change the mode; confirmed by a MODE event once the cycle has reached it.
    SetMode {
        /// The mode wanted.
        mode: Mode,
    },
    /// Report the server's state.
    Status,
    /// Announce a notification subscriber. Broadcasts and confirmations reach any subscriber;
    /// announcing is what makes the server wait for this one's alarm acknowledgements, and
    /// what shows it in the status.
    Subscribe {
        /// The subscriber's id (random, chosen by the subscriber).
        subscriber: u64,
        /// A name for status displays and messages.
        name: String,
        /// The subscriber's process id.
        pid: u32,
        /// The iceoryx2 node id of the subscriber, so the server notices when it dies.
        node_id: String,
        /// The server waits for this subscriber's [`Request::AcknowledgeAlarm`] before it
        /// acknowledges an alarm to the device (IO-Base: when the alarm callback returns).
        /// A server in the device role takes it and ignores it: the PLC acknowledges the
        /// station's alarms.
        acknowledge_alarms: bool,
    },
    /// Withdraw a subscriber; alarms waiting for it are acknowledged if nobody else waits.
    Unsubscribe {
        /// The subscriber's id.
        subscriber: u64,
    },
    /// Read a record; answered with [`Response::Accepted`], the data follows as a
    /// [`Notification::Record`](crate::services::Notification::Record) to `reply_to`.
    RecordRead {
        /// The subscriber that gets the confirmation.
        reply_to: u64,
        /// Echoed in the confirmation.
        reference: u64,
        /// The record.
        target: RecordTarget,
        /// The most bytes wanted.
        max_len: u32,
    },
    /// Write a record; answered with [`Response::Accepted`], the result follows as a
    /// [`Notification::Record`](crate::services::Notification::Record) to `reply_to`.
    RecordWrite {
        /// The subscriber that gets the confirmation.
        reply_to: u64,
        /// Echoed in the confirmation.
        reference: u64,
        /// The record.
        target: RecordTarget,
        /// The record.
        data: Vec<u8>,
    },
    /// Activate or deactivate a device (IO-Base `PNIO_device_activate`); not in OFFLINE.
    /// Confirmed by a [`Notification::Activation`](crate::services::Notification::Activation)
    /// to `reply_to`.
    ActivateDevice {
        /// The subscriber that gets the confirmation.
        reply_to: u64,
        /// Device index.
        device: u32,
        /// Activate (`true`) or deactivate.
        active: bool,
    },
    /// Acknowledge an alarm this subscriber was given with `ack_expected`.
    AcknowledgeAlarm {
        /// The subscriber's id.
        subscriber: u64,
        /// The alarm's id.
        alarm: u64,
    },
    /// The state of every device; answered with [`Response::Diagnosis`].
    Diagnosis,
    /// In the device role: a change of the diagnosis of one of the station's submodules,
    /// which the PLC gets as a diagnosis alarm and in the diagnosis records; answered with
    /// [`Response::Done`].
    StationDiagnosis {
        /// What changes.
        change: StationDiagnosisChange,
        /// Only the store changes (the records, the SubmoduleState, the station problem):
        /// the alarm is the client's to send ([`Request::StationAlarm`]), as IO-Base's
        /// device interface has it.
        #[serde(default)]
        silent: bool,
    },
    /// In the device role: a process alarm (high priority) of one of the station's
    /// submodules to the PLC, with a manufacturer-specific USI and its data; answered with
    /// [`Response::Done`] once it went out (its acknowledgement shows in the status).
    StationProcessAlarm {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
        /// UserStructureIdentifier, 0x0000 to 0x7FFF.
        usi: u16,
        /// The alarm's data.
        data: Vec<u8>,
    },
    /// In the device role: the application reports a problem of the station (`true`) or
    /// none: the PLC sees it in the StationProblemIndicator of the input data's DataStatus,
    /// as it sees a pending fault diagnosis (IO-Base's `PNIO_set_dev_state`); answered with
    /// [`Response::Done`].
    StationProblem {
        /// A problem (`true`) or none.
        problem: bool,
    },
    /// In the device role: an alarm of one of the station's submodules, of the client's
    /// making, to the PLC's AR in data exchange; answered with [`Response::Done`] once it
    /// went out, then the PLC's acknowledgement comes to the subscriber as
    /// [`Notification::StationAlarmDone`](crate::services::Notification::StationAlarmDone)
    /// with `tag`.
    StationAlarm {
        /// The subscriber the acknowledgement goes to.
        subscriber: u64,
        /// The client's name for the alarm, given back with its acknowledgement.
        tag: u64,
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
        /// What alarm.
        alarm: StationAlarmKind,
        /// UserStructureIdentifier of the item: 0x0000–0x7FFF manufacturer data (process
        /// and diagnosis alarms), 0x8000 channel and 0x8002 extended channel diagnosis.
        #[serde(default)]
        usi: u16,
        /// The item's data after the USI (none: no item).
        #[serde(default)]
        data: Vec<u8>,
    },
    /// In the device role: plug a submodule at a configured position of the station, with
    /// these ident numbers and the configured IO lengths (IO-Base's `PNIO_sub_plug`, GOAL's
    /// and GS20-PN's add item). Answered with [`Response::Done`]; to a PLC's AR in data
    /// exchange it is a Plug alarm (the expected submodule: the PLC writes its parameters
    /// again, then its data turns GOOD) or a Plug Wrong Submodule alarm (other ident
    /// numbers: its data stays BAD). Refused between a PLC's Connect and data exchange.
    StationPlug {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
        /// ModuleIdentNumber of what is plugged.
        module_ident: u32,
        /// SubmoduleIdentNumber of what is plugged.
        submodule_ident: u32,
    },
    /// In the device role: pull the submodule at a position of the station (IO-Base's
    /// `PNIO_sub_pull`); its place in the image stays, its data turns BAD towards the PLC,
    /// which gets a Pull alarm. Answered with [`Response::Done`].
    StationPull {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
    },
    /// In the device role: say that a submodule's data is valid again after it was BAD for
    /// a while (IO-Base's `PNIO_ret_of_sub_alarm_send`): a Return of Submodule alarm to the
    /// PLC's AR in data exchange. Answered with [`Response::Done`].
    StationReturnSubmodule {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
    },
    /// In the device role: take (`own`) or give back the user records (indices
    /// 0x0000–0x7FFF) of a submodule of the station. The PLC's reads and writes of them then
    /// come to this subscriber as
    /// [`Notification::StationRecord`](crate::services::Notification::StationRecord) jobs,
    /// each to be answered with [`Request::StationRecordAnswer`] within
    /// [`STATION_RECORD_TIMEOUT_MS`](crate::services::STATION_RECORD_TIMEOUT_MS). One
    /// subscriber at a time takes a submodule's records; they come back when it unsubscribes
    /// or its process ends.
    StationOwnRecords {
        /// The subscriber's id.
        subscriber: u64,
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
        /// Take (`true`) or give back.
        own: bool,
        /// With them the submodule's I&M0–I&M4 records (0xAFF0–0xAFF4), which procimgd
        /// answers otherwise.
        #[serde(default)]
        im: bool,
    },
    /// In the device role: check every new AR (`check`), or stop. The PLC's Connect then
    /// waits for this subscriber's [`Request::StationArCheckAnswer`] to a
    /// [`Notification::StationArCheck`](crate::services::Notification::StationArCheck), at
    /// most [`AR_CHECK_TIMEOUT_MS`](crate::services::AR_CHECK_TIMEOUT_MS), after which the AR
    /// is accepted. One subscriber at a time checks.
    StationCheckArs {
        /// The subscriber's id.
        subscriber: u64,
        /// Check (`true`) or stop.
        check: bool,
    },
    /// In the device role: accept a new AR, or refuse it with a Connect error.
    StationArCheckAnswer {
        /// The subscriber's id (the one the check went to).
        subscriber: u64,
        /// The check.
        job: u64,
        /// `None` accepts; else the Connect's ErrorCode1 and ErrorCode2 (ErrorCode 0xDB,
        /// ErrorDecode PNIO): (0x40, 0x04) "out of AR resources" is what a busy device says.
        #[serde(default)]
        refuse: Option<(u8, u8)>,
    },
    /// In the device role: check DCP's changes of the station's name and address (and its
    /// reset to factory), or stop. A DCP Set then waits for this subscriber's
    /// [`Request::StationDcpSetAnswer`] to a
    /// [`Notification::StationDcpSetCheck`](crate::services::Notification::StationDcpSetCheck),
    /// at most [`DCP_SET_CHECK_TIMEOUT_MS`](crate::services::DCP_SET_CHECK_TIMEOUT_MS), after
    /// which it is carried out. One subscriber at a time checks.
    StationVerifyDcp {
        /// The subscriber's id.
        subscriber: u64,
        /// Check (`true`) or stop.
        verify: bool,
    },
    /// In the device role: allow a DCP Set of the station's name or address, or veto it (the
    /// DCP client gets "SET not possible").
    StationDcpSetAnswer {
        /// The subscriber's id (the one the check went to).
        subscriber: u64,
        /// The check.
        job: u64,
        /// Allow (`true`) or veto.
        allow: bool,
    },
    /// In the device role: the answer to a record job.
    StationRecordAnswer {
        /// The subscriber's id (the one the job went to).
        subscriber: u64,
        /// The job.
        job: u64,
        /// For a read, the record (cut to what the PLC takes); ignored for a write.
        #[serde(default)]
        data: Vec<u8>,
        /// The PNIORW error the PLC gets instead: ErrorCode1 (0xB0 invalid index, 0xB1 write
        /// length error, 0xB8 invalid parameter, …) and ErrorCode2 (user specific).
        #[serde(default)]
        error: Option<(u8, u8)>,
    },
    /// In the device role: hold the ApplicationReady after every PrmEnd (END_OF_PARAM) until
    /// this subscriber says its parameters are applied ([`Request::StationApplicationReady`]),
    /// or stop holding it. It goes out when every holder said so, or after
    /// [`APP_READY_HOLD_TIMEOUT_MS`](crate::services::APP_READY_HOLD_TIMEOUT_MS).
    StationHoldApplicationReady {
        /// The subscriber's id.
        subscriber: u64,
        /// Hold (`true`) or not.
        hold: bool,
    },
    /// In the device role: this subscriber applied the PLC's parameters; the ApplicationReady
    /// may go out as far as it is concerned.
    StationApplicationReady {
        /// The subscriber's id.
        subscriber: u64,
        /// Submodules (API, slot, subslot) it is not ready for: the PLC gets them as
        /// "application ready pending" until a Return of Submodule alarm of each.
        #[serde(default)]
        not_ready: Vec<(u32, u16, u16)>,
    },
    /// The cycle thread's latency histograms since start, bucket by bucket; answered with
    /// [`Response::Histograms`]. Two answers subtracted give the histograms of the time
    /// between them.
    Histograms,
    /// Force bytes of the image, as a PLC's force table does: from the next cycle on, the
    /// server puts `data` at `address` in every cycle, over what the devices deliver (I) or
    /// what clients write (Q, sent with IOPS GOOD in OPERATE whoever owns the outputs), until
    /// an [`Request::Unforce`] or the server's end. The bytes lie in one submodule.
    Force {
        /// I or Q.
        space: Space,
        /// First logical address.
        address: u32,
        /// The forced values.
        data: Vec<u8>,
    },
    /// End forcing: `length` bytes from `address`, the rest of its submodule when `None`;
    /// every force when `address` is `None`.
    Unforce {
        /// I or Q.
        space: Space,
        /// First logical address; `None`: every force (in both spaces).
        address: Option<u32>,
        /// Bytes; `None`: to the end of the submodule.
        length: Option<u32>,
    },
}

impl Request {
    /// Whether it is one of the IO device role's station services (the station's
    /// diagnosis, alarms, records, AR checks, DCP checks and ApplicationReady).
    pub const fn is_station_service(&self) -> bool {
        matches!(
            self,
            Request::StationDiagnosis { .. }
                | Request::StationProcessAlarm { .. }
                | Request::StationAlarm { .. }
                | Request::StationProblem { .. }
                | Request::StationPlug { .. }
                | Request::StationPull { .. }
                | Request::StationReturnSubmodule { .. }
                | Request::StationOwnRecords { .. }
                | Request::StationCheckArs { .. }
                | Request::StationVerifyDcp { .. }
                | Request::StationDcpSetAnswer { .. }
                | Request::StationArCheckAnswer { .. }
                | Request::StationRecordAnswer { .. }
                | Request::StationHoldApplicationReady { .. }
                | Request::StationApplicationReady { .. }
        )
    }
}

/// The two address spaces of an IO system.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Space {
    /// Inputs (I).
    Input,
    /// Outputs (Q).
    Output,
}

impl core::fmt::Display for Space {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Space::Input => "I",
            Space::Output => "Q",
        })
    }
}

/// The server's answer.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "response", rename_all = "snake_case")]
pub enum Response {
    /// Registration accepted.
    Registered {
        /// The client's slot (0..MAX_CLIENTS).
        slot: u32,
        /// Identifies this registration in later requests and in output samples.
        token: u64,
        /// The server's generation: the data services are named after it.
        generation: u64,
        /// Hash of the server's layout.
        layout_hash: u64,
        /// The server's process id: a client tells its server from a successor started under
        /// the same name (0 from servers that do not say).
        #[serde(default)]
        server_pid: u32,
    },
    /// The request was carried out.
    Done,
    /// The request was refused.
    Refused(Refusal),
    /// The server's state.
    Status(Box<StatusReport>),
    /// The job was taken; its confirmation follows as a notification.
    Accepted,
    /// The devices' state.
    Diagnosis(Box<DiagnosisReport>),
    /// The cycle thread's latency histograms.
    Histograms(Box<HistogramsReport>),
}

use crate::services::{DiagnosisReport, RecordTarget};

use alloc::boxed::Box;

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

/// An alarm a client of the device role sends ([`Request::StationAlarm`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StationAlarmKind {
    /// A process alarm (high priority).
    Process,
    /// A diagnosis appears (the entry is in the store already).
    DiagnosisAppears,
    /// A diagnosis disappears (the entry is out of the store already).
    DiagnosisDisappears,
    /// Return of Submodule: the submodule's data is good again.
    ReturnOfSubmodule,
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

/// Percentiles of a latency histogram, in ns.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Percentiles {
    /// Number of samples.
    pub count: u64,
    /// Smallest.
    pub min_ns: u64,
    /// Median.
    pub p50_ns: u64,
    /// 99th percentile.
    pub p99_ns: u64,
    /// 99.9th percentile.
    pub p999_ns: u64,
    /// Largest.
    pub max_ns: u64,
    /// Mean.
    pub mean_ns: u64,
}

/// One bucket of a latency histogram: `count` values at most `ns` (and more than the
/// previous bucket's `ns`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Bucket {
    /// The bucket's highest value, in ns.
    pub ns: u64,
    /// Values recorded in it.
    pub count: u64,
}

/// The cycle thread's latency histograms since the server started, to 2 significant digits
/// (each bucket's `ns` within 1 % of the values in it),
/// with only the buckets that hold values, in rising order.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HistogramsReport {
    /// Cycles run when the histograms were taken.
    pub cycles: u64,
    /// Actual minus planned cycle start (the cycle thread's wake-up latency).
    pub wakeup: Vec<Bucket>,
    /// STARTOP → OPDONE received, per synchronous client and cycle (the round trip).
    pub handshake: Vec<Bucket>,
    /// A client's OPDONE sent → received by the cycle thread (one way).
    pub opdone: Vec<Bucket>,
    /// Cycle start → outputs handed to the IO system.
    pub work: Vec<Bucket>,
}

/// One claimed output submodule in a status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ClaimReport {
    /// Submodule table index.
    pub submodule: u32,
    /// Station name of its device.
    pub device: String,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// First logical output address.
    pub output_address: u32,
    /// Output bytes.
    pub output_length: u16,
}

/// One attached client in a status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ClientReport {
    /// Slot.
    pub slot: u32,
    /// Name it registered with.
    pub name: String,
    /// Process id.
    pub pid: u32,
    /// Role.
    pub role: ClientRole,
    /// OPFAULTs it got.
    pub opfaults: u64,
    /// The cycle of its last OPFAULT (0: none yet).
    #[serde(default)]
    pub last_opfault_cycle: u64,
    /// Its claims.
    pub claims: Vec<ClaimReport>,
}

/// One IO device in a status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct DeviceReport {
    /// NameOfStation.
    pub name: String,
    /// Where it is in its life.
    pub state: DeviceState,
}

/// What arrived at the network interface, as the cycle thread counted it.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct NetworkReport {
    /// Cyclic frames taken into the image.
    pub cyclic_frames: u64,
    /// Frames too short or malformed for what they claimed to be (dropped).
    pub malformed: u64,
    /// Frames with a FrameID no AR uses, from a foreign MAC, or not PROFINET (dropped).
    pub unknown: u64,
    /// Cyclic frames with an old CycleCounter (dropped).
    pub stale: u64,
    /// Frames dropped for lack of buffer or queue space.
    pub dropped: u64,
    /// Frames the interface refused to send.
    pub send_errors: u64,
    /// Consumer watchdog expiries (devices lost).
    pub watchdog_expiries: u64,
    /// UDP datagrams on port 34964 that were not a well-formed RPC PDU (dropped).
    #[serde(default)]
    pub malformed_datagrams: u64,
    /// Well-formed RPC datagrams no call or AR was waiting for (dropped).
    #[serde(default)]
    pub unexpected_datagrams: u64,
}

/// The server's state, as `procimg status` shows it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StatusReport {
    /// Instance name.
    pub instance: String,
    /// The server's PROFINET role: `"controller"` or `"device"`.
    #[serde(default = "controller_role")]
    pub role: String,
    /// In the device role: the station and its AR.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub station: Option<StationReport>,
    /// Server process id.
    pub pid: u32,
    /// Server generation (in JSON a hex string: see [`hex_id`]).
    #[serde(with = "hex_id")]
    pub generation: u64,
    /// Layout hash (in JSON a hex string: see [`hex_id`]).
    #[serde(with = "hex_id")]
    pub layout_hash: u64,
    /// Current mode.
    pub mode: Mode,
    /// Cycle time in ns.
    pub cycle_ns: u64,
    /// OPDONE deadline in ns after the cycle start.
    pub opdone_deadline_ns: u64,
    /// Cycles run since the server started.
    pub cycle_count: u64,
    /// Cycles whose work did not finish within the cycle time (their successors were skipped).
    pub overruns: u64,
    /// OPFAULTs given to all clients.
    pub opfaults: u64,
    /// Whether the cycle thread runs with real-time scheduling.
    pub realtime: bool,
    /// Calls of the system allocator made by the cycle thread in its cycles: the figure that
    /// must stay 0.
    pub rt_heap_allocations: u64,
    /// Calls of the system allocator made by the cycle thread while it set up or tore down
    /// a client's shared-memory connection, outside the cycle (iceoryx2 allocates there; a
    /// few hundred per client attach are normal).
    #[serde(default)]
    pub rt_setup_allocations: u64,
    /// Receives of client outputs that failed (a dead client's connection being removed).
    #[serde(default)]
    pub receive_errors: u64,
    /// Cycles without an input image: every image slot was held (readers keep old images),
    /// so nobody got STARTOP. Must stay 0.
    #[serde(default)]
    pub unpublished_images: u64,
    /// Output writes dropped because the sender did not hold the claim.
    #[serde(default)]
    pub rejected_writes: u64,
    /// Wake-up latency of the cycle thread (actual minus planned cycle start).
    pub wakeup_latency: Percentiles,
    /// STARTOP → OPDONE round trip of synchronous clients.
    pub handshake_round_trip: Percentiles,
    /// OPDONE sent by a client → received by the cycle thread (one way).
    #[serde(default)]
    pub opdone_one_way: Percentiles,
    /// Time from cycle start until the outputs are sent.
    pub cycle_work: Percentiles,
    /// Attached clients.
    pub clients: Vec<ClientReport>,
    /// The IO devices, in configuration order.
    #[serde(default)]
    pub devices: Vec<DeviceReport>,
    /// Network interface counters.
    #[serde(default)]
    pub network: NetworkReport,
    /// Announced notification subscribers.
    #[serde(default)]
    pub subscribers: Vec<SubscriberReport>,
    /// Forced bytes, one entry per run of consecutive forced addresses.
    #[serde(default)]
    pub forces: Vec<ForceReport>,
}

fn controller_role() -> String {
    String::from("controller")
}

/// A change of the station's diagnosis (device role): on one submodule, by API, slot and
/// subslot.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "op", rename_all = "snake_case")]
pub enum StationDiagnosisChange {
    /// An entry appears (or an entry of the same channel and error changes its severity).
    Add {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
        /// The entry.
        entry: DiagnosisEntry,
    },
    /// The entry of the same channel and error (or USI) disappears.
    Remove {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
        /// The entry (its channel, direction, accumulative flag and errors, or its USI).
        entry: DiagnosisEntry,
    },
    /// Every entry of the submodule disappears.
    Clear {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
    },
}

/// The format of a diagnosis entry.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DiagnosisKind {
    /// Channel diagnosis (USI 0x8000).
    #[default]
    Channel,
    /// Extended channel diagnosis (USI 0x8002).
    Extended,
    /// Qualified channel diagnosis (USI 0x8003).
    Qualified,
    /// Manufacturer-specific diagnosis: a USI 0x0000–0x7FFF and its data.
    Manufacturer,
}

/// ChannelProperties.Direction of a channel diagnosis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DiagnosisDirection {
    /// Manufacturer specific (the default).
    #[default]
    Manufacturer,
    /// An input channel.
    Input,
    /// An output channel.
    Output,
    /// An input/output channel.
    InputOutput,
}

/// How severe a channel diagnosis is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DiagnosisSeverity {
    /// A fault (the station problem indicator goes on).
    #[default]
    Fault,
    /// Maintenance required.
    MaintenanceRequired,
    /// Maintenance demanded.
    MaintenanceDemanded,
}

/// One diagnosis entry as a client gives it. Fields that do not apply to its `kind` are
/// left at their defaults.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct DiagnosisEntry {
    /// Its format.
    pub kind: DiagnosisKind,
    /// ChannelNumber: 0 to 0x7FFF, or 0x8000 (the default) for the whole submodule.
    pub channel: u16,
    /// ChannelErrorType (e.g. 1 short circuit, 6 wire break).
    pub error_type: u16,
    /// ExtChannelErrorType (extended and qualified).
    pub ext_error_type: u16,
    /// ExtChannelAddValue (extended and qualified).
    pub ext_add_value: u32,
    /// QualifiedChannelQualifier (qualified): one of bits 3 to 31.
    pub qualifier: u32,
    /// The channel's direction.
    pub direction: DiagnosisDirection,
    /// Fault or maintenance (channel and extended).
    pub severity: DiagnosisSeverity,
    /// ChannelProperties.Type: the channel's data width (0 for the whole submodule).
    pub data_type: u8,
    /// ChannelProperties.Accumulative: a group message for several channels.
    pub accumulative: bool,
    /// UserStructureIdentifier of a manufacturer entry, 0 to 0x7FFF.
    pub usi: u16,
    /// The data of a manufacturer entry.
    pub data: Vec<u8>,
}

impl Default for DiagnosisEntry {
    fn default() -> Self {
        DiagnosisEntry {
            kind: DiagnosisKind::Channel,
            channel: 0x8000,
            error_type: 0,
            ext_error_type: 0,
            ext_add_value: 0,
            qualifier: 0,
            direction: DiagnosisDirection::Manufacturer,
            severity: DiagnosisSeverity::Fault,
            data_type: 0,
            accumulative: false,
            usi: 0,
            data: Vec::new(),
        }
    }
}

/// The station of a server in the IO device role, for the status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct StationReport {
    /// NameOfStation now.
    pub name: String,
    /// The station's MAC address (the interface's).
    #[serde(default)]
    pub mac: String,
    /// IPv4 address now (`0.0.0.0`: none).
    pub ip: String,
    /// VendorID.
    pub vendor_id: u16,
    /// DeviceID.
    pub device_id: u16,
    /// The AR with a PLC, if there is one.
    pub ar: Option<ArReport>,
    /// ARs that ended other than by the PLC's Release.
    pub aborted_ars: u64,
    /// AlarmAcks the PLCs sent for the station's alarms.
    #[serde(default)]
    pub alarms_acknowledged: u64,
    /// Why the last one ended so.
    #[serde(default)]
    pub last_abort: Option<String>,
}

/// An AR of the device role, for the status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ArReport {
    /// Where it stands.
    pub state: ArState,
    /// The ARUUID.
    pub ar_uuid: String,
    /// The PLC's MAC address.
    pub controller_mac: String,
    /// Whether the PLC's provider is in RUN (its output frames' DataStatus); none before its
    /// first frame.
    #[serde(default)]
    pub plc_running: Option<bool>,
}

/// A run of forced bytes in a status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ForceReport {
    /// I or Q.
    pub space: Space,
    /// First logical address.
    pub address: u32,
    /// The forced values.
    pub data: Vec<u8>,
    /// Station name of the submodule's device.
    pub device: String,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
}

impl StatusReport {
    /// The forces that cover any of `length` bytes from `address` in `space`.
    pub fn forces_in(
        &self,
        space: Space,
        address: u32,
        length: u32,
    ) -> impl Iterator<Item = &ForceReport> {
        let end = address.saturating_add(length);
        self.forces.iter().filter(move |f| {
            f.space == space
                && f.address < end
                && address < f.address.saturating_add(f.data.len() as u32)
        })
    }
}

/// Serde for 64-bit identifiers (generation, layout hash) as 16 hex digits: JSON numbers
/// above 2^53 lose their low bits in JavaScript and jq. Numbers are still read, for
/// messages from older servers.
pub mod hex_id {
    use alloc::format;
    use alloc::string::String;
    use serde::{Deserialize, Deserializer, Serializer};

    /// Writes `v` as 16 lowercase hex digits.
    pub fn serialize<S: Serializer>(v: &u64, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&format!("{v:016x}"))
    }

    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Either {
        Hex(String),
        Number(u64),
    }

    /// Reads hex digits (with or without `0x`) or a number.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
        match Either::deserialize(d)? {
            Either::Number(n) => Ok(n),
            Either::Hex(h) => {
                let digits = h.strip_prefix("0x").unwrap_or(&h);
                u64::from_str_radix(digits, 16)
                    .map_err(|e| serde::de::Error::custom(format!("{h:?} is not hex: {e}")))
            }
        }
    }
}

/// One announced notification subscriber in a status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SubscriberReport {
    /// Name it announced.
    pub name: String,
    /// Process id.
    pub pid: u32,
    /// Whether alarms wait for its acknowledgement.
    pub acknowledges_alarms: bool,
    /// Alarms waiting for its acknowledgement now.
    pub alarms_waiting: u32,
}

/// Encodes a message for the control service.
pub fn encode<T: Serialize>(message: &T) -> Vec<u8> {
    // Serialising these plain types into a Vec cannot fail.
    serde_json::to_vec(message).unwrap_or_default()
}

/// Decodes a message from the control service.
pub fn decode<'a, T: Deserialize<'a>>(bytes: &'a [u8]) -> Result<T, String> {
    serde_json::from_slice(bytes).map_err(|e| format!("{e}"))
}

/// The iceoryx2 file prefix of every procimg service, so its files in `/dev/shm` and
/// iceoryx2's directory are recognisable (`procimg_…`) and apart from other iceoryx2 users.
pub const IOX2_PREFIX: &str = "procimg_";
