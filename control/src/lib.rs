// SPDX-License-Identifier: MIT OR Apache-2.0
//! The control protocol of procimg: what clients ask the server over the request-response
//! service `procimg/<instance>/control` ([`Request`]), what it answers ([`Response`]), and what
//! it tells subscribers later ([`services::Notification`]). Messages travel as JSON in
//! byte-slice payloads, so both sides can add optional fields without breaking the other.
//!
//! Requests come in three groups, one type each: [`CoreRequest`] (registration, claims, modes,
//! status, subscriptions, forces: either role), [`ControllerRequest`] (the IO controller's
//! services) and [`DeviceRequest`] (the IO device's station services).
//!
//! Also here, beside the protocol they serve: the instance's service names ([`names`]), the
//! control thread's [`doorbell`] a client rings after a request, and the Linux [`futex`] the
//! doorbell and the shared memory's handshake block sleep on. The shared-memory image itself
//! is `procimg-shm-layout`'s.

mod diagnosis;
// The doorbell maps a file and sleeps on a futex word in it.
#[allow(unsafe_code)]
pub mod doorbell;
// The futex calls are system calls.
#[allow(unsafe_code)]
pub mod futex;
pub mod hex_id;
pub mod names;
pub mod pe;
mod refusal;
mod request;
mod response;
pub mod services;
mod space;
mod states;
mod status;

pub use diagnosis::{
    DiagnosisDirection, DiagnosisEntry, DiagnosisKind, DiagnosisSeverity, StationDiagnosis,
    StationDiagnosisChange,
};
pub use names::*;
pub use refusal::{AlarmRefusal, PlugRefusal, Refusal};
pub use request::{
    ClientRole, ControllerRequest, CoreRequest, DefinedIdentity, DeviceRequest, Request,
    RestartClients, StationAlarmKind, StationTreeEntry, Tailoring, TreeRecords,
};
pub use response::Response;
pub use services::PortRef;
pub use space::Space;
pub use states::{ArState, DeviceState};
pub use status::{
    AccessArReport, ArReport, Bucket, ClaimReport, ClientReport, ControllerReport, DeviceReport,
    ForceReport, HistogramsReport, InterfaceCounters, NeighbourReport, NetworkReport, Percentiles,
    StationProgramReport, StationReport, StatusReport, SubscriberReport,
};

use serde::{Deserialize, Serialize};

/// Largest encoded request or response.
pub const MAX_MESSAGE_LEN: usize = 256 * 1024;

/// Encodes a message for the control service.
pub fn encode<T: Serialize>(message: &T) -> Vec<u8> {
    // Serialising these plain types into a Vec cannot fail.
    serde_json::to_vec(message).unwrap_or_default()
}

/// Decodes a message from the control service.
pub fn decode<'a, T: Deserialize<'a>>(bytes: &'a [u8]) -> Result<T, String> {
    serde_json::from_slice(bytes).map_err(|e| format!("{e}"))
}
