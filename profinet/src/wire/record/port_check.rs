// SPDX-License-Identifier: MIT OR Apache-2.0
//! What a PLC expects of a port and sets on it: PDPortDataCheck (block 0x0200, record
//! 0x802B) and PDPortDataAdjust (0x0202, record 0x802F), each a slot and subslot and a list
//! of sub-blocks.
//!
//! ```text
//! PDPortDataCheck / PDPortDataAdjust   pad(2) Slot Subslot sub-blocks…
//! CheckPeers                NumberOfPeers (LengthPeerPortID PeerPortID LengthPeerChassisID PeerChassisID)* pad
//! CheckLineDelay            pad(2) LineDelay
//! CheckMAUType              MAUType
//! CheckLinkState            LinkState
//! CheckSyncDifference       CheckSyncMode
//! CheckMAUTypeDifference    MAUTypeMode
//! AdjustDomainBoundary      pad(2) DomainBoundary (v1.1: Ingress Egress) AdjustProperties pad(2)
//! AdjustMulticastBoundary   pad(2) MulticastBoundary AdjustProperties pad(2)
//! AdjustMAUType             pad(2) MAUType AdjustProperties
//! AdjustLinkState           pad(2) LinkState AdjustProperties
//! AdjustPeerToPeerBoundary  pad(2) PeerToPeerBoundary AdjustProperties pad(2)
//! AdjustDCPBoundary         pad(2) DCPBoundary AdjustProperties pad(2)
//! ```
//!
//! Every sub-block is padded to 4 bytes, the padding counted in its BlockLength, as
//! Wireshark reads them one after another. A sub-block this codec does not know is kept as
//! it came ([`PortCheck::Other`], [`PortAdjust::Other`]).

use super::super::cursor::{Reader, Writer};
use super::pdev::align4;
use super::{BlockHeader, BlockType, EmitError, EmitResult, Error, Result, emit_block};
use crate::wire::common::blocks;

/// AdjustPeerToPeerBoundary bit 0: the port sends no LLDP frames.
pub const PEER_TO_PEER_NO_LLDP: u32 = 1 << 0;
/// AdjustDCPBoundary bit 0: DCP Identify multicasts do not leave the port.
pub const DCP_BOUNDARY_IDENTIFY: u32 = 1 << 0;
/// AdjustDCPBoundary bit 1: DCP Hello multicasts do not leave the port.
pub const DCP_BOUNDARY_HELLO: u32 = 1 << 1;

/// A peer the PLC expects.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct CheckedPeer {
    /// PeerPortID: the neighbour's port name.
    pub port_id: String,
    /// PeerChassisID: the neighbour's NameOfStation.
    pub chassis_id: String,
}

/// One check of PDPortDataCheck.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum PortCheck {
    /// CheckPeers: the neighbours the port must have.
    Peers(Vec<CheckedPeer>),
    /// CheckLineDelay: the line delay (bit 31 clear: ns).
    LineDelay(u32),
    /// CheckMAUType: the MAU type the port must run.
    MauType(u16),
    /// CheckLinkState: the link state.
    LinkState(u16),
    /// CheckSyncDifference: CheckSyncMode.
    SyncDifference(u16),
    /// CheckMAUTypeDifference: MAUTypeMode (1: the peer must run the same MAU type).
    MauTypeDifference(u16),
    /// Any other sub-block, kept whole (header included).
    Other(Vec<u8>),
}

/// One setting of PDPortDataAdjust; each carries its AdjustProperties where it has one.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum PortAdjust {
    /// AdjustDomainBoundary: version 1.0 one boundary (`egress` `None`), 1.1 ingress and
    /// egress.
    DomainBoundary {
        /// DomainBoundary (v1.0) or DomainBoundaryIngress (v1.1).
        ingress: u32,
        /// DomainBoundaryEgress (v1.1).
        egress: Option<u32>,
        /// AdjustProperties.
        properties: u16,
    },
    /// AdjustMulticastBoundary.
    MulticastBoundary {
        /// MulticastBoundary.
        boundary: u32,
        /// AdjustProperties.
        properties: u16,
    },
    /// AdjustMAUType.
    MauType {
        /// MAUType.
        mau_type: u16,
        /// AdjustProperties.
        properties: u16,
    },
    /// AdjustLinkState.
    LinkState {
        /// LinkState.
        state: u16,
        /// AdjustProperties.
        properties: u16,
    },
    /// AdjustPeerToPeerBoundary ([`PEER_TO_PEER_NO_LLDP`], …).
    PeerToPeerBoundary {
        /// PeerToPeerBoundary.
        boundary: u32,
        /// AdjustProperties.
        properties: u16,
    },
    /// AdjustDCPBoundary ([`DCP_BOUNDARY_IDENTIFY`], [`DCP_BOUNDARY_HELLO`]).
    DcpBoundary {
        /// DCPBoundary.
        boundary: u32,
        /// AdjustProperties.
        properties: u16,
    },
    /// Any other sub-block, kept whole (header included).
    Other(Vec<u8>),
}

