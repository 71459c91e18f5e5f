// SPDX-License-Identifier: MIT OR Apache-2.0
//! The services clients use besides the process image: of an IO controller, record
//! read/write jobs, device activation, alarms with acknowledgement, device events and
//! diagnosis; of an IO device (`role = "device"`), the station's events (its AR, the PLC's
//! RUN/STOP, DCP).
//!
//! Requests go over the control service (see [`crate::Request`]); what happens later
//! arrives on the notification service `procimg/<instance>/notifications`, one JSON
//! [`Notification`] per sample, with a wake-up on the event service
//! `procimg/<instance>/notify-events`. Alarms, device and station events go to every subscriber;
//! confirmations carry the `reply_to` of the subscriber that asked, so every subscriber sees
//! only its own. Both services outlive a server restart, like the control service: a
//! subscriber keeps its ports and learns of the new server from [`Notification::ServerStarted`].

use crate::states::{ArState, DeviceState};
use serde::{Deserialize, Serialize};

/// The notification publish-subscribe service of an instance.
pub fn notification_service(instance: &str) -> String {
    format!("procimg/{instance}/notifications")
}

/// The event service that wakes subscribers when notifications were published.
pub fn notify_event_service(instance: &str) -> String {
    format!("procimg/{instance}/notify-events")
}

/// Event id on the notify-event service: notifications are waiting.
pub const EVENT_NOTIFICATIONS: usize = 1;

/// Notifications a subscriber buffers; older ones are lost when it falls further behind
/// (the subscriber counts them).
pub const NOTIFICATION_BUFFER: usize = 256;

/// Record jobs one subscriber may have open at a time (IO-Base's PN Driver allows 16).
pub const MAX_RECORD_JOBS: usize = 16;

/// Largest record a job reads or writes (IO-Base's `PNIO_MAX_REC_LEN`).
pub const MAX_RECORD_LEN: u32 = 4096;

/// How long a restart ([`crate::CoreRequest::Restart`]) waits for the programs it asked to
/// stop to detach.
pub const RESTART_WAIT_MS: u64 = 10_000;

/// How long the server waits for the acknowledging subscribers of an alarm before it
/// acknowledges the alarm to the device itself.
pub const ALARM_ACK_TIMEOUT_MS: u64 = 5000;

/// A PNIOStatus with its additional values, as a record job ends (IO-Base `PNIO_ERR_STAT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct RecordStatus {
    /// ErrorCode (0 = OK; 0xDE read error, 0xDF write error, 0xC0 no connection).
    pub error_code: u8,
    /// ErrorDecode (0x80 PNIORW, 0x81 PNIO).
    pub error_decode: u8,
    /// ErrorCode1.
    pub error_code1: u8,
    /// ErrorCode2.
    pub error_code2: u8,
    /// AdditionalValue1 (for a read that succeeded, 1 means the record holds more data).
    pub add_value1: u16,
    /// AdditionalValue2.
    pub add_value2: u16,
}

impl RecordStatus {
    /// The job succeeded.
    pub const OK: RecordStatus = RecordStatus {
        error_code: 0,
        error_decode: 0,
        error_code1: 0,
        error_code2: 0,
        add_value1: 0,
        add_value2: 0,
    };

    /// There is no connection to the device, or it broke during the job: the status IO-Base
    /// reports then (0xC0, 0x80, 0xA3, 0).
    pub const NO_CONNECTION: RecordStatus = RecordStatus {
        error_code: 0xC0,
        error_decode: 0x80,
        error_code1: 0xA3,
        error_code2: 0,
        add_value1: 0,
        add_value2: 0,
    };

    /// Whether the job succeeded.
    pub const fn is_ok(&self) -> bool {
        self.error_code == 0
    }
}

/// Where a record lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RecordTarget {
    /// Device index (in the layout's device table).
    pub device: u32,
    /// API (0 for most devices).
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// Record index (0xAFF0 is I&M0).
    pub index: u16,
}

