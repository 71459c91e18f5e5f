// SPDX-License-Identifier: MIT OR Apache-2.0
//! The connectionless DCE/RPC plumbing of the device: the server side of port 34964
//! (duplicate requests answered from a cache, fragment reassembly with FACK, ping, reject,
//! fragmented responses) and the client side of the one call a device makes, the
//! ApplicationReady CControl.
//!
//! A CL server must answer a retransmitted request (same activity, same sequence number) with
//! the response it already sent, without executing the call again: a PNIO controller
//! retransmits when a response is lost and a Write or PrmEnd executed twice would be wrong.
//! Most calls complete at once; one whose records the application answers is still being
//! carried out for a while: the device drops retransmissions of it and answers pings with
//! "working" (see [`super::delegated_records`]).

use super::DeviceAction;
use crate::wire::control::ControlBlock;
use crate::wire::rpc::{self, Header, MAX_PDU_LEN, NDR_LEN, Ndr, NdrResponse, PacketType, flags1};
use crate::wire::{PnioStatus, Uuid};
use std::collections::{BTreeMap, VecDeque};
use std::net::SocketAddrV4;

/// Reject status: the interface is not served here (DCE `nca_unk_if`).
pub(super) const NCA_UNKNOWN_INTERFACE: u32 = 0x1c01_0003;
/// Reject status: the operation number is out of range (DCE `nca_op_rng_error`).
pub(super) const NCA_OP_RANGE_ERROR: u32 = 0x1c01_0002;

/// ServerBootTime in our responses. p-net sends 0 too; a client only compares it between
/// calls, and a simulated device never reboots under a running activity.
const SERVER_BOOT_TIME: u32 = 0;
/// Activities whose last response is kept for duplicates (one per controller connection is
/// enough; a few more cover tools reading records alongside).
const CACHE_LEN: usize = 8;
/// Calls being reassembled at the same time.
const MAX_PARTIAL: usize = 4;
/// Largest reassembled request body: the NDR header caps PNIO bodies at what fits 16 bits.
const MAX_REASSEMBLED: usize = 65_535;
/// Window size we announce in a FACK: fragments the client may send ahead.
const FACK_WINDOW: u16 = 8;

/// The PDU `header` describes with `body` after it: LengthOfBody set, header in its DREP.
pub(super) fn pdu(header: &Header, body: &[u8]) -> Option<Vec<u8>> {
    rpc::emit_with_body(header, body).ok()
}

/// A response kept for duplicates.
struct Cached {
    activity: Uuid,
    seq: u32,
    datagrams: Vec<Vec<u8>>,
}

/// A fragmented request being collected.
struct Partial {
    activity: Uuid,
    seq: u32,
    first: Option<Header>,
    fragments: BTreeMap<u16, Vec<u8>>,
    last: Option<u16>,
    bytes: usize,
}

/// The server side of the device's RPC endpoint.
#[derive(Default)]
pub(super) struct Server {
    cache: VecDeque<Cached>,
    partial: Vec<Partial>,
}

impl Server {
    /// A request PDU (`body` = its LengthOfBody bytes) from `from`. Answers duplicates from
    /// the cache and collects fragments; returns a whole new call to execute (its header with
    /// the fragment flags cleared, and its body) or `None` when nothing is left to do.
    pub(super) fn request(
        &mut self,
        header: &Header,
        body: &[u8],
        from: SocketAddrV4,
        out: &mut Vec<DeviceAction>,
    ) -> Option<(Header, Vec<u8>)> {
        if let Some(c) = self.cache.iter().find(|c| c.activity == header.activity) {
            if c.seq == header.sequence_number {
                resend(c, from, out);
                return None;
            }
            if header.sequence_number < c.seq {
                // An old call of this activity, overtaken by a newer one: no answer.
                return None;
            }
        }
        if !header.is_fragment() {
            return Some((*header, body.to_vec()));
        }
        self.fragment(header, body, from, out)
    }

    fn fragment(
        &mut self,
        header: &Header,
        body: &[u8],
        from: SocketAddrV4,
        out: &mut Vec<DeviceAction>,
    ) -> Option<(Header, Vec<u8>)> {
        let i = match self
            .partial
            .iter()
            .position(|p| p.activity == header.activity && p.seq == header.sequence_number)
        {
            Some(i) => i,
            None => {
                // A new call of this activity replaces an unfinished older one.
                self.partial.retain(|p| p.activity != header.activity);
                if self.partial.len() >= MAX_PARTIAL {
                    self.partial.remove(0);
                }
                self.partial.push(Partial {
                    activity: header.activity,
                    seq: header.sequence_number,
                    first: None,
                    fragments: BTreeMap::new(),
                    last: None,
                    bytes: 0,
                });
                self.partial.len() - 1
            }
        };
        let p = &mut self.partial[i];
        let n = header.fragment_number;
        if !p.fragments.contains_key(&n) {
            p.bytes = p.bytes.saturating_add(body.len());
            if p.bytes > MAX_REASSEMBLED {
                self.partial.remove(i);
                return None;
            }
            p.fragments.insert(n, body.to_vec());
        }
        if n == 0 {
            p.first = Some(*header);
        }
        let last = header.flags1 & flags1::LAST_FRAGMENT != 0;
        if last {
            p.last = Some(n);
        }
        if !last && header.flags1 & flags1::NO_FACK == 0 {
            fack(header, from, out);
        }
        let (Some(first), Some(last)) = (p.first, p.last) else {
            return None;
        };
        if p.fragments.len() != usize::from(last) + 1
            || p.fragments.keys().next_back() != Some(&last)
        {
            return None;
        }
        let p = self.partial.remove(i);
        let body: Vec<u8> = p.fragments.into_values().flatten().collect();
        let header = Header {
            flags1: first.flags1 & !(flags1::FRAGMENT | flags1::LAST_FRAGMENT),
            fragment_number: 0,
            ..first
        };
        Some((header, body))
    }

