// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFIenergy's service records: a controller writes a PE request (block 0x0800) to record
//! 0x80A0 of a submodule and reads the answer (block 0x0801) from the same record; until
//! the answer is ready the device refuses the read with PNIORW "resource unavailable"
//! (ErrorCode1 0xC3) and the controller reads again.
//!
//! ```text
//! request   BlockHeader(0x0800, v1.0) Service_Request_ID Request_Reference Modifier
//!           Data_Structure_Identifier_RQ  service data…
//! response  BlockHeader(0x0801, v1.0) Service_Request_ID Request_Reference Status
//!           Data_Structure_Identifier_RS  service data…
//! negative  … Status 2, Data_Structure_Identifier_RS 0xFF, Error_Code, reserved
//! ```
//!
//! Every field is big-endian; times are milliseconds (u32), powers kW and energies kWh
//! (IEEE-754 float32, from and to their bit patterns). A service whose data this codec does
//! not decode keeps its bytes ([`PeCommand::Other`], [`PeAnswer::Other`]). Lists of byte
//! values (modes, services) are padded to an even length, as devices send them; a parser
//! takes them with or without the pad.

use super::super::cursor::{Reader, Writer};
use super::{BlockHeader, BlockType, EmitResult, Error, Result, emit_block};

/// The PE service access point: record 0x80A0 of the submodule.
pub const INDEX_PE_SERVICE: u16 = 0x80a0;

/// Service_Request_IDs.
pub mod service {
    /// Start_Pause.
    pub const START_PAUSE: u8 = 0x01;
    /// End_Pause.
    pub const END_PAUSE: u8 = 0x02;
    /// Query_Modes.
    pub const QUERY_MODES: u8 = 0x03;
    /// PEM_Status.
    pub const PEM_STATUS: u8 = 0x04;
    /// PE_Identify.
    pub const PE_IDENTIFY: u8 = 0x05;
    /// Query_Version.
    pub const QUERY_VERSION: u8 = 0x06;
    /// Query_Measurement.
    pub const QUERY_MEASUREMENT: u8 = 0x10;
}

/// The response Status.
pub mod status {
    /// Ready: the data follows.
    pub const READY: u8 = 0x01;
    /// Ready with an error: an Error_Code follows.
    pub const READY_WITH_ERROR: u8 = 0x02;
}

/// Error_Codes of a negative response.
pub mod error {
    /// Invalid Service_Request_ID.
    pub const INVALID_SERVICE: u8 = 0x01;
    /// Bad Request_Reference.
    pub const BAD_REFERENCE: u8 = 0x02;
    /// Invalid Modifier.
    pub const INVALID_MODIFIER: u8 = 0x03;
    /// Invalid Data_Structure_Identifier_RQ.
    pub const INVALID_REQUEST_DATA: u8 = 0x04;
    /// No PE energy-saving mode supported.
    pub const NO_ENERGY_SAVING: u8 = 0x06;
    /// Invalid block header.
    pub const INVALID_BLOCK_HEADER: u8 = 0x08;
    /// No suitable energy-saving mode available.
    pub const NO_SUITABLE_MODE: u8 = 0x50;
    /// Time not supported.
    pub const TIME_NOT_SUPPORTED: u8 = 0x51;
    /// Impermissible PE_Mode_ID.
    pub const IMPERMISSIBLE_MODE: u8 = 0x52;
    /// No switch to energy saving because of state operate.
    pub const STATE_OPERATE: u8 = 0x53;
    /// Service or function temporarily not available.
    pub const TEMPORARILY_NOT_AVAILABLE: u8 = 0x54;
}

/// PE_Mode_ID 0xFF: ready to operate.
pub const MODE_READY_TO_OPERATE: u8 = 0xff;
/// PE_Mode_ID 0x00: power off.
pub const MODE_POWER_OFF: u8 = 0x00;

/// A PE command, as a request carries it.
#[derive(Clone, Debug, PartialEq)]
pub enum PeCommand {
    /// Start_Pause (modifier 0): pause for `pause_ms`.
    StartPause {
        /// The pause expected, ms.
        pause_ms: u32,
    },
    /// End_Pause: back to operation.
    EndPause,
    /// Query_Modes, List_Energy_Saving_Modes (modifier 1).
    ListModes,
    /// Query_Modes, Get_Mode (modifier 2): one mode's figures.
    GetMode {
        /// PE_Mode_ID.
        mode: u8,
    },
    /// PEM_Status: where the device is.
    PemStatus,
    /// PE_Identify: the services the device offers.
    Identify,
    /// Query_Version.
    QueryVersion,
    /// Query_Measurement, Get_Measurement_List (modifier 1).
    MeasurementList,
    /// Query_Measurement, Get_Measurement_Values (modifier 2).
    MeasurementValues {
        /// The Measurement_IDs wanted.
        ids: Vec<u16>,
    },
    /// Another service, kept as it is.
    Other {
        /// Service_Request_ID.
        service: u8,
        /// Modifier.
        modifier: u8,
        /// Data_Structure_Identifier_RQ.
        structure: u8,
        /// The service data.
        data: Vec<u8>,
    },
}