/// The end of a record read or write.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RecordConfirmation {
    /// The reference the requester gave.
    pub reference: u64,
    /// The record.
    pub target: RecordTarget,
    /// A write (`true`) or a read.
    pub write: bool,
    /// The outcome.
    pub status: RecordStatus,
    /// The record read (empty for writes and failures).
    #[serde(default)]
    pub data: Vec<u8>,
    /// Why it failed, in words (empty when it succeeded).
    #[serde(default)]
    pub message: String,
}

/// An alarm a device sent (IO-Base `PNIO_CBE_ALARM_IND`). Every subscriber gets it; the
/// server waits with the AlarmAck to the device for the subscribers that announced
/// themselves with `acknowledge_alarms` when the alarm arrived.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct AlarmReport {
    /// Identifies the alarm in [`crate::ControllerRequest::AcknowledgeAlarm`].
    pub id: u64,
    /// Device index.
    pub device: u32,
    /// Station name of the device.
    pub device_name: String,
    /// High (`true`) or low priority.
    pub high_priority: bool,
    /// AlarmType (1 diagnosis, 2 process, 3 pull, 4 plug, …).
    pub alarm_type: u16,
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// ModuleIdentNumber.
    pub module_ident: u32,
    /// SubmoduleIdentNumber.
    pub submodule_ident: u32,
    /// AlarmSpecifier as sent.
    pub specifier: u16,
    /// The bytes after the AlarmSpecifier: UserStructureIdentifier and its data, if any.
    #[serde(default)]
    pub payload: Vec<u8>,
    /// The alarm in words, for logs.
    pub text: String,
}

impl AlarmReport {
    /// The UserStructureIdentifier of the payload, if there is one.
    pub fn usi(&self) -> Option<u16> {
        match self.payload.as_slice() {
            [a, b, ..] => Some(u16::from_be_bytes([*a, *b])),
            _ => None,
        }
    }
}

