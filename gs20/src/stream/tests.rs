// SPDX-License-Identifier: MIT OR Apache-2.0
//! The stream decoder: frames back to back, split anywhere, with garbage, CRC errors, bad
//! LENs and silences between them.

use super::*;
use crate::frame::tests::any_frame;
use crate::frame::{MAX_IO_DATA, crc16};
use proptest::prelude::*;

static REQUEST_STATUS: [u8; 4] = [0x20, 0x00, 0x18, 0x70];
static REQUEST_START: [u8; 4] = [0x22, 0x00, 0x19, 0x10];
static ADD_ITEM: [u8; 10] = [0x03, 0x06, 0x0B, 0xC0, 0x00, 0x00, 0x00, 0x01, 0xA6, 0xB4];

/// What the decoder hands out, owned: the frame's bytes re-emitted, or the error.
#[derive(Debug, PartialEq, Eq)]
enum Out {
    Frame(Vec<u8>),
    Error(StreamError),
}

fn feed(d: &mut Decoder, bytes: &[u8], now: Instant) -> Vec<Out> {
    let mut out = Vec::new();
    d.feed(bytes, now, |r| {
        out.push(match r {
            Ok(f) => Out::Frame(f.to_vec().unwrap()),
            Err(e) => Out::Error(e),
        })
    });
    out
}

fn frames(bytes: &[&[u8]]) -> Vec<Out> {
    bytes.iter().map(|b| Out::Frame(b.to_vec())).collect()
}

#[test]
fn frames_back_to_back_and_byte_by_byte() {
    let all = [&REQUEST_STATUS[..], &ADD_ITEM, &REQUEST_START].concat();
    let t = Instant::now();
    let mut d = Decoder::new();
    assert_eq!(
        feed(&mut d, &all, t),
        frames(&[&REQUEST_STATUS, &ADD_ITEM, &REQUEST_START])
    );
    let mut d = Decoder::new();
    let mut out = Vec::new();
    for b in &all {
        out.extend(feed(&mut d, std::slice::from_ref(b), t));
    }
    assert_eq!(out, frames(&[&REQUEST_STATUS, &ADD_ITEM, &REQUEST_START]));
    assert_eq!(d.buffered(), 0);
    assert_eq!(
        d.stats(),
        DecoderStats {
            frames: 3,
            errors: 0,
            skipped_bytes: 0
        }
    );
}

#[test]
fn garbage_between_frames_is_one_error_and_skipped() {
    let t = Instant::now();
    let mut d = Decoder::new();
    let garbage = [0x00, 0xFF, 0x55, 0x13, 0x99];
    let all = [&REQUEST_STATUS[..], &garbage, &ADD_ITEM].concat();
    assert_eq!(
        feed(&mut d, &all, t),
        vec![
            Out::Frame(REQUEST_STATUS.to_vec()),
            Out::Error(StreamError::UnknownId(0x00)),
            Out::Frame(ADD_ITEM.to_vec()),
        ]
    );
    assert_eq!(d.stats().skipped_bytes, 5);
}

#[test]
fn a_crc_error_drops_the_frame_and_the_next_one_comes() {
    let t = Instant::now();
    let mut d = Decoder::new();
    let mut damaged = ADD_ITEM;
    damaged[5] ^= 0x10;
    let all = [&damaged[..], &REQUEST_STATUS].concat();
    let out = feed(&mut d, &all, t);
    assert!(
        matches!(
            out[0],
            Out::Error(StreamError::Crc {
                id: FrameId::AddItem,
                received: 0xB4A6,
                ..
            })
        ),
        "{out:?}"
    );
    assert_eq!(out[1..], frames(&[&REQUEST_STATUS]));
}