/// A PE request block.
#[derive(Clone, Debug, PartialEq)]
pub struct PeRequest {
    /// Request_Reference, echoed in the answer.
    pub reference: u8,
    /// The command.
    pub command: PeCommand,
}

impl PeCommand {
    /// Service_Request_ID, Modifier and Data_Structure_Identifier_RQ.
    pub fn codes(&self) -> (u8, u8, u8) {
        match self {
            PeCommand::StartPause { .. } => (service::START_PAUSE, 0, 1),
            PeCommand::EndPause => (service::END_PAUSE, 0, 0),
            PeCommand::ListModes => (service::QUERY_MODES, 1, 0),
            PeCommand::GetMode { .. } => (service::QUERY_MODES, 2, 1),
            PeCommand::PemStatus => (service::PEM_STATUS, 0, 0),
            PeCommand::Identify => (service::PE_IDENTIFY, 0, 0),
            PeCommand::QueryVersion => (service::QUERY_VERSION, 0, 0),
            PeCommand::MeasurementList => (service::QUERY_MEASUREMENT, 1, 0),
            PeCommand::MeasurementValues { .. } => (service::QUERY_MEASUREMENT, 2, 1),
            PeCommand::Other {
                service,
                modifier,
                structure,
                ..
            } => (*service, *modifier, *structure),
        }
    }

    fn data_len(&self) -> usize {
        match self {
            PeCommand::StartPause { .. } => 4,
            PeCommand::GetMode { .. } => 2,
            PeCommand::MeasurementValues { ids } => 2 + 2 * ids.len(),
            PeCommand::Other { data, .. } => data.len(),
            _ => 0,
        }
    }
}

impl PeRequest {
    /// Bytes of the block.
    pub fn buffer_len(&self) -> usize {
        10 + self.command.data_len()
    }

    /// Writes the block into the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<usize> {
        let (id, modifier, structure) = self.command.codes();
        let body = 4 + self.command.data_len();
        emit_block(
            "PE request",
            BlockType::PeServiceRequest,
            0,
            body,
            buf,
            |w| {
                w.put(&[id, self.reference, modifier, structure])?;
                match &self.command {
                    PeCommand::StartPause { pause_ms } => w.u32(*pause_ms),
                    PeCommand::GetMode { mode } => w.put(&[*mode, 0]),
                    PeCommand::MeasurementValues { ids } => {
                        let n = u8::try_from(ids.len()).map_err(|_| super::EmitError::TooLong {
                            field: "Measurement_IDs",
                            value: ids.len(),
                            max: 255,
                        })?;
                        w.put(&[n, 0])?;
                        ids.iter().try_for_each(|id| w.u16(*id))
                    }
                    PeCommand::Other { data, .. } => w.put(data),
                    _ => Ok(()),
                }
            },
        )
    }

    /// The block as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b).map(|_| ()))
    }

    /// Parses a request block; a known service with data of the wrong shape is an error.
    pub fn parse(b: &[u8]) -> Result<PeRequest> {
        let h = BlockHeader::parse(b)?;
        if h.block_type != BlockType::PeServiceRequest || h.version_high != 1 {
            return Err(Error);
        }
        let mut r = Reader::new(h.body(b));
        let [id, reference, modifier, structure] = r.array::<4>()?;
        let command = match (id, modifier, structure) {
            (service::START_PAUSE, 0, 1) => PeCommand::StartPause { pause_ms: r.u32()? },
            (service::END_PAUSE, 0, 0) => PeCommand::EndPause,
            (service::QUERY_MODES, 1, 0) => PeCommand::ListModes,
            (service::QUERY_MODES, 2, 1) => {
                let [mode, _] = r.array::<2>()?;
                PeCommand::GetMode { mode }
            }
            (service::PEM_STATUS, 0, 0) => PeCommand::PemStatus,
            (service::PE_IDENTIFY, 0, 0) => PeCommand::Identify,
            (service::QUERY_VERSION, 0, 0) => PeCommand::QueryVersion,
            (service::QUERY_MEASUREMENT, 1, 0) => PeCommand::MeasurementList,
            (service::QUERY_MEASUREMENT, 2, 1) => {
                let [n, _] = r.array::<2>()?;
                let ids = (0..n).map(|_| r.u16()).collect::<Result<Vec<_>>>()?;
                PeCommand::MeasurementValues { ids }
            }
            _ => PeCommand::Other {
                service: id,
                modifier,
                structure,
                data: r.rest().to_vec(),
            },
        };
        if !matches!(command, PeCommand::Other { .. }) {
            r.end()?;
        }
        Ok(PeRequest { reference, command })
    }
}