/// What the server tells subscribers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "notification", rename_all = "snake_case")]
pub enum Notification {
    /// A server (re)started: announce again (its predecessor's subscriptions, jobs and
    /// alarms are gone).
    ServerStarted {
        /// Its generation (in JSON a hex string).
        #[serde(with = "crate::hex_id")]
        generation: u64,
    },
    /// A device's state changed (see [`crate::DeviceReport::state`]).
    DeviceState {
        /// Device index.
        device: u32,
        /// Station name.
        name: String,
        /// The new state.
        state: DeviceState,
    },
    /// A device in data exchange failed; its inputs are BAD (IO-Base `PNIO_ALARM_DEV_FAILURE`).
    DeviceFailure {
        /// Device index.
        device: u32,
        /// Station name.
        name: String,
        /// Why.
        reason: String,
    },
    /// A failed device is back in data exchange (IO-Base `PNIO_ALARM_DEV_RETURN`).
    DeviceReturn {
        /// Device index.
        device: u32,
        /// Station name.
        name: String,
    },
    /// A device's real modules differ from the configuration (its ModuleDiffBlock).
    ModuleDiff {
        /// Device index.
        device: u32,
        /// Station name.
        name: String,
        /// The submodules that differ.
        submodules: Vec<SubmoduleDiff>,
    },
    /// An alarm.
    Alarm(AlarmReport),
    /// A record job of `reply_to` ended.
    Record {
        /// The subscriber that asked.
        reply_to: u64,
        /// The outcome.
        confirmation: RecordConfirmation,
    },
    /// An activation or deactivation of `reply_to` was carried out (IO-Base
    /// `PNIO_CBE_DEV_ACT_CONF`); the state change itself follows as device events.
    Activation {
        /// The subscriber that asked.
        reply_to: u64,
        /// Device index.
        device: u32,
        /// Activated (`true`) or deactivated.
        active: bool,
        /// Whether the device took it.
        ok: bool,
    },
    /// A reconfiguration of the IO system of `reply_to` was done or refused (IO-Base
    /// `PNIO_CBE_IOSYSTEM_RECONFIG`); the devices' state changes follow as device events.
    Reconfigured {
        /// The subscriber that asked.
        reply_to: u64,
        /// Tailored: the devices wanted are activated (`true`); or every device is
        /// deactivated (`false`).
        active: bool,
        /// Why it was refused, changing nothing; `None`: done.
        refused: Option<TailoringRefusal>,
    },
    /// The server is to restart (a configuration download, a reset): every program attached
    /// is asked to stop, to close its controller or device (IO-Base's CP_STOP_REQ). The
    /// restart waits for them up to [`RESTART_WAIT_MS`].
    StopRequest {
        /// Why, in words.
        reason: String,
    },
    /// A [`crate::CoreRequest::Restart`] of `reply_to` takes effect now (a
    /// [`Notification::ServerStarted`] follows when the new server runs), or was given up.
    Restart {
        /// The subscriber that asked.
        reply_to: u64,
        /// It takes effect.
        done: bool,
        /// What happens, or why not.
        message: String,
    },
    /// Controller role: a PROFIenergy command of `reply_to` ended
    /// ([`crate::ControllerRequest::PeCommand`]): the device's answer, or the record job's
    /// failure (no answer within [`crate::pe::PE_LIFETIME_MS`] is IO-Base's "no
    /// connection" status).
    PeConfirmation {
        /// The subscriber that asked.
        reply_to: u64,
        /// The request's reference.
        reference: u64,
        /// The submodule.
        target: RecordTarget,
        /// The command.
        command: crate::pe::PeCommand,
        /// The answer; `None` when the command could not be carried out (`status` says
        /// why).
        answer: Option<crate::pe::PeAnswer>,
        /// The record jobs' PNIO status (0: the answer came).
        status: RecordStatus,
        /// Why it failed, in words (empty when the answer came).
        #[serde(default)]
        message: String,
    },
    /// Controller role: an alarm of the controller's own interface (IO-Base
    /// `PNIO_CBE_IFC_ALARM_IND`), such as its port's PortDataChangeNotification when the
    /// neighbour or the link is not what the configuration expects, or is again. `device`
    /// is 0 and `device_name` the controller's station name; nothing acknowledges it.
    InterfaceAlarm(AlarmReport),
    /// Controller role: a read of a record of the controller's own interface of `reply_to`
    /// ended ([`crate::ControllerRequest::InterfaceRecordRead`]).
    InterfaceRecord {
        /// The subscriber that asked.
        reply_to: u64,
        /// The request's reference.
        reference: u64,
        /// The subslot read.
        subslot: u16,
        /// The record index.
        index: u16,
        /// The PNIO status (0: read).
        status: RecordStatus,
        /// The record, cut to the length asked for.
        #[serde(default)]
        data: Vec<u8>,
        /// Why it failed, in words (empty when it succeeded).
        #[serde(default)]
        message: String,
    },
    /// Controller role: the controller's own station has a new NameOfStation or IP suite,
    /// set by DCP from an engineering tool (`reply_to` `None`, to every subscriber), or a
    /// program's change of them ([`crate::ControllerRequest::SetControllerAddress`]) was
    /// made or refused (to `reply_to`).
    ControllerAddress {
        /// The subscriber that asked, if one did.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reply_to: Option<u64>,
        /// The station's name now.
        name: String,
        /// Its IP address now.
        ip: String,
        /// Its subnet mask now.
        netmask: String,
        /// Its default gateway now ("0.0.0.0": none).
        gateway: String,
        /// The change is kept across a restart.
        permanent: bool,
        /// Why the change was refused, leaving name and address as they were; `None`: done.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        refused: Option<AddressRefusal>,
    },
    /// Controller role: a DCP Signal came to the controller's own station, which is to flash
    /// its LED for three seconds (IO-Base `PNIO_CBE_START_LED_FLASH`, then
    /// `PNIO_CBE_STOP_LED_FLASH`).
    ControllerSignal,
    /// Device role: the station's AR reached a state (GOAL's and IO-Base's AR indications).
    StationAr {
        /// The state it reached. A state passed within one step of the station may not be
        /// reported on its own; [`ArState::Data`] always is.
        state: ArState,
        /// The ARUUID.
        ar_uuid: String,
        /// The PLC's MAC address.
        controller_mac: String,
        /// The PLC's NameOfStation (empty from an older server).
        #[serde(default)]
        controller_name: String,
    },
    /// Device role: the station's AR ended.
    StationArEnded {
        /// The ARUUID.
        ar_uuid: String,
        /// Why, in words: "released by the PLC", or the abort code (an IO data timeout when
        /// the PLC's frames stopped, a name change by DCP, …).
        reason: String,
        /// It was aborted (by either side), not released by the PLC.
        aborted: bool,
        /// This station ended it on purpose: procimgd stopping or going OFFLINE.
        planned: bool,
        /// The RTA abort code (ErrorCode2 of the ERR-RTA, 0x05 "consumer data hold time
        /// expired" and so on) when it was aborted; `None` when released, and from a server
        /// that does not send it.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        abort_code: Option<u8>,
    },
    /// Device role: the DataStatus of the PLC's output frames changed: RUN (`true`) or
    /// STOP, a station problem, primary or backup.
    StationPlcRunning {
        /// RUN.
        running: bool,
        /// The PLC reports a station problem (its StationProblemIndicator).
        #[serde(default)]
        station_problem: bool,
        /// The PLC's provider is the backup of a redundant pair, not the primary.
        #[serde(default)]
        backup: bool,
    },
    /// Device role: DCP Signal, an engineering tool asks the station to make itself seen
    /// (flash its LED).
    StationBlink,
    /// Device role: the neighbour on the station's port changed (GOAL's LLDP_UPDATE): one
    /// came, went (its TTL ran out, it withdrew, the link dropped) or announced something
    /// else. The port's neighbours as they are now, and the alias name they give the
    /// station.
    StationNeighbours {
        /// The port (1 for `port-001`).
        port: u8,
        /// Its neighbours, as LLDP announced them.
        neighbours: Vec<crate::NeighbourReport>,
        /// The alias name (`<peer port>.<peer station>`) DCP Identify answers to, if the
        /// port has one PROFINET neighbour.
        alias_name: Option<String>,
    },
    /// Device role: DCP set the station's name or IP suite, or reset it to factory. A new
    /// name or address ends the AR, if one is up (a [`Notification::StationArEnded`]
    /// follows).
    StationIdentity {
        /// NameOfStation (empty: none).
        name: String,
        /// IP address ("0.0.0.0": none).
        ip: String,
        /// Subnet mask.
        netmask: String,
        /// Default gateway.
        gateway: String,
        /// The change is kept across a restart (DCP's "permanent"), in the state file.
        permanent: bool,
        /// It was a reset to factory: the station has no name and no address now and
        /// keeps it so. (A permanent Set of an empty name and address 0.0.0.0 leaves the
        /// same state and is reported the same.)
        factory_reset: bool,
    },
    /// Device role: a submodule of the station was plugged or pulled (by a client's
    /// [`crate::DeviceRequest::StationPlug`] or
    /// [`crate::DeviceRequest::StationPull`]).
    StationPlug {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
        /// Plugged (`true`) or pulled.
        plugged: bool,
        /// ModuleIdentNumber of what is plugged (0 when pulled).
        module_ident: u32,
        /// SubmoduleIdentNumber of what is plugged (0 when pulled).
        submodule_ident: u32,
        /// The alarm the PLC got: "pull", "plug", "plug wrong submodule", or "" (no AR in
        /// data exchange expects a submodule there).
        alarm: String,
    },
    /// Device role: the PLC ended the parameters of a submodule plugged in data exchange
    /// (its PlugPrmEnd; IO-Base's `PNIO_CBF_PRM_END_IND` with a subslot). A subscriber that
    /// holds the ApplicationReady releases the submodule's PlugApplicationReady with
    /// [`crate::DeviceRequest::StationApplicationReady`].
    StationPlugParameterized {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
    },
    /// Device role: the PLC acknowledged the alarm `reply_to` sent with
    /// [`crate::DeviceRequest::StationAlarm`], or its AR ended first.
    StationAlarmDone {
        /// The subscriber that sent the alarm.
        reply_to: u64,
        /// The alarm's tag.
        tag: u64,
        /// The AlarmAck's PNIOStatus (ErrorCode, ErrorDecode, ErrorCode1, ErrorCode2; all
        /// zero: accepted), or none when the AR ended before the acknowledgement came.
        status: Option<[u8; 4]>,
    },
    /// Device role: the PLC reads or writes a record of a submodule whose records `reply_to`
    /// took ([`crate::DeviceRequest::StationOwnRecords`]); answer with
    /// [`crate::DeviceRequest::StationRecordAnswer`] within
    /// [`STATION_RECORD_TIMEOUT_MS`].
    StationRecord {
        /// The subscriber that took the records.
        reply_to: u64,
        /// The job.
        job: StationRecordJob,
    },
    /// Device role: a PLC connects (GOAL's NEW_AR, IO-Base's `PNIO_CBF_AR_CHECK_IND`): the
    /// subscriber that checks ARs ([`crate::DeviceRequest::StationCheckArs`]) accepts or
    /// refuses it with [`crate::DeviceRequest::StationArCheckAnswer`] within
    /// [`AR_CHECK_TIMEOUT_MS`].
    StationArCheck {
        /// The subscriber that checks.
        reply_to: u64,
        /// The new AR.
        check: StationArCheckJob,
    },
    /// Device role: a DCP Set gives the station a name or address, or resets it (GOAL's
    /// STATION_NAME_VERIFY, NET_IP_SET_VERIFY): the subscriber that checks DCP's changes
    /// ([`crate::DeviceRequest::StationVerifyDcp`]) allows or vetoes it with
    /// [`crate::DeviceRequest::StationDcpSetAnswer`] within [`DCP_SET_CHECK_TIMEOUT_MS`].
    StationDcpSetCheck {
        /// The subscriber that checks.
        reply_to: u64,
        /// The change.
        check: StationDcpSetJob,
    },
}

