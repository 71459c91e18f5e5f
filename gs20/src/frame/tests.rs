// SPDX-License-Identifier: MIT OR Apache-2.0
//! The frame codec against the reference's bytes (§1.4), its errors, and its properties.

use super::*;
use proptest::prelude::*;

/// Request Status, Request Reset and Request Start as the reference prints them.
static REQUEST_STATUS: [u8; 4] = [0x20, 0x00, 0x18, 0x70];
static REQUEST_RESET: [u8; 4] = [0x21, 0x00, 0x19, 0xE0];
static REQUEST_START: [u8; 4] = [0x22, 0x00, 0x19, 0x10];
/// Add Item 3008 (0x0BC0) at slot 1.
static ADD_ITEM: [u8; 10] = [0x03, 0x06, 0x0B, 0xC0, 0x00, 0x00, 0x00, 0x01, 0xA6, 0xB4];
/// The module's answer: Config mode with the error flag, error "no network configuration",
/// PROFINET, version 1.
static ADAPTER_RESPONSE: [u8; 10] = [0xF0, 0x06, 0x00, 0x03, 0x00, 0x04, 0x02, 0x01, 0xEC, 0x2E];

/// CRC-16/Modbus bit by bit, straight from its definition: an oracle independent of the
/// `crc` crate's tables.
fn modbus_by_bits(bytes: &[u8]) -> u16 {
    let mut crc = 0xFFFF_u16;
    for &b in bytes {
        crc ^= u16::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xA001
            } else {
                crc >> 1
            };
        }
    }
    crc
}

#[test]
fn crc_is_modbus_low_byte_first() {
    // The check value of CRC-16/Modbus.
    assert_eq!(crc16(b"123456789"), 0x4B37);
    for frame in [
        &REQUEST_STATUS[..],
        &REQUEST_RESET,
        &REQUEST_START,
        &ADD_ITEM,
        &ADAPTER_RESPONSE,
    ] {
        let (covered, sent) = frame.split_at(frame.len() - 2);
        assert_eq!(crc16(covered).to_le_bytes(), sent, "{frame:02X?}");
        assert_eq!(modbus_by_bits(covered), crc16(covered));
    }
}

#[test]
fn deconstruct_add_item() {
    let f = Frame::new_checked(&ADD_ITEM[..]).unwrap();
    assert_eq!(f.id(), Some(FrameId::AddItem));
    assert_eq!(f.len_width(), LenWidth::One);
    assert_eq!(f.payload_len(), 6);
    assert_eq!(f.payload(), &[0x0B, 0xC0, 0, 0, 0, 1]);
    assert_eq!(f.crc(), 0xB4A6);
    assert_eq!(f.computed_crc(), 0xB4A6);
    let repr = FrameRepr::parse(&f).unwrap();
    assert_eq!(repr.id, FrameId::AddItem);
    assert_eq!(repr.buffer_len(), ADD_ITEM.len());
}

#[test]
fn construct_the_reference_frames() {
    for bytes in [
        &REQUEST_STATUS[..],
        &REQUEST_RESET,
        &REQUEST_START,
        &ADD_ITEM,
        &ADAPTER_RESPONSE,
    ] {
        let repr = FrameRepr::parse_bytes(bytes).unwrap();
        let mut buf = [0xA5; 16];
        assert_eq!(repr.emit(&mut buf), Ok(bytes.len()));
        assert_eq!(&buf[..bytes.len()], bytes);
        // Nothing past the frame is touched.
        assert!(buf[bytes.len()..].iter().all(|&b| b == 0xA5));
    }
}

#[test]
fn two_byte_len_is_big_endian_and_data_starts_at_index_3() {
    let data: Vec<u8> = (0..300).map(|i| i as u8).collect();
    let v = FrameRepr {
        id: FrameId::SetBusData,
        payload: &data,
    }
    .to_vec()
    .unwrap();
    assert_eq!(&v[..3], &[0x30, 0x01, 0x2C]);
    assert_eq!(&v[3..303], &data[..]);
    assert_eq!(v.len(), 305);
    assert_eq!(
        u16::from_le_bytes([v[303], v[304]]),
        modbus_by_bits(&v[..303])
    );
    let f = Frame::new_checked(&v[..]).unwrap();
    assert_eq!(f.len_width(), LenWidth::Two);
    assert_eq!(FrameRepr::parse(&f).unwrap().payload, &data[..]);
}