/// Query_Modes Get_Mode's figures of one mode.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ModeInfo {
    /// PE_Mode_ID.
    pub mode: u8,
    /// PE_Mode_Attributes (bit 0: the times and energies are dynamic).
    pub attributes: u8,
    /// Time_min_Pause, ms.
    pub time_min_pause: u32,
    /// Time_to_Pause, ms.
    pub time_to_pause: u32,
    /// Time_to_operate, ms.
    pub time_to_operate: u32,
    /// Time_min_length_of_stay, ms.
    pub time_min_length_of_stay: u32,
    /// Time_max_length_of_stay, ms.
    pub time_max_length_of_stay: u32,
    /// Mode_Power_Consumption, kW.
    pub power_kw: f32,
    /// Energy_Consumption_to_pause, kWh.
    pub energy_to_pause_kwh: f32,
    /// Energy_Consumption_to_operate, kWh.
    pub energy_to_operate_kwh: f32,
}

/// PEM_Status: where the device is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PemStatus {
    /// PE_Mode_ID_Source.
    pub source: u8,
    /// PE_Mode_ID_Destination.
    pub destination: u8,
    /// Time_to_operate, ms.
    pub time_to_operate: u32,
    /// Remaining_time_to_destination, ms.
    pub remaining_time_to_destination: u32,
    /// Mode_Power_Consumption, kW.
    pub power_kw: f32,
    /// Energy_Consumption_to_Destination, kWh.
    pub energy_to_destination_kwh: f32,
    /// Energy_Consumption_to_operate, kWh.
    pub energy_to_operate_kwh: f32,
}

/// One measurement a device offers.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeasurementInfo {
    /// Measurement_ID.
    pub id: u16,
    /// Accuracy_Domain.
    pub accuracy_domain: u8,
    /// Accuracy_Class.
    pub accuracy_class: u8,
    /// Range.
    pub range: f32,
}

/// One measured value (Measurement_Data_Structure_ID 1, a float32 value).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeasurementValue {
    /// Measurement_ID.
    pub id: u16,
    /// Status_of_Measurement_Value (1 valid, 2 not available, 3 temporarily not).
    pub status: u8,
    /// The value.
    pub value: f32,
}

/// What a PE answer carries.
#[derive(Clone, Debug, PartialEq)]
pub enum PeAnswer {
    /// Start_Pause: the mode reached.
    StartPause {
        /// PE_Mode_ID.
        mode: u8,
    },
    /// End_Pause: the time until operation.
    EndPause {
        /// Time_to_operate, ms.
        time_to_operate: u32,
    },
    /// Query_Modes List: the modes.
    ModeList(Vec<u8>),
    /// Query_Modes Get_Mode.
    Mode(ModeInfo),
    /// PEM_Status.
    PemStatus(PemStatus),
    /// PE_Identify: the services offered.
    Identify(Vec<u8>),
    /// Query_Version.
    Version {
        /// Major.
        major: u8,
        /// Minor.
        minor: u8,
    },
    /// Get_Measurement_List.
    MeasurementList(Vec<MeasurementInfo>),
    /// Get_Measurement_Values.
    MeasurementValues(Vec<MeasurementValue>),
    /// A negative response: Error_Code.
    Error(u8),
    /// Another answer, kept as it is.
    Other {
        /// Status.
        status: u8,
        /// Data_Structure_Identifier_RS.
        structure: u8,
        /// The service data.
        data: Vec<u8>,
    },
}

/// A PE response block.
#[derive(Clone, Debug, PartialEq)]
pub struct PeResponse {
    /// Service_Request_ID of the request.
    pub service: u8,
    /// Request_Reference of the request.
    pub reference: u8,
    /// The answer.
    pub answer: PeAnswer,
}