/// What the DataStatus of the PLC's frames says, in words: "RUN", "STOP", with ", with a
/// station problem" and ", as the backup" when they apply.
pub fn plc_state_text(running: bool, station_problem: bool, backup: bool) -> String {
    format!(
        "{}{}{}",
        if running { "RUN" } else { "STOP" },
        if station_problem {
            ", with a station problem"
        } else {
            ""
        },
        if backup { ", as the backup" } else { "" }
    )
}

impl Notification {
    /// The subscriber this notification is for, or `None` for all.
    pub fn reply_to(&self) -> Option<u64> {
        match self {
            Notification::Record { reply_to, .. }
            | Notification::Activation { reply_to, .. }
            | Notification::Reconfigured { reply_to, .. }
            | Notification::StationRecord { reply_to, .. }
            | Notification::StationAlarmDone { reply_to, .. }
            | Notification::StationArCheck { reply_to, .. }
            | Notification::StationDcpSetCheck { reply_to, .. }
            | Notification::InterfaceRecord { reply_to, .. }
            | Notification::Restart { reply_to, .. }
            | Notification::PeConfirmation { reply_to, .. } => Some(*reply_to),
            Notification::ControllerAddress { reply_to, .. } => *reply_to,
            _ => None,
        }
    }
}

/// Why a change of the controller station's name or address was refused.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct AddressRefusal {
    /// What was wrong.
    pub problem: AddressProblem,
    /// The refusal in words.
    pub message: String,
}

