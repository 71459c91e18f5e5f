// SPDX-License-Identifier: MIT OR Apache-2.0
//! RTA (acyclic real-time, RTA_CLASS_1) PDUs over Ethernet: the frames that carry alarms.
//!
//! The PDU starts at the FrameID, i.e. at the Ethernet payload behind the optional 802.1Q tag
//! and the EtherType 0x8892. FrameID 0xFC01 carries high-priority alarms (sent with PCP 6),
//! 0xFE01 low-priority ones (PCP 5):
//!
//! ```text
//! FrameID(2) AlarmDstEndpoint(2) AlarmSrcEndpoint(2) PDUType(1) AddFlags(1)
//! SendSeqNum(2) AckSeqNum(2) VarPartLen(2) VarPart…
//! ```
//!
//! PDUType: low nibble the type (1 DATA, 2 NACK, 3 ACK, 4 ERR), high nibble the version (1).
//! AddFlags: low nibble WindowSize (1), bit 4 TACK (the sender wants a transport ack); bits
//! 5–7 are reserved: ignored by [`RtaHeader::parse`], written as 0.
//!
//! The VarPart of a DATA-RTA holds PNIO blocks: one [`AlarmNotification`] or [`AlarmAck`]
//! in practice (their codecs are in [`super::alarm`]). An ERR-RTA carries a PNIOStatus (`CF 81 FD <abort code>`, see [`ErrRta`]),
//! possibly followed by vendor data; ACK- and NACK-RTA carry nothing. Bytes after VarPartLen
//! are Ethernet padding (an S7 pads with stale bytes, not zeros) and are ignored.
//!
//! Sequence numbers ([`next_seq`], [`RtaSequence`]): one DATA-RTA in flight per priority and
//! direction. Numbers start at [`SEQ_INITIAL`] (0xFFFF; the "last" value before the first
//! is [`SEQ_INITIAL_LAST`], 0xFFFE), then run 0x0000..=0x7FFF and wrap to 0x0000.
//!
//! Everything is big-endian. Alarms are not on the cyclic path, so the Reprs own their data.

use super::alarm::{AlarmAck, AlarmBlock, AlarmNotification, Priority};
use super::common::blocks;
use super::cursor::{Reader, Writer};
use super::{EmitError, EmitResult, Error, Field, Rest, Result, be16, check_announced_len};

mod err;
mod sequence;
pub use err::{AbortCode, ERROR_CODE_RTA, ERROR_CODE1_RTA_PROTOCOL, ERROR_DECODE_PNIO, ErrRta};
pub use sequence::{Received, RtaSequence, SEQ_INITIAL, SEQ_INITIAL_LAST, SEQ_MAX, next_seq};

/// The RTA version (high nibble of PDUType).
pub const RTA_VERSION: u8 = 1;
/// The only window size RTA_CLASS_1 uses.
pub const WINDOW_SIZE: u8 = 1;

mod field {
    use super::{Field, Rest};
    pub const FRAME_ID: Field = 0..2;
    pub const DST_ENDPOINT: Field = 2..4;
    pub const SRC_ENDPOINT: Field = 4..6;
    pub const PDU_TYPE: usize = 6;
    pub const ADD_FLAGS: usize = 7;
    pub const SEND_SEQ: Field = 8..10;
    pub const ACK_SEQ: Field = 10..12;
    pub const VAR_PART_LEN: Field = 12..14;
    pub const VAR_PART: Rest = 14..;
}

/// Bytes from the FrameID to the VarPart.
pub const HEADER_LEN: usize = field::VAR_PART.start;
/// Bytes of the RTA header proper (after the FrameID), what [`RtaHeader`] covers.
pub const RTA_HEADER_LEN: usize = HEADER_LEN - field::DST_ENDPOINT.start;

/// AddFlags: the WindowSize nibble.
const ADD_FLAGS_WINDOW: u8 = 0x0f;
/// AddFlags: TACK.
const ADD_FLAGS_TACK: u8 = 0x10;

