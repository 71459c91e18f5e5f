// SPDX-License-Identifier: MIT OR Apache-2.0
//! One outstanding connectionless RPC call of the controller: the request PDU, when to send
//! it again, and which datagram answers it.
//!
//! PNIO calls are idempotent, so a lost request or response is recovered by sending the same
//! PDU (same activity and sequence number) again; the server answers a repeat from its
//! cache. After the last attempt the call has failed.

use super::super::wire::common::PnioStatus;
use super::super::wire::rpc::{self, Header, Ndr, PacketType};
use super::super::wire::{Result, Uuid};

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

/// An outstanding call.
#[derive(Clone, Debug)]
pub struct RpcCall {
    /// The request PDU as sent.
    pub pdu: Vec<u8>,
    activity: Uuid,
    sequence_number: u32,
    /// Opnum, for messages.
    pub opnum: u16,
    sent_ns: u64,
    attempts: u32,
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
    ) -> Result<RpcCall> {
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
        Ok(RpcCall {
            pdu: rpc::emit_request(&h, (blocks.len() as u32).saturating_add(more), blocks)?,
            activity,
            sequence_number,
            opnum,
            sent_ns: now_ns,
            attempts: 1,
        })
    }

    /// The answer in `datagram`, if it answers this call.
    pub fn answer(&self, datagram: &[u8]) -> Option<Answer> {
        let packet = rpc::Packet::new_checked(datagram).ok()?;
        let h = Header::parse(&packet).ok()?;
        if h.activity != self.activity || h.sequence_number != self.sequence_number {
            return None;
        }
        match h.packet_type {
            PacketType::Response => {
                let (ndr, blocks) =
                    rpc::parse_body(PacketType::Response, h.little_endian, packet.body()).ok()?;
                let Ndr::Response(r) = ndr else { return None };
                let n = (r.args_length as usize).min(blocks.len());
                Some(Answer::Response {
                    status: r.status,
                    blocks: blocks[..n].to_vec(),
                })
            }
            PacketType::Reject | PacketType::Fault => {
                let b = packet.body();
                let status = match b.get(..4) {
                    Some(s) if h.little_endian => u32::from_le_bytes([s[0], s[1], s[2], s[3]]),
                    Some(s) => u32::from_be_bytes([s[0], s[1], s[2], s[3]]),
                    None => 0,
                };
                Some(Answer::Refused(status))
            }
            _ => None,
        }
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