/// What was wrong with a change of the controller station's name or address.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AddressProblem {
    /// The configuration keeps it (`[interface] name_by_program`, `address_by_program`).
    NotAllowed,
    /// Not a NameOfStation.
    Name,
    /// Not an IP suite.
    Ip,
    /// The network interface would not take the address.
    Interface,
}

/// A port submodule of a device.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct PortRef {
    /// Device index.
    pub device: u32,
    /// Slot (0).
    pub slot: u16,
    /// Subslot (0x8001 …).
    pub subslot: u16,
}

/// Why a tailoring of the IO system was refused.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "refusal", rename_all = "snake_case")]
pub enum TailoringRefusal {
    /// The device named is not optional, or there is no such device (IO-Base
    /// `PNIO_ERR_INVALID_STATION`).
    Station {
        /// Device index.
        device: u32,
        /// What is wrong, in words.
        reason: String,
    },
    /// The port named has no programmable peer, or is joined twice (IO-Base
    /// `PNIO_ERR_INVALID_PORT`).
    Port {
        /// The port.
        port: PortRef,
        /// What is wrong, in words.
        reason: String,
    },
}

/// One submodule whose real state differs from the expected one.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SubmoduleDiff {
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// The device's SubmoduleState word.
    pub state: u16,
    /// It in words ("no submodule", "wrong submodule", "substitute", …).
    pub text: String,
}