#[test]
fn the_len_widths_of_the_reference() {
    for id in FrameId::ALL {
        let two = matches!(id.as_u8(), 0x30 | 0x31 | 0x50 | 0x51 | 0xE1);
        assert_eq!(id.len_width() == LenWidth::Two, two, "{id}");
        assert_eq!(FrameId::from_u8(id.as_u8()), Some(id));
    }
    let known = (0..=255u8)
        .filter(|&b| FrameId::from_u8(b).is_some())
        .count();
    assert_eq!(known, FrameId::ALL.len());
}

#[test]
fn errors() {
    assert_eq!(
        FrameRepr::parse_bytes(&[]),
        Err(FrameError::Truncated { needed: 2, len: 0 })
    );
    assert_eq!(
        FrameRepr::parse_bytes(&[0x99, 0, 0, 0]),
        Err(FrameError::UnknownId(0x99))
    );
    assert_eq!(
        FrameRepr::parse_bytes(&ADD_ITEM[..9]),
        Err(FrameError::Truncated { needed: 10, len: 9 })
    );
    assert_eq!(
        FrameRepr::parse_bytes(&[0x30, 0x01]),
        Err(FrameError::Truncated { needed: 3, len: 2 })
    );
    // Request Status with one data byte: LEN does not fit the type.
    let mut bad = vec![0x20, 0x01, 0x00];
    bad.extend(crc16(&bad).to_le_bytes());
    assert_eq!(
        FrameRepr::parse_bytes(&bad),
        Err(FrameError::BadLen {
            id: FrameId::RequestStatus,
            len: 1
        })
    );
    let mut damaged = ADD_ITEM;
    damaged[7] = 2;
    assert!(matches!(
        FrameRepr::parse_bytes(&damaged),
        Err(FrameError::Crc {
            id: FrameId::AddItem,
            received: 0xB4A6,
            ..
        })
    ));
    // A 0x30 over the largest image is "frame too large".
    let big = vec![0; MAX_IO_DATA + 1];
    let repr = FrameRepr {
        id: FrameId::SetBusData,
        payload: &big,
    };
    assert_eq!(
        repr.to_vec(),
        Err(EmitError::BadLen {
            id: FrameId::SetBusData,
            len: MAX_IO_DATA + 1
        })
    );
    let mut short = [0; 9];
    assert_eq!(
        FrameRepr::parse_bytes(&ADD_ITEM).unwrap().emit(&mut short),
        Err(EmitError::BufferTooShort { needed: 10, len: 9 })
    );
    // Every error tells what to do.
    let e = FrameError::BadLen {
        id: FrameId::AddItem,
        len: 5,
    };
    assert!(e.to_string().contains("exactly 6 bytes"), "{e}");
}

/// A frame type and data of a length it allows.
pub(crate) fn any_frame() -> impl Strategy<Value = (FrameId, Vec<u8>)> {
    proptest::sample::select(&FrameId::ALL[..]).prop_flat_map(|id| {
        let r = id.payload_len();
        // Long data is rare on the wire and slow to shrink: mostly short frames.
        let max = r.max.min(r.min + 64);
        (
            Just(id),
            prop_oneof![
                4 => proptest::collection::vec(any::<u8>(), r.min..=max),
                1 => proptest::collection::vec(any::<u8>(), r.min..=r.max),
            ],
        )
    })
}

proptest! {
    #[test]
    fn emit_then_parse_is_the_same_frame((id, payload) in any_frame()) {
        let repr = FrameRepr { id, payload: &payload };
        let bytes = repr.to_vec().unwrap();
        prop_assert_eq!(bytes.len(), repr.buffer_len());
        prop_assert_eq!(FrameRepr::parse_bytes(&bytes), Ok(repr));
        // Any one damaged byte is caught: a CRC error, or the header no longer fits.
        let at = bytes.len() / 2;
        let mut damaged = bytes.clone();
        damaged[at] ^= 0x5A;
        prop_assert_ne!(FrameRepr::parse_bytes(&damaged), Ok(repr));
    }

    #[test]
    fn parse_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
        let f = Frame::new_unchecked(&bytes[..]);
        let _ = (f.raw_id(), f.id(), f.payload_len(), f.frame_len());
        if let Ok(repr) = FrameRepr::parse(&f) {
            // What parses emits to the same bytes.
            prop_assert_eq!(&repr.to_vec().unwrap()[..], &bytes[..repr.buffer_len()]);
        }
    }
}