coded_enum! {
    /// The type of an RTA PDU: the low nibble of PDUType (the high nibble is the version).
    pub enum PduType(u8) display "PDUType({})" {
        /// 1: DATA-RTA, carries an alarm block.
        Data = 1 => "DATA",
        /// 2: NACK-RTA.
        Nack = 2 => "NACK",
        /// 3: ACK-RTA (transport acknowledgement).
        Ack = 3 => "ACK",
        /// 4: ERR-RTA (abort).
        Err = 4 => "ERR",
    }
}

impl PduType {
    /// The type in a PDUType byte: its low nibble (the version nibble is ignored).
    pub const fn from_pdu_type_byte(b: u8) -> PduType {
        PduType::from_raw(b & 0x0f)
    }

    /// The PDUType byte of this type and `version`: both are nibbles, higher bits are dropped.
    pub const fn pdu_type_byte(self, version: u8) -> u8 {
        (version << 4) | (self.raw() & 0x0f)
    }
}

buffer_view! {
    /// A view of an RTA PDU, from the FrameID on.
    pub struct Packet;
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// Checks the buffer holds the header and the VarPartLen bytes it announces. Bytes after
    /// them (Ethernet padding) are allowed and ignored.
    pub fn check_len(&self) -> Result<()> {
        check_announced_len(self.buffer.as_ref(), field::VAR_PART_LEN, HEADER_LEN)
    }

    /// FrameID (0xFC01 or 0xFE01 for RTA).
    pub fn frame_id(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::FRAME_ID])
    }

    /// AlarmDstEndpoint: the receiver's LocalAlarmReference.
    pub fn dst_endpoint(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::DST_ENDPOINT])
    }

    /// AlarmSrcEndpoint: the sender's LocalAlarmReference.
    pub fn src_endpoint(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::SRC_ENDPOINT])
    }

    /// The PDU type (low nibble of PDUType).
    pub fn pdu_type(&self) -> PduType {
        PduType::from_pdu_type_byte(self.buffer.as_ref()[field::PDU_TYPE])
    }

    /// The RTA version (high nibble of PDUType; 1).
    pub fn version(&self) -> u8 {
        self.buffer.as_ref()[field::PDU_TYPE] >> 4
    }

    /// The raw AddFlags byte.
    pub fn add_flags(&self) -> u8 {
        self.buffer.as_ref()[field::ADD_FLAGS]
    }

    /// WindowSize (low nibble of AddFlags; 1).
    pub fn window_size(&self) -> u8 {
        self.add_flags() & ADD_FLAGS_WINDOW
    }

    /// TACK: the sender asks for an ACK-RTA.
    pub fn tack(&self) -> bool {
        self.add_flags() & ADD_FLAGS_TACK != 0
    }

    /// SendSeqNum.
    pub fn send_seq(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::SEND_SEQ])
    }

    /// AckSeqNum.
    pub fn ack_seq(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::ACK_SEQ])
    }

    /// VarPartLen.
    pub fn var_part_len(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::VAR_PART_LEN])
    }

    /// The VarPart: exactly VarPartLen bytes, Ethernet padding excluded. Empty if the buffer is
    /// too short (never the case after `check_len`).
    pub fn var_part(&self) -> &[u8] {
        let end = HEADER_LEN + usize::from(self.var_part_len());
        self.buffer
            .as_ref()
            .get(field::VAR_PART.start..end)
            .unwrap_or(&[])
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Packet<T> {
    /// Sets the FrameID.
    pub fn set_frame_id(&mut self, v: u16) {
        self.buffer.as_mut()[field::FRAME_ID].copy_from_slice(&v.to_be_bytes());
    }

    /// Sets AlarmDstEndpoint.
    pub fn set_dst_endpoint(&mut self, v: u16) {
        self.buffer.as_mut()[field::DST_ENDPOINT].copy_from_slice(&v.to_be_bytes());
    }

    /// Sets AlarmSrcEndpoint.
    pub fn set_src_endpoint(&mut self, v: u16) {
        self.buffer.as_mut()[field::SRC_ENDPOINT].copy_from_slice(&v.to_be_bytes());
    }

    /// Sets PDUType from a type and a version (both nibbles; higher bits are dropped).
    pub fn set_pdu_type(&mut self, pdu_type: PduType, version: u8) {
        self.buffer.as_mut()[field::PDU_TYPE] = pdu_type.pdu_type_byte(version);
    }

    /// Sets AddFlags from a window size (a nibble) and TACK.
    pub fn set_add_flags(&mut self, window_size: u8, tack: bool) {
        let tack = if tack { ADD_FLAGS_TACK } else { 0 };
        self.buffer.as_mut()[field::ADD_FLAGS] = (window_size & ADD_FLAGS_WINDOW) | tack;
    }

    /// Sets SendSeqNum.
    pub fn set_send_seq(&mut self, v: u16) {
        self.buffer.as_mut()[field::SEND_SEQ].copy_from_slice(&v.to_be_bytes());
    }

    /// Sets AckSeqNum.
    pub fn set_ack_seq(&mut self, v: u16) {
        self.buffer.as_mut()[field::ACK_SEQ].copy_from_slice(&v.to_be_bytes());
    }

    /// Sets VarPartLen.
    pub fn set_var_part_len(&mut self, v: u16) {
        self.buffer.as_mut()[field::VAR_PART_LEN].copy_from_slice(&v.to_be_bytes());
    }

    /// The VarPart, mutable: VarPartLen bytes (empty if the buffer is too short).
    pub fn var_part_mut(&mut self) -> &mut [u8] {
        let end = HEADER_LEN + usize::from(self.var_part_len());
        self.buffer
            .as_mut()
            .get_mut(field::VAR_PART.start..end)
            .unwrap_or(&mut [])
    }
}

impl<T: AsRef<[u8]>> core::fmt::Display for Packet<T> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match RtaPdu::parse(&Packet::new_unchecked(self.buffer.as_ref())) {
            Ok(r) => write!(f, "{r}"),
            Err(_) => f.write_str("RTA (malformed)"),
        }
    }
}

