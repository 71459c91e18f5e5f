// SPDX-License-Identifier: MIT OR Apache-2.0
//! A whole PDU as plain data: header fields, the optional context, the payload.

use super::codec::{Reader, Writer, octets_len};
use super::{
    ByteOrder, EmitError, Flags, HEADER_LEN, Header, HeaderRepr, MAX_PAYLOAD_LEN, ParseError, Pdu,
};

/// One AgentX PDU.
///
/// The header's NETWORK_BYTE_ORDER and NON_DEFAULT_CONTEXT flags are not in `flags`:
/// they follow from `byte_order` and `context` when the PDU is written, and set them when
/// it is parsed.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct PduRepr {
    /// The order of every multi-byte field.
    pub byte_order: ByteOrder,
    /// INSTANCE_REGISTRATION, NEW_INDEX and ANY_INDEX (other bits are dropped).
    pub flags: Flags,
    /// h.sessionID: the master's number for the session (0 in Open).
    pub session_id: u32,
    /// h.transactionID: one SNMP request's PDUs share it.
    pub transaction_id: u32,
    /// h.packetID: a Response repeats its request's.
    pub packet_id: u32,
    /// The non-default context, for the types that carry one
    /// ([`PduType::carries_context`](super::PduType::carries_context)).
    pub context: Option<Vec<u8>>,
    /// The payload.
    pub pdu: Pdu,
}

impl PduRepr {
    /// A PDU in network byte order without flags or context.
    pub fn new(session_id: u32, transaction_id: u32, packet_id: u32, pdu: Pdu) -> PduRepr {
        PduRepr {
            byte_order: ByteOrder::Big,
            flags: Flags::default(),
            session_id,
            transaction_id,
            packet_id,
            context: None,
            pdu,
        }
    }

    /// Parses exactly one PDU: `bytes` holds its header and payload_length bytes more
    /// ([`frame_len`](super::frame_len) tells how many that is on a stream).
    pub fn parse(bytes: &[u8]) -> Result<PduRepr, ParseError> {
        let header = HeaderRepr::parse(&Header::new_checked(bytes)?)?;
        let expected = super::frame_len(bytes)?.ok_or(ParseError::Truncated { field: "header" })?;
        if bytes.len() != expected {
            return Err(ParseError::Length {
                expected,
                given: bytes.len(),
            });
        }
        let byte_order = header.byte_order();
        let mut r = Reader::new(bytes.get(HEADER_LEN..).unwrap_or_default(), byte_order);
        let context = if header.flags.contains(Flags::NON_DEFAULT_CONTEXT)
            && header.pdu_type.carries_context()
        {
            Some(r.octets("context")?.to_vec())
        } else {
            None
        };
        let pdu = Pdu::read(header.pdu_type, &mut r)?;
        Ok(PduRepr {
            byte_order,
            flags: Flags(header.flags.0 & Flags::REPR_MASK),
            session_id: header.session_id,
            transaction_id: header.transaction_id,
            packet_id: header.packet_id,
            context,
            pdu,
        })
    }

    /// The payload's length: the context (if any) and the PDU's own fields.
    fn payload_len(&self) -> usize {
        self.context.as_ref().map_or(0, |c| octets_len(c.len())) + self.pdu.wire_len()
    }

    /// The PDU's length on the wire: 20 + payload_length.
    pub fn buffer_len(&self) -> usize {
        HEADER_LEN + self.payload_len()
    }

    /// The header this PDU is sent with.
    pub fn header(&self) -> Result<HeaderRepr, EmitError> {
        let pdu_type = self.pdu.pdu_type();
        if self.context.is_some() && !pdu_type.carries_context() {
            return Err(EmitError::ContextNotCarried(pdu_type));
        }
        let payload_len = self.payload_len();
        let payload_length = u32::try_from(payload_len)
            .ok()
            .filter(|len| *len <= MAX_PAYLOAD_LEN)
            .ok_or(EmitError::PayloadTooLong(payload_len))?;
        let mut flags = Flags(self.flags.0 & Flags::REPR_MASK);
        if self.byte_order == ByteOrder::Big {
            flags = flags.union(Flags::NETWORK_BYTE_ORDER);
        }
        if self.context.is_some() {
            flags = flags.union(Flags::NON_DEFAULT_CONTEXT);
        }
        Ok(HeaderRepr {
            pdu_type,
            flags,
            session_id: self.session_id,
            transaction_id: self.transaction_id,
            packet_id: self.packet_id,
            payload_length,
        })
    }

    /// Writes the PDU into the front of `buffer`; returns its length, `buffer_len()`.
    pub fn emit(&self, buffer: &mut [u8]) -> Result<usize, EmitError> {
        let header = self.header()?;
        let needed = self.buffer_len();
        if buffer.len() < needed {
            return Err(EmitError::BufferTooShort {
                needed,
                got: buffer.len(),
            });
        }
        header.emit(buffer)?;
        let mut w = Writer::new(
            buffer.get_mut(HEADER_LEN..).unwrap_or_default(),
            self.byte_order,
        );
        if let Some(context) = &self.context {
            w.octets(context)?;
        }
        self.pdu.write(&mut w)?;
        Ok(HEADER_LEN + w.position())
    }

    /// The PDU's bytes.
    pub fn to_bytes(&self) -> Result<Vec<u8>, EmitError> {
        let mut bytes = vec![0; self.buffer_len()];
        let len = self.emit(&mut bytes)?;
        bytes.truncate(len);
        Ok(bytes)
    }
}