/// What [`crate::ControllerRequest::Diagnosis`] answers: the dynamic state of the IO system;
/// the configured submodules are in the layout every client has.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct DiagnosisReport {
    /// One entry per configured device, in layout order.
    pub devices: Vec<DeviceDiagnosis>,
}

/// Why a device left data exchange or could not be brought up: the kinds of failure a
/// program tells apart (IO-Base's `PNIO_CTRL_REASON_*`); the words are in `last_error`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FailureCause {
    /// No failure (running, or never tried).
    #[default]
    None,
    /// No device of its name answered DCP Identify.
    NotFound,
    /// Giving it its IP address (DCP Set) failed, or it has none.
    IpSetFailed,
    /// It did not answer an RPC call (Connect, Write, PrmEnd, Release) in time.
    RpcTimeout,
    /// Its RPC layer refused a call, or answered with something unreadable.
    RpcError,
    /// It refused the configuration: a negative PNIO status to Connect, Write or PrmEnd.
    Refused,
    /// It sent no ApplicationReady after the parameters.
    NoApplicationReady,
    /// Its cyclic data stopped coming (the watchdog expired).
    NoCyclicData,
    /// It aborted the AR.
    DeviceAborted,
    /// The controller aborted the AR (its alarm channel failed).
    ControllerAborted,
    /// The controller released it, going OFFLINE.
    Released,
    /// A client deactivated it.
    Deactivated,
    /// The controller could not build a request for it (a configuration it cannot carry).
    Internal,
    /// A cause this program does not know (from a newer server).
    #[serde(other)]
    Unknown,
}

/// The state of one device.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct DeviceDiagnosis {
    /// Device index.
    pub device: u32,
    /// Station name.
    pub name: String,
    /// Its state.
    pub state: DeviceState,
    /// Activated (by configuration or by a client's activation).
    pub active: bool,
    /// The last failure or problem, if it is not running.
    #[serde(default)]
    pub last_error: String,
    /// What kind of failure `last_error` is, for programs ([`FailureCause::None`] while
    /// running).
    #[serde(default)]
    pub cause: FailureCause,
    /// How often it failed in data exchange since the server started.
    pub failures: u64,
    /// The submodules the device reported as different at its last connect.
    #[serde(default)]
    pub module_diff: Vec<SubmoduleDiff>,
    /// The PNIO status of the last failure (ErrorCode, ErrorDecode, ErrorCode1, ErrorCode2),
    /// when it has one: the negative Connect, Write or PrmEnd response's status of a
    /// refusal, or the ERR-RTA's `CF 81 FD <abort code>` of an AR aborted by the device or
    /// by the server. `None` while running, and for failures without a status (not found,
    /// no answer).
    #[serde(default)]
    pub pnio_status: Option<[u8; 4]>,
}

