// SPDX-License-Identifier: MIT OR Apache-2.0
//! The records a device serves itself: the worked examples of the Siemens manual
//! "PROFINET IO: From PROFIBUS DP to PROFINET IO" (records-diagnosis.md §4, TV1–TV9) byte
//! for byte, I&M1–I&M4, I&M0FilterData, and round trips of every codec.

use super::*;
use crate::test_fixtures::hex;
use crate::wire::connect::{ModuleDiffBlock, ModuleState};
use crate::wire::diagnosis::{
    AlarmItem, CHANNEL_NUMBER_SUBMODULE, ChannelDiagnosis, ChannelDirection, ChannelProperties,
    ChannelSpecifier, Diagnosis, DiagnosisFormat,
};
use crate::wire::test_strategies::alarm_item;
use proptest::prelude::*;

/// TV1: record 0x800A, ET 200S slot 2 subslot 1, wire break on output channel 1.
const TV1: &str = "0010001601010000000000020001800008008000000148010006";
/// TV2: the same module, wire break on channels 1 and 0.
const TV2: &str = "0010001c01010000000000020001800008008000000148010006000048010006";
/// TV3: record 0x800C, slot 3 subslot 1, short circuit on input channel 0.
const TV3: &str = "0010001601010000000000030001800008008000000028010001";
/// TV8: record 0x800A in BlockVersion 1.0, slot 2, wire break on output channel 0.
const TV8: &str = "00100012010000020001800008008000000048010006";
/// TV9: the same in BlockVersion 1.1 (the manual's table uses slot 1 here).
const TV9: &str = "0010001601010000000000010001800008008000000048010006";
/// TV5: record 0xE000, the expected configuration of an ET 200S with five slots.
const TV5: &str = concat!(
    "00120050010100010000000000050000000003220001000100000000",
    "00010000068400010001000000000002000088a10001000100000000",
    "00030000109400010001000000000004 0000d6d800010001 00000000",
);
/// TV6: record 0xE001, the real configuration: slot 2 pulled, slot 4 another module.
const TV6: &str = concat!(
    "00130042010100010000000000040000000003220001000100000000",
    "00010000068400010001000000000003000010940001000100000000",
    "0004000017ff00010001 00000000",
);
/// TV7: record 0xE002, slot 2 missing, slot 4 wrong (its subslot 1 SubmoduleState 0x9000).
const TV7: &str = concat!(
    "81040026010000010000000000020002000088a100000000",
    "0004000017ff000100010001000000009000",
);

/// A channel diagnosis block of the manual's examples: API 0, the submodule's header
/// (ChannelNumber 0x8000, ChannelProperties 0x0800: a fault appears), USI 0x8000.
fn manual_block(version: RecordVersion, slot: u16, entries: &[(u16, u16, u16)]) -> DiagnosisData {
    DiagnosisData {
        version,
        api: 0,
        slot,
        subslot: 1,
        channel_number: CHANNEL_NUMBER_SUBMODULE,
        channel_properties: ChannelProperties(0x0800),
        item: AlarmItem::Diagnosis(Diagnosis {
            format: DiagnosisFormat::Channel,
            entries: entries
                .iter()
                .map(|&(ch, props, err)| ChannelDiagnosis::new(ch, ChannelProperties(props), err))
                .collect(),
        }),
    }
}

/// Parses `hex` as one DiagnosisData block, checks it is `expected` and emits the same bytes.
fn same_block(hex_str: &str, expected: &DiagnosisData) {
    let bytes = hex(hex_str);
    let d = DiagnosisData::parse(&bytes).unwrap();
    assert_eq!(&d, expected);
    assert_eq!(d.buffer_len(), bytes.len());
    assert_eq!(d.to_vec().unwrap(), bytes);
}

#[test]
fn tv1_tv2_tv3_tv8_tv9_diagnosis_blocks() {
    let tv1 = manual_block(RecordVersion::V1_1, 2, &[(1, 0x4801, 6)]);
    same_block(TV1, &tv1);
    let e = tv1.item.diagnosis().unwrap().entries[0];
    assert_eq!(e.channel_properties.data_type(), 1);
    assert_eq!(e.channel_properties.specifier(), ChannelSpecifier::Appears);
    assert_eq!(e.channel_properties.direction(), ChannelDirection::Output);
    same_block(
        TV2,
        &manual_block(RecordVersion::V1_1, 2, &[(1, 0x4801, 6), (0, 0x4801, 6)]),
    );
    let tv3 = manual_block(RecordVersion::V1_1, 3, &[(0, 0x2801, 1)]);
    same_block(TV3, &tv3);
    let tv3_props = tv3.item.diagnosis().unwrap().entries[0].channel_properties;
    assert_eq!(tv3_props.direction(), ChannelDirection::Input);
    same_block(
        TV8,
        &manual_block(RecordVersion::V1_0, 2, &[(0, 0x4801, 6)]),
    );
    same_block(
        TV9,
        &manual_block(RecordVersion::V1_1, 1, &[(0, 0x4801, 6)]),
    );
    // BlockLength per channel count, as the manual's Table 5-9 gives it.
    for (version, n, len) in [
        (RecordVersion::V1_0, 1, 18),
        (RecordVersion::V1_0, 4, 36),
        (RecordVersion::V1_1, 1, 22),
        (RecordVersion::V1_1, 4, 40),
    ] {
        let entries = vec![(0, 0x4801, 6); n];
        let b = manual_block(version, 2, &entries).to_vec().unwrap();
        assert_eq!(u16::from_be_bytes([b[2], b[3]]), len);
    }
}