/// PDPortDataCheck: what the PLC expects of a port.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct PdPortDataCheck {
    /// The port's slot.
    pub slot: u16,
    /// The port's subslot.
    pub subslot: u16,
    /// The checks, in order.
    pub checks: Vec<PortCheck>,
}

/// PDPortDataAdjust: what the PLC sets on a port.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct PdPortDataAdjust {
    /// The port's slot.
    pub slot: u16,
    /// The port's subslot.
    pub subslot: u16,
    /// The settings, in order.
    pub adjusts: Vec<PortAdjust>,
}

fn short_text(r: &mut Reader<'_>) -> Result<String> {
    let n = r.u8()?;
    core::str::from_utf8(r.take(usize::from(n))?)
        .map(str::to_owned)
        .map_err(|_| Error)
}

fn put_short_text(w: &mut Writer<'_>, field: &'static str, s: &str) -> EmitResult<()> {
    let n = u8::try_from(s.len()).map_err(|_| EmitError::TooLong {
        field,
        value: s.len(),
        max: 255,
    })?;
    w.u8(n)?;
    w.put(s.as_bytes())
}

/// The slot, subslot and sub-blocks of a check or adjust block of `block_type` at the
/// start of `b`.
fn parse_frame(b: &[u8], block_type: BlockType) -> Result<(u16, u16, &[u8])> {
    let h = BlockHeader::parse(b)?;
    if h.block_type != block_type || (h.version_high, h.version_low) != (1, 0) {
        return Err(Error);
    }
    let mut r = Reader::new(h.body(b));
    r.take(2)?;
    let (slot, subslot) = (r.u16()?, r.u16()?);
    Ok((slot, subslot, r.rest()))
}

/// A sub-block's body after its header, checked to be of version 1.0.
fn body_1_0<'a>(h: &BlockHeader, block: &'a [u8]) -> Option<Reader<'a>> {
    ((h.version_high, h.version_low) == (1, 0)).then(|| Reader::new(h.body(block)))
}

impl PortCheck {
    fn parse(h: &BlockHeader, block: &[u8]) -> Result<PortCheck> {
        let known = match h.block_type {
            BlockType::CheckPeers => body_1_0(h, block).map(|mut r| {
                let n = r.u8()?;
                let peers = (0..n)
                    .map(|_| {
                        Ok(CheckedPeer {
                            port_id: short_text(&mut r)?,
                            chassis_id: short_text(&mut r)?,
                        })
                    })
                    .collect::<Result<Vec<_>>>()?;
                Ok(PortCheck::Peers(peers))
            }),
            BlockType::CheckLineDelay => body_1_0(h, block).map(|mut r| {
                r.take(2)?;
                Ok(PortCheck::LineDelay(r.u32()?))
            }),
            BlockType::CheckMauType => {
                body_1_0(h, block).map(|mut r| Ok(PortCheck::MauType(r.u16()?)))
            }
            BlockType::CheckLinkState => {
                body_1_0(h, block).map(|mut r| Ok(PortCheck::LinkState(r.u16()?)))
            }
            BlockType::CheckSyncDifference => {
                body_1_0(h, block).map(|mut r| Ok(PortCheck::SyncDifference(r.u16()?)))
            }
            BlockType::CheckMauTypeDifference => {
                body_1_0(h, block).map(|mut r| Ok(PortCheck::MauTypeDifference(r.u16()?)))
            }
            _ => None,
        };
        known.unwrap_or_else(|| Ok(PortCheck::Other(block[..h.total_len()].to_vec())))
    }

    /// (block type, body length before padding) of a known check.
    fn shape(&self) -> Option<(BlockType, usize)> {
        Some(match self {
            PortCheck::Peers(p) => (
                BlockType::CheckPeers,
                1 + p
                    .iter()
                    .map(|p| 2 + p.port_id.len() + p.chassis_id.len())
                    .sum::<usize>(),
            ),
            PortCheck::LineDelay(_) => (BlockType::CheckLineDelay, 6),
            PortCheck::MauType(_) => (BlockType::CheckMauType, 2),
            PortCheck::LinkState(_) => (BlockType::CheckLinkState, 2),
            PortCheck::SyncDifference(_) => (BlockType::CheckSyncDifference, 2),
            PortCheck::MauTypeDifference(_) => (BlockType::CheckMauTypeDifference, 2),
            PortCheck::Other(_) => return None,
        })
    }

