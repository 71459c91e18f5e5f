// SPDX-License-Identifier: MIT OR Apache-2.0
//! The physical device's records as they are: PDInterfaceDataReal (block 0x0240, record
//! 0x8080), PDPortDataReal (0x020F, record 0x802A), PDPortStatistic (0x0251, record 0x8072)
//! and the MultipleBlockHeader (0x0400) that PDRealData (0xF841) and PDExpectedData
//! (0xF842) put around each submodule's blocks.
//!
//! Their padding aligns fields to 4 bytes from the block's start, as Wireshark's dissector
//! decodes them (it aligns on its buffer, whose records start aligned): a block written
//! here is always a multiple of 4 bytes long, the padding counted in its BlockLength, so
//! that blocks follow one another aligned.
//!
//! ```text
//! PDInterfaceDataReal  LengthOwnChassisID OwnChassisID pad MAC pad(2) IP Mask Gateway
//! PDPortDataReal       pad(2) Slot Subslot LengthOwnPortID OwnPortID NumberOfPeers pad
//!                      (LengthPeerPortID PeerPortID LengthPeerChassisID PeerChassisID pad
//!                       LineDelay PeerMAC pad(2))*
//!                      MAUType pad(2) DomainBoundary MulticastBoundary LinkState pad(2) MediaType
//! PDPortStatistic      CounterStatus (v1.1; padding in v1.0) ifIn/OutOctets ifIn/OutDiscards ifIn/OutErrors
//! MultipleBlockHeader  pad(2) API Slot Subslot blocks…
//! ```

use super::super::cursor::{Reader, Writer};
use super::{BlockHeader, BlockType, EmitError, EmitResult, Error, Result, emit_block};
use crate::wire::MacAddress;

/// Record index of PDPortDataReal.
pub const INDEX_PD_PORT_DATA_REAL: u16 = 0x802a;
/// Record index of PDPortDataCheck.
pub const INDEX_PD_PORT_DATA_CHECK: u16 = 0x802b;
/// Record index of PDPortDataAdjust.
pub const INDEX_PD_PORT_DATA_ADJUST: u16 = 0x802f;
/// Record index of PDPortStatistic.
pub const INDEX_PD_PORT_STATISTIC: u16 = 0x8072;
/// Record index of PDInterfaceDataReal.
pub const INDEX_PD_INTERFACE_DATA_REAL: u16 = 0x8080;
/// Record index of PDRealData (the device's).
pub const INDEX_PD_REAL_DATA: u16 = 0xf841;
/// Record index of PDExpectedData (the device's).
pub const INDEX_PD_EXPECTED_DATA: u16 = 0xf842;

/// `n` rounded up to a multiple of 4.
pub(super) const fn align4(n: usize) -> usize {
    n.saturating_add(3) & !3
}

/// A length-prefixed (u8) text of at most 255 bytes.
fn short_text(w: &mut Writer<'_>, field: &'static str, s: &str) -> EmitResult<()> {
    let n = u8::try_from(s.len()).map_err(|_| EmitError::TooLong {
        field,
        value: s.len(),
        max: 255,
    })?;
    w.u8(n)?;
    w.put(s.as_bytes())
}

fn read_short_text(r: &mut Reader<'_>) -> Result<String> {
    let n = r.u8()?;
    let b = r.take(usize::from(n))?;
    core::str::from_utf8(b)
        .map(str::to_owned)
        .map_err(|_| Error)
}

/// Pads a writer whose block started at position `start` to the next multiple of 4.
fn pad_to4(w: &mut Writer<'_>, start: usize) -> EmitResult<()> {
    let at = w.position() - start;
    w.zeros(align4(at) - at)
}

/// Skips a reader's padding up to the next multiple of 4 from the block's start, `taken`
/// bytes of the block (header included) being read.
fn skip_to4(r: &mut Reader<'_>, taken: usize) -> Result<()> {
    r.take(align4(taken) - taken).map(|_| ())
}

