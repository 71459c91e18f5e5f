// SPDX-License-Identifier: MIT OR Apache-2.0
//! A device program's say in the PLC's AR, through its [`Services`] handle (GOAL's NEW_AR,
//! record and END_OF_PARAM callbacks, IO-Base's `PNIO_CBF_AR_CHECK_IND`,
//! `PNIO_CBF_REC_READ/WRITE`, `PNIO_CBF_PRM_END_IND` and `PNIO_set_appl_state_ready`): it may
//! check new ARs ([`Notification::StationArCheck`](crate::Notification::StationArCheck)),
//! the records of the submodules it takes come to it as
//! [`Notification::StationRecord`](crate::Notification::StationRecord) jobs, and it may hold
//! the station's ApplicationReady until its parameters are applied.
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use procimg_client::{Notification, RecordRefusal, ServiceOptions, Services};
//! use std::time::Duration;
//! let mut services = Services::open("procimg", ServiceOptions::new("params"))?;
//! services.take_records((0, 1, 1))?;
//! while let Some(n) = services.next(Duration::from_secs(1)) {
//!     if let Notification::StationRecord { job, .. } = n {
//!         let answer = match (job.write, job.index, job.data.len()) {
//!             (true, 1, 4) => Ok(&[][..]),
//!             (true, 1, _) => Err(RecordRefusal::new(RecordRefusal::WRITE_LENGTH_ERROR)),
//!             _ => Err(RecordRefusal::new(RecordRefusal::INVALID_INDEX)),
//!         };
//!         services.answer_record(&job, answer)?;
//!     }
//! }
//! # Ok(()) }
//! ```

use crate::services::Services;
use crate::{ControlError, DEFAULT_CONTROL_TIMEOUT};
use procimg_control::services::{StationArCheckJob, StationDcpSetJob, StationRecordJob};
use procimg_control::{DefinedIdentity, DeviceRequest, Refusal, Response, StationTreeEntry};

/// The Connect error (ErrorCode1 CMRPC, ErrorCode2 "out of AR resources") a device gives
/// when it cannot take an AR now.
pub const AR_REFUSED_NO_RESOURCES: (u8, u8) = (0x40, 0x04);

/// The PNIORW error a record job ends with instead of data: ErrorCode1 (class and code) and
/// ErrorCode2 (user specific).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RecordRefusal {
    /// ErrorCode1.
    pub code1: u8,
    /// ErrorCode2.
    pub code2: u8,
}

impl RecordRefusal {
    /// Application: read error.
    pub const READ_ERROR: u8 = 0xa0;
    /// Application: write error.
    pub const WRITE_ERROR: u8 = 0xa1;
    /// Application: busy.
    pub const BUSY: u8 = 0xa7;
    /// Access: invalid index.
    pub const INVALID_INDEX: u8 = 0xb0;
    /// Access: write length error.
    pub const WRITE_LENGTH_ERROR: u8 = 0xb1;
    /// Access: state conflict.
    pub const STATE_CONFLICT: u8 = 0xb5;
    /// Access: access denied.
    pub const ACCESS_DENIED: u8 = 0xb6;
    /// Access: invalid range.
    pub const INVALID_RANGE: u8 = 0xb7;
    /// Access: invalid parameter.
    pub const INVALID_PARAMETER: u8 = 0xb8;
    /// Resource: resource busy.
    pub const RESOURCE_BUSY: u8 = 0xc2;

    /// The error `code1` with ErrorCode2 0.
    pub const fn new(code1: u8) -> RecordRefusal {
        RecordRefusal { code1, code2: 0 }
    }
}

impl Services {
    /// Sends `req`, which is answered with Done.
    pub(crate) fn station_request(&self, req: DeviceRequest) -> Result<(), ControlError> {
        let mut response = self
            .control()
            .request(req.clone(), DEFAULT_CONTROL_TIMEOUT)?;
        // A server that started since this handle last looked (a restart, a station its
        // program defined anew) does not know it yet: announce it, then ask again.
        if response == Response::Refused(Refusal::UnknownSubscriber) && self.announce().is_ok() {
            response = self.control().request(req, DEFAULT_CONTROL_TIMEOUT)?;
        }
        match response {
            Response::Done | Response::Accepted => Ok(()),
            Response::Refused(r) => Err(ControlError::Refused(r)),
            other => Err(ControlError::Protocol {
                instance: self.control().instance().to_string(),
                detail: format!("{other:?}"),
            }),
        }
    }

