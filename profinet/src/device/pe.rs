// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFIenergy at the station: a controller writes a PE request to record 0x80A0 of a
//! submodule and reads the answer from it. A program that enabled PE (IO-Base's
//! `PNIO_CEP_PE_MODE_ENABLE`) answers its submodules' PE records itself, as user records
//! (the station's `delegated_records`); for the others the station gives the standard's answer of
//! a PE entity that cannot save energy: its one mode is "ready to operate" (0xFF), a
//! Start_Pause is refused with "no PE energy-saving mode supported", an End_Pause and the
//! status queries answer with the station operating, it has no measurements, and a service
//! it does not know is refused with "invalid Service_Request_ID". The answer is kept as the
//! record the next read returns; a read before any request finds none (PNIORW "state
//! conflict").

use crate::wire::record::pe::{
    MODE_READY_TO_OPERATE, MeasurementValue, ModeInfo, PeAnswer, PeCommand, PeRequest, PeResponse,
    PemStatus, error, service,
};

/// The PE version the station's answers follow.
pub const PE_VERSION: (u8, u8) = (1, 1);

/// Measurement status "not available".
const NOT_AVAILABLE: u8 = 2;

/// The station's answer to `request`, a PE entity without energy-saving modes.
pub fn standard_answer(request: &PeRequest) -> PeResponse {
    let answer = match &request.command {
        PeCommand::StartPause { .. } => PeAnswer::Error(error::NO_ENERGY_SAVING),
        PeCommand::EndPause => PeAnswer::EndPause { time_to_operate: 0 },
        PeCommand::ListModes => PeAnswer::ModeList(vec![MODE_READY_TO_OPERATE]),
        PeCommand::GetMode {
            mode: MODE_READY_TO_OPERATE,
        } => PeAnswer::Mode(ModeInfo {
            mode: MODE_READY_TO_OPERATE,
            ..ModeInfo::default()
        }),
        PeCommand::GetMode { .. } => PeAnswer::Error(error::IMPERMISSIBLE_MODE),
        PeCommand::PemStatus => PeAnswer::PemStatus(PemStatus {
            source: MODE_READY_TO_OPERATE,
            destination: MODE_READY_TO_OPERATE,
            ..PemStatus::default()
        }),
        PeCommand::Identify => PeAnswer::Identify(vec![
            service::START_PAUSE,
            service::END_PAUSE,
            service::QUERY_MODES,
            service::PEM_STATUS,
            service::PE_IDENTIFY,
            service::QUERY_VERSION,
            service::QUERY_MEASUREMENT,
        ]),
        PeCommand::QueryVersion => PeAnswer::Version {
            major: PE_VERSION.0,
            minor: PE_VERSION.1,
        },
        PeCommand::MeasurementList => PeAnswer::MeasurementList(Vec::new()),
        PeCommand::MeasurementValues { ids } => PeAnswer::MeasurementValues(
            ids.iter()
                .map(|&id| MeasurementValue {
                    id,
                    status: NOT_AVAILABLE,
                    value: 0.0,
                })
                .collect(),
        ),
        PeCommand::Other { .. } => PeAnswer::Error(error::INVALID_SERVICE),
    };
    PeResponse {
        service: request.command.codes().0,
        reference: request.reference,
        answer,
    }
}

/// The answer to the bytes of a PE write: a request the station cannot read is answered
/// with "invalid block header" (echoing what it can of the header), as the profile asks.
pub fn answer_bytes(data: &[u8]) -> Vec<u8> {
    let response = match PeRequest::parse(data) {
        Ok(request) => standard_answer(&request),
        Err(_) => PeResponse {
            service: data.get(6).copied().unwrap_or(0),
            reference: data.get(7).copied().unwrap_or(0),
            answer: PeAnswer::Error(error::INVALID_BLOCK_HEADER),
        },
    };
    // Emitting a value built here cannot fail; an empty record would read as "no answer".
    response.to_vec().unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ask(command: PeCommand) -> PeAnswer {
        let request = PeRequest {
            reference: 5,
            command,
        };
        let response = PeResponse::parse(&answer_bytes(&request.to_vec().unwrap())).unwrap();
        assert_eq!(response.reference, 5);
        response.answer
    }

    #[test]
    fn a_station_without_saving_modes_says_so() {
        assert_eq!(
            ask(PeCommand::StartPause { pause_ms: 60_000 }),
            PeAnswer::Error(error::NO_ENERGY_SAVING)
        );
        assert_eq!(
            ask(PeCommand::EndPause),
            PeAnswer::EndPause { time_to_operate: 0 }
        );
        assert_eq!(ask(PeCommand::ListModes), PeAnswer::ModeList(vec![0xff]));
        assert_eq!(
            ask(PeCommand::GetMode { mode: 1 }),
            PeAnswer::Error(error::IMPERMISSIBLE_MODE)
        );
        assert!(matches!(ask(PeCommand::Identify), PeAnswer::Identify(s) if s.len() == 7));
        assert_eq!(
            ask(PeCommand::QueryVersion),
            PeAnswer::Version { major: 1, minor: 1 }
        );
        assert_eq!(
            ask(PeCommand::Other {
                service: 0x42,
                modifier: 0,
                structure: 0,
                data: vec![]
            }),
            PeAnswer::Error(error::INVALID_SERVICE)
        );
    }

    #[test]
    fn an_unreadable_request_gets_invalid_block_header() {
        let r = PeResponse::parse(&answer_bytes(&[0x08, 0x00, 0x00])).unwrap();
        assert_eq!(r.answer, PeAnswer::Error(error::INVALID_BLOCK_HEADER));
    }
}