/// PDInterfaceDataReal: the interface's name, MAC address and IP suite.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct PdInterfaceDataReal {
    /// OwnChassisID: the NameOfStation (at most 255 bytes).
    pub chassis_id: String,
    /// The interface's MAC address.
    pub mac: MacAddress,
    /// IP address (0.0.0.0: none).
    pub ip: [u8; 4],
    /// Subnet mask.
    pub mask: [u8; 4],
    /// Standard gateway.
    pub gateway: [u8; 4],
}

impl PdInterfaceDataReal {
    /// Bytes of the block.
    pub fn buffer_len(&self) -> usize {
        align4(7 + self.chassis_id.len()) + 20
    }

    /// Writes the block into the first [`buffer_len`](Self::buffer_len) bytes of `buf`.
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<usize> {
        let body = self.buffer_len() - 6;
        emit_block(
            "PDInterfaceDataReal",
            BlockType::PdInterfaceDataReal,
            0,
            body,
            buf,
            |w| {
                short_text(w, "OwnChassisID", &self.chassis_id)?;
                pad_to4(w, 0)?;
                w.put(&self.mac.0)?;
                w.zeros(2)?;
                w.put(&self.ip)?;
                w.put(&self.mask)?;
                w.put(&self.gateway)
            },
        )
    }

    /// The block as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b).map(|_| ()))
    }

    /// Parses the block at the start of `b`.
    pub fn parse(b: &[u8]) -> Result<PdInterfaceDataReal> {
        let h = version_1_0(b, BlockType::PdInterfaceDataReal)?;
        let mut r = Reader::new(h.body(b));
        let chassis_id = read_short_text(&mut r)?;
        skip_to4(&mut r, 7 + chassis_id.len())?;
        let mac = r.mac()?;
        r.take(2)?;
        let v = PdInterfaceDataReal {
            chassis_id,
            mac,
            ip: r.array()?,
            mask: r.array()?,
            gateway: r.array()?,
        };
        r.end()?;
        Ok(v)
    }
}

/// The header of `b`'s first block, which must be `block_type` in version 1.0.
fn version_1_0(b: &[u8], block_type: BlockType) -> Result<BlockHeader> {
    let h = BlockHeader::parse(b)?;
    if h.block_type != block_type || (h.version_high, h.version_low) != (1, 0) {
        return Err(Error);
    }
    Ok(h)
}

/// A neighbour as PDPortDataReal reports it.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct PeerReal {
    /// PeerPortID: the neighbour's port name (`port-001`).
    pub port_id: String,
    /// PeerChassisID: the neighbour's NameOfStation.
    pub chassis_id: String,
    /// LineDelay: bit 31 clear, the measured line delay in ns (0: not measured).
    pub line_delay: u32,
    /// The neighbour's MAC address.
    pub mac: MacAddress,
}

impl PeerReal {
    fn len(&self) -> usize {
        align4(2 + self.port_id.len() + self.chassis_id.len()) + 12
    }
}

/// LinkState.Link: the link is up.
pub const LINK_UP: u8 = 1;
/// LinkState.Link: the link is down.
pub const LINK_DOWN: u8 = 2;
/// LinkState.Port: unknown (an end station's port without a bridge state).
pub const PORT_STATE_UNKNOWN: u8 = 0;
/// LinkState.Port: forwarding.
pub const PORT_STATE_FORWARDING: u8 = 5;
/// MediaType: copper cable.
pub const MEDIA_COPPER: u32 = 1;
/// MediaType: unknown.
pub const MEDIA_UNKNOWN: u32 = 0;

