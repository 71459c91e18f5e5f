// SPDX-License-Identifier: MIT OR Apache-2.0
//! The 20-byte NDR header PNIO puts in front of its blocks in a request (ArgsMaximum) or a
//! response (PNIOStatus), in the PDU's DREP order.

use super::*;

mod ndr_field {
    use super::Field;
    /// ArgsMaximum (request) or PNIOStatus (response).
    pub const FIRST: Field = 0..4;
    pub const ARGS_LENGTH: Field = 4..8;
    pub const MAXIMUM_COUNT: Field = 8..12;
    pub const OFFSET: Field = 12..16;
    pub const ACTUAL_COUNT: Field = 16..20;
}

/// Bytes of an NDR request or response header.
pub const NDR_LEN: usize = ndr_field::ACTUAL_COUNT.end;

/// The five u32 of an NDR header, in DREP order, from the first 20 bytes of `b`.
fn parse_ndr_words(b: &[u8], little_endian: bool) -> Result<[u32; 5]> {
    let b = b.get(..NDR_LEN).ok_or(Error)?;
    Ok([
        rd32(&b[ndr_field::FIRST], little_endian),
        rd32(&b[ndr_field::ARGS_LENGTH], little_endian),
        rd32(&b[ndr_field::MAXIMUM_COUNT], little_endian),
        rd32(&b[ndr_field::OFFSET], little_endian),
        rd32(&b[ndr_field::ACTUAL_COUNT], little_endian),
    ])
}

/// Writes the five u32 of an NDR header, in DREP order, into the first 20 bytes of `b`.
fn emit_ndr_words(w: [u32; 5], b: &mut [u8], little_endian: bool) -> EmitResult<()> {
    let len = b.len();
    let b = b.get_mut(..NDR_LEN).ok_or(EmitError::BufferTooShort {
        what: "NDR header",
        needed: NDR_LEN,
        len,
    })?;
    wr32(&mut b[ndr_field::FIRST], w[0], little_endian);
    wr32(&mut b[ndr_field::ARGS_LENGTH], w[1], little_endian);
    wr32(&mut b[ndr_field::MAXIMUM_COUNT], w[2], little_endian);
    wr32(&mut b[ndr_field::OFFSET], w[3], little_endian);
    wr32(&mut b[ndr_field::ACTUAL_COUNT], w[4], little_endian);
    Ok(())
}

/// A length as an NDR u32, saturating (such a length never fits a PDU anyway).
fn len32(len: usize) -> u32 {
    u32::try_from(len).unwrap_or(u32::MAX)
}

/// The NDR header of a PNIO request (20 bytes, DREP order).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct NdrRequest {
    /// ArgsMaximum: the response size the client accepts.
    pub args_maximum: u32,
    /// ArgsLength: bytes of PNIO blocks.
    pub args_length: u32,
    /// MaximumCount (= ArgsMaximum).
    pub maximum_count: u32,
    /// Offset (0).
    pub offset: u32,
    /// ActualCount (= ArgsLength).
    pub actual_count: u32,
}

impl NdrRequest {
    /// The header of a request carrying `blocks_len` bytes of blocks and accepting responses
    /// of up to `args_maximum` bytes: MaximumCount = ArgsMaximum, Offset 0, ArgsLength =
    /// ActualCount = `blocks_len` (saturated to `u32::MAX`).
    pub const fn for_blocks(args_maximum: u32, blocks_len: usize) -> NdrRequest {
        // Checked against u32::MAX just before, so the cast keeps every bit (`try_from` is
        // not `const`).
        let len = if blocks_len > u32::MAX as usize {
            u32::MAX
        } else {
            blocks_len as u32
        };
        NdrRequest {
            args_maximum,
            args_length: len,
            maximum_count: args_maximum,
            offset: 0,
            actual_count: len,
        }
    }

    /// Parses the first 20 bytes of `b` in the given DREP; a shorter `b` gives [`Error`].
    pub fn parse(b: &[u8], little_endian: bool) -> Result<NdrRequest> {
        let [
            args_maximum,
            args_length,
            maximum_count,
            offset,
            actual_count,
        ] = parse_ndr_words(b, little_endian)?;
        Ok(NdrRequest {
            args_maximum,
            args_length,
            maximum_count,
            offset,
            actual_count,
        })
    }

    /// Bytes of the header (20).
    pub const fn buffer_len(&self) -> usize {
        NDR_LEN
    }

    /// Writes the 20 bytes into the start of `b` in the given DREP; a shorter `b` gives
    /// [`EmitError::BufferTooShort`].
    pub fn emit(&self, b: &mut [u8], little_endian: bool) -> EmitResult<()> {
        let w = [
            self.args_maximum,
            self.args_length,
            self.maximum_count,
            self.offset,
            self.actual_count,
        ];
        emit_ndr_words(w, b, little_endian)
    }

    /// Whether the header is what [`for_blocks`](Self::for_blocks) would build for
    /// `blocks_len` bytes of blocks (the shape p-net and the S7 send and check).
    pub fn is_consistent(&self, blocks_len: usize) -> bool {
        *self == NdrRequest::for_blocks(self.args_maximum, blocks_len)
    }
}

/// The NDR header of a PNIO response (20 bytes, DREP order).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct NdrResponse {
    /// PNIOStatus: a u32 in DREP order with ErrorCode most significant (a little-endian
    /// response stores ErrorCode2 first).
    pub status: PnioStatus,
    /// ArgsLength: bytes of PNIO blocks.
    pub args_length: u32,
    /// MaximumCount: echoes the request's ArgsMaximum.
    pub maximum_count: u32,
    /// Offset (0).
    pub offset: u32,
    /// ActualCount (= ArgsLength).
    pub actual_count: u32,
}

