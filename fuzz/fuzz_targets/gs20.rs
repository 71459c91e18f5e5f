// SPDX-License-Identifier: MIT OR Apache-2.0
//! The GS20-PN host link: the input as one frame, as a frame type and data with a good CRC
//! (so that the message parsers see more than the CRC lets through), and as a UART byte
//! stream, fed in chunks with silences between some of them; every frame the stream decoder
//! yields is parsed as a message, and everything it yields drives the module's host-link
//! state machine, whose every answer must be a frame that parses.
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_gs20::frame::{FrameId, FrameRepr, MAX_FRAME_LEN};
use procimg_gs20::link::{Action, Baskets, ItemSlot, Link};
use procimg_gs20::messages::{AdapterMessage, AnyMessage, HostMessage, ItemId, StatusFlags};
use procimg_gs20::stream::{DEFAULT_GAP, Decoder};
use std::time::{Duration, Instant};

fuzz_target!(|data: &[u8]| {
    if let Ok(f) = FrameRepr::parse_bytes(data) {
        // What parses is whole: it emits back to the bytes it came from.
        assert_eq!(
            f.to_vec().expect("a parsed frame emits"),
            data[..f.buffer_len()]
        );
        message(&f);
    }
    if let Some((&id, payload)) = data.split_first()
        && let Some(id) = FrameId::from_u8(id)
        && id.payload_len().contains(payload.len())
    {
        message(&FrameRepr { id, payload });
    }
    stream(data);
});

/// Parses a good frame as a message; what parses emits back to the same frame.
fn message(f: &FrameRepr<'_>) {
    let bytes = f.to_vec().expect("a frame of an allowed length emits");
    let Ok(m) = AnyMessage::parse(f) else {
        return;
    };
    assert_eq!(m.id(), f.id);
    assert_eq!(m.to_vec().expect("a parsed message emits"), bytes);
    let _ = format!("{m:?}");
    // The checks of what the bytes mean never panic either.
    match m {
        AnyMessage::Host(HostMessage::AddItem(a)) => {
            if let Ok((item, slot)) = a.validate() {
                assert_eq!(item.to_u16(), a.item_id);
                assert_eq!(u32::from(slot), a.position);
                assert!(item.input_len() + item.output_len() > 0);
            }
        }
        AnyMessage::Host(HostMessage::SetNetworkConfig(c)) => {
            let _ = c.validate().map_err(|e| e.to_string());
            if let Ok(name) = c.station_name() {
                assert_eq!(name.len(), c.host_name.len());
            }
        }
        AnyMessage::Host(HostMessage::SetSocketOption(o)) => {
            let _ = o.option.data_len();
        }
        _ => {}
    }
}

/// The input as the UART's bytes: once in one go, once in chunks (sizes and silences drawn
/// from the input's own bytes).
fn stream(data: &[u8]) {
    let t0 = Instant::now();
    let mut whole = Decoder::new();
    let mut frames = 0u64;
    let mut link = link();
    whole.feed(data, t0, |r| {
        if let Ok(f) = &r {
            frames += 1;
            message(f);
        }
        drive(&mut link, r);
    });
    assert!(whole.buffered() <= MAX_FRAME_LEN);
    assert_eq!(whole.stats().frames, frames);

    let mut chunked = Decoder::new();
    let mut t = t0;
    let mut rest = data;
    let mut i = 0;
    while !rest.is_empty() {
        let b = data[i % data.len()];
        let n = (usize::from(b % 37) + 1).min(rest.len());
        if b & 0x80 != 0 {
            t += DEFAULT_GAP;
        } else {
            t += Duration::from_millis(u64::from(b & 3));
        }
        chunked.feed(&rest[..n], t, |r| {
            if let Ok(f) = r {
                message(&f);
            }
        });
        assert!(chunked.buffered() <= MAX_FRAME_LEN);
        if let Some(at) = chunked.poll_at() {
            assert!(at > t0);
        }
        rest = &rest[n..];
        i += 1;
    }
    // Whatever is left is given up after the silence, and the decoder is empty.
    let end = t + DEFAULT_GAP;
    while let Some(r) = chunked.poll(end) {
        let _ = r.map(|f| message(&f));
    }
    assert_eq!(chunked.buffered(), 0);
}

/// A module whose Ethernet link is up, with one basket (ID 1) to select.
fn link() -> Link {
    let mut baskets = Baskets::new();
    let items = [(3008, 1), (1002, 2)].map(|(id, slot)| ItemSlot {
        item: ItemId::from_u16(id).expect("catalogue items"),
        slot,
    });
    baskets.insert(1, items.to_vec());
    let mut link = Link::new(baskets);
    link.set_flags(StatusFlags::LINK_KNOWN | StatusFlags::LINK_UP);
    link
}

/// One item of the decoder into the link; its frames parse, its Start starts, and the Run
/// frames keep to their mode and lengths.
fn drive(link: &mut Link, item: Result<FrameRepr<'_>, procimg_gs20::stream::StreamError>) {
    let step = link.handle(item);
    for bytes in &step.send {
        let f = FrameRepr::parse_bytes(bytes).expect("the link sends whole frames");
        assert_eq!(f.buffer_len(), bytes.len());
        assert!(matches!(
            AdapterMessage::parse(&f),
            Ok(AdapterMessage::AdapterResponse(_))
        ));
    }
    for a in &step.actions {
        match a {
            Action::Start(station) => {
                assert!(!station.items.is_empty() && station.network.is_some());
                assert!(station.input_len() <= 384 && station.output_len() <= 384);
                link.started();
                let out = vec![0; station.output_len()];
                assert!(link.adapter_data(&out).is_some());
            }
            Action::SetInputs(data) => assert_eq!(data.len(), link.station().input_len()),
            Action::Warn(w) => {
                let _ = w.to_string();
            }
            Action::Reset | Action::Socket(_) => {}
        }
    }
}