    /// Takes the user records (indices 0x0000–0x7FFF) of the station's submodule
    /// (`api`, `slot`, `subslot`): the PLC's reads and writes of them come to this handle as
    /// [`Notification::StationRecord`](crate::Notification::StationRecord) jobs, to be
    /// answered with [`answer_record`](Self::answer_record) within
    /// [`STATION_RECORD_TIMEOUT_MS`](crate::STATION_RECORD_TIMEOUT_MS). Refused when another
    /// handle took them.
    pub fn take_records(&self, at: (u32, u16, u16)) -> Result<(), ControlError> {
        self.own_records(at, true, false, false)
    }

    /// [`take_records`](Self::take_records), and the submodule's I&M0–I&M4 records
    /// (0xAFF0–0xAFF4) with them: reads and writes of those come as jobs too, which the
    /// handle answers with the whole record (BlockHeader included; a refused write with
    /// [`RecordRefusal::ACCESS_DENIED`] for I&M0).
    pub fn take_records_and_im(&self, at: (u32, u16, u16)) -> Result<(), ControlError> {
        self.own_records(at, true, true, false)
    }

    /// [`take_records`](Self::take_records), with the submodule's I&M records if `im` and
    /// its PROFIenergy record (0x80A0) if `pe`: a PE request the PLC writes comes as a write
    /// job, and the read that fetches the answer as a read job (answered with the PE
    /// response block, or [`RecordRefusal`] "state conflict" 0xB5 when nothing was asked,
    /// "resource unavailable" 0xC3 while the answer is not ready).
    pub fn take_records_with(
        &self,
        at: (u32, u16, u16),
        im: bool,
        pe: bool,
    ) -> Result<(), ControlError> {
        self.own_records(at, true, im, pe)
    }

    /// Gives the records of a submodule (and its I&M and PE records, if it took them) back
    /// to the station, which answers them itself again.
    pub fn give_back_records(&self, at: (u32, u16, u16)) -> Result<(), ControlError> {
        self.own_records(at, false, true, true)
    }