/// How long the station waits for a subscriber's answer to a record job before it answers
/// the PLC itself with PNIORW "resource busy" (0xC2): a PLC repeats its call after about a
/// second and gives up after a few.
pub const STATION_RECORD_TIMEOUT_MS: u64 = 2000;

/// How long a PLC's Connect waits for the checking subscriber's answer before the station
/// accepts the AR.
pub const AR_CHECK_TIMEOUT_MS: u64 = 2000;

/// How long a DCP Set of the station waits for the checking subscriber's verdict before it
/// is carried out: a DCP client waits about a second for its response.
pub const DCP_SET_CHECK_TIMEOUT_MS: u64 = 500;

/// A DCP Set of the station's name or address, for the subscriber that checks them.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct StationDcpSetJob {
    /// The check, named in the answer.
    pub job: u64,
    /// The DCP client's MAC address.
    pub from: String,
    /// The new NameOfStation, if the Set gives one.
    #[serde(default)]
    pub name: Option<String>,
    /// The new IP address, subnet mask and gateway, if the Set gives them.
    #[serde(default)]
    pub ip_suite: Option<[String; 3]>,
    /// To be kept across a restart.
    pub permanent: bool,
    /// A reset to factory (no name, no address).
    pub reset: bool,
}

/// A new AR for the subscriber that checks ARs.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct StationArCheckJob {
    /// The check, named in the answer.
    pub job: u64,
    /// ARUUID.
    pub ar_uuid: String,
    /// ARType (1: IO controller AR).
    pub ar_type: u16,
    /// SessionKey.
    pub session_key: u16,
    /// The PLC's MAC address.
    pub controller_mac: String,
    /// The PLC's station name.
    pub controller_name: String,
    /// The PLC's IP address, where its Connect came from ("0.0.0.0" from an older server).
    #[serde(default = "no_ip")]
    pub controller_ip: String,
    /// ARProperties of the Connect (0 from an older server).
    #[serde(default)]
    pub ar_properties: u32,
    /// CMInitiatorObjectUUID of the Connect (empty from an older server).
    #[serde(default)]
    pub cmi_object_uuid: String,
    /// Every submodule the PLC expects, with what is plugged there (GOAL's EXP_SUBMOD).
    pub expected: Vec<ExpectedSubmodule>,
    /// The AR's IO CRs, input CR first (none from an older server).
    #[serde(default)]
    pub crs: Vec<ArCr>,
}

/// An IO CR of a new AR, as IO-Base's `PNIO_IOCR_TYPE` gives it to the program: the
/// IOCRBlockReq's values, with the FrameID the station's frames use.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ArCr {
    /// Input CR (the PLC's I data), else output CR (its Q data).
    pub input: bool,
    /// IOCRProperties' RTClass: 1, 2 (RT), 3 (IRT), 4 (UDP).
    pub rt_class: u8,
    /// FrameID.
    pub frame_id: u16,
    /// SendClockFactor, in 31.25 µs.
    pub send_clock_factor: u16,
    /// ReductionRatio.
    pub reduction_ratio: u16,
    /// Phase.
    pub phase: u16,
    /// DataHoldFactor.
    pub data_hold_factor: u16,
    /// DataLength (C_SDU bytes).
    pub data_length: u16,
    /// The IODataObjects, in the Connect's order.
    pub data_objects: Vec<CrDataObject>,
}

/// Where a submodule's data object sits in the frames of an IO CR.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CrDataObject {
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// Its first byte in the C_SDU.
    pub frame_offset: u16,
}

