// SPDX-License-Identifier: MIT OR Apache-2.0
//! One RTA alarm channel (`profinet::rta`) driven by a sequence of operations: received PDUs
//! (as bytes, or built from sequence numbers so that the window logic is reached quickly),
//! alarm blocks to send, time, and aborts. Besides not panicking, the channel must only send
//! well-formed PDUs between its own endpoints, go quiet once aborted, and confirm only what
//! it has outstanding.
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_fuzz::ops::Reader;
use procimg_profinet::rta::{RtaChannel, RtaEvent};
use procimg_profinet::wire::alarm::{AlarmBlock, Priority};
use procimg_profinet::wire::common::blocks;
use procimg_profinet::wire::rta_pdu::{AbortCode, ErrRta, Packet, RtaBody, RtaPdu, RtaSequence};

const MS: u64 = 1_000_000;

struct Bench {
    ch: RtaChannel,
    priority: Priority,
    local: u16,
    remote: u16,
    now: u64,
}

fuzz_target!(|data: &[u8]| {
    let mut r = Reader::new(data);
    let Some(mut b) = bench(&mut r) else {
        return;
    };
    while op(&mut b, &mut r).is_some() {}
});

fn bench(r: &mut Reader<'_>) -> Option<Bench> {
    let priority = if r.u8()? % 2 == 0 {
        Priority::High
    } else {
        Priority::Low
    };
    let (local, remote) = (r.u16()?, r.u16()?);
    let (timeout_factor, retries) = (r.u16()?, r.u16()? % 16);
    let ch = if r.u8()? % 2 == 0 {
        RtaChannel::new(priority, local, remote, timeout_factor, retries)
    } else {
        let seq = RtaSequence::from_parts(r.u16()?, r.u16()?, r.u16()?, r.u16()?);
        RtaChannel::resume(priority, local, remote, timeout_factor, retries, seq)
    };
    Some(Bench {
        ch,
        priority,
        local,
        remote,
        now: MS,
    })
}

fn op(b: &mut Bench, r: &mut Reader<'_>) -> Option<()> {
    let mut out = Vec::new();
    let aborted = b.ch.is_aborted();
    let busy = b.ch.is_busy();
    let mut received_data = false;
    match r.u8()? % 5 {
        0 => {
            let bytes = r.bytes()?;
            if let Ok(p) = Packet::new_checked(bytes)
                && let Ok(pdu) = RtaPdu::parse(&p)
            {
                received_data = matches!(pdu.body, RtaBody::Data(_));
                b.ch.receive(&pdu, b.now, &mut out);
            }
        }
        1 => {
            let (kind, send_seq, ack_seq) = (r.u8()?, r.u16()?, r.u16()?);
            let (dst, src) = (b.local, b.remote);
            let pdu = match kind % 4 {
                0 => RtaPdu::data(b.priority, dst, src, send_seq, ack_seq, Vec::new()),
                1 => RtaPdu::ack(b.priority, dst, src, send_seq, ack_seq),
                2 => RtaPdu::nack(b.priority, dst, src, send_seq, ack_seq),
                _ => RtaPdu::err(
                    b.priority,
                    dst,
                    src,
                    send_seq,
                    ack_seq,
                    ErrRta::abort(AbortCode::from(kind / 4)),
                ),
            };
            received_data = kind % 4 == 0;
            b.ch.receive(&pdu, b.now, &mut out);
        }
        2 => {
            let bytes = r.bytes()?;
            let list: Vec<AlarmBlock> = blocks(bytes)
                .map_while(Result::ok)
                .filter_map(|(_, block)| AlarmBlock::parse(block).ok())
                .collect();
            b.ch.send(list, b.now, &mut out);
        }
        3 => {
            b.now = b.now.saturating_add(u64::from(r.u16()?) * MS);
            b.ch.poll(b.now, &mut out);
        }
        _ => b.ch.abort(AbortCode::from(r.u8()?), &mut out),
    }
    if aborted {
        assert!(out.is_empty(), "an aborted channel still acts: {out:?}");
    }
    for e in &out {
        match e {
            RtaEvent::Send(pdu) => {
                assert_eq!(pdu.priority, b.priority);
                assert_eq!(
                    (pdu.header.dst_endpoint, pdu.header.src_endpoint),
                    (b.remote, b.local)
                );
                let v = pdu.to_vec().expect("sent PDUs emit");
                let q = Packet::new_checked(&v[..]).expect("sent PDUs are whole");
                assert_eq!(RtaPdu::parse(&q).as_ref(), Ok(pdu));
            }
            RtaEvent::Deliver(_) => assert!(received_data, "delivered without DATA"),
            RtaEvent::Confirmed => assert!(busy, "confirmed with nothing outstanding"),
            RtaEvent::Abort { .. } => assert!(b.ch.is_aborted()),
        }
    }
    Some(())
}