/// PDPortDataReal: a port as it is (its name, its neighbours, its link).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct PdPortDataReal {
    /// The port submodule's slot.
    pub slot: u16,
    /// The port submodule's subslot (0x8001 for port 1).
    pub subslot: u16,
    /// OwnPortID: the port's name.
    pub own_port_id: String,
    /// The neighbours LLDP announced (usually none or one).
    pub peers: Vec<PeerReal>,
    /// MAUType (IETF RFC 4836; 0: unknown, the link is down).
    pub mau_type: u16,
    /// DomainBoundary.
    pub domain_boundary: u32,
    /// MulticastBoundary.
    pub multicast_boundary: u32,
    /// LinkState.Port ([`PORT_STATE_UNKNOWN`], [`PORT_STATE_FORWARDING`], …).
    pub port_state: u8,
    /// LinkState.Link ([`LINK_UP`], [`LINK_DOWN`], …).
    pub link: u8,
    /// MediaType ([`MEDIA_COPPER`], …).
    pub media_type: u32,
}

impl PdPortDataReal {
    fn head_len(&self) -> usize {
        align4(14 + self.own_port_id.len())
    }

    /// Bytes of the block.
    pub fn buffer_len(&self) -> usize {
        self.peers
            .iter()
            .fold(self.head_len(), |n, p| n.saturating_add(p.len()))
            .saturating_add(20)
    }

    /// Writes the block into the first [`buffer_len`](Self::buffer_len) bytes of `buf`.
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<usize> {
        let peers = u8::try_from(self.peers.len())
            .map_err(|_| EmitError::too_long_u16("NumberOfPeers", self.peers.len()))?;
        let body = self.buffer_len() - 6;
        emit_block(
            "PDPortDataReal",
            BlockType::PdPortDataReal,
            0,
            body,
            buf,
            |w| {
                w.zeros(2)?;
                w.u16(self.slot)?;
                w.u16(self.subslot)?;
                short_text(w, "OwnPortID", &self.own_port_id)?;
                w.u8(peers)?;
                pad_to4(w, 0)?;
                for p in &self.peers {
                    short_text(w, "PeerPortID", &p.port_id)?;
                    short_text(w, "PeerChassisID", &p.chassis_id)?;
                    pad_to4(w, 0)?;
                    w.u32(p.line_delay)?;
                    w.put(&p.mac.0)?;
                    w.zeros(2)?;
                }
                w.u16(self.mau_type)?;
                w.zeros(2)?;
                w.u32(self.domain_boundary)?;
                w.u32(self.multicast_boundary)?;
                w.u8(self.port_state)?;
                w.u8(self.link)?;
                w.zeros(2)?;
                w.u32(self.media_type)
            },
        )
    }

    /// The block as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b).map(|_| ()))
    }

    /// Parses the block at the start of `b`.
    pub fn parse(b: &[u8]) -> Result<PdPortDataReal> {
        let h = version_1_0(b, BlockType::PdPortDataReal)?;
        let mut r = Reader::new(h.body(b));
        r.take(2)?;
        let (slot, subslot) = (r.u16()?, r.u16()?);
        let own_port_id = read_short_text(&mut r)?;
        let n = r.u8()?;
        skip_to4(&mut r, 14 + own_port_id.len())?;
        let mut peers = Vec::new();
        for _ in 0..n {
            let port_id = read_short_text(&mut r)?;
            let chassis_id = read_short_text(&mut r)?;
            skip_to4(&mut r, 2 + port_id.len() + chassis_id.len())?;
            let line_delay = r.u32()?;
            let mac = r.mac()?;
            r.take(2)?;
            peers.push(PeerReal {
                port_id,
                chassis_id,
                line_delay,
                mac,
            });
        }
        let mau_type = r.u16()?;
        r.take(2)?;
        let v = PdPortDataReal {
            slot,
            subslot,
            own_port_id,
            peers,
            mau_type,
            domain_boundary: r.u32()?,
            multicast_boundary: r.u32()?,
            port_state: r.u8()?,
            link: r.u8()?,
            media_type: {
                r.take(2)?;
                r.u32()?
            },
        };
        r.end()?;
        Ok(v)
    }
}

