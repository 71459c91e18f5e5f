// SPDX-License-Identifier: MIT OR Apache-2.0
//! The PE records, byte by byte as the PROFIenergy profile lays them out (Wireshark's
//! PROFIenergy dissector reads the same fields), and round trips of every answer.

use super::*;
use proptest::prelude::*;

#[test]
fn start_pause_and_its_answer_byte_for_byte() {
    let req = PeRequest {
        reference: 7,
        command: PeCommand::StartPause { pause_ms: 5000 },
    };
    let bytes = req.to_vec().unwrap();
    assert_eq!(
        bytes,
        [
            0x08, 0x00, 0x00, 0x0a, 0x01, 0x00, 0x01, 0x07, 0x00, 0x01, 0x00, 0x00, 0x13, 0x88
        ]
    );
    assert_eq!(PeRequest::parse(&bytes).unwrap(), req);
    let res = PeResponse {
        service: service::START_PAUSE,
        reference: 7,
        answer: PeAnswer::StartPause { mode: 1 },
    };
    let bytes = res.to_vec().unwrap();
    assert_eq!(
        bytes,
        [
            0x08, 0x01, 0x00, 0x08, 0x01, 0x00, 0x01, 0x07, 0x01, 0x01, 0x01, 0x00
        ]
    );
    assert_eq!(PeResponse::parse(&bytes).unwrap(), res);
}

#[test]
fn end_pause_and_a_negative_answer_byte_for_byte() {
    let req = PeRequest {
        reference: 8,
        command: PeCommand::EndPause,
    };
    assert_eq!(
        req.to_vec().unwrap(),
        [0x08, 0x00, 0x00, 0x06, 0x01, 0x00, 0x02, 0x08, 0x00, 0x00]
    );
    let res = PeResponse {
        service: service::END_PAUSE,
        reference: 8,
        answer: PeAnswer::EndPause {
            time_to_operate: 6000,
        },
    };
    assert_eq!(
        res.to_vec().unwrap(),
        [
            0x08, 0x01, 0x00, 0x0a, 0x01, 0x00, 0x02, 0x08, 0x01, 0x01, 0x00, 0x00, 0x17, 0x70
        ]
    );
    let unknown = PeRequest {
        reference: 9,
        command: PeCommand::Other {
            service: 0x42,
            modifier: 0,
            structure: 0,
            data: Vec::new(),
        },
    };
    let neg = PeResponse::error(&unknown, error::INVALID_SERVICE);
    assert_eq!(
        neg.to_vec().unwrap(),
        [
            0x08, 0x01, 0x00, 0x08, 0x01, 0x00, 0x42, 0x09, 0x02, 0xff, 0x01, 0x00
        ]
    );
    assert_eq!(
        PeRequest::parse(&unknown.to_vec().unwrap()).unwrap(),
        unknown
    );
}

#[test]
fn lists_are_padded_to_an_even_length_and_read_with_or_without_it() {
    let res = PeResponse {
        service: service::QUERY_MODES,
        reference: 1,
        answer: PeAnswer::ModeList(vec![0xff, 0x01]),
    };
    let bytes = res.to_vec().unwrap();
    assert_eq!(&bytes[10..], [2, 0xff, 0x01, 0]);
    assert_eq!(PeResponse::parse(&bytes).unwrap(), res);
    // Without the pad (BlockLength one less).
    let mut short = bytes[..13].to_vec();
    short[3] -= 1;
    assert_eq!(PeResponse::parse(&short).unwrap(), res);
}

