// SPDX-License-Identifier: MIT OR Apache-2.0
//! The requests only a server in the IO device role answers: the station's services (its
//! diagnosis, alarms, plugging, records, AR and DCP checks, ApplicationReady).

use crate::diagnosis::StationDiagnosisChange;
use serde::{Deserialize, Serialize};

/// An alarm a client of the device role sends ([`DeviceRequest::StationAlarm`]).
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

/// Who answers the PLC's reads and writes of a defined submodule's records
/// ([`StationTreeEntry::records`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TreeRecords {
    /// The station: the parameter records the GSDML file gives, "invalid index" for others.
    #[default]
    Station,
    /// The program (as after `StationOwnRecords` with `im` false): indices 0x0000–0x7FFF
    /// come to it as jobs from the station's first moment on the wire.
    Program,
    /// The program, with the submodule's I&M records (0xAFF0–0xAFF4) too.
    ProgramWithIm,
}

/// One submodule of a station its program defines ([`DeviceRequest::StationDefine`]): where,
/// and which module and submodule by ident number; the station's GSDML file gives the rest.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct StationTreeEntry {
    /// API.
    pub api: u32,
    /// Slot, 1 and up.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// ModuleIdentNumber.
    pub module_ident: u32,
    /// SubmoduleIdentNumber.
    pub submodule_ident: u32,
    /// Who answers its records. Given with the tree, so that a PLC that connects at once
    /// already finds them taken.
    #[serde(default)]
    pub records: TreeRecords,
}

/// What a station's program says of the station's identity with its tree
/// ([`DeviceRequest::StationDefine`]): each part given replaces the configuration's, as a
/// GS20-PN host's network configuration and serial number make its module's. What is not
/// given stays as configured.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct DefinedIdentity {
    /// NameOfStation.
    pub name: Option<String>,
    /// The IP suite: address, netmask, gateway (`0.0.0.0`: none). `Some` with address
    /// `0.0.0.0`: no address of its own, the PLC assigns one by DCP.
    pub ip: Option<[[u8; 4]; 3]>,
    /// The serial number (I&M0), at most 16 characters.
    pub serial_number: Option<String>,
}

/// A request of the IO device's station services.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "request", rename_all = "snake_case")]
pub enum DeviceRequest {
    /// In the device role: a change of the diagnosis of one of the station's submodules,
    /// which the PLC gets as a diagnosis alarm and in the diagnosis records; answered with
    /// [`Response::Done`](crate::Response::Done).
    StationDiagnosis {
        /// What changes.
        change: StationDiagnosisChange,
        /// Only the store changes (the records, the SubmoduleState, the station problem):
        /// the alarm is the client's to send ([`DeviceRequest::StationAlarm`]), as IO-Base's
        /// device interface has it.
        #[serde(default)]
        silent: bool,
    },
    /// In the device role: a process alarm (high priority) of one of the station's
    /// submodules to the PLC, with a manufacturer-specific USI and its data; answered with
    /// [`Response::Done`](crate::Response::Done) once it went out (its acknowledgement shows in the status).
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
    /// [`Response::Done`](crate::Response::Done).
    StationProblem {
        /// A problem (`true`) or none.
        problem: bool,
    },
    /// In the device role: an alarm of one of the station's submodules, of the client's
    /// making, to the PLC's AR in data exchange; answered with [`Response::Done`](crate::Response::Done) once it
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
    /// and GS20-PN's add item). Answered with [`Response::Done`](crate::Response::Done); to a PLC's AR in data
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
    /// which gets a Pull alarm. Answered with [`Response::Done`](crate::Response::Done).
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
    /// PLC's AR in data exchange. Answered with [`Response::Done`](crate::Response::Done).
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
    /// each to be answered with [`DeviceRequest::StationRecordAnswer`] within
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
        /// With them its PROFIenergy record (0x80A0), which procimgd answers otherwise as
        /// a station without energy-saving modes.
        #[serde(default)]
        pe: bool,
    },
    /// In the device role: check every new AR (`check`), or stop. The PLC's Connect then
    /// waits for this subscriber's [`DeviceRequest::StationArCheckAnswer`] to a
    /// [`Notification::StationArCheck`](crate::services::Notification::StationArCheck), at
    /// most [`AR_CHECK_TIMEOUT_MS`](crate::services::AR_CHECK_TIMEOUT_MS), after which the AR
    /// is accepted. One subscriber at a time checks.
    StationCheckArs {
        /// The subscriber's id.
        subscriber: u64,
        /// Check (`true`) or stop.
        check: bool,
    },
    /// In the device role, a station whose configuration names its GSDML file and no
    /// submodules: the subscriber's program defines the station's tree (every submodule
    /// after the device access point). Checked against the GSDML file; once accepted the
    /// station runs anew with the tree (a new generation and layout, which clients follow)
    /// and goes on the wire. Refused while an AR runs, when another program defined the
    /// station, and for a configured station.
    StationDefine {
        /// The subscriber's id: the station's program from now on.
        subscriber: u64,
        /// The submodules after the device access point.
        tree: Vec<StationTreeEntry>,
        /// The station's name, address and serial number, where the program gives them.
        #[serde(default)]
        identity: DefinedIdentity,
    },
    /// In the device role: whether the station's GSDML file allows `tree`, checked as
    /// [`DeviceRequest::StationDefine`] checks it, without defining anything (a program
    /// checks each plug when it is made). Answered with
    /// [`Response::Done`](crate::Response::Done), or refused naming what is wrong.
    StationCheckTree {
        /// The submodules after the device access point.
        tree: Vec<StationTreeEntry>,
    },
    /// In the device role: the station's program ends (IO-Base's `PNIO_device_close`): its
    /// AR ends with an abort and the station waits, off the wire, for a program to define it
    /// again. The same happens when the program's process is gone.
    StationRelease {
        /// The subscriber's id (the one that defined the station).
        subscriber: u64,
    },
    /// In the device role: end the AR `ar_uuid` from the station's side (an ERR-RTA with
    /// AbortRequest, IO-Base's `PNIO_device_ar_abort`); the station stays on the wire and
    /// takes the PLC's next Connect. Refused with [`Refusal::ArGone`](crate::Refusal::ArGone)
    /// when `ar_uuid` is not the current AR.
    StationAbortAr {
        /// The ARUUID, as the notifications write it.
        ar_uuid: String,
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
    /// [`DeviceRequest::StationDcpSetAnswer`] to a
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
    /// this subscriber says its parameters are applied ([`DeviceRequest::StationApplicationReady`]),
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
}

impl DeviceRequest {
    /// What it asks for, in words, for a refusal by a server in another role.
    pub const fn service(&self) -> &'static str {
        "the IO device's station services (its records, ApplicationReady, diagnosis and alarms)"
    }
}
