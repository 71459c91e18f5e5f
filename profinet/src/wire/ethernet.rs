// SPDX-License-Identifier: MIT OR Apache-2.0
//! Ethernet II frames, with or without one IEEE 802.1Q tag.
//!
//! PROFINET sends RT frames tagged (PCP 6, VID 0); DCP may be tagged or not; Linux often
//! strips the tag before AF_PACKET sees a frame. The view finds the EtherType behind an
//! optional tag, so callers see one form.

use super::{EmitError, EmitResult, Error, Field, MacAddress, Rest, Result, be16};

/// EtherType of PROFINET real-time frames (RT, DCP, RTA alarms).
pub const ETHERTYPE_PROFINET: u16 = 0x8892;
/// TPID of an IEEE 802.1Q tag.
pub const TPID_VLAN: u16 = 0x8100;

mod field {
    use super::{Field, Rest};
    pub const DST: Field = 0..6;
    pub const SRC: Field = 6..12;
    pub const TYPE: Field = 12..14;
    pub const TCI: Field = 14..16;
    pub const INNER_TYPE: Field = 16..18;
    pub const PAYLOAD_UNTAGGED: Rest = 14..;
    pub const PAYLOAD_TAGGED: Rest = 18..;
}

/// Bytes of an untagged header.
pub const HEADER_LEN: usize = field::PAYLOAD_UNTAGGED.start;
/// Bytes of a tagged header.
pub const TAGGED_HEADER_LEN: usize = field::PAYLOAD_TAGGED.start;

buffer_view! {
    /// A view of an Ethernet II frame.
    pub struct Frame;
}

impl<T: AsRef<[u8]>> Frame<T> {
    /// Checks the buffer holds the header (including a tag if there is one).
    pub fn check_len(&self) -> Result<()> {
        let len = self.buffer.as_ref().len();
        if len < HEADER_LEN || (self.is_tagged() && len < TAGGED_HEADER_LEN) {
            Err(Error)
        } else {
            Ok(())
        }
    }

    /// Destination MAC.
    pub fn dst(&self) -> MacAddress {
        MacAddress::from_slice(&self.buffer.as_ref()[field::DST])
    }

    /// Source MAC.
    pub fn src(&self) -> MacAddress {
        MacAddress::from_slice(&self.buffer.as_ref()[field::SRC])
    }

    /// Whether an 802.1Q tag follows the addresses. Safe on any buffer.
    pub fn is_tagged(&self) -> bool {
        self.buffer
            .as_ref()
            .get(field::TYPE)
            .is_some_and(|b| be16(b) == TPID_VLAN)
    }

    /// The tag control information, if tagged.
    pub fn tci(&self) -> Option<u16> {
        self.is_tagged()
            .then(|| be16(&self.buffer.as_ref()[field::TCI]))
    }

    /// The EtherType (behind the tag, if any).
    pub fn ethertype(&self) -> u16 {
        let b = self.buffer.as_ref();
        if self.is_tagged() {
            be16(&b[field::INNER_TYPE])
        } else {
            be16(&b[field::TYPE])
        }
    }

    /// Offset of the payload.
    pub fn header_len(&self) -> usize {
        if self.is_tagged() {
            TAGGED_HEADER_LEN
        } else {
            HEADER_LEN
        }
    }
}

impl<'a, T: AsRef<[u8]> + ?Sized> Frame<&'a T> {
    /// The payload after the (tagged or untagged) header.
    pub fn payload(&self) -> &'a [u8] {
        let at = self.header_len();
        &self.buffer.as_ref()[at..]
    }
}

/// An 802.1Q tag.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VlanTag {
    /// Priority code point, 0..=7.
    pub pcp: u8,
    /// Drop eligible indicator.
    pub dei: bool,
    /// VLAN id, 0..=4095.
    pub vid: u16,
}

impl VlanTag {
    /// PROFINET RT: priority 6, VLAN 0 (TCI 0xC000).
    pub const RT: VlanTag = VlanTag {
        pcp: 6,
        dei: false,
        vid: 0,
    };

    /// From a TCI.
    pub const fn from_tci(tci: u16) -> VlanTag {
        VlanTag {
            // The top 3 bits of the TCI: 0..=7, so the cast keeps every bit.
            pcp: (tci >> 13) as u8,
            dei: tci & 0x1000 != 0,
            vid: tci & 0x0fff,
        }
    }

    /// As a TCI.
    pub const fn tci(&self) -> u16 {
        ((self.pcp as u16 & 7) << 13) | if self.dei { 0x1000 } else { 0 } | (self.vid & 0x0fff)
    }
}

/// A parsed Ethernet header.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Repr {
    /// Destination.
    pub dst: MacAddress,
    /// Source.
    pub src: MacAddress,
    /// The tag, if any.
    pub vlan: Option<VlanTag>,
    /// EtherType (behind the tag).
    pub ethertype: u16,
}