/// Bytes of a list of `n` bytes after its count, padded to an even length.
const fn padded_list(n: usize) -> usize {
    (1 + n).next_multiple_of(2)
}

impl PeAnswer {
    /// Status and Data_Structure_Identifier_RS.
    fn codes(&self) -> (u8, u8) {
        match self {
            PeAnswer::Mode(_) | PeAnswer::MeasurementList(_) => (status::READY, 2),
            PeAnswer::Error(_) => (status::READY_WITH_ERROR, 0xff),
            PeAnswer::Other {
                status, structure, ..
            } => (*status, *structure),
            _ => (status::READY, 1),
        }
    }

    fn data_len(&self) -> usize {
        match self {
            PeAnswer::StartPause { .. } | PeAnswer::Version { .. } | PeAnswer::Error(_) => 2,
            PeAnswer::EndPause { .. } => 4,
            PeAnswer::ModeList(v) | PeAnswer::Identify(v) => padded_list(v.len()),
            PeAnswer::Mode(_) => 34,
            PeAnswer::PemStatus(_) => 22,
            PeAnswer::MeasurementList(v) => 2 + 8 * v.len(),
            PeAnswer::MeasurementValues(v) => 2 + 10 * v.len(),
            PeAnswer::Other { data, .. } => data.len(),
        }
    }
}

fn list_len(what: &'static str, n: usize) -> EmitResult<u8> {
    u8::try_from(n).map_err(|_| super::EmitError::TooLong {
        field: what,
        value: n,
        max: 255,
    })
}

fn emit_answer(w: &mut Writer<'_>, a: &PeAnswer) -> EmitResult<()> {
    match a {
        PeAnswer::StartPause { mode } => w.put(&[*mode, 0]),
        PeAnswer::EndPause { time_to_operate } => w.u32(*time_to_operate),
        PeAnswer::ModeList(v) | PeAnswer::Identify(v) => {
            w.u8(list_len("PE list", v.len())?)?;
            w.put(v)?;
            w.zeros(padded_list(v.len()) - 1 - v.len())
        }
        PeAnswer::Mode(m) => {
            w.put(&[m.mode, m.attributes])?;
            for t in [
                m.time_min_pause,
                m.time_to_pause,
                m.time_to_operate,
                m.time_min_length_of_stay,
                m.time_max_length_of_stay,
            ] {
                w.u32(t)?;
            }
            for f in [m.power_kw, m.energy_to_pause_kwh, m.energy_to_operate_kwh] {
                w.u32(f.to_bits())?;
            }
            Ok(())
        }
        PeAnswer::PemStatus(s) => {
            w.put(&[s.source, s.destination])?;
            w.u32(s.time_to_operate)?;
            w.u32(s.remaining_time_to_destination)?;
            for f in [
                s.power_kw,
                s.energy_to_destination_kwh,
                s.energy_to_operate_kwh,
            ] {
                w.u32(f.to_bits())?;
            }
            Ok(())
        }
        PeAnswer::Version { major, minor } => w.put(&[*major, *minor]),
        PeAnswer::MeasurementList(v) => {
            w.put(&[list_len("Measurement_IDs", v.len())?, 0])?;
            v.iter().try_for_each(|m| {
                w.u16(m.id)?;
                w.put(&[m.accuracy_domain, m.accuracy_class])?;
                w.u32(m.range.to_bits())
            })
        }
        PeAnswer::MeasurementValues(v) => {
            w.put(&[list_len("Measurement values", v.len())?, 0])?;
            v.iter().try_for_each(|m| {
                // Length_of_Structure (the whole item), Measurement_Data_Structure_ID 1.
                w.u16(10)?;
                w.u8(1)?;
                w.u16(m.id)?;
                w.u8(m.status)?;
                w.u32(m.value.to_bits())
            })
        }
        PeAnswer::Error(code) => w.put(&[*code, 0]),
        PeAnswer::Other { data, .. } => w.put(data),
    }
}

fn f32_of(r: &mut Reader<'_>) -> Result<f32> {
    r.u32().map(f32::from_bits)
}

/// A list of bytes after its count, with or without its pad.
fn byte_list(r: &mut Reader<'_>) -> Result<Vec<u8>> {
    let n = r.u8()?;
    let v = r.take(usize::from(n))?.to_vec();
    Ok(v)
}