    fn buffer_len(&self) -> usize {
        match (self, self.shape()) {
            (_, Some((_, body))) => align4(6 + body),
            (PortCheck::Other(b), None) => b.len(),
            (_, None) => 0,
        }
    }

    fn emit(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        let Some((block_type, _)) = self.shape() else {
            return match self {
                PortCheck::Other(b) => w.put(b),
                _ => Ok(()),
            };
        };
        let total = self.buffer_len();
        w.block_header(block_type, total - 6)?;
        let start = w.position();
        match self {
            PortCheck::Peers(peers) => {
                let n = u8::try_from(peers.len())
                    .map_err(|_| EmitError::too_long_u16("NumberOfPeers", peers.len()))?;
                w.u8(n)?;
                for p in peers {
                    put_short_text(w, "PeerPortID", &p.port_id)?;
                    put_short_text(w, "PeerChassisID", &p.chassis_id)?;
                }
            }
            PortCheck::LineDelay(d) => {
                w.zeros(2)?;
                w.u32(*d)?;
            }
            PortCheck::MauType(v)
            | PortCheck::LinkState(v)
            | PortCheck::SyncDifference(v)
            | PortCheck::MauTypeDifference(v) => w.u16(*v)?,
            PortCheck::Other(_) => {}
        }
        let written = 6 + w.position() - start;
        w.zeros(total - written)
    }
}

impl PortAdjust {
    fn parse(h: &BlockHeader, block: &[u8]) -> Result<PortAdjust> {
        let boundary = |h: &BlockHeader, make: fn(u32, u16) -> PortAdjust| {
            body_1_0(h, block).map(|mut r| {
                r.take(2)?;
                let b = r.u32()?;
                Ok(make(b, r.u16()?))
            })
        };
        let known = match h.block_type {
            BlockType::AdjustDomainBoundary if h.version_high == 1 && h.version_low <= 1 => {
                let mut r = Reader::new(h.body(block));
                Some((|| {
                    r.take(2)?;
                    let ingress = r.u32()?;
                    let egress = if h.version_low == 1 {
                        Some(r.u32()?)
                    } else {
                        None
                    };
                    Ok(PortAdjust::DomainBoundary {
                        ingress,
                        egress,
                        properties: r.u16()?,
                    })
                })())
            }
            BlockType::AdjustMulticastBoundary => {
                boundary(h, |boundary, properties| PortAdjust::MulticastBoundary {
                    boundary,
                    properties,
                })
            }
            BlockType::AdjustPeerToPeerBoundary => {
                boundary(h, |boundary, properties| PortAdjust::PeerToPeerBoundary {
                    boundary,
                    properties,
                })
            }
            BlockType::AdjustDcpBoundary => {
                boundary(h, |boundary, properties| PortAdjust::DcpBoundary {
                    boundary,
                    properties,
                })
            }
            BlockType::AdjustMauType => body_1_0(h, block).map(|mut r| {
                r.take(2)?;
                Ok(PortAdjust::MauType {
                    mau_type: r.u16()?,
                    properties: r.u16()?,
                })
            }),
            BlockType::AdjustLinkState => body_1_0(h, block).map(|mut r| {
                r.take(2)?;
                Ok(PortAdjust::LinkState {
                    state: r.u16()?,
                    properties: r.u16()?,
                })
            }),
            _ => None,
        };
        known.unwrap_or_else(|| Ok(PortAdjust::Other(block[..h.total_len()].to_vec())))
    }

    /// (block type, version low, bytes of the block) of a known setting.
    fn shape(&self) -> Option<(BlockType, u8, usize)> {
        Some(match self {
            PortAdjust::DomainBoundary { egress: None, .. } => {
                (BlockType::AdjustDomainBoundary, 0, 16)
            }
            PortAdjust::DomainBoundary {
                egress: Some(_), ..
            } => (BlockType::AdjustDomainBoundary, 1, 20),
            PortAdjust::MulticastBoundary { .. } => (BlockType::AdjustMulticastBoundary, 0, 16),
            PortAdjust::MauType { .. } => (BlockType::AdjustMauType, 0, 12),
            PortAdjust::LinkState { .. } => (BlockType::AdjustLinkState, 0, 12),
            PortAdjust::PeerToPeerBoundary { .. } => (BlockType::AdjustPeerToPeerBoundary, 0, 16),
            PortAdjust::DcpBoundary { .. } => (BlockType::AdjustDcpBoundary, 0, 16),
            PortAdjust::Other(_) => return None,
        })
    }

    fn buffer_len(&self) -> usize {
        match (self, self.shape()) {
            (_, Some((_, _, total))) => total,
            (PortAdjust::Other(b), None) => b.len(),
            (_, None) => 0,
        }
    }