#[test]
fn a_frame_inside_a_broken_frames_length_is_found() {
    // The host starts Set Bus Data with 10 bytes, sends 2 of them, resets and sends Request
    // Status: the broken header's LEN reaches over the good frame, which is still found.
    let t = Instant::now();
    let mut d = Decoder::with_gap(None);
    let mut out = feed(&mut d, &[0x30, 0x00, 0x0A, 0x01, 0x02], t);
    out.extend(feed(&mut d, &REQUEST_STATUS, t));
    assert_eq!(out, []);
    // Bytes after it complete the broken candidate: its CRC fails, and the decoder goes
    // back to the byte after its start.
    out.extend(feed(&mut d, &[0xAA; 6], t));
    assert!(
        matches!(
            out[..],
            [
                Out::Error(StreamError::Crc {
                    id: FrameId::SetBusData,
                    ..
                }),
                Out::Frame(ref f),
                // The rest of the bytes are garbage after the good frame.
                Out::Error(StreamError::UnknownId(0xAA)),
            ] if f[..] == REQUEST_STATUS
        ),
        "{out:?}"
    );
}

#[test]
fn a_silence_gives_up_a_begun_frame() {
    let t = Instant::now();
    let mut d = Decoder::new();
    let mut out = feed(&mut d, &[0x30, 0x00, 0x0A, 0x01, 0x02], t);
    assert_eq!(d.poll_at(), Some(t + DEFAULT_GAP));
    // Not yet.
    assert!(d.poll(t + DEFAULT_GAP / 2).is_none());
    // The host resets and, after the silence, sends Request Status: it is answered at once.
    out.extend(feed(&mut d, &REQUEST_STATUS, t + DEFAULT_GAP));
    assert_eq!(
        out,
        vec![
            Out::Error(StreamError::Truncated {
                id: FrameId::SetBusData,
                needed: 15,
                received: 5
            }),
            Out::Frame(REQUEST_STATUS.to_vec()),
        ]
    );
    assert_eq!(d.buffered(), 0);
    assert_eq!(d.poll_at(), None);
    // The same when poll runs at the deadline, before any new byte.
    let mut d = Decoder::new();
    feed(&mut d, &ADD_ITEM[..7], t);
    assert_eq!(
        d.poll(t + DEFAULT_GAP),
        Some(Err(StreamError::Truncated {
            id: FrameId::AddItem,
            needed: 10,
            received: 7
        }))
    );
    assert!(d.poll(t + DEFAULT_GAP).is_none());
    assert_eq!(d.buffered(), 0);
}

#[test]
fn a_len_that_does_not_fit_is_a_frame_error() {
    let t = Instant::now();
    let mut d = Decoder::new();
    // Request Start with LEN 3.
    let mut bad = vec![0x22, 0x03, 1, 2, 3];
    bad.extend(crc16(&bad).to_le_bytes());
    // Set Bus Data with more than the largest image.
    let too_big = (MAX_IO_DATA as u16 + 1).to_be_bytes();
    let all = [
        &bad[..],
        &REQUEST_STATUS,
        &[0x30, too_big[0], too_big[1]],
        &REQUEST_START,
    ]
    .concat();
    assert_eq!(
        feed(&mut d, &all, t),
        vec![
            Out::Error(StreamError::BadLen {
                id: FrameId::RequestStart,
                len: 3
            }),
            Out::Frame(REQUEST_STATUS.to_vec()),
            Out::Error(StreamError::BadLen {
                id: FrameId::SetBusData,
                len: MAX_IO_DATA + 1
            }),
            Out::Frame(REQUEST_START.to_vec()),
        ]
    );
}

#[test]
fn buffering_is_bounded() {
    let t = Instant::now();
    let mut d = Decoder::with_gap(None);
    // A socket data header with the largest LEN, then noise: the decoder waits for the
    // whole candidate, never holds more than the largest frame, and finds the frame after.
    let mut noise = vec![0x50, 0x05, 0xC1];
    noise.extend((0..20_000u32).map(|i| {
        let b = (i.wrapping_mul(2_654_435_761) >> 24) as u8;
        if FrameId::from_u8(b).is_some() { 0 } else { b }
    }));
    let mut seen = 0;
    for chunk in noise.chunks(333) {
        let mut rest = chunk;
        while !rest.is_empty() {
            let n = d.push(rest, t);
            rest = &rest[n..];
            assert!(d.buffered() <= MAX_FRAME_LEN);
            while let Some(r) = d.poll(t) {
                assert!(r.is_err(), "noise is no frame");
                seen += 1;
            }
        }
    }
    assert_eq!(seen, 1, "one error for the whole noise");
    assert_eq!(feed(&mut d, &REQUEST_STATUS, t), frames(&[&REQUEST_STATUS]));
}

