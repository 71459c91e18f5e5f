// SPDX-License-Identifier: MIT OR Apache-2.0

use super::*;
use proptest::prelude::*;

fn io_ar() -> ArDataEntry {
    ArDataEntry {
        ar_uuid: Uuid([0x11; 16]),
        initiator_object_uuid: Uuid([0x22; 16]),
        parameter_server_object_uuid: Uuid([0; 16]),
        ar_properties: 0x4000_0011,
        ar_type: 1,
        alarm_cr_type: 1,
        local_alarm_reference: 1,
        remote_alarm_reference: 3,
        initiator_udp_rt_port: 0x8892,
        responder_udp_rt_port: 0x8892,
        initiator_station_name: "plc".into(),
        parameter_server_station_name: String::new(),
        iocrs: vec![ArDataIocr {
            properties: 2,
            iocr_type: 1,
            frame_id: 0x8000,
            cycle_counter: 0x1234,
            data_status: 0x35,
            transfer_status: 0,
        }],
        apis: vec![0],
    }
}

#[test]
fn ar_data_lays_an_ar_out_aligned() {
    let d = ArData { ars: vec![io_ar()] };
    let b = d.to_vec().unwrap();
    // Header v1.1, one AR, its UUID at offset 8.
    assert_eq!(
        &b[..8],
        &[
            0x00,
            0x18,
            0x00,
            (b.len() - 4) as u8,
            0x01,
            0x01,
            0x00,
            0x01
        ]
    );
    assert_eq!(&b[8..24], &[0x11; 16]);
    // The name "plc" at 74..77, padded to 80; the empty server name 80..82, padded to 84;
    // NumberOfIOCRs at 84.
    assert_eq!(&b[72..77], &[0x00, 0x03, b'p', b'l', b'c']);
    assert_eq!(&b[84..88], &[0x00, 0x01, 0x00, 0x00]);
    assert_eq!(b.len(), 8 + 76 + 4 + 12 + 4 + 4 + 4);
    assert_eq!(ArData::parse(&b).unwrap(), d);
    assert_eq!(
        ArData::default().to_vec().unwrap(),
        [0, 0x18, 0, 4, 1, 1, 0, 0]
    );
}

#[test]
fn api_data_and_log_book() {
    let a = ApiData { apis: vec![0] };
    let b = a.to_vec().unwrap();
    assert_eq!(
        b,
        [0x00, 0x1a, 0x00, 0x08, 0x01, 0x00, 0x00, 0x01, 0, 0, 0, 0]
    );
    assert_eq!(ApiData::parse(&b).unwrap(), a);
    let l = LogBookData {
        now: 5_000,
        entries: vec![LogEntry {
            time_stamp: 1_000,
            ar_uuid: Uuid([0x11; 16]),
            status: PnioStatus {
                error_code: 0xcf,
                error_decode: 0x81,
                error_code1: 0xfd,
                error_code2: 0x05,
            },
            detail: 0,
        }],
    };
    let b = l.to_vec().unwrap();
    assert_eq!(b.len(), 48);
    assert_eq!(&b[..6], &[0x00, 0x19, 0x00, 0x2c, 0x01, 0x00]);
    assert_eq!(&b[40..44], &[0xcf, 0x81, 0xfd, 0x05]);
    assert_eq!(LogBookData::parse(&b).unwrap(), l);
}

proptest! {
    #[test]
    fn ar_data_round_trips(names in proptest::collection::vec(("[a-z.-]{0,40}", "[a-z]{0,9}"), 0..3),
                           iocrs in 0usize..3, apis in 0usize..3) {
        let d = ArData {
            ars: names.into_iter().map(|(n, s)| ArDataEntry {
                initiator_station_name: n,
                parameter_server_station_name: s,
                iocrs: io_ar().iocrs.into_iter().cycle().take(iocrs).collect(),
                apis: vec![0; apis],
                ..io_ar()
            }).collect(),
        };
        let b = d.to_vec().unwrap();
        prop_assert!(b.len().is_multiple_of(4));
        prop_assert_eq!(ArData::parse(&b).unwrap(), d);
    }

    #[test]
    fn the_parsers_take_any_bytes(b in proptest::collection::vec(any::<u8>(), 0..200)) {
        let _ = ArData::parse(&b);
        let _ = ApiData::parse(&b);
        let _ = LogBookData::parse(&b);
    }
}