    /// Answers `request` with a PNIO response: the NDR response header (MaximumCount = the
    /// request's ArgsMaximum) and `blocks`, fragmented when it does not fit one PDU, in the
    /// request's DREP. Keeps it for duplicates.
    pub(super) fn respond(
        &mut self,
        request: &Header,
        to: SocketAddrV4,
        status: PnioStatus,
        args_maximum: u32,
        blocks: &[u8],
        out: &mut Vec<DeviceAction>,
    ) {
        let mut body = vec![0u8; NDR_LEN];
        let ndr = NdrResponse::for_blocks(status, args_maximum, blocks.len());
        if ndr.emit(&mut body, request.little_endian).is_err() {
            return;
        }
        body.extend_from_slice(blocks);
        let reply = request.reply(SERVER_BOOT_TIME);
        // NoFack: the client need not acknowledge our fragments; they are few and small, and
        // a lost one is repaired by the client's retry.
        let datagrams = rpc::fragments(&reply, &body, true).unwrap_or_default();
        let cached = Cached {
            activity: request.activity,
            seq: request.sequence_number,
            datagrams,
        };
        resend(&cached, to, out);
        self.cache.retain(|c| c.activity != request.activity);
        if self.cache.len() >= CACHE_LEN {
            self.cache.pop_front();
        }
        self.cache.push_back(cached);
    }

    /// Rejects `request` (unknown interface or operation): a reject PDU whose body is the
    /// DCE status in the request's DREP.
    pub(super) fn reject(
        &mut self,
        request: &Header,
        to: SocketAddrV4,
        nca_status: u32,
        out: &mut Vec<DeviceAction>,
    ) {
        let h = Header {
            packet_type: PacketType::Reject,
            ..request.reply(SERVER_BOOT_TIME)
        };
        let body = if request.little_endian {
            nca_status.to_le_bytes()
        } else {
            nca_status.to_be_bytes()
        };
        if let Some(d) = pdu(&h, &body) {
            out.push(datagram(to, d));
        }
    }

    /// A ping: the call is finished (its response goes out again) or unknown (no-call).
    pub(super) fn ping(
        &mut self,
        header: &Header,
        from: SocketAddrV4,
        out: &mut Vec<DeviceAction>,
    ) {
        match self
            .cache
            .iter()
            .find(|c| c.activity == header.activity && c.seq == header.sequence_number)
        {
            Some(c) => resend(c, from, out),
            None => {
                let h = Header {
                    packet_type: PacketType::NoCall,
                    ..header.reply(SERVER_BOOT_TIME)
                };
                if let Some(d) = pdu(&h, &[]) {
                    out.push(datagram(from, d));
                }
            }
        }
    }

    /// A ping for a call that is still being carried out: "working".
    pub(super) fn working(&self, header: &Header, from: SocketAddrV4, out: &mut Vec<DeviceAction>) {
        let h = Header {
            packet_type: PacketType::Working,
            ..header.reply(SERVER_BOOT_TIME)
        };
        if let Some(d) = pdu(&h, &[]) {
            out.push(datagram(from, d));
        }
    }

    /// The client acknowledged our response: it needs no retransmission any more.
    pub(super) fn ack(&mut self, header: &Header) {
        self.cache
            .retain(|c| !(c.activity == header.activity && c.seq == header.sequence_number));
    }
}

/// A datagram from the RPC port.
fn datagram(to: SocketAddrV4, payload: Vec<u8>) -> DeviceAction {
    DeviceAction::Datagram {
        to,
        from_port: rpc::RPC_PORT,
        payload,
    }
}

fn resend(c: &Cached, to: SocketAddrV4, out: &mut Vec<DeviceAction>) {
    out.extend(c.datagrams.iter().map(|d| datagram(to, d.clone())));
}

