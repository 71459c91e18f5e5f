// SPDX-License-Identifier: MIT OR Apache-2.0
//! Whole PNIO calls: a PDU with its RPC header, NDR header and blocks, parsed or emitted in
//! one step, split into fragments, and the FACK for a fragment.

use super::*;

/// A whole unfragmented PNIO request or response: RPC header, NDR header and PNIO block bytes
/// (big-endian, not interpreted here).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pdu<'a> {
    /// The RPC header. Its `packet_type` matches `ndr`; its `body_len` is 20 + the blocks
    /// after parsing and is ignored (recomputed) on emission.
    pub header: Header,
    /// The NDR header.
    pub ndr: Ndr,
    /// The PNIO blocks: the body after the NDR header.
    pub blocks: &'a [u8],
}

impl<'a> Pdu<'a> {
    /// Parses a request or response PDU (the UDP payload). Other packet types, PDUs with the
    /// Fragment flag (reassemble them and use [`parse_body`]), a body shorter than the NDR
    /// header or a malformed header give [`Error`]. Bytes after LengthOfBody are ignored.
    pub fn parse(bytes: &'a [u8]) -> Result<Pdu<'a>> {
        let header = Header::parse(&Packet::new_unchecked(bytes))?;
        if header.is_fragment() {
            return Err(Error);
        }
        let body = bytes
            .get(HEADER_LEN..HEADER_LEN + usize::from(header.body_len))
            .ok_or(Error)?;
        let (ndr, blocks) = parse_body(header.packet_type, header.little_endian, body)?;
        Ok(Pdu {
            header,
            ndr,
            blocks,
        })
    }

    /// Bytes of the body: 20 + the blocks.
    pub fn body_len(&self) -> usize {
        NDR_LEN.saturating_add(self.blocks.len())
    }

    /// Bytes of the PDU: 80 + 20 + the blocks.
    pub fn buffer_len(&self) -> usize {
        HEADER_LEN.saturating_add(self.body_len())
    }

    /// Writes the PDU into the first [`buffer_len`](Self::buffer_len) bytes of `buf`, header
    /// and NDR header in the header's DREP, LengthOfBody computed from the blocks. Never
    /// panics: a short buffer, a body above 65535 bytes, the Fragment flag, or a packet type
    /// that does not match the NDR header give [`EmitError`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        if self.header.packet_type != self.ndr.packet_type() {
            return Err(EmitError::Inconsistent(
                "the PacketType does not match the NDR header",
            ));
        }
        if self.header.is_fragment() {
            return Err(EmitError::Inconsistent(
                "a whole PDU cannot carry the Fragment flag",
            ));
        }
        let body_len = self.body_len();
        let body_len = u16::try_from(body_len)
            .map_err(|_| EmitError::too_long_u16("LengthOfBody", body_len))?;
        let (needed, len) = (self.buffer_len(), buf.len());
        let pdu = buf.get_mut(..needed).ok_or(EmitError::BufferTooShort {
            what: "RPC PDU",
            needed,
            len,
        })?;
        let (header, body) = pdu.split_at_mut(HEADER_LEN);
        Header {
            body_len,
            ..self.header
        }
        .emit(header)?;
        let (ndr, blocks) = body.split_at_mut(NDR_LEN);
        self.ndr.emit(ndr, self.header.little_endian)?;
        blocks.copy_from_slice(self.blocks);
        Ok(())
    }

    /// The PDU as a new vector of [`buffer_len`](Self::buffer_len) bytes.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b))
    }
}

/// Parses a request or response PDU into its header, NDR header and block bytes (see
/// [`Pdu::parse`]).
pub fn parse_pdu(bytes: &[u8]) -> Result<(Header, Ndr, &[u8])> {
    Pdu::parse(bytes).map(|p| (p.header, p.ndr, p.blocks))
}

/// A request PDU: `header` (its packet type forced to request, its body length computed), an
/// NDR header from [`NdrRequest::for_blocks`] and the blocks. A body above 65535 bytes or the
/// Fragment flag give [`EmitError`].
pub fn emit_request(header: &Header, args_maximum: u32, blocks: &[u8]) -> EmitResult<Vec<u8>> {
    Pdu {
        header: Header {
            packet_type: PacketType::Request,
            ..*header
        },
        ndr: Ndr::Request(NdrRequest::for_blocks(args_maximum, blocks.len())),
        blocks,
    }
    .to_vec()
}