#[test]
fn tv4_e00c_is_two_blocks_walked_to_the_end() {
    let record = hex(&format!("{TV2}{TV3}"));
    assert_eq!(record.len(), 58);
    let blocks = DiagnosisData::parse_record(&record).unwrap();
    assert_eq!(
        blocks,
        vec![
            manual_block(RecordVersion::V1_1, 2, &[(1, 0x4801, 6), (0, 0x4801, 6)]),
            manual_block(RecordVersion::V1_1, 3, &[(0, 0x2801, 1)]),
        ]
    );
    assert_eq!(DiagnosisData::record_to_vec(&blocks).unwrap(), record);
    // The walk must end on the last byte; an empty record has no block.
    assert_eq!(DiagnosisData::parse_record(&record[..57]), Err(Error));
    assert_eq!(DiagnosisData::parse_record(&[]), Ok(vec![]));
    assert_eq!(DiagnosisData::record_to_vec(&[]), Ok(vec![]));
}

#[test]
fn tv5_tv6_identification() {
    let modules = [
        (0, 0x322),
        (1, 0x684),
        (2, 0x88a1),
        (3, 0x1094),
        (4, 0xd6d8),
    ];
    let expected = IdentificationData {
        kind: IdentificationKind::Expected,
        version: RecordVersion::V1_1,
        apis: IdentApi::group(modules.iter().map(|&(slot, m)| (0, slot, m, 1, 0))),
    };
    let tv5 = hex(TV5);
    assert_eq!(IdentificationData::parse(&tv5).unwrap(), expected);
    assert_eq!(expected.to_vec().unwrap(), tv5);

    let real_modules = [(0, 0x322), (1, 0x684), (3, 0x1094), (4, 0x17ff)];
    let real = IdentificationData {
        kind: IdentificationKind::Real,
        version: RecordVersion::V1_1,
        apis: IdentApi::group(real_modules.iter().map(|&(slot, m)| (0, slot, m, 1, 0))),
    };
    let tv6 = hex(TV6);
    assert_eq!(IdentificationData::parse(&tv6).unwrap(), real);
    assert_eq!(real.to_vec().unwrap(), tv6);
    assert_eq!(
        IdentApi::flatten(&real.apis).collect::<Vec<_>>(),
        real_modules
            .iter()
            .map(|&(slot, m)| (0, slot, m, 1, 0))
            .collect::<Vec<_>>()
    );

    // Version 1.0 of the same: no API level (4 bytes shorter per API and count).
    let v1_0 = IdentificationData {
        version: RecordVersion::V1_0,
        ..real.clone()
    };
    let bytes = v1_0.to_vec().unwrap();
    assert_eq!(bytes.len(), tv6.len() - 6);
    assert_eq!(&bytes[4..6], &[1, 0]);
    assert_eq!(&bytes[6..], &tv6[12..]);
    assert_eq!(IdentificationData::parse(&bytes).unwrap(), v1_0);
    // Which cannot describe another API.
    let mut other = v1_0.clone();
    other.apis[0].api = 1;
    assert!(matches!(other.to_vec(), Err(EmitError::Inconsistent(_))));
}

#[test]
fn tv7_module_diff() {
    let tv7 = hex(TV7);
    let d = ModuleDiffBlock::parse(&tv7).unwrap();
    let m = &d.apis[0].modules;
    assert_eq!(
        (m[0].slot, m[0].state, m[0].submodules.len()),
        (2, ModuleState::NoModule, 0)
    );
    assert_eq!((m[1].slot, m[1].module_ident), (4, 0x17ff));
    assert_eq!(m[1].state, ModuleState::WrongModule);
    let s = m[1].submodules[0].state;
    assert_eq!(s.0, 0x9000);
    assert!(s.format_indicator() && !s.fault() && !s.maintenance_required());
    assert_eq!(d.to_vec().unwrap(), tv7);
}