/// PDPortStatistic: the interface's or a port's counters (MIB-II's ifTable, 32 bits).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PdPortStatistic {
    /// CounterStatus (version 1.1): a set bit marks a counter that is not supported (bit 0
    /// ifInOctets … bit 5 ifOutErrors); `None` writes version 1.0.
    pub counter_status: Option<u16>,
    /// ifInOctets.
    pub in_octets: u32,
    /// ifOutOctets.
    pub out_octets: u32,
    /// ifInDiscards.
    pub in_discards: u32,
    /// ifOutDiscards.
    pub out_discards: u32,
    /// ifInErrors.
    pub in_errors: u32,
    /// ifOutErrors.
    pub out_errors: u32,
}

impl PdPortStatistic {
    /// Bytes of the block.
    pub const LEN: usize = 32;

    /// Writes the block into the first 32 bytes of `buf`.
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<usize> {
        let low = u8::from(self.counter_status.is_some());
        emit_block(
            "PDPortStatistic",
            BlockType::PdPortStatistic,
            low,
            26,
            buf,
            |w| {
                w.u16(self.counter_status.unwrap_or(0))?;
                for v in [
                    self.in_octets,
                    self.out_octets,
                    self.in_discards,
                    self.out_discards,
                    self.in_errors,
                    self.out_errors,
                ] {
                    w.u32(v)?;
                }
                Ok(())
            },
        )
    }

    /// The block as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(Self::LEN, |b| self.emit(b).map(|_| ()))
    }

    /// Parses the block (version 1.0 or 1.1) at the start of `b`.
    pub fn parse(b: &[u8]) -> Result<PdPortStatistic> {
        let h = BlockHeader::parse(b)?;
        if h.block_type != BlockType::PdPortStatistic || h.version_high != 1 || h.version_low > 1 {
            return Err(Error);
        }
        let mut r = Reader::new(h.body(b));
        let status = r.u16()?;
        let v = PdPortStatistic {
            counter_status: (h.version_low == 1).then_some(status),
            in_octets: r.u32()?,
            out_octets: r.u32()?,
            in_discards: r.u32()?,
            out_discards: r.u32()?,
            in_errors: r.u32()?,
            out_errors: r.u32()?,
        };
        r.end()?;
        Ok(v)
    }
}

/// A MultipleBlockHeader: the blocks of one submodule in PDRealData or PDExpectedData.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct MultipleBlockHeader {
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// The blocks, one after another, each a multiple of 4 bytes long.
    pub blocks: Vec<u8>,
}

impl MultipleBlockHeader {
    /// Bytes of the block.
    pub fn buffer_len(&self) -> usize {
        16usize.saturating_add(self.blocks.len())
    }

    /// Writes the block into the first [`buffer_len`](Self::buffer_len) bytes of `buf`.
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<usize> {
        if !self.blocks.len().is_multiple_of(4) {
            return Err(EmitError::Inconsistent(
                "the blocks of a MultipleBlockHeader must end 4-aligned",
            ));
        }
        let body = self.buffer_len() - 6;
        emit_block(
            "MultipleBlockHeader",
            BlockType::MultipleBlockHeader,
            0,
            body,
            buf,
            |w| {
                w.zeros(2)?;
                w.u32(self.api)?;
                w.u16(self.slot)?;
                w.u16(self.subslot)?;
                w.put(&self.blocks)
            },
        )
    }

    /// The block as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b).map(|_| ()))
    }

    /// Parses the block at the start of `b`.
    pub fn parse(b: &[u8]) -> Result<MultipleBlockHeader> {
        let h = version_1_0(b, BlockType::MultipleBlockHeader)?;
        let mut r = Reader::new(h.body(b));
        r.take(2)?;
        Ok(MultipleBlockHeader {
            api: r.u32()?,
            slot: r.u16()?,
            subslot: r.u16()?,
            blocks: r.rest().to_vec(),
        })
    }
}

#[cfg(test)]
mod tests;