/// The 12-byte RTA header (after the FrameID).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RtaHeader {
    /// AlarmDstEndpoint: the receiver's LocalAlarmReference (from the AlarmCR block of the
    /// other side).
    pub dst_endpoint: u16,
    /// AlarmSrcEndpoint: the sender's LocalAlarmReference.
    pub src_endpoint: u16,
    /// PDU type.
    pub pdu_type: PduType,
    /// Version nibble ([`RTA_VERSION`]).
    pub version: u8,
    /// WindowSize nibble ([`WINDOW_SIZE`]).
    pub window_size: u8,
    /// TACK: the sender wants an ACK-RTA (set in DATA-RTA).
    pub tack: bool,
    /// SendSeqNum.
    pub send_seq: u16,
    /// AckSeqNum.
    pub ack_seq: u16,
    /// VarPartLen: bytes of VarPart that follow.
    pub var_part_len: u16,
}

impl RtaHeader {
    /// A version-1, window-1 header; TACK is set for DATA only.
    pub const fn new(
        pdu_type: PduType,
        dst_endpoint: u16,
        src_endpoint: u16,
        send_seq: u16,
        ack_seq: u16,
        var_part_len: u16,
    ) -> RtaHeader {
        RtaHeader {
            dst_endpoint,
            src_endpoint,
            pdu_type,
            version: RTA_VERSION,
            window_size: WINDOW_SIZE,
            tack: matches!(pdu_type, PduType::Data),
            send_seq,
            ack_seq,
            var_part_len,
        }
    }