impl NdrResponse {
    /// The header of a response carrying `blocks_len` bytes of blocks to a request whose
    /// ArgsMaximum was `args_maximum`: MaximumCount = that ArgsMaximum, Offset 0, ArgsLength =
    /// ActualCount = `blocks_len` (saturated to `u32::MAX`).
    pub const fn for_blocks(
        status: PnioStatus,
        args_maximum: u32,
        blocks_len: usize,
    ) -> NdrResponse {
        let r = NdrRequest::for_blocks(args_maximum, blocks_len);
        NdrResponse {
            status,
            args_length: r.args_length,
            maximum_count: args_maximum,
            offset: 0,
            actual_count: r.actual_count,
        }
    }

    /// Parses the first 20 bytes of `b` in the given DREP; a shorter `b` gives [`Error`].
    pub fn parse(b: &[u8], little_endian: bool) -> Result<NdrResponse> {
        let [status, args_length, maximum_count, offset, actual_count] =
            parse_ndr_words(b, little_endian)?;
        Ok(NdrResponse {
            status: PnioStatus::from_u32(status),
            args_length,
            maximum_count,
            offset,
            actual_count,
        })
    }

    /// Bytes of the header (20).
    pub const fn buffer_len(&self) -> usize {
        NDR_LEN
    }

    /// Writes the 20 bytes into the start of `b` in the given DREP; a shorter `b` gives
    /// [`EmitError::BufferTooShort`].
    pub fn emit(&self, b: &mut [u8], little_endian: bool) -> EmitResult<()> {
        let w = [
            self.status.to_u32(),
            self.args_length,
            self.maximum_count,
            self.offset,
            self.actual_count,
        ];
        emit_ndr_words(w, b, little_endian)
    }

    /// Whether ArgsLength = ActualCount = `blocks_len`, Offset is 0 and ArgsLength does not
    /// exceed MaximumCount (the shape p-net and the S7 send and check).
    pub fn is_consistent(&self, blocks_len: usize) -> bool {
        let len = len32(blocks_len);
        self.args_length == len
            && self.actual_count == len
            && self.offset == 0
            && self.args_length <= self.maximum_count
    }
}

/// The NDR header of a PNIO call, by packet type: a request or a response.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Ndr {
    /// The header of a request (PacketType 0).
    Request(NdrRequest),
    /// The header of a response (PacketType 2).
    Response(NdrResponse),
}

impl Ndr {
    /// Parses the NDR header at the start of a body of this packet type: requests and
    /// responses only; other packet types or fewer than 20 bytes give [`Error`].
    pub fn parse(packet_type: PacketType, b: &[u8], little_endian: bool) -> Result<Ndr> {
        match packet_type {
            PacketType::Request => NdrRequest::parse(b, little_endian).map(Ndr::Request),
            PacketType::Response => NdrResponse::parse(b, little_endian).map(Ndr::Response),
            _ => Err(Error),
        }
    }

    /// The packet type that carries this header.
    pub const fn packet_type(&self) -> PacketType {
        match self {
            Ndr::Request(_) => PacketType::Request,
            Ndr::Response(_) => PacketType::Response,
        }
    }

    /// ArgsLength.
    pub const fn args_length(&self) -> u32 {
        match self {
            Ndr::Request(r) => r.args_length,
            Ndr::Response(r) => r.args_length,
        }
    }

    /// ActualCount.
    pub const fn actual_count(&self) -> u32 {
        match self {
            Ndr::Request(r) => r.actual_count,
            Ndr::Response(r) => r.actual_count,
        }
    }

    /// MaximumCount.
    pub const fn maximum_count(&self) -> u32 {
        match self {
            Ndr::Request(r) => r.maximum_count,
            Ndr::Response(r) => r.maximum_count,
        }
    }

    /// The PNIOStatus of a response; `None` for a request.
    pub const fn status(&self) -> Option<PnioStatus> {
        match self {
            Ndr::Request(_) => None,
            Ndr::Response(r) => Some(r.status),
        }
    }

    /// Bytes of the header (20).
    pub const fn buffer_len(&self) -> usize {
        NDR_LEN
    }

    /// Writes the 20 bytes into the start of `b` in the given DREP; a shorter `b` gives
    /// [`EmitError::BufferTooShort`].
    pub fn emit(&self, b: &mut [u8], little_endian: bool) -> EmitResult<()> {
        match self {
            Ndr::Request(r) => r.emit(b, little_endian),
            Ndr::Response(r) => r.emit(b, little_endian),
        }
    }

    /// Whether the header has the shape p-net and the S7 send for `blocks_len` bytes of
    /// blocks (see [`NdrRequest::is_consistent`], [`NdrResponse::is_consistent`]).
    pub fn is_consistent(&self, blocks_len: usize) -> bool {
        match self {
            Ndr::Request(r) => r.is_consistent(blocks_len),
            Ndr::Response(r) => r.is_consistent(blocks_len),
        }
    }
}

/// Splits a whole (unfragmented or reassembled) request or response body into its NDR header
/// and the block bytes after it. The blocks are everything after the 20 NDR bytes; whether
/// ArgsLength agrees is left to the caller ([`Ndr::is_consistent`]).
pub fn parse_body(
    packet_type: PacketType,
    little_endian: bool,
    body: &[u8],
) -> Result<(Ndr, &[u8])> {
    let (ndr, blocks) = body.split_at_checked(NDR_LEN).ok_or(Error)?;
    Ok((Ndr::parse(packet_type, ndr, little_endian)?, blocks))
}
