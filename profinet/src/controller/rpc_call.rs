// SPDX-License-Identifier: MIT OR Apache-2.0
//! One outstanding connectionless RPC call of the controller: the request PDU, when to send
//! it again, and which datagram answers it.
//!
//! PNIO calls are idempotent, so a lost request or response is recovered by sending the same
//! PDU (same activity and sequence number) again; the server answers a repeat from its
//! cache. After the last attempt the call has failed.
//!
//! Calls and answers longer than one PDU travel as connectionless fragments: the request's
//! fragments go out together (a record is at most a few of them, well inside any server's
//! window), the server's FACKs are taken as they come, and the answer's fragments are
//! collected by number, each acknowledged with a FACK unless it says NoFack.

use super::ControllerAction;
use crate::wire::common::PnioStatus;
use crate::wire::rpc::{self, Header, MAX_PDU_LEN, Ndr, PacketType, flags1};
use crate::wire::{EmitError, EmitResult, Uuid};
use std::collections::BTreeMap;
use std::net::SocketAddrV4;

/// How long to wait for a response before sending the request again.
pub const RETRY_NS: u64 = 1_000_000_000;
/// Sends of one request before the call fails.
pub const ATTEMPTS: u32 = 3;

/// What came back for a call.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Answer {
    /// A response: its PNIOStatus and block bytes.
    Response {
        /// PNIOStatus from the NDR header.
        status: PnioStatus,
        /// The PNIO blocks.
        blocks: Vec<u8>,
    },
    /// A Reject or Fault PDU: the RPC layer refused the call (status from its body).
    Refused(u32),
}

/// What a datagram meant for a call.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Reply {
    /// It is not for this call.
    Foreign,
    /// A part of the answer (a fragment, or a FACK of ours); more is to come.
    Partial,
    /// The whole answer.
    Done(Answer),
}

/// The largest answer body collected from fragments (what the NDR lengths can describe).
const MAX_ANSWER_BODY: usize = 65_535;
/// The window we announce in our FACKs: fragments the server may send ahead.
const FACK_WINDOW: u16 = 8;

/// An outstanding call.
#[derive(Clone, Debug)]
pub struct RpcCall {
    /// The request PDUs as sent: one, or its fragments in order.
    pub pdus: Vec<Vec<u8>>,
    activity: Uuid,
    sequence_number: u32,
    /// Opnum, for messages.
    pub opnum: u16,
    sent_ns: u64,
    attempts: u32,
    /// The answer's fragments so far, by number, and the number of the last one.
    fragments: BTreeMap<u16, Vec<u8>>,
    last_fragment: Option<u16>,
    fragment_header: Option<Header>,
}

impl RpcCall {
    /// A call of `opnum` on the device interface of object `object`, carrying `blocks`.
    /// The NDR ArgsMaximum (the most response bytes we take) is the request's own length
    /// plus `more`, as the S7-1500 sets it: `more` is 0 except for a Read, where it is the
    /// record length asked for.
    pub fn new(
        object: Uuid,
        activity: Uuid,
        sequence_number: u32,
        opnum: u16,
        blocks: &[u8],
        more: u32,
        now_ns: u64,
    ) -> EmitResult<RpcCall> {
        // Little-endian NDR, as the S7-1500 sends it; devices answer in either order.
        let h = Header {
            little_endian: true,
            ..Header::request(
                object,
                rpc::DEVICE_INTERFACE,
                activity,
                sequence_number,
                opnum,
            )
        };
        let args_maximum = u32::try_from(blocks.len())
            .map_err(|_| EmitError::TooLong {
                field: "ArgsMaximum",
                value: blocks.len(),
                max: u32::MAX as usize,
            })?
            .saturating_add(more);
        let whole = rpc::emit_request(&h, args_maximum, blocks)?;
        let pdus = if whole.len() <= MAX_PDU_LEN {
            vec![whole]
        } else {
            rpc::fragments(&h, &whole[rpc::HEADER_LEN..], false)?
        };
        Ok(RpcCall {
            pdus,
            activity,
            sequence_number,
            opnum,
            sent_ns: now_ns,
            attempts: 1,
            fragments: BTreeMap::new(),
            last_fragment: None,
            fragment_header: None,
        })
    }