impl ArCr {
    /// The period of its frames in µs: SendClockFactor × 31.25 µs × ReductionRatio.
    pub fn period_us(&self) -> f64 {
        f64::from(self.send_clock_factor) * 31.25 * f64::from(self.reduction_ratio)
    }
}

/// No IP address, as an older server leaves it.
fn no_ip() -> String {
    "0.0.0.0".to_owned()
}

/// A submodule the PLC expects in a new AR.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ExpectedSubmodule {
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// The expected ModuleIdentNumber.
    pub module_ident: u32,
    /// The expected SubmoduleIdentNumber.
    pub submodule_ident: u32,
    /// Expected input bytes.
    pub input_length: u16,
    /// Expected output bytes.
    pub output_length: u16,
    /// The (module, submodule) ident numbers plugged there, if anything is.
    #[serde(default)]
    pub plugged: Option<(u32, u32)>,
}

/// The longest the subscribers may hold the ApplicationReady after a PrmEnd.
pub const APP_READY_HOLD_TIMEOUT_MS: u64 = 10_000;

/// A record of the station that the PLC reads or writes, for the subscriber that took the
/// submodule's records (GOAL's record callbacks, IO-Base's `PNIO_CBF_REC_READ/WRITE`).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct StationRecordJob {
    /// The job, named in the answer.
    pub job: u64,
    /// A write (`true`) or a read.
    pub write: bool,
    /// The AR it came in (all zeros: an implicit read outside any AR).
    pub ar_uuid: String,
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// Record index.
    pub index: u16,
    /// What the PLC wrote (empty for a read).
    #[serde(default)]
    pub data: Vec<u8>,
    /// For a read, the most bytes the PLC takes.
    #[serde(default)]
    pub max_len: u32,
}

#[cfg(test)]
mod tests {

    #[test]
    fn the_plcs_state_in_words() {
        assert_eq!(plc_state_text(true, false, false), "RUN");
        assert_eq!(
            plc_state_text(false, true, true),
            "STOP, with a station problem, as the backup"
        );
    }
    use super::*;
    use crate::{decode, encode};

    #[test]
    fn station_notifications_go_to_everyone_under_their_snake_case_names() {
        let all = vec![
            (
                Notification::StationAr {
                    state: ArState::Data,
                    ar_uuid: "0f2c0a43-1b53-4a8f-9e57-8c4bd8b1f7a2".into(),
                    controller_mac: "02:50:49:fe:00:01".into(),
                    controller_name: "plc-1".into(),
                },
                "station_ar",
            ),
            (
                Notification::StationArEnded {
                    ar_uuid: "0f2c0a43-1b53-4a8f-9e57-8c4bd8b1f7a2".into(),
                    reason: "released by the PLC".into(),
                    aborted: false,
                    planned: false,
                    abort_code: None,
                },
                "station_ar_ended",
            ),
            (
                Notification::StationPlcRunning {
                    running: false,
                    station_problem: false,
                    backup: false,
                },
                "station_plc_running",
            ),
            (Notification::StationBlink, "station_blink"),
            (
                Notification::StationNeighbours {
                    port: 1,
                    neighbours: Vec::new(),
                    alias_name: None,
                },
                "station_neighbours",
            ),
            (
                Notification::StationIdentity {
                    name: "pc-device".into(),
                    ip: "10.47.0.50".into(),
                    netmask: "255.255.255.0".into(),
                    gateway: "0.0.0.0".into(),
                    permanent: true,
                    factory_reset: false,
                },
                "station_identity",
            ),
        ];
        for (n, tag) in all {
            let bytes = encode(&n);
            let text = core::str::from_utf8(&bytes).unwrap().to_string();
            assert!(
                text.contains(&format!("\"notification\":\"{tag}\"")),
                "{text}"
            );
            assert_eq!(decode::<Notification>(&bytes).unwrap(), n);
            assert_eq!(n.reply_to(), None);
        }
    }
}
