// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFIenergy commands and their answers as clients name them
//! ([`crate::ControllerRequest::PeCommand`], [`crate::services::Notification::PeConfirmation`]):
//! the controller carries each as a write of record 0x80A0 of the submodule and reads the
//! answer, again until it is ready, for at most [`PE_LIFETIME_MS`] (IO-Base's
//! `PNIO_PE_SERVICE_REQ_LIFETIME_DEFAULT`). Times are ms, powers kW, energies kWh.

use serde::{Deserialize, Serialize};

/// How long a PE command may take, its answer polled (IO-Base's 10 s).
pub const PE_LIFETIME_MS: u64 = 10_000;

/// A PE command.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "command", rename_all = "snake_case")]
pub enum PeCommand {
    /// Start_Pause: pause for `pause_ms`.
    StartPause {
        /// The pause expected, ms.
        pause_ms: u32,
    },
    /// End_Pause.
    EndPause,
    /// Query_Modes, the list of modes.
    ListModes,
    /// Query_Modes, one mode's figures.
    GetMode {
        /// PE_Mode_ID.
        mode: u8,
    },
    /// PEM_Status.
    PemStatus,
    /// PE_Identify: the services offered.
    Identify,
    /// Query_Version.
    QueryVersion,
    /// Query_Measurement, the list of measurements.
    MeasurementList,
    /// Query_Measurement, values.
    MeasurementValues {
        /// Measurement_IDs.
        ids: Vec<u16>,
    },
}

/// One mode's figures (Query_Modes Get_Mode).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PeModeInfo {
    /// PE_Mode_ID.
    pub mode: u8,
    /// PE_Mode_Attributes (bit 0: dynamic figures).
    pub attributes: u8,
    /// Time_min_Pause.
    pub time_min_pause: u32,
    /// Time_to_Pause.
    pub time_to_pause: u32,
    /// Time_to_operate.
    pub time_to_operate: u32,
    /// Time_min_length_of_stay.
    pub time_min_length_of_stay: u32,
    /// Time_max_length_of_stay.
    pub time_max_length_of_stay: u32,
    /// Mode_Power_Consumption.
    pub power_kw: f32,
    /// Energy_Consumption_to_pause.
    pub energy_to_pause_kwh: f32,
    /// Energy_Consumption_to_operate.
    pub energy_to_operate_kwh: f32,
}

/// PEM_Status.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PePemStatus {
    /// PE_Mode_ID_Source.
    pub source: u8,
    /// PE_Mode_ID_Destination.
    pub destination: u8,
    /// Time_to_operate.
    pub time_to_operate: u32,
    /// Remaining_time_to_destination.
    pub remaining_time_to_destination: u32,
    /// Mode_Power_Consumption.
    pub power_kw: f32,
    /// Energy_Consumption_to_Destination.
    pub energy_to_destination_kwh: f32,
    /// Energy_Consumption_to_operate.
    pub energy_to_operate_kwh: f32,
}

/// A measurement offered.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PeMeasurementInfo {
    /// Measurement_ID.
    pub id: u16,
    /// Accuracy_Domain.
    pub accuracy_domain: u8,
    /// Accuracy_Class.
    pub accuracy_class: u8,
    /// Range.
    pub range: f32,
}

/// A value measured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PeMeasurementValue {
    /// Measurement_ID.
    pub id: u16,
    /// Status (1 valid, 2 not available, 3 temporarily not available).
    pub status: u8,
    /// The value.
    pub value: f32,
}

/// What a device answered.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "answer", rename_all = "snake_case")]
pub enum PeAnswer {
    /// Start_Pause: the mode reached.
    StartPause {
        /// PE_Mode_ID.
        mode: u8,
    },
    /// End_Pause: the time until operation.
    EndPause {
        /// Time_to_operate.
        time_to_operate: u32,
    },
    /// The modes.
    ModeList {
        /// PE_Mode_IDs.
        modes: Vec<u8>,
    },
    /// One mode's figures.
    Mode(PeModeInfo),
    /// PEM_Status.
    PemStatus(PePemStatus),
    /// The services offered.
    Identify {
        /// Service_Request_IDs.
        services: Vec<u8>,
    },
    /// The PE version.
    Version {
        /// Major.
        major: u8,
        /// Minor.
        minor: u8,
    },
    /// The measurements offered.
    MeasurementList {
        /// Them.
        items: Vec<PeMeasurementInfo>,
    },
    /// The values.
    MeasurementValues {
        /// Them.
        values: Vec<PeMeasurementValue>,
    },
    /// A negative answer: the PE Error_Code.
    Error {
        /// Error_Code.
        code: u8,
    },
    /// An answer of another shape.
    Other {
        /// Status.
        status: u8,
        /// Data_Structure_Identifier_RS.
        structure: u8,
        /// The service data.
        data: Vec<u8>,
    },
}