/// Bytes that are never a frame ID, so that no candidate frame can start in them.
fn non_id_garbage() -> impl Strategy<Value = Vec<u8>> {
    proptest::collection::vec(
        any::<u8>().prop_filter("not a frame ID", |&b| FrameId::from_u8(b).is_none()),
        0..12,
    )
}

/// Frames, each after a run of garbage, emitted.
fn frames_after_garbage(
    garbage: impl Strategy<Value = Vec<u8>>,
) -> impl Strategy<Value = Vec<(Vec<u8>, Vec<u8>)>> {
    proptest::collection::vec(
        (
            garbage,
            any_frame().prop_map(|(id, payload)| {
                crate::frame::FrameRepr {
                    id,
                    payload: &payload,
                }
                .to_vec()
                .unwrap()
            }),
        ),
        1..8,
    )
}

proptest! {
    #[test]
    fn frames_with_garbage_between_decode_to_the_same_frames(
        items in frames_after_garbage(non_id_garbage()),
        split in 1usize..40,
    ) {
        let t = Instant::now();
        let wire: Vec<u8> = items.iter().flat_map(|(g, f)| [&g[..], &f[..]].concat()).collect();
        let mut d = Decoder::with_gap(None);
        let mut out = Vec::new();
        for chunk in wire.chunks(split) {
            out.extend(feed(&mut d, chunk, t));
        }
        let (got, errors): (Vec<_>, Vec<_>) =
            out.into_iter().partition(|o| matches!(o, Out::Frame(_)));
        let want: Vec<Out> = items.iter().map(|(_, f)| Out::Frame(f.clone())).collect();
        prop_assert_eq!(got, want);
        // One error per run of garbage.
        prop_assert_eq!(errors.len(), items.iter().filter(|(g, _)| !g.is_empty()).count());
        prop_assert_eq!(d.buffered(), 0);
    }

    /// Any garbage at all — broken headers, frame prefixes cut short — followed by a silence:
    /// the frame after the silence comes whole.
    #[test]
    fn frames_after_any_garbage_and_a_silence_decode(
        items in frames_after_garbage(prop_oneof![
            proptest::collection::vec(any::<u8>(), 0..24),
            any_frame().prop_flat_map(|(id, payload)| {
                let v = crate::frame::FrameRepr { id, payload: &payload }.to_vec().unwrap();
                let n = v.len();
                (Just(v), 1..n).prop_map(|(v, cut)| v[..cut].to_vec())
            }),
        ]),
    ) {
        let mut t = Instant::now();
        let mut d = Decoder::new();
        let mut got = Vec::new();
        for (garbage, frame) in &items {
            got.extend(feed(&mut d, garbage, t));
            t += DEFAULT_GAP;
            got.extend(feed(&mut d, frame, t));
        }
        got.retain(|o| matches!(o, Out::Frame(_)));
        let want: Vec<Out> = items.iter().map(|(_, f)| Out::Frame(f.clone())).collect();
        prop_assert_eq!(got, want);
    }

    #[test]
    fn the_decoder_never_panics_and_stays_bounded(
        chunks in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..200), 0..20),
        steps in proptest::collection::vec(0u64..80, 20),
    ) {
        let mut t = Instant::now();
        let mut d = Decoder::new();
        for (chunk, ms) in chunks.iter().zip(steps.iter().cycle()) {
            t += Duration::from_millis(*ms);
            d.feed(chunk, t, |r| {
                if let Ok(f) = r {
                    // Every frame handed out is a whole, good frame.
                    let bytes = f.to_vec().unwrap();
                    assert_eq!(crate::frame::FrameRepr::parse_bytes(&bytes), Ok(f));
                }
            });
            prop_assert!(d.buffered() <= MAX_FRAME_LEN);
        }
    }
}