/// Body bytes of one fragment: [`MAX_PDU_LEN`] − 80, the fragment size p-net and the S7 use.
pub const MAX_FRAGMENT_BODY: usize = MAX_PDU_LEN - HEADER_LEN;

/// The PDU `header` describes with `body` after it: LengthOfBody set, the header in its
/// DREP. A body above 65535 bytes gives [`EmitError::TooLong`].
pub fn emit_with_body(header: &Header, body: &[u8]) -> EmitResult<Vec<u8>> {
    let body_len = u16::try_from(body.len())
        .map_err(|_| EmitError::too_long_u16("LengthOfBody", body.len()))?;
    let mut v = vec![0u8; HEADER_LEN];
    Header {
        body_len,
        ..*header
    }
    .emit(&mut v)?;
    v.extend_from_slice(body);
    Ok(v)
}

/// The PDUs that carry `body` under `header`: one when it fits [`MAX_FRAGMENT_BODY`], else
/// fragments numbered from 0 with the Fragment flag, LastFragment on the last, and NoFack
/// when `no_fack` (the receiver need not acknowledge them).
pub fn fragments(header: &Header, body: &[u8], no_fack: bool) -> EmitResult<Vec<Vec<u8>>> {
    if body.len() <= MAX_FRAGMENT_BODY {
        return Ok(vec![emit_with_body(header, body)?]);
    }
    let count = body.len().div_ceil(MAX_FRAGMENT_BODY);
    body.chunks(MAX_FRAGMENT_BODY)
        .enumerate()
        .map(|(i, chunk)| {
            // LastFragment belongs to the last fragment only and NoFack is the caller's
            // choice, whatever the header (a reply header carries both).
            let base = header.flags1 & !(flags1::LAST_FRAGMENT | flags1::NO_FACK);
            let mut f = base | flags1::FRAGMENT;
            if i + 1 == count {
                f |= flags1::LAST_FRAGMENT;
            }
            if no_fack {
                f |= flags1::NO_FACK;
            }
            let h = Header {
                flags1: f,
                fragment_number: u16::try_from(i)
                    .map_err(|_| EmitError::too_long_u16("FragmentNumber", i))?,
                ..*header
            };
            emit_with_body(&h, chunk)
        })
        .collect()
}

/// A FACK for the fragment whose header is `fragment`: its fragment number and serial, the
/// given boot time, and the body (in the fragment's DREP) version 0, pad, `window` (fragments
/// the sender may send ahead), `max_tsdu` (largest whole body taken), `max_frag` (largest
/// fragment PDU taken), serial number and an empty selective-ack list.
pub fn fack(
    fragment: &Header,
    boot_time: u32,
    window: u16,
    max_tsdu: u32,
    max_frag: u32,
) -> EmitResult<Vec<u8>> {
    let h = Header {
        packet_type: PacketType::Fack,
        flags1: 0,
        fragment_number: fragment.fragment_number,
        ..fragment.reply(boot_time)
    };
    let le = fragment.little_endian;
    let u16b = |v: u16| if le { v.to_le_bytes() } else { v.to_be_bytes() };
    let u32b = |v: u32| if le { v.to_le_bytes() } else { v.to_be_bytes() };
    let mut body = vec![0u8, 0];
    body.extend_from_slice(&u16b(window));
    body.extend_from_slice(&u32b(max_tsdu));
    body.extend_from_slice(&u32b(max_frag));
    body.extend_from_slice(&u16b(fragment.serial));
    body.extend_from_slice(&u16b(0));
    emit_with_body(&h, &body)
}

/// A response PDU: `header` (its packet type forced to response, its body length computed;
/// see [`Header::reply`]), an NDR header from [`NdrResponse::for_blocks`] with the request's
/// ArgsMaximum, and the blocks. A body above 65535 bytes or the Fragment flag give
/// [`EmitError`].
pub fn emit_response(
    header: &Header,
    status: PnioStatus,
    request_args_maximum: u32,
    blocks: &[u8],
) -> EmitResult<Vec<u8>> {
    Pdu {
        header: Header {
            packet_type: PacketType::Response,
            ..*header
        },
        ndr: Ndr::Response(NdrResponse::for_blocks(
            status,
            request_args_maximum,
            blocks.len(),
        )),
        blocks,
    }
    .to_vec()
}