#[test]
fn get_mode_and_pem_status_have_the_profiles_sizes() {
    let mode = PeResponse {
        service: service::QUERY_MODES,
        reference: 2,
        answer: PeAnswer::Mode(ModeInfo {
            mode: 1,
            time_min_pause: 1000,
            power_kw: 0.25,
            ..ModeInfo::default()
        }),
    };
    let bytes = mode.to_vec().unwrap();
    assert_eq!(bytes.len(), 10 + 34);
    assert_eq!(
        &bytes[8..10],
        [0x01, 0x02],
        "ready, Data_Structure_Identifier_RS 2"
    );
    assert_eq!(
        &bytes[32..36],
        0.25f32.to_bits().to_be_bytes(),
        "Mode_Power_Consumption"
    );
    assert_eq!(PeResponse::parse(&bytes).unwrap(), mode);
    let pem = PeResponse {
        service: service::PEM_STATUS,
        reference: 3,
        answer: PeAnswer::PemStatus(PemStatus {
            source: 0xff,
            destination: 1,
            time_to_operate: 200,
            ..PemStatus::default()
        }),
    };
    assert_eq!(pem.to_vec().unwrap().len(), 10 + 22);
    assert_eq!(PeResponse::parse(&pem.to_vec().unwrap()).unwrap(), pem);
}

#[test]
fn a_request_of_a_known_service_with_the_wrong_shape_is_refused() {
    // Start_Pause without its pause time.
    let bytes = [0x08, 0x00, 0x00, 0x06, 0x01, 0x00, 0x01, 0x07, 0x00, 0x01];
    assert!(PeRequest::parse(&bytes).is_err());
    // A response block is no request.
    assert!(
        PeRequest::parse(&[0x08, 0x01, 0x00, 0x06, 0x01, 0x00, 0x02, 0x08, 0x01, 0x01]).is_err()
    );
}

fn answer() -> impl Strategy<Value = PeAnswer> {
    let f = any::<u32>().prop_map(|b| f32::from_bits(b & 0x7f7f_ffff));
    prop_oneof![
        any::<u8>().prop_map(|mode| PeAnswer::StartPause { mode }),
        any::<u32>().prop_map(|time_to_operate| PeAnswer::EndPause { time_to_operate }),
        prop::collection::vec(any::<u8>(), 0..20).prop_map(PeAnswer::ModeList),
        prop::collection::vec(any::<u8>(), 0..20).prop_map(PeAnswer::Identify),
        (any::<u8>(), any::<u8>()).prop_map(|(major, minor)| PeAnswer::Version { major, minor }),
        any::<u8>().prop_map(PeAnswer::Error),
        (any::<u8>(), any::<u8>(), any::<[u32; 5]>(), f.clone()).prop_map(
            |(mode, attributes, t, p)| {
                PeAnswer::Mode(ModeInfo {
                    mode,
                    attributes,
                    time_min_pause: t[0],
                    time_to_pause: t[1],
                    time_to_operate: t[2],
                    time_min_length_of_stay: t[3],
                    time_max_length_of_stay: t[4],
                    power_kw: p,
                    energy_to_pause_kwh: p,
                    energy_to_operate_kwh: p,
                })
            }
        ),
        prop::collection::vec((any::<u16>(), any::<u8>(), f), 0..8).prop_map(|v| {
            PeAnswer::MeasurementValues(
                v.into_iter()
                    .map(|(id, status, value)| MeasurementValue { id, status, value })
                    .collect(),
            )
        }),
    ]
}

proptest! {
    #[test]
    fn every_answer_reads_back(service in any::<u8>(), reference in any::<u8>(), a in answer()) {
        // The answer's service decides how its data reads: take the one it belongs to.
        let service = match &a {
            PeAnswer::StartPause { .. } => service::START_PAUSE,
            PeAnswer::EndPause { .. } => service::END_PAUSE,
            PeAnswer::ModeList(_) | PeAnswer::Mode(_) => service::QUERY_MODES,
            PeAnswer::Identify(_) => service::PE_IDENTIFY,
            PeAnswer::Version { .. } => service::QUERY_VERSION,
            PeAnswer::MeasurementValues(_) => service::QUERY_MEASUREMENT,
            _ => service,
        };
        let res = PeResponse { service, reference, answer: a };
        let bytes = res.to_vec().unwrap();
        prop_assert_eq!(bytes.len(), res.buffer_len());
        prop_assert_eq!(PeResponse::parse(&bytes).unwrap(), res);
    }

    #[test]
    fn no_input_panics_the_parsers(b in prop::collection::vec(any::<u8>(), 0..64)) {
        let _ = PeRequest::parse(&b);
        let _ = PeResponse::parse(&b);
    }
}