    /// Parses the header from the first [`RTA_HEADER_LEN`] bytes of `b` (which starts at
    /// AlarmDstEndpoint, i.e. right after the FrameID).
    pub fn parse(b: &[u8]) -> Result<RtaHeader> {
        let mut r = Reader::new(b);
        let dst_endpoint = r.u16()?;
        let src_endpoint = r.u16()?;
        let pdu = r.u8()?;
        let flags = r.u8()?;
        Ok(RtaHeader {
            dst_endpoint,
            src_endpoint,
            pdu_type: PduType::from_pdu_type_byte(pdu),
            version: pdu >> 4,
            window_size: flags & ADD_FLAGS_WINDOW,
            tack: flags & ADD_FLAGS_TACK != 0,
            send_seq: r.u16()?,
            ack_seq: r.u16()?,
            var_part_len: r.u16()?,
        })
    }

    /// Bytes of the header ([`RTA_HEADER_LEN`]).
    pub const fn buffer_len(&self) -> usize {
        RTA_HEADER_LEN
    }

    /// Writes the header into the first [`RTA_HEADER_LEN`] bytes of `buf` (the bytes after
    /// the FrameID). `version` and `window_size` are nibbles; higher bits are dropped. A
    /// shorter buffer gives [`EmitError::BufferTooShort`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        EmitError::check_len("RTA header", RTA_HEADER_LEN, buf.len())?;
        let mut w = Writer::new("RTA header", buf);
        w.u16(self.dst_endpoint)?;
        w.u16(self.src_endpoint)?;
        let tack = if self.tack { ADD_FLAGS_TACK } else { 0 };
        w.put(&[
            self.pdu_type.pdu_type_byte(self.version),
            (self.window_size & ADD_FLAGS_WINDOW) | tack,
        ])?;
        w.u16(self.send_seq)?;
        w.u16(self.ack_seq)?;
        w.u16(self.var_part_len)
    }
}

/// What an RTA PDU carries; it determines the PDU type.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum RtaBody {
    /// DATA-RTA: the blocks of the VarPart (one in practice; possibly none).
    Data(Vec<AlarmBlock>),
    /// NACK-RTA.
    Nack,
    /// ACK-RTA.
    Ack,
    /// ERR-RTA.
    Err(ErrRta),
}

impl RtaBody {
    /// The PDU type of this body.
    pub const fn pdu_type(&self) -> PduType {
        match self {
            RtaBody::Data(_) => PduType::Data,
            RtaBody::Nack => PduType::Nack,
            RtaBody::Ack => PduType::Ack,
            RtaBody::Err(_) => PduType::Err,
        }
    }

    /// Bytes of the VarPart.
    pub fn var_part_len(&self) -> usize {
        match self {
            RtaBody::Data(blocks) => blocks
                .iter()
                .fold(0usize, |n, b| n.saturating_add(b.buffer_len())),
            RtaBody::Nack | RtaBody::Ack => 0,
            RtaBody::Err(e) => e.buffer_len(),
        }
    }
}

/// A parsed RTA PDU, from the FrameID to the end of the VarPart.
///
/// `header.pdu_type` and `header.var_part_len` describe what was parsed; [`RtaPdu::emit`]
/// writes the PDU type and VarPartLen of `body` instead, so a changed body needs no header
/// update.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct RtaPdu {
    /// The priority (from the FrameID).
    pub priority: Priority,
    /// The RTA header.
    pub header: RtaHeader,
    /// The VarPart.
    pub body: RtaBody,
}

impl RtaPdu {
    /// Parses a PDU (checking its length first). A FrameID other than 0xFC01/0xFE01, an unknown
    /// PDU type, an ACK/NACK with a VarPart, an ERR shorter than its PNIOStatus or DATA blocks
    /// that do not split or decode give [`Error`].
    pub fn parse<T: AsRef<[u8]> + ?Sized>(packet: &Packet<&T>) -> Result<RtaPdu> {
        packet.check_len()?;
        let priority = Priority::from_frame_id(packet.frame_id()).ok_or(Error)?;
        let b: &[u8] = packet.buffer.as_ref();
        let header = RtaHeader::parse(b.get(field::DST_ENDPOINT.start..).ok_or(Error)?)?;
        let var = packet.var_part();
        let body = match header.pdu_type {
            PduType::Data => RtaBody::Data(
                blocks(var)
                    .map(|r| r.and_then(|(_, block)| AlarmBlock::parse(block)))
                    .collect::<Result<Vec<_>>>()?,
            ),
            PduType::Ack if var.is_empty() => RtaBody::Ack,
            PduType::Nack if var.is_empty() => RtaBody::Nack,
            PduType::Err => RtaBody::Err(ErrRta::parse(var)?),
            _ => return Err(Error),
        };
        Ok(RtaPdu {
            priority,
            header,
            body,
        })
    }

