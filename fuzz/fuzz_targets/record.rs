// SPDX-License-Identifier: MIT OR Apache-2.0
//! Record services: IOD Read/Write request and response headers and the data they split off,
//! WriteMultiple requests and responses, I&M0, and record error statuses; the records a
//! device serves itself: diagnosis, identification, I&M1–I&M4 and I&M0FilterData.
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_profinet::wire::record::{
    DiagnosisData, IOD_HEADER_LEN, IdentificationData, Im0, Im0FilterData, Im1, Im2, Im3, Im4,
    IodHeader, IodKind, RecordError, join_write_multiple_to_vec, split_write_multiple,
    split_write_multiple_response, write_multiple_len,
};

fuzz_target!(|data: &[u8]| {
    if let Ok(h) = IodHeader::parse(data) {
        header(&h);
    }
    if let Ok((h, record, rest)) = IodHeader::split(data) {
        assert_eq!(IOD_HEADER_LEN + record.len() + rest.len(), data.len());
        if !h.kind.carries_data() {
            assert!(record.is_empty());
        }
        if h.is_write_multiple() && h.kind == IodKind::WriteReq {
            write_multiple(record);
        }
        // The record data of an I&M0 read, or of the other records a device serves.
        im0(record);
        served(record);
    }
    // The record data of a WriteMultiple without its outer header, and a response.
    write_multiple(data);
    if let Ok((outer, inner)) = split_write_multiple_response(data) {
        assert_eq!(outer.kind, IodKind::WriteRes);
        assert!(inner.iter().all(|h| h.kind == IodKind::WriteRes));
    }
    im0(data);
    served(data);
});

fn header(h: &IodHeader) {
    // What the kind carries survives; what it does not is left nil/0/OK by parsing.
    let bytes = h.to_bytes();
    assert_eq!(bytes.len(), h.buffer_len());
    assert_eq!(IodHeader::parse(&bytes), Ok(*h));
    assert_eq!(IodKind::from_block_type(h.kind.block_type()), Some(h.kind));
    assert!(!h.kind.response().is_request());
    if h.kind.is_request() {
        let res = h.response(h.record_data_length);
        assert_eq!(IodHeader::parse(&res.to_bytes()), Ok(res));
    }
    if let Some(e) = RecordError::from_status(h.status) {
        assert_eq!(e.status(), h.status);
        let _ = (e.to_string(), e.code.class());
    }
}

/// split → join → split gives the same writes.
fn write_multiple(data: &[u8]) {
    let Ok(writes) = split_write_multiple(data) else {
        return;
    };
    let joined = join_write_multiple_to_vec(&writes).expect("split writes join");
    assert_eq!(joined.len(), write_multiple_len(&writes));
    assert_eq!(joined.len() % 4, 0);
    assert_eq!(split_write_multiple(&joined), Ok(writes));
}

fn im0(data: &[u8]) {
    let Ok(i) = Im0::parse(data) else {
        return;
    };
    let _ = (
        i.order_id_str(),
        i.serial_number_str(),
        i.software_revision.to_string(),
    );
    let supported = (0..=16).filter(|&n| i.supports(n)).count();
    assert!(supported <= 15, "I&M1..15 only");
    let bytes = i.to_bytes();
    assert_eq!(bytes.len(), i.buffer_len());
    // Every byte but the block version, which parsing does not check and emits as 1.0.
    assert_eq!(&bytes[..4], &data[..4]);
    assert_eq!(&bytes[6..], &data[6..bytes.len()]);
    assert_eq!(Im0::parse(&bytes), Ok(i));
}

/// The records a device serves itself: what parses emits back.
fn served(data: &[u8]) {
    // A diagnosis record is whole blocks to its last byte, each kept as it is.
    if let Ok(blocks) = DiagnosisData::parse_record(data) {
        let bytes = DiagnosisData::record_to_vec(&blocks).expect("parsed blocks emit");
        assert_eq!(bytes, data);
    }
    // Identification lists fill their block exactly.
    if let Ok(i) = IdentificationData::parse(data) {
        let bytes = i.to_vec().expect("parsed identification emits");
        assert_eq!(&bytes[..], &data[..bytes.len()]);
    }
    // I&M0FilterData drops empty blocks and puts them in order: the same lists again.
    if let Ok(f) = Im0FilterData::parse(data) {
        let bytes = f.to_vec().expect("parsed filter data emits");
        assert_eq!(Im0FilterData::parse(&bytes), Ok(f));
    }
    // I&M1–I&M4: every byte but the block version, which parsing does not check.
    let same = |bytes: &[u8]| {
        assert_eq!(&bytes[..4], &data[..4]);
        assert_eq!(&bytes[6..], &data[6..bytes.len()]);
    };
    if let Ok(i) = Im1::parse(data) {
        same(&i.to_bytes());
    }
    if let Ok(i) = Im2::parse(data) {
        same(&i.to_bytes());
    }
    if let Ok(i) = Im3::parse(data) {
        same(&i.to_bytes());
    }
    if let Ok(i) = Im4::parse(data) {
        same(&i.to_bytes());
    }
}