#[test]
fn im1_to_im4() {
    let im1 = Im1 {
        tag_function: blank_padded("pressure sensor 7").unwrap(),
        tag_location: blank_padded("production hall 3").unwrap(),
    };
    let b = im1.to_bytes();
    assert_eq!(&b[..6], &[0x00, 0x21, 0x00, 0x38, 0x01, 0x00]);
    assert_eq!(&b[6..23], b"pressure sensor 7");
    assert_eq!(Im1::parse(&b), Ok(im1));
    let im2 = Im2 {
        date: blank_padded("2008-05-04 10:15").unwrap(),
    };
    let b = im2.to_bytes();
    assert_eq!(&b[..6], &[0x00, 0x22, 0x00, 0x12, 0x01, 0x00]);
    assert_eq!(Im2::parse(&b), Ok(im2));
    let b = Im3::default().to_bytes();
    assert_eq!(&b[..6], &[0x00, 0x23, 0x00, 0x38, 0x01, 0x00]);
    assert!(b[6..].iter().all(|&c| c == b' '));
    let b = Im4::default().to_bytes();
    assert_eq!(&b[..6], &[0x00, 0x24, 0x00, 0x38, 0x01, 0x00]);
    assert!(b[6..].iter().all(|&c| c == 0));
    // Another block type, a short block, a short buffer.
    assert_eq!(Im3::parse(&Im4::default().to_bytes()), Err(Error));
    assert_eq!(Im2::parse(&Im2::default().to_bytes()[..21]), Err(Error));
    assert!(Im1::default().emit(&mut [0; 59]).is_err());
}

#[test]
fn im0_filter_data() {
    let dap = IdentApi::group([(0, 0, 0x1, 1, 0x1)]);
    let f = Im0FilterData {
        submodules: IdentApi::group([(0, 0, 0x1, 1, 0x1), (0, 1, 0x30, 1, 0x130)]),
        modules: dap.clone(),
        device: dap,
    };
    let b = f.to_vec().unwrap();
    assert_eq!(b.len(), f.buffer_len());
    assert_eq!(&b[..6], &[0x00, 0x30, 0x00, 0x26, 0x01, 0x00]);
    assert_eq!(Im0FilterData::parse(&b), Ok(f.clone()));
    // The module block comes second, the device block last; empty lists have none.
    let module_at = 42;
    assert_eq!(&b[module_at..module_at + 2], &[0x00, 0x31]);
    let only = Im0FilterData {
        modules: vec![],
        device: vec![],
        ..f.clone()
    };
    assert_eq!(only.to_vec().unwrap(), b[..module_at]);
    assert_eq!(Im0FilterData::default().to_vec(), Ok(vec![]));
    // A kind twice, another block, another version: errors.
    let twice = [&b[..module_at], &b[..module_at]].concat();
    assert_eq!(Im0FilterData::parse(&twice), Err(Error));
    let mut other = b.clone();
    other[1] = 0x33;
    assert_eq!(Im0FilterData::parse(&other), Err(Error));
    let mut v = b.clone();
    v[5] = 1;
    assert_eq!(Im0FilterData::parse(&v), Err(Error));
}

#[test]
fn malformed_records() {
    let tv1 = hex(TV1);
    // Another version or type, a body shorter than the fixed part.
    let mut v = tv1.clone();
    v[5] = 2;
    assert_eq!(DiagnosisData::parse(&v), Err(Error));
    let mut t = tv1.clone();
    t[1] = 0x11;
    assert_eq!(DiagnosisData::parse(&t), Err(Error));
    let mut short = tv1[..18].to_vec();
    short[3] = 14;
    assert_eq!(DiagnosisData::parse(&short), Err(Error));
    // Channel data that is not whole entries is kept raw.
    let mut odd = tv1[..25].to_vec();
    odd[3] = 0x15;
    let d = DiagnosisData::parse(&odd).unwrap();
    assert!(matches!(d.item, AlarmItem::Other { usi: 0x8000, .. }));
    assert_eq!(d.to_vec().unwrap(), odd);
    // Version 1.0 with an API other than 0.
    let mut api = manual_block(RecordVersion::V1_0, 2, &[]);
    api.api = 3;
    assert!(matches!(api.to_vec(), Err(EmitError::Inconsistent(_))));
    // Identification lists that do not fill the block, or run past it.
    let tv5 = hex(TV5);
    let mut long = tv5.clone();
    long[3] += 2;
    long.extend_from_slice(&[0, 0]);
    assert_eq!(IdentificationData::parse(&long), Err(Error));
    assert_eq!(IdentificationData::parse(&tv5[..80]), Err(Error));
}