    /// Takes (`own`; with the I&M records if `im`, the PE record if `pe`) or gives back the
    /// records of a submodule.
    fn own_records(
        &self,
        (api, slot, subslot): (u32, u16, u16),
        own: bool,
        im: bool,
        pe: bool,
    ) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationOwnRecords {
            subscriber: self.id(),
            api,
            slot,
            subslot,
            own,
            im,
            pe,
        })
    }

    /// Answers record job `job`: `Ok` with the record read (cut to what the PLC takes; any
    /// bytes for a write, which are ignored), or the PNIORW error the PLC gets. An answer after
    /// the timeout is refused with `StaleRecordJob` (the PLC had "resource busy").
    pub fn answer_record(
        &self,
        job: &StationRecordJob,
        answer: Result<&[u8], RecordRefusal>,
    ) -> Result<(), ControlError> {
        let (data, error) = match answer {
            Ok(d) if !job.write => (d.to_vec(), None),
            Ok(_) => (Vec::new(), None),
            Err(e) => (Vec::new(), Some((e.code1, e.code2))),
        };
        self.station_request(DeviceRequest::StationRecordAnswer {
            subscriber: self.id(),
            job: job.job,
            data,
            error,
        })
    }

    /// Defines the station's tree, for a station whose configuration names its GSDML file and
    /// no submodules: `tree` is every submodule after the device access point, by place and
    /// ident numbers, and who answers its records; the file gives their IO lengths and
    /// parameter records. Once accepted the station runs anew with the tree and goes on the
    /// wire: clients re-attach and follow the new layout
    /// ([`Event::LayoutChanged`](crate::Event::LayoutChanged)). What this handle said
    /// before (it checks ARs or DCP's changes, holds the ApplicationReady, took records of
    /// the device access point) holds in the new station from its first moment, so that a
    /// PLC that connects at once meets the program. This handle is the station's program
    /// until [`release_station`](Self::release_station) or its
    /// process's end, which take the station off the wire again. Refused, naming what is
    /// wrong, for an ident or place the file does not allow, while an AR runs, when another
    /// program defined the station, and for a configured station.
    pub fn define_station(&self, tree: &[StationTreeEntry]) -> Result<(), ControlError> {
        self.define_station_as(tree, &DefinedIdentity::default())
    }

    /// [`define_station`](Self::define_station), the station's name, address and serial
    /// number taken from `identity` where it gives them (as a GS20-PN host's network
    /// configuration makes its module's). Refused, naming it, for a name that is not a
    /// NameOfStation, an address that is not a host's, a serial number over 16 characters.
    pub fn define_station_as(
        &self,
        tree: &[StationTreeEntry],
        identity: &DefinedIdentity,
    ) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationDefine {
            subscriber: self.id(),
            tree: tree.to_vec(),
            identity: identity.clone(),
        })
    }

    /// Checks `tree` as [`define_station`](Self::define_station) would, without defining
    /// anything: refused, naming what is wrong, for an ident or place the station's GSDML
    /// file does not allow. A program that builds its tree plug by plug checks each.
    pub fn check_station_tree(&self, tree: &[StationTreeEntry]) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationCheckTree {
            tree: tree.to_vec(),
        })
    }

    /// Ends this handle's part as the station's program: the AR ends with an abort and the
    /// station waits, off the wire, for a program to define it again.
    pub fn release_station(&self) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationRelease {
            subscriber: self.id(),
        })
    }

    /// Ends the station's AR `ar_uuid` (as the notifications write it) from the station's
    /// side: an ERR-RTA with AbortRequest goes to the PLC, the station stays on the wire and
    /// takes the PLC's next Connect. A [`Notification::StationArEnded`](crate::Notification::StationArEnded)
    /// follows. Refused with `ArGone` when it is not the current AR.
    pub fn abort_ar(&self, ar_uuid: &str) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationAbortAr {
            ar_uuid: ar_uuid.to_owned(),
        })
    }

    /// Checks every new AR from now on (`true`) or not: a PLC's Connect waits for this
    /// handle's [`answer_ar_check`](Self::answer_ar_check) to a
    /// [`Notification::StationArCheck`](crate::Notification::StationArCheck), at most
    /// [`AR_CHECK_TIMEOUT_MS`](crate::AR_CHECK_TIMEOUT_MS) (then the AR is accepted). One
    /// handle at a time checks.
    pub fn check_ars(&self, check: bool) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationCheckArs {
            subscriber: self.id(),
            check,
        })
    }

    /// Accepts the new AR of `check` (`Ok`), or refuses it with the Connect's ErrorCode1 and
    /// ErrorCode2 (ErrorCode 0xDB, ErrorDecode PNIO; [`AR_REFUSED_NO_RESOURCES`] is what a
    /// busy device says). An answer after the timeout is refused with `StaleArCheck`.
    pub fn answer_ar_check(
        &self,
        check: &StationArCheckJob,
        answer: Result<(), (u8, u8)>,
    ) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationArCheckAnswer {
            subscriber: self.id(),
            job: check.job,
            refuse: answer.err(),
        })
    }

    /// Checks DCP's changes of the station's name and address (and its reset to factory)
    /// from now on (`true`) or not: a DCP Set then waits for this handle's
    /// [`answer_dcp_set`](Self::answer_dcp_set) to a
    /// [`Notification::StationDcpSetCheck`](crate::Notification::StationDcpSetCheck), at most
    /// [`DCP_SET_CHECK_TIMEOUT_MS`](crate::DCP_SET_CHECK_TIMEOUT_MS) (then it is carried
    /// out). One handle at a time checks.
    pub fn verify_dcp_sets(&self, verify: bool) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationVerifyDcp {
            subscriber: self.id(),
            verify,
        })
    }

    /// Allows (`true`) or vetoes the DCP Set of `check` (the DCP client gets "SET not
    /// possible" and the station keeps its name and address).
    pub fn answer_dcp_set(
        &self,
        check: &StationDcpSetJob,
        allow: bool,
    ) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationDcpSetAnswer {
            subscriber: self.id(),
            job: check.job,
            allow,
        })
    }

    /// Holds the station's ApplicationReady after every PrmEnd (a
    /// [`Notification::StationAr`](crate::Notification::StationAr) with state
    /// [`ArState::Parameterized`](crate::ArState::Parameterized)) until this handle calls
    /// [`application_ready`](Self::application_ready) — or not (`false`).
    pub fn hold_application_ready(&self, hold: bool) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationHoldApplicationReady {
            subscriber: self.id(),
            hold,
        })
    }

    /// Says that this handle applied the PLC's parameters: the ApplicationReady goes out once
    /// every handle that holds it said so.
    pub fn application_ready(&self) -> Result<(), ControlError> {
        self.application_ready_except(&[])
    }

    /// [`application_ready`](Self::application_ready), but not for the submodules
    /// `not_ready` (API, slot, subslot): the PLC gets them as "application ready pending"
    /// (IO-Base's list of `PNIO_set_appl_state_ready`), each until its Return of Submodule
    /// alarm ([`Client::return_submodule`](crate::Client::return_submodule) or
    /// [`send_alarm`](Self::send_alarm)).
    pub fn application_ready_except(
        &self,
        not_ready: &[(u32, u16, u16)],
    ) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationApplicationReady {
            subscriber: self.id(),
            not_ready: not_ready.to_vec(),
        })
    }
}