/// Acknowledges one request fragment (see [`rpc::fack`]).
fn fack(fragment: &Header, to: SocketAddrV4, out: &mut Vec<DeviceAction>) {
    // Both constants are below 2^16, so the casts keep every bit.
    if let Ok(d) = rpc::fack(
        fragment,
        SERVER_BOOT_TIME,
        FACK_WINDOW,
        MAX_REASSEMBLED as u32,
        MAX_PDU_LEN as u32,
    ) {
        out.push(datagram(to, d));
    }
}

/// The UDP port the device's RPC client sends from (p-net's choice; the controller answers
/// to whatever port the request came from).
pub(super) const CLIENT_PORT: u16 = 0xc001;
/// ArgsMaximum of our requests: the response size we accept (p-net's value).
const CLIENT_ARGS_MAXIMUM: u32 = 1340;

/// What a PDU means for an outstanding client call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum CallOutcome {
    /// Not about this call.
    NotOurs,
    /// The server is still at it, or asked for nothing: keep waiting.
    Pending,
    /// A positive response that answers the request.
    Confirmed,
    /// A negative or wrong response, a fault or a reject.
    Failed,
}

/// One outstanding request of the device's RPC client (the ApplicationReady CControl),
/// retransmitted until its response arrives.
pub(super) struct ClientCall {
    header: Header,
    to: SocketAddrV4,
    datagram: Vec<u8>,
    sent_ns: u64,
    transmissions: u32,
    request: ControlBlock,
}

impl ClientCall {
    /// Retransmission interval (p-net's).
    pub(super) const RETRY_NS: u64 = 2_000_000_000;
    /// Transmissions before the call counts as failed (p-net's: the first and 2 retries).
    pub(super) const TRANSMISSIONS: u32 = 3;

    /// A Control request (opnum 4) carrying `request` and then `extra` blocks, to `to` on the
    /// controller interface with object `object`, on a new `activity` (sequence 0). Big-endian,
    /// idempotent, as p-net sends it.
    pub(super) fn control(
        request: ControlBlock,
        extra: &[u8],
        object: Uuid,
        activity: Uuid,
        to: SocketAddrV4,
    ) -> Option<ClientCall> {
        let header = Header::request(
            object,
            rpc::CONTROLLER_INTERFACE,
            activity,
            0,
            rpc::opnum::CONTROL,
        );
        let mut blocks = request.to_bytes().to_vec();
        blocks.extend_from_slice(extra);
        let datagram = rpc::emit_request(&header, CLIENT_ARGS_MAXIMUM, &blocks).ok()?;
        Some(ClientCall {
            header,
            to,
            datagram,
            sent_ns: 0,
            transmissions: 0,
            request,
        })
    }

    /// Sends (or resends) the request.
    pub(super) fn transmit(&mut self, now_ns: u64, out: &mut Vec<DeviceAction>) {
        self.sent_ns = now_ns;
        self.transmissions = self.transmissions.saturating_add(1);
        out.push(DeviceAction::Datagram {
            to: self.to,
            from_port: CLIENT_PORT,
            payload: self.datagram.clone(),
        });
    }

    /// When [`poll`](Self::poll) has something to do.
    pub(super) fn deadline(&self) -> u64 {
        self.sent_ns.saturating_add(ClientCall::RETRY_NS)
    }

    /// Retransmits when the interval passed; `false` when every transmission is used up.
    pub(super) fn poll(&mut self, now_ns: u64, out: &mut Vec<DeviceAction>) -> bool {
        if now_ns < self.deadline() {
            return true;
        }
        if self.transmissions >= ClientCall::TRANSMISSIONS {
            return false;
        }
        self.transmit(now_ns, out);
        true
    }

    /// A PDU (header and body) that may belong to this call.
    pub(super) fn on_pdu(
        &mut self,
        header: &Header,
        body: &[u8],
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> CallOutcome {
        if header.activity != self.header.activity
            || header.sequence_number != self.header.sequence_number
        {
            return CallOutcome::NotOurs;
        }
        match header.packet_type {
            PacketType::Response if !header.is_fragment() => {
                let Ok((Ndr::Response(ndr), blocks)) =
                    rpc::parse_body(PacketType::Response, header.little_endian, body)
                else {
                    return CallOutcome::Failed;
                };
                let answered = ndr.status.is_ok()
                    && ndr.is_consistent(blocks.len())
                    && ControlBlock::parse(blocks).is_ok_and(|b| b.answers(&self.request));
                if answered {
                    CallOutcome::Confirmed
                } else {
                    CallOutcome::Failed
                }
            }
            PacketType::Fault | PacketType::Reject => CallOutcome::Failed,
            PacketType::Working => {
                // The controller is busy with the call: wait a full interval again.
                self.sent_ns = now_ns;
                CallOutcome::Pending
            }
            PacketType::NoCall => {
                // The request was lost: send it again now rather than after the interval.
                if self.transmissions < ClientCall::TRANSMISSIONS {
                    self.transmit(now_ns, out);
                }
                CallOutcome::Pending
            }
            _ => CallOutcome::Pending,
        }
    }
}