fn version() -> impl Strategy<Value = RecordVersion> {
    prop_oneof![Just(RecordVersion::V1_0), Just(RecordVersion::V1_1)]
}

fn diagnosis_data() -> impl Strategy<Value = DiagnosisData> {
    (
        version(),
        any::<(u32, u16, u16, u16, u16)>(),
        alarm_item(0..4),
    )
        .prop_map(
            |(version, (api, slot, subslot, ch, props), item)| DiagnosisData {
                version,
                api: if version == RecordVersion::V1_0 {
                    0
                } else {
                    api
                },
                slot,
                subslot,
                channel_number: ch,
                channel_properties: ChannelProperties(props),
                item,
            },
        )
}

fn apis() -> impl Strategy<Value = Vec<IdentApi>> {
    proptest::collection::vec(any::<(u32, u16, u32, u16, u32)>(), 0..8).prop_map(IdentApi::group)
}

fn identification() -> impl Strategy<Value = IdentificationData> {
    let kind = prop_oneof![
        Just(IdentificationKind::Expected),
        Just(IdentificationKind::Real)
    ];
    (kind, version(), apis()).prop_map(|(kind, version, mut apis)| {
        if version == RecordVersion::V1_0 {
            // Version 1.0 describes API 0 alone.
            let modules = apis.drain(..).flat_map(|a| a.modules).collect();
            apis = vec![IdentApi { api: 0, modules }];
        }
        IdentificationData {
            kind,
            version,
            apis,
        }
    })
}

proptest! {
    #[test]
    fn diagnosis_data_round_trip(d in diagnosis_data()) {
        let b = d.to_vec().unwrap();
        prop_assert_eq!(b.len(), d.buffer_len());
        prop_assert_eq!(DiagnosisData::parse(&b).unwrap(), d.clone());
        let record = DiagnosisData::record_to_vec(&[d.clone(), d.clone()]).unwrap();
        prop_assert_eq!(DiagnosisData::parse_record(&record).unwrap(), vec![d.clone(), d]);
    }

    #[test]
    fn identification_round_trip(i in identification()) {
        let b = i.to_vec().unwrap();
        prop_assert_eq!(b.len(), i.buffer_len());
        prop_assert_eq!(IdentificationData::parse(&b).unwrap(), i);
    }

    #[test]
    fn im0_filter_round_trip(submodules in apis(), modules in apis(), device in apis()) {
        let f = Im0FilterData { submodules, modules, device };
        let b = f.to_vec().unwrap();
        prop_assert_eq!(b.len(), f.buffer_len());
        prop_assert_eq!(Im0FilterData::parse(&b).unwrap(), f);
    }

    #[test]
    fn im_round_trip(a in any::<[u8; 32]>(), b in any::<[u8; 22]>(), c in any::<[u8; 16]>(),
                     d in proptest::collection::vec(any::<u8>(), 54)) {
        let im1 = Im1 { tag_function: a, tag_location: b };
        prop_assert_eq!(Im1::parse(&im1.to_bytes()), Ok(im1));
        let im2 = Im2 { date: c };
        prop_assert_eq!(Im2::parse(&im2.to_bytes()), Ok(im2));
        let arr: [u8; 54] = d.try_into().unwrap();
        let im3 = Im3 { descriptor: arr };
        prop_assert_eq!(Im3::parse(&im3.to_bytes()), Ok(im3));
        let im4 = Im4 { signature: arr };
        prop_assert_eq!(Im4::parse(&im4.to_bytes()), Ok(im4));
    }

    #[test]
    fn record_parsers_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        let _ = DiagnosisData::parse(&bytes);
        let _ = DiagnosisData::parse_record(&bytes);
        let _ = IdentificationData::parse(&bytes);
        let _ = Im0FilterData::parse(&bytes);
        let _ = Im1::parse(&bytes);
        let _ = Im2::parse(&bytes);
        let _ = Im3::parse(&bytes);
        let _ = Im4::parse(&bytes);
    }

    #[test]
    fn plausible_diagnosis_blocks_never_panic(
        v in 0u8..3,
        usi in prop_oneof![Just(0x8000u16), Just(0x8002u16), Just(0x8003u16), 0u16..0x8000],
        body in proptest::collection::vec(any::<u8>(), 0..60),
    ) {
        let mut b = vec![0x00, 0x10];
        b.extend_from_slice(&((body.len() + 16) as u16).to_be_bytes());
        b.extend_from_slice(&[1, v, 0, 0, 0, 0, 0, 1, 0, 1, 0x80, 0, 0x08, 0]);
        b.extend_from_slice(&usi.to_be_bytes());
        b.extend_from_slice(&body);
        if let Ok(d) = DiagnosisData::parse(&b) {
            prop_assert_eq!(d.to_vec().unwrap(), b);
        }
    }
}