fn parse_answer(service: u8, st: u8, structure: u8, r: &mut Reader<'_>) -> Result<PeAnswer> {
    Ok(match (service, st, structure) {
        (_, status::READY_WITH_ERROR, 0xff) => {
            let [code, _] = r.array::<2>()?;
            PeAnswer::Error(code)
        }
        (service::START_PAUSE, status::READY, 1) => {
            let [mode, _] = r.array::<2>()?;
            PeAnswer::StartPause { mode }
        }
        (service::END_PAUSE, status::READY, 1) => PeAnswer::EndPause {
            time_to_operate: r.u32()?,
        },
        (service::QUERY_MODES, status::READY, 1) => PeAnswer::ModeList(byte_list(r)?),
        (service::QUERY_MODES, status::READY, 2) => {
            let [mode, attributes] = r.array::<2>()?;
            PeAnswer::Mode(ModeInfo {
                mode,
                attributes,
                time_min_pause: r.u32()?,
                time_to_pause: r.u32()?,
                time_to_operate: r.u32()?,
                time_min_length_of_stay: r.u32()?,
                time_max_length_of_stay: r.u32()?,
                power_kw: f32_of(r)?,
                energy_to_pause_kwh: f32_of(r)?,
                energy_to_operate_kwh: f32_of(r)?,
            })
        }
        (service::PEM_STATUS, status::READY, 1) => {
            let [source, destination] = r.array::<2>()?;
            PeAnswer::PemStatus(PemStatus {
                source,
                destination,
                time_to_operate: r.u32()?,
                remaining_time_to_destination: r.u32()?,
                power_kw: f32_of(r)?,
                energy_to_destination_kwh: f32_of(r)?,
                energy_to_operate_kwh: f32_of(r)?,
            })
        }
        (service::PE_IDENTIFY, status::READY, 1) => PeAnswer::Identify(byte_list(r)?),
        (service::QUERY_VERSION, status::READY, 1) => {
            let [major, minor] = r.array::<2>()?;
            PeAnswer::Version { major, minor }
        }
        (service::QUERY_MEASUREMENT, status::READY, 2) => {
            let [n, _] = r.array::<2>()?;
            let items = (0..n)
                .map(|_| {
                    let id = r.u16()?;
                    let [accuracy_domain, accuracy_class] = r.array::<2>()?;
                    Ok(MeasurementInfo {
                        id,
                        accuracy_domain,
                        accuracy_class,
                        range: f32_of(r)?,
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            PeAnswer::MeasurementList(items)
        }
        (service::QUERY_MEASUREMENT, status::READY, 1) => {
            let [n, _] = r.array::<2>()?;
            let items = (0..n)
                .map(|_| {
                    let len = usize::from(r.u16()?);
                    let item = r.take(len.checked_sub(2).ok_or(Error)?)?;
                    let mut i = Reader::new(item);
                    // Measurement_Data_Structure_ID 1: a float32 value (a time stamp
                    // after it, if any, is skipped).
                    if i.u8()? != 1 {
                        return Err(Error);
                    }
                    Ok(MeasurementValue {
                        id: i.u16()?,
                        status: i.u8()?,
                        value: f32_of(&mut i)?,
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            PeAnswer::MeasurementValues(items)
        }
        _ => PeAnswer::Other {
            status: st,
            structure,
            data: r.rest().to_vec(),
        },
    })
}

impl PeResponse {
    /// A negative response to `request`.
    pub fn error(request: &PeRequest, code: u8) -> PeResponse {
        PeResponse {
            service: request.command.codes().0,
            reference: request.reference,
            answer: PeAnswer::Error(code),
        }
    }

    /// Bytes of the block.
    pub fn buffer_len(&self) -> usize {
        10 + self.answer.data_len()
    }

    /// Writes the block into the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<usize> {
        let (st, structure) = self.answer.codes();
        let body = 4 + self.answer.data_len();
        emit_block(
            "PE response",
            BlockType::PeServiceResponse,
            0,
            body,
            buf,
            |w| {
                w.put(&[self.service, self.reference, st, structure])?;
                emit_answer(w, &self.answer)
            },
        )
    }

    /// The block as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b).map(|_| ()))
    }

    /// Parses a response block; bytes after a known answer (a list's pad) are ignored.
    pub fn parse(b: &[u8]) -> Result<PeResponse> {
        let h = BlockHeader::parse(b)?;
        if h.block_type != BlockType::PeServiceResponse || h.version_high != 1 {
            return Err(Error);
        }
        let mut r = Reader::new(h.body(b));
        let [service, reference, st, structure] = r.array::<4>()?;
        let answer = parse_answer(service, st, structure, &mut r)?;
        Ok(PeResponse {
            service,
            reference,
            answer,
        })
    }
}

#[cfg(test)]
mod tests;