    fn emit(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        let Some((block_type, version_low, total)) = self.shape() else {
            return match self {
                PortAdjust::Other(b) => w.put(b),
                _ => Ok(()),
            };
        };
        let header = BlockHeader {
            version_low,
            ..BlockHeader::v1(block_type, total - 6)?
        };
        w.put(&header.to_bytes())?;
        w.zeros(2)?;
        match self {
            PortAdjust::DomainBoundary {
                ingress,
                egress,
                properties,
            } => {
                w.u32(*ingress)?;
                if let Some(e) = egress {
                    w.u32(*e)?;
                }
                w.u16(*properties)?;
                w.zeros(2)
            }
            PortAdjust::MulticastBoundary {
                boundary,
                properties,
            }
            | PortAdjust::PeerToPeerBoundary {
                boundary,
                properties,
            }
            | PortAdjust::DcpBoundary {
                boundary,
                properties,
            } => {
                w.u32(*boundary)?;
                w.u16(*properties)?;
                w.zeros(2)
            }
            PortAdjust::MauType {
                mau_type: v,
                properties,
            }
            | PortAdjust::LinkState {
                state: v,
                properties,
            } => {
                w.u16(*v)?;
                w.u16(*properties)
            }
            PortAdjust::Other(_) => Ok(()),
        }
    }
}

/// The sub-blocks of `b`, each parsed by `parse`.
fn sub_blocks<T>(b: &[u8], parse: fn(&BlockHeader, &[u8]) -> Result<T>) -> Result<Vec<T>> {
    blocks(b)
        .map(|r| r.and_then(|(h, block)| parse(&h, block)))
        .collect()
}

impl PdPortDataCheck {
    /// Bytes of the block.
    pub fn buffer_len(&self) -> usize {
        self.checks
            .iter()
            .fold(12usize, |n, c| n.saturating_add(c.buffer_len()))
    }

    /// The block as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        let body = self.buffer_len() - 6;
        crate::wire::emit_to_vec(self.buffer_len(), |b| {
            emit_block(
                "PDPortDataCheck",
                BlockType::PdPortDataCheck,
                0,
                body,
                b,
                |w| {
                    w.zeros(2)?;
                    w.u16(self.slot)?;
                    w.u16(self.subslot)?;
                    self.checks.iter().try_for_each(|c| c.emit(w))
                },
            )
            .map(|_| ())
        })
    }

    /// Parses the block at the start of `b`.
    pub fn parse(b: &[u8]) -> Result<PdPortDataCheck> {
        let (slot, subslot, subs) = parse_frame(b, BlockType::PdPortDataCheck)?;
        Ok(PdPortDataCheck {
            slot,
            subslot,
            checks: sub_blocks(subs, PortCheck::parse)?,
        })
    }

    /// The peers CheckPeers expects, if the PLC checks them.
    pub fn peers(&self) -> Option<&[CheckedPeer]> {
        self.checks.iter().find_map(|c| match c {
            PortCheck::Peers(p) => Some(p.as_slice()),
            _ => None,
        })
    }
}

impl PdPortDataAdjust {
    /// Bytes of the block.
    pub fn buffer_len(&self) -> usize {
        self.adjusts
            .iter()
            .fold(12usize, |n, a| n.saturating_add(a.buffer_len()))
    }

    /// The block as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        let body = self.buffer_len() - 6;
        crate::wire::emit_to_vec(self.buffer_len(), |b| {
            emit_block(
                "PDPortDataAdjust",
                BlockType::PdPortDataAdjust,
                0,
                body,
                b,
                |w| {
                    w.zeros(2)?;
                    w.u16(self.slot)?;
                    w.u16(self.subslot)?;
                    self.adjusts.iter().try_for_each(|a| a.emit(w))
                },
            )
            .map(|_| ())
        })
    }

    /// Parses the block at the start of `b`.
    pub fn parse(b: &[u8]) -> Result<PdPortDataAdjust> {
        let (slot, subslot, subs) = parse_frame(b, BlockType::PdPortDataAdjust)?;
        Ok(PdPortDataAdjust {
            slot,
            subslot,
            adjusts: sub_blocks(subs, PortAdjust::parse)?,
        })
    }

    /// The PeerToPeerBoundary it sets, if it does.
    pub fn peer_to_peer_boundary(&self) -> Option<u32> {
        self.adjusts.iter().find_map(|a| match a {
            PortAdjust::PeerToPeerBoundary { boundary, .. } => Some(*boundary),
            _ => None,
        })
    }

    /// The DCPBoundary it sets, if it does.
    pub fn dcp_boundary(&self) -> Option<u32> {
        self.adjusts.iter().find_map(|a| match a {
            PortAdjust::DcpBoundary { boundary, .. } => Some(*boundary),
            _ => None,
        })
    }
}

#[cfg(test)]
mod tests;