    pub(super) fn new(
        priority: Priority,
        dst_endpoint: u16,
        src_endpoint: u16,
        send_seq: u16,
        ack_seq: u16,
        body: RtaBody,
    ) -> RtaPdu {
        // Only describes the body: `emit` writes VarPartLen from the body and refuses one
        // over 65535 bytes, so the saturated value never reaches the wire.
        let len = u16::try_from(body.var_part_len()).unwrap_or(u16::MAX);
        RtaPdu {
            priority,
            header: RtaHeader::new(
                body.pdu_type(),
                dst_endpoint,
                src_endpoint,
                send_seq,
                ack_seq,
                len,
            ),
            body,
        }
    }

    /// A DATA-RTA (version 1, window 1, TACK) carrying `blocks`.
    pub fn data(
        priority: Priority,
        dst_endpoint: u16,
        src_endpoint: u16,
        send_seq: u16,
        ack_seq: u16,
        blocks: Vec<AlarmBlock>,
    ) -> RtaPdu {
        let body = RtaBody::Data(blocks);
        RtaPdu::new(
            priority,
            dst_endpoint,
            src_endpoint,
            send_seq,
            ack_seq,
            body,
        )
    }

    /// An ACK-RTA: `send_seq` is the sender's last sent DATA, `ack_seq` the DATA acknowledged.
    pub fn ack(
        priority: Priority,
        dst_endpoint: u16,
        src_endpoint: u16,
        send_seq: u16,
        ack_seq: u16,
    ) -> RtaPdu {
        RtaPdu::new(
            priority,
            dst_endpoint,
            src_endpoint,
            send_seq,
            ack_seq,
            RtaBody::Ack,
        )
    }

    /// A NACK-RTA.
    pub fn nack(
        priority: Priority,
        dst_endpoint: u16,
        src_endpoint: u16,
        send_seq: u16,
        ack_seq: u16,
    ) -> RtaPdu {
        RtaPdu::new(
            priority,
            dst_endpoint,
            src_endpoint,
            send_seq,
            ack_seq,
            RtaBody::Nack,
        )
    }

    /// An ERR-RTA.
    pub fn err(
        priority: Priority,
        dst_endpoint: u16,
        src_endpoint: u16,
        send_seq: u16,
        ack_seq: u16,
        err: ErrRta,
    ) -> RtaPdu {
        RtaPdu::new(
            priority,
            dst_endpoint,
            src_endpoint,
            send_seq,
            ack_seq,
            RtaBody::Err(err),
        )
    }

    /// The transport ACK-RTA for the DATA-RTA `received` from a side that has sent no
    /// DATA-RTA yet: endpoints swapped, SendSeqNum [`SEQ_INITIAL_LAST`], AckSeqNum the received
    /// SendSeqNum.
    pub fn first_ack_of(priority: Priority, received: &RtaHeader) -> RtaPdu {
        RtaPdu::ack(
            priority,
            received.src_endpoint,
            received.dst_endpoint,
            SEQ_INITIAL_LAST,
            received.send_seq,
        )
    }

    /// The first DATA-RTA of a side, answering the DATA-RTA `received` with `blocks` (an
    /// AlarmAck in practice): endpoints swapped, SendSeqNum [`SEQ_INITIAL`], acknowledging
    /// `received`.
    pub fn first_reply_to(
        priority: Priority,
        received: &RtaHeader,
        blocks: Vec<AlarmBlock>,
    ) -> RtaPdu {
        RtaPdu::data(
            priority,
            received.src_endpoint,
            received.dst_endpoint,
            SEQ_INITIAL,
            received.send_seq,
            blocks,
        )
    }