    /// What `datagram` means for this call; FACKs to send back are pushed to `facks`.
    pub fn take(&mut self, datagram: &[u8], facks: &mut Vec<Vec<u8>>) -> Reply {
        let Ok(packet) = rpc::Packet::new_checked(datagram) else {
            return Reply::Foreign;
        };
        let Ok(h) = Header::parse(&packet) else {
            return Reply::Foreign;
        };
        if h.activity != self.activity || h.sequence_number != self.sequence_number {
            return Reply::Foreign;
        }
        match h.packet_type {
            PacketType::Response if h.is_fragment() => self.fragment(&h, packet.body(), facks),
            PacketType::Response => match response(&h, packet.body()) {
                Some(a) => Reply::Done(a),
                None => Reply::Partial,
            },
            PacketType::Reject | PacketType::Fault => {
                let b = packet.body();
                let status = match b.get(..4) {
                    Some(s) if h.little_endian => u32::from_le_bytes([s[0], s[1], s[2], s[3]]),
                    Some(s) => u32::from_be_bytes([s[0], s[1], s[2], s[3]]),
                    None => 0,
                };
                Reply::Done(Answer::Refused(status))
            }
            // The server's FACKs of our fragments, pings answered, …: nothing to do.
            _ => Reply::Partial,
        }
    }

    fn fragment(&mut self, h: &Header, body: &[u8], facks: &mut Vec<Vec<u8>>) -> Reply {
        let n = h.fragment_number;
        let last = h.flags1 & flags1::LAST_FRAGMENT != 0;
        // Both constants are below 2^16, so the casts keep every bit.
        if !last
            && h.flags1 & flags1::NO_FACK == 0
            && let Ok(f) = rpc::fack(
                h,
                h.server_boot_time,
                FACK_WINDOW,
                MAX_ANSWER_BODY as u32,
                MAX_PDU_LEN as u32,
            )
        {
            facks.push(f);
        }
        if !self.fragments.contains_key(&n) {
            let held: usize = self.fragments.values().map(Vec::len).sum();
            if held.saturating_add(body.len()) > MAX_ANSWER_BODY {
                // More than any PNIO answer can be: start over, the retry brings it again.
                self.fragments.clear();
                self.last_fragment = None;
                return Reply::Partial;
            }
            self.fragments.insert(n, body.to_vec());
        }
        if n == 0 {
            self.fragment_header = Some(*h);
        }
        if last {
            self.last_fragment = Some(n);
        }
        let (Some(first), Some(last)) = (self.fragment_header, self.last_fragment) else {
            return Reply::Partial;
        };
        if self.fragments.len() != usize::from(last) + 1
            || self.fragments.keys().next_back() != Some(&last)
        {
            return Reply::Partial;
        }
        let body: Vec<u8> = core::mem::take(&mut self.fragments)
            .into_values()
            .flatten()
            .collect();
        self.last_fragment = None;
        match response(&first, &body) {
            Some(a) => Reply::Done(a),
            None => Reply::Partial,
        }
    }

    /// Sends the request (all its fragments) to `to`.
    pub fn send(&self, to: SocketAddrV4, out: &mut Vec<ControllerAction>) {
        out.extend(self.pdus.iter().map(|p| ControllerAction::Datagram {
            to,
            payload: p.clone(),
        }));
    }

    /// Whether the request should go out again now.
    pub fn retry_due(&self, now_ns: u64) -> bool {
        now_ns.saturating_sub(self.sent_ns) >= RETRY_NS && self.attempts < ATTEMPTS
    }

    /// Whether the call has run out of attempts and time.
    pub fn expired(&self, now_ns: u64) -> bool {
        now_ns.saturating_sub(self.sent_ns) >= RETRY_NS && self.attempts >= ATTEMPTS
    }

    /// Notes a repeated send at `now_ns`.
    pub fn resent(&mut self, now_ns: u64) {
        self.sent_ns = now_ns;
        self.attempts += 1;
    }

    /// When the call next needs attention.
    pub const fn deadline_ns(&self) -> u64 {
        self.sent_ns + RETRY_NS
    }
}