impl Repr {
    /// Parses the header of a checked frame.
    pub fn parse<T: AsRef<[u8]>>(frame: &Frame<T>) -> Result<Repr> {
        frame.check_len()?;
        Ok(Repr {
            dst: frame.dst(),
            src: frame.src(),
            vlan: frame.tci().map(VlanTag::from_tci),
            ethertype: frame.ethertype(),
        })
    }

    /// Bytes of the header.
    pub const fn buffer_len(&self) -> usize {
        if self.vlan.is_some() {
            TAGGED_HEADER_LEN
        } else {
            HEADER_LEN
        }
    }

    /// The header bytes: the first [`buffer_len`](Self::buffer_len) of the array.
    fn bytes(&self) -> [u8; TAGGED_HEADER_LEN] {
        let mut b = [0u8; TAGGED_HEADER_LEN];
        b[field::DST].copy_from_slice(&self.dst.0);
        b[field::SRC].copy_from_slice(&self.src.0);
        match self.vlan {
            Some(tag) => {
                b[field::TYPE].copy_from_slice(&TPID_VLAN.to_be_bytes());
                b[field::TCI].copy_from_slice(&tag.tci().to_be_bytes());
                b[field::INNER_TYPE].copy_from_slice(&self.ethertype.to_be_bytes());
            }
            None => b[field::TYPE].copy_from_slice(&self.ethertype.to_be_bytes()),
        }
        b
    }

    /// Writes the header into the first `buffer_len()` bytes of `buf`; a shorter buffer gives
    /// [`EmitError::BufferTooShort`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        let (needed, len) = (self.buffer_len(), buf.len());
        let out = buf.get_mut(..needed).ok_or(EmitError::BufferTooShort {
            what: "Ethernet header",
            needed,
            len,
        })?;
        out.copy_from_slice(&self.bytes()[..needed]);
        Ok(())
    }

    /// A frame of this header followed by `payload`, padded with zeros to at least `min_len`
    /// bytes (60 without FCS is the Ethernet minimum; tagged PROFINET frames are padded to 64
    /// so that they keep it once a switch removes the tag).
    pub fn frame(&self, payload: &[u8], min_len: usize) -> Vec<u8> {
        let header = self.bytes();
        let mut f = Vec::with_capacity(min_len.max(TAGGED_HEADER_LEN + payload.len()));
        f.extend_from_slice(header.get(..self.buffer_len()).unwrap_or(&header));
        f.extend_from_slice(payload);
        if f.len() < min_len {
            f.resize(min_len, 0);
        }
        f
    }
}

/// The smallest Ethernet frame without FCS; shorter frames are padded.
pub const MIN_FRAME_LEN: usize = 60;

/// An Ethernet frame around a PROFINET PDU, tagged if `tci` is given, padded to
/// [`MIN_FRAME_LEN`] bytes.
pub fn profinet_frame(dst: MacAddress, src: MacAddress, tci: Option<u16>, pdu: &[u8]) -> Vec<u8> {
    let eth = Repr {
        dst,
        src,
        vlan: tci.map(VlanTag::from_tci),
        ethertype: ETHERTYPE_PROFINET,
    };
    eth.frame(pdu, MIN_FRAME_LEN)
}

#[cfg(test)]
mod tests {
    use super::*;

    // S7-1515 -> p-net cyclic frame (captures/rt/rtc_cpu_8001.hex), first 20 bytes.
    static TAGGED: [u8; 20] = [
        0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8, 0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f, 0x81, 0x00, 0xc0,
        0x00, 0x88, 0x92, 0x80, 0x01,
    ];

    #[test]
    fn deconstruct_tagged() {
        let f = Frame::new_checked(&TAGGED[..]).unwrap();
        let r = Repr::parse(&f).unwrap();
        assert_eq!(r.vlan, Some(VlanTag::RT));
        assert_eq!(r.ethertype, ETHERTYPE_PROFINET);
        assert_eq!(r.src, MacAddress([0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f]));
        assert_eq!(f.payload(), &[0x80, 0x01]);
    }

    #[test]
    fn construct_tagged() {
        let r = Repr::parse(&Frame::new_unchecked(&TAGGED[..])).unwrap();
        let mut buf = [0xa5u8; 18];
        r.emit(&mut buf).unwrap();
        assert_eq!(&buf[..], &TAGGED[..18]);
        assert_eq!(
            r.emit(&mut buf[..17]),
            Err(EmitError::BufferTooShort {
                what: "Ethernet header",
                needed: 18,
                len: 17
            })
        );
        let f = r.frame(&TAGGED[18..], 60);
        assert_eq!((&f[..20], f.len()), (&TAGGED[..], 60));
    }

    #[test]
    fn short_buffers_are_refused() {
        for n in 0..TAGGED_HEADER_LEN {
            let f = Frame::new_unchecked(&TAGGED[..n]);
            assert!(Repr::parse(&f).is_err() || n >= HEADER_LEN && !f.is_tagged());
        }
    }
}