    /// Bytes of the PDU from the FrameID on, without Ethernet padding.
    pub fn buffer_len(&self) -> usize {
        HEADER_LEN.saturating_add(self.body.var_part_len())
    }

    /// Writes the PDU into the first [`buffer_len`](Self::buffer_len) bytes of `buf` (a slice
    /// starting at the FrameID; the caller adds the Ethernet header and pads the frame). Never
    /// panics: a shorter buffer or a VarPart above 65535 bytes give [`EmitError`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        let var_part_len = self.body.var_part_len();
        let var_len = u16::try_from(var_part_len)
            .map_err(|_| EmitError::too_long_u16("VarPartLen", var_part_len))?;
        let total = self.buffer_len();
        let len = buf.len();
        let pdu = buf.get_mut(..total).ok_or(EmitError::BufferTooShort {
            what: "RTA PDU",
            needed: total,
            len,
        })?;
        let (head, var) = pdu.split_at_mut(HEADER_LEN);
        head[field::FRAME_ID].copy_from_slice(&self.priority.frame_id().to_be_bytes());
        let header = RtaHeader {
            pdu_type: self.body.pdu_type(),
            var_part_len: var_len,
            ..self.header
        };
        header.emit(&mut head[field::DST_ENDPOINT.start..])?;
        let mut w = Writer::new("RTA VarPart", var);
        match &self.body {
            RtaBody::Data(blocks) => blocks.iter().try_for_each(|b| b.write(&mut w))?,
            RtaBody::Nack | RtaBody::Ack => {}
            RtaBody::Err(e) => e.write(&mut w)?,
        }
        w.finish()
    }

    /// The PDU as a new vector of [`buffer_len`](Self::buffer_len) bytes.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b))
    }

    /// The first AlarmNotification of a DATA-RTA.
    pub fn notification(&self) -> Option<&AlarmNotification> {
        match &self.body {
            RtaBody::Data(blocks) => blocks.iter().find_map(|b| match b {
                AlarmBlock::Notification(n) => Some(n),
                _ => None,
            }),
            _ => None,
        }
    }

    /// The first AlarmAck of a DATA-RTA.
    pub fn alarm_ack(&self) -> Option<&AlarmAck> {
        match &self.body {
            RtaBody::Data(blocks) => blocks.iter().find_map(|b| match b {
                AlarmBlock::Ack(a) => Some(a),
                _ => None,
            }),
            _ => None,
        }
    }
}

impl core::fmt::Display for RtaPdu {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let h = &self.header;
        write!(
            f,
            "RTA {} {} {:#06x}->{:#06x} send={:#06x} ack={:#06x}",
            self.priority,
            self.body.pdu_type(),
            h.src_endpoint,
            h.dst_endpoint,
            h.send_seq,
            h.ack_seq
        )?;
        match &self.body {
            RtaBody::Data(blocks) => {
                for b in blocks {
                    match b {
                        AlarmBlock::Notification(n) => write!(
                            f,
                            " [AlarmNotification {} api={} slot={:#06x}/{:#06x} seq={}]",
                            n.alarm_type, n.api, n.slot, n.subslot, n.specifier.sequence_number
                        )?,
                        AlarmBlock::Ack(a) => write!(
                            f,
                            " [AlarmAck {} api={} slot={:#06x}/{:#06x} seq={} {}]",
                            a.alarm_type,
                            a.api,
                            a.slot,
                            a.subslot,
                            a.specifier.sequence_number,
                            a.status
                        )?,
                        AlarmBlock::Other { block_type, .. } => {
                            write!(f, " [block {:#06x}]", block_type.raw())?
                        }
                    }
                }
                Ok(())
            }
            RtaBody::Nack | RtaBody::Ack => Ok(()),
            RtaBody::Err(e) => write!(f, " {e}"),
        }
    }
}