/// The answer in a whole response body.
fn response(h: &Header, body: &[u8]) -> Option<Answer> {
    let (ndr, blocks) = rpc::parse_body(PacketType::Response, h.little_endian, body).ok()?;
    let Ndr::Response(r) = ndr else { return None };
    let n = (r.args_length as usize).min(blocks.len());
    Some(Answer::Response {
        status: r.status,
        blocks: blocks[..n].to_vec(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const OBJECT: Uuid = rpc::object_uuid(1, 2, 3);
    const ACTIVITY: Uuid = rpc::object_uuid(9, 9, 9);

    fn call(blocks: &[u8]) -> RpcCall {
        RpcCall::new(OBJECT, ACTIVITY, 5, rpc::opnum::WRITE, blocks, 0, 0).unwrap()
    }

    /// The server's answer to `c` carrying `blocks`, in fragments, big-endian as devices
    /// answer.
    fn answer(c: &RpcCall, blocks: &[u8], no_fack: bool) -> Vec<Vec<u8>> {
        let req = Header::parse(&rpc::Packet::new_checked(&c.pdus[0]).unwrap()).unwrap();
        let reply = Header {
            little_endian: false,
            ..req.reply(7)
        };
        let mut body = vec![0u8; rpc::NDR_LEN];
        rpc::NdrResponse::for_blocks(PnioStatus::OK, 8192, blocks.len())
            .emit(&mut body, false)
            .unwrap();
        body.extend_from_slice(blocks);
        rpc::fragments(&reply, &body, no_fack).unwrap()
    }

    #[test]
    fn a_long_request_goes_out_in_numbered_fragments() {
        let blocks: Vec<u8> = (0..3000u32).map(|i| i as u8).collect();
        let c = call(&blocks);
        assert_eq!(c.pdus.len(), 3);
        let mut body = Vec::new();
        for (i, p) in c.pdus.iter().enumerate() {
            assert!(p.len() <= MAX_PDU_LEN);
            let packet = rpc::Packet::new_checked(p).unwrap();
            let h = Header::parse(&packet).unwrap();
            assert_eq!(h.fragment_number, i as u16);
            assert!(h.is_fragment());
            let last = h.flags1 & flags1::LAST_FRAGMENT != 0;
            assert_eq!(last, i == 2, "LastFragment on fragment {i}");
            body.extend_from_slice(packet.body());
        }
        let (_, b) = rpc::parse_body(PacketType::Request, true, &body).unwrap();
        assert_eq!(b, &blocks[..]);
        assert_eq!(call(&blocks[..100]).pdus.len(), 1);
    }

    #[test]
    fn a_fragmented_answer_is_collected_in_any_order_and_acknowledged() {
        let mut c = call(&[1, 2, 3]);
        let blocks: Vec<u8> = (0..3500u32).map(|i| (i * 3) as u8).collect();
        let mut frags = answer(&c, &blocks, false);
        assert_eq!(frags.len(), 3);
        frags.swap(0, 2);
        let mut facks = Vec::new();
        assert_eq!(c.take(&frags[0], &mut facks), Reply::Partial);
        assert_eq!(c.take(&frags[1], &mut facks), Reply::Partial);
        // A repeat changes nothing.
        assert_eq!(c.take(&frags[1], &mut facks), Reply::Partial);
        let Reply::Done(Answer::Response { status, blocks: b }) = c.take(&frags[2], &mut facks)
        else {
            panic!("the answer was not completed");
        };
        assert!(status.is_ok());
        assert_eq!(b, blocks);
        // Every fragment but the last is acknowledged with its number (the repeat again: its
        // first FACK may have been lost), as it came: 2 (last), 1, 1, 0.
        let numbers: Vec<u16> = facks
            .iter()
            .map(|f| {
                let h = Header::parse(&rpc::Packet::new_checked(f).unwrap()).unwrap();
                assert_eq!(h.packet_type, PacketType::Fack);
                h.fragment_number
            })
            .collect();
        assert_eq!(numbers, vec![1, 1, 0]);

        let mut c = call(&[1, 2, 3]);
        let mut facks = Vec::new();
        for f in answer(&c, &blocks, true) {
            let _ = c.take(&f, &mut facks);
        }
        assert!(facks.is_empty(), "NoFack fragments were acknowledged");
    }

    #[test]
    fn datagrams_of_other_calls_are_not_taken() {
        let mut c = call(&[1]);
        // Another activity's answer.
        let theirs = RpcCall::new(OBJECT, OBJECT, 5, 0, &[1], 0, 0).unwrap();
        let frags = answer(&theirs, &[0; 10], true);
        assert_eq!(c.take(&frags[0], &mut Vec::new()), Reply::Foreign);
        assert_eq!(c.take(&[0u8; 10], &mut Vec::new()), Reply::Foreign);
    }
}
