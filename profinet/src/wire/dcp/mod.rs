// SPDX-License-Identifier: MIT OR Apache-2.0
//! DCP (Discovery and basic Configuration Protocol) PDUs.
//!
//! The PDU starts at the FrameID, i.e. at the Ethernet payload behind the optional 802.1Q tag
//! and the EtherType 0x8892:
//!
//! ```text
//! FrameID(2) ServiceID(1) ServiceType(1) Xid(4) ResponseDelay-or-Reserved(2) DCPDataLength(2) blocks…
//! ```
//!
//! A block is `Option(1) Suboption(1) DCPBlockLength(2) value…`, followed by one 0x00 when
//! DCPBlockLength is odd. The pad byte is not counted in DCPBlockLength but is counted in
//! DCPDataLength, after the last block too (the p-net Set response in the tests ends with
//! `05 04 00 03 01 02 00` + pad and has DCPDataLength 8). [`Repr::emit`] always pads;
//! [`Repr::parse`] also accepts a last odd block without its pad.
//!
//! What a block value starts with depends on the PDU ([`BlockContext`]): responses prefix it with
//! BlockInfo, Set requests with BlockQualifier, Identify filters have no prefix and Get requests
//! are a bare list of (option, suboption) pairs. The ControlResponse block (05/04) never has a
//! prefix. [`Block::prefix`] holds the BlockInfo or BlockQualifier, 0 when there is none.
//!
//! Everything is big-endian. DCP is not on the real-time path, so [`Repr`] owns its blocks.

use super::cursor::Writer;
use super::{
    EmitError, EmitResult, Error, Field, MacAddress, Rest, Result, be16, be32, check_announced_len,
};

mod block;
#[cfg(test)]
mod tests;

pub use block::{Block, BlockContext, BlockRepr};

/// FrameID of a Hello request (device initiative), sent to [`MacAddress::DCP_HELLO`].
pub const FRAME_ID_HELLO: u16 = 0xfefc;
/// FrameID of Get and Set requests and responses (unicast).
pub const FRAME_ID_GET_SET: u16 = 0xfefd;
/// FrameID of an Identify request, sent to [`MacAddress::DCP_IDENTIFY`].
pub const FRAME_ID_IDENTIFY_REQUEST: u16 = 0xfefe;
/// FrameID of an Identify response (unicast to the requester).
pub const FRAME_ID_IDENTIFY_RESPONSE: u16 = 0xfeff;

/// BlockQualifier of a Set request: apply temporarily (lost at power off).
pub const QUALIFIER_TEMPORARY: u16 = 0x0000;
/// BlockQualifier of a Set request: apply and store permanently.
pub const QUALIFIER_PERMANENT: u16 = 0x0001;

/// Above this ResponseDelayFactor a device answers an Identify request at once.
pub const MAX_RESPONSE_DELAY_FACTOR: u16 = 6400;

/// (Option, Suboption) codes of the blocks, usable with [`Repr::get`].
pub mod code {
    /// 01/01 MAC address.
    pub const MAC_ADDRESS: (u8, u8) = (0x01, 0x01);
    /// 01/02 IP parameter (IP, mask, gateway).
    pub const IP_PARAMETER: (u8, u8) = (0x01, 0x02);
    /// 01/03 full IP suite (IP parameter + 4 DNS servers).
    pub const FULL_IP_SUITE: (u8, u8) = (0x01, 0x03);
    /// 02/01 device vendor (TypeOfStation).
    pub const DEVICE_VENDOR: (u8, u8) = (0x02, 0x01);
    /// 02/02 NameOfStation.
    pub const NAME_OF_STATION: (u8, u8) = (0x02, 0x02);
    /// 02/03 VendorID and DeviceID.
    pub const DEVICE_ID: (u8, u8) = (0x02, 0x03);
    /// 02/04 device role.
    pub const DEVICE_ROLE: (u8, u8) = (0x02, 0x04);
    /// 02/05 device options (supported option/suboption pairs).
    pub const DEVICE_OPTIONS: (u8, u8) = (0x02, 0x05);
    /// 02/06 alias name (Identify filter only).
    pub const ALIAS_NAME: (u8, u8) = (0x02, 0x06);
    /// 02/07 device instance.
    pub const DEVICE_INSTANCE: (u8, u8) = (0x02, 0x07);
    /// 05/01 control: start transaction.
    pub const CONTROL_START: (u8, u8) = (0x05, 0x01);
    /// 05/02 control: stop transaction.
    pub const CONTROL_STOP: (u8, u8) = (0x05, 0x02);
    /// 05/03 control: signal (flash LED).
    pub const CONTROL_SIGNAL: (u8, u8) = (0x05, 0x03);
    /// 05/04 control: response (result of one Set/Get block).
    pub const CONTROL_RESPONSE: (u8, u8) = (0x05, 0x04);
    /// 05/05 control: factory reset.
    pub const FACTORY_RESET: (u8, u8) = (0x05, 0x05);
    /// 05/06 control: reset to factory (mode in the qualifier).
    pub const RESET_TO_FACTORY: (u8, u8) = (0x05, 0x06);
    /// 06/01 device initiative.
    pub const DEVICE_INITIATIVE: (u8, u8) = (0x06, 0x01);
    /// FF/FF all selector (Identify All).
    pub const ALL_SELECTOR: (u8, u8) = (0xff, 0xff);
}

/// BlockError values of a ControlResponse block.
pub mod block_error {
    /// No error.
    pub const OK: u8 = 0;
    /// Option not supported.
    pub const OPTION_UNSUPPORTED: u8 = 1;
    /// Suboption not supported or no data set available.
    pub const SUBOPTION_UNSUPPORTED: u8 = 2;
    /// Suboption not set.
    pub const SUBOPTION_NOT_SET: u8 = 3;
    /// Resource error.
    pub const RESOURCE_ERROR: u8 = 4;
    /// Set not possible for local reasons.
    pub const SET_NOT_POSSIBLE: u8 = 5;
    /// Set not possible in operation.
    pub const SET_NOT_POSSIBLE_IN_OPERATION: u8 = 6;
}

mod field {
    use super::{Field, Rest};
    pub const FRAME_ID: Field = 0..2;
    pub const SERVICE_ID: usize = 2;
    pub const SERVICE_TYPE: usize = 3;
    pub const XID: Field = 4..8;
    pub const RESPONSE_DELAY: Field = 8..10;
    pub const DATA_LENGTH: Field = 10..12;
    pub const BLOCKS: Rest = 12..;
}

/// Bytes of the header (FrameID included) before the blocks.
pub const HEADER_LEN: usize = field::BLOCKS.start;

/// Bytes of a block header (Option, Suboption, DCPBlockLength).
const BLOCK_HEADER_LEN: usize = 4;
/// Bytes of a BlockInfo or BlockQualifier.
const PREFIX_LEN: usize = 2;

coded_enum! {
    /// DCP ServiceID.
    pub enum ServiceId(u8) display "Service({:#04x})" {
        /// 3: Get.
        Get = 3 => "Get",
        /// 4: Set.
        Set = 4 => "Set",
        /// 5: Identify.
        Identify = 5 => "Identify",
        /// 6: Hello.
        Hello = 6 => "Hello",
    }
}

coded_enum! {
    /// DCP ServiceType.
    pub enum ServiceType(u8) display "Type({:#04x})" {
        /// 0x00: request.
        Request = 0x00 => "Request",
        /// 0x01: response, success.
        Success = 0x01 => "Success",
        /// 0x05: response, request not supported.
        NotSupported = 0x05 => "NotSupported",
    }
}

buffer_view! {
    /// A view of a DCP PDU, from the FrameID on.
    pub struct Packet;
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// Checks the buffer holds the header and the DCPDataLength bytes of blocks it announces.
    /// Bytes after them (Ethernet padding) are allowed and ignored.
    pub fn check_len(&self) -> Result<()> {
        check_announced_len(self.buffer.as_ref(), field::DATA_LENGTH, HEADER_LEN)
    }

    /// FrameID (one of the `FRAME_ID_*` constants for DCP).
    pub fn frame_id(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::FRAME_ID])
    }

    /// ServiceID.
    pub fn service_id(&self) -> ServiceId {
        ServiceId::from(self.buffer.as_ref()[field::SERVICE_ID])
    }

    /// ServiceType.
    pub fn service_type(&self) -> ServiceType {
        ServiceType::from(self.buffer.as_ref()[field::SERVICE_TYPE])
    }

    /// Xid (transaction id chosen by the requester, echoed in the response).
    pub fn xid(&self) -> u32 {
        be32(&self.buffer.as_ref()[field::XID])
    }

    /// ResponseDelayFactor in Identify requests; reserved (0) elsewhere.
    pub fn response_delay(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::RESPONSE_DELAY])
    }

    /// DCPDataLength: bytes of blocks, pads included.
    pub fn data_length(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::DATA_LENGTH])
    }

    /// The block bytes: exactly DCPDataLength bytes, trailing Ethernet padding excluded.
    /// Empty if the buffer is too short (never the case after `check_len`).
    pub fn blocks(&self) -> &[u8] {
        let end = HEADER_LEN + usize::from(self.data_length());
        self.buffer
            .as_ref()
            .get(field::BLOCKS.start..end)
            .unwrap_or(&[])
    }

    /// The context the blocks are encoded in.
    pub fn context(&self) -> BlockContext {
        BlockContext::of(self.service_id(), self.service_type())
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Packet<T> {
    /// Sets the FrameID.
    pub fn set_frame_id(&mut self, v: u16) {
        self.buffer.as_mut()[field::FRAME_ID].copy_from_slice(&v.to_be_bytes());
    }

    /// Sets the ServiceID.
    pub fn set_service_id(&mut self, v: ServiceId) {
        self.buffer.as_mut()[field::SERVICE_ID] = v.into();
    }

    /// Sets the ServiceType.
    pub fn set_service_type(&mut self, v: ServiceType) {
        self.buffer.as_mut()[field::SERVICE_TYPE] = v.into();
    }

    /// Sets the Xid.
    pub fn set_xid(&mut self, v: u32) {
        self.buffer.as_mut()[field::XID].copy_from_slice(&v.to_be_bytes());
    }

    /// Sets the ResponseDelayFactor / reserved field.
    pub fn set_response_delay(&mut self, v: u16) {
        self.buffer.as_mut()[field::RESPONSE_DELAY].copy_from_slice(&v.to_be_bytes());
    }

    /// Sets DCPDataLength.
    pub fn set_data_length(&mut self, v: u16) {
        self.buffer.as_mut()[field::DATA_LENGTH].copy_from_slice(&v.to_be_bytes());
    }

    /// The block bytes, mutable: DCPDataLength bytes (empty if the buffer is too short).
    pub fn blocks_mut(&mut self) -> &mut [u8] {
        let end = HEADER_LEN + usize::from(self.data_length());
        self.buffer
            .as_mut()
            .get_mut(field::BLOCKS.start..end)
            .unwrap_or(&mut [])
    }
}

impl<T: AsRef<[u8]>> core::fmt::Display for Packet<T> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match Repr::parse(&Packet::new_unchecked(self.buffer.as_ref())) {
            Ok(r) => write!(f, "{r}"),
            Err(_) => f.write_str("DCP (malformed)"),
        }
    }
}

/// A parsed DCP PDU.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Repr {
    /// FrameID (`FRAME_ID_*`).
    pub frame_id: u16,
    /// ServiceID.
    pub service_id: ServiceId,
    /// ServiceType.
    pub service_type: ServiceType,
    /// Xid.
    pub xid: u32,
    /// ResponseDelayFactor (Identify requests) or the reserved field (0 elsewhere).
    pub response_delay: u16,
    /// The blocks, in order. In a Get request they are [`BlockRepr::Requested`] pairs.
    pub blocks: Vec<Block>,
}

impl Repr {
    /// Parses a PDU (checking its length first). Malformed framing (a block running past
    /// DCPDataLength, a missing prefix, an odd Get request) gives [`Error`]; values that do
    /// not decode become [`BlockRepr::Unknown`].
    pub fn parse<T: AsRef<[u8]> + ?Sized>(packet: &Packet<&T>) -> Result<Repr> {
        packet.check_len()?;
        let ctx = packet.context();
        let mut data = packet.blocks();
        let mut blocks = Vec::new();
        if ctx == BlockContext::GetRequest {
            let (pairs, rest) = data.as_chunks::<2>();
            if !rest.is_empty() {
                return Err(Error);
            }
            blocks.extend(pairs.iter().map(|&[option, suboption]| {
                Block::bare(BlockRepr::Requested { option, suboption })
            }));
        } else {
            while !data.is_empty() {
                let (hdr, rest) = data.split_at_checked(BLOCK_HEADER_LEN).ok_or(Error)?;
                let len = usize::from(be16(&hdr[2..4]));
                let (body, rest) = rest.split_at_checked(len).ok_or(Error)?;
                blocks.push(Block::parse(ctx, hdr[0], hdr[1], body)?);
                // The pad after an odd block; tolerated missing after the last one.
                data = match rest.split_first() {
                    Some((_, after_pad)) if len % 2 == 1 => after_pad,
                    _ => rest,
                };
            }
        }
        Ok(Repr {
            frame_id: packet.frame_id(),
            service_id: packet.service_id(),
            service_type: packet.service_type(),
            xid: packet.xid(),
            response_delay: packet.response_delay(),
            blocks,
        })
    }

    /// The context the blocks are encoded in.
    pub const fn context(&self) -> BlockContext {
        BlockContext::of(self.service_id, self.service_type)
    }

    /// Bytes of the blocks (DCPDataLength), pads included.
    pub fn data_len(&self) -> usize {
        let ctx = self.context();
        self.blocks
            .iter()
            .fold(0usize, |n, b| n.saturating_add(b.buffer_len(ctx)))
    }

    /// Bytes of the PDU from the FrameID on, without Ethernet padding.
    pub fn buffer_len(&self) -> usize {
        HEADER_LEN.saturating_add(self.data_len())
    }

    /// Writes the PDU into the first [`buffer_len`](Self::buffer_len) bytes of `buf` (a plain
    /// slice starting at the FrameID; the caller adds the Ethernet header and pads the frame to
    /// 60 bytes). Never panics: a buffer shorter than `buffer_len()`, a block longer than
    /// 65535 bytes or DCPDataLength above 65535 give [`EmitError`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        let ctx = self.context();
        let data_len = self.data_len();
        let data_len = u16::try_from(data_len)
            .map_err(|_| EmitError::too_long_u16("DCPDataLength", data_len))?;
        let total = self.buffer_len();
        let len = buf.len();
        let pdu = buf.get_mut(..total).ok_or(EmitError::BufferTooShort {
            what: "DCP PDU",
            needed: total,
            len,
        })?;
        let (header, blocks) = pdu.split_at_mut(HEADER_LEN);
        let mut p = Packet::new_unchecked(header);
        p.set_frame_id(self.frame_id);
        p.set_service_id(self.service_id);
        p.set_service_type(self.service_type);
        p.set_xid(self.xid);
        p.set_response_delay(self.response_delay);
        p.set_data_length(data_len);
        let mut w = Writer::new("DCP blocks", blocks);
        self.blocks.iter().try_for_each(|b| b.emit(ctx, &mut w))?;
        w.finish()
    }

    /// The PDU as a new vector of [`buffer_len`](Self::buffer_len) bytes.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b))
    }

    fn request(
        frame_id: u16,
        service_id: ServiceId,
        xid: u32,
        rdf: u16,
        blocks: Vec<Block>,
    ) -> Repr {
        Repr {
            frame_id,
            service_id,
            service_type: ServiceType::Request,
            xid,
            response_delay: rdf,
            blocks,
        }
    }

    /// Identify All (to [`MacAddress::DCP_IDENTIFY`]): one AllSelector block. Use a large
    /// `response_delay` factor (e.g. 0x80) when scanning a network.
    pub fn identify_all(xid: u32, response_delay: u16) -> Repr {
        Repr::request(
            FRAME_ID_IDENTIFY_REQUEST,
            ServiceId::Identify,
            xid,
            response_delay,
            vec![Block::bare(BlockRepr::AllSelector)],
        )
    }

    /// Identify by NameOfStation (to [`MacAddress::DCP_IDENTIFY`]); the S7 uses factor 1.
    pub fn identify_by_name(xid: u32, response_delay: u16, name: &str) -> Repr {
        Repr::request(
            FRAME_ID_IDENTIFY_REQUEST,
            ServiceId::Identify,
            xid,
            response_delay,
            vec![Block::bare(BlockRepr::NameOfStation(name.into()))],
        )
    }

    fn set(xid: u32, block: Block) -> Repr {
        Repr::request(FRAME_ID_GET_SET, ServiceId::Set, xid, 0, vec![block])
    }

    const fn qualifier(permanent: bool) -> u16 {
        if permanent {
            QUALIFIER_PERMANENT
        } else {
            QUALIFIER_TEMPORARY
        }
    }

    /// Set IP parameter (unicast). A gateway equal to `ip` means "no gateway".
    pub fn set_ip(xid: u32, ip: [u8; 4], mask: [u8; 4], gateway: [u8; 4], permanent: bool) -> Repr {
        Repr::set(
            xid,
            Block::new(
                Repr::qualifier(permanent),
                BlockRepr::IpParameter { ip, mask, gateway },
            ),
        )
    }

    /// Set NameOfStation (unicast).
    pub fn set_name(xid: u32, name: &str, permanent: bool) -> Repr {
        Repr::set(
            xid,
            Block::new(
                Repr::qualifier(permanent),
                BlockRepr::NameOfStation(name.into()),
            ),
        )
    }

    /// Reset to factory (05/06) in reset `mode` (1 application data, 2 communication
    /// parameters, 8 all data, …), carried in bits 1 to 15 of the BlockQualifier.
    pub fn reset_to_factory(xid: u32, mode: u16) -> Repr {
        let qualifier = mode << 1;
        Repr::set(
            xid,
            Block::new(qualifier, BlockRepr::ResetToFactory(qualifier)),
        )
    }

    /// Flash the device's LED: ControlSignal, qualifier 0, SignalValue 0x0100.
    pub fn signal(xid: u32) -> Repr {
        Repr::set(
            xid,
            Block::new(QUALIFIER_TEMPORARY, BlockRepr::ControlSignal(0x0100)),
        )
    }

    /// Get request for these (option, suboption) pairs (see [`code`]).
    pub fn get(xid: u32, pairs: &[(u8, u8)]) -> Repr {
        let blocks = pairs
            .iter()
            .map(|&(option, suboption)| Block::bare(BlockRepr::Requested { option, suboption }))
            .collect();
        Repr::request(FRAME_ID_GET_SET, ServiceId::Get, xid, 0, blocks)
    }

    fn values(&self) -> impl Iterator<Item = &BlockRepr> {
        self.blocks.iter().map(|b| &b.value)
    }

    /// The first NameOfStation block's name.
    pub fn name_of_station(&self) -> Option<&str> {
        self.values().find_map(|v| match v {
            BlockRepr::NameOfStation(s) => Some(s.as_str()),
            _ => None,
        })
    }

    /// The first DeviceVendor block's text.
    pub fn device_vendor(&self) -> Option<&str> {
        self.values().find_map(|v| match v {
            BlockRepr::DeviceVendor(s) => Some(s.as_str()),
            _ => None,
        })
    }

    /// (ip, mask, gateway) of the first IpParameter or FullIpSuite block.
    pub fn ip(&self) -> Option<([u8; 4], [u8; 4], [u8; 4])> {
        self.values().find_map(|v| match v {
            BlockRepr::IpParameter { ip, mask, gateway }
            | BlockRepr::FullIpSuite {
                ip, mask, gateway, ..
            } => Some((*ip, *mask, *gateway)),
            _ => None,
        })
    }

    /// (VendorID, DeviceID) of the first DeviceId block.
    pub fn device_id(&self) -> Option<(u16, u16)> {
        self.values().find_map(|v| match v {
            BlockRepr::DeviceId {
                vendor_id,
                device_id,
            } => Some((*vendor_id, *device_id)),
            _ => None,
        })
    }

    /// The first MacAddress block's address (p-net does not send one; use the Ethernet source).
    pub fn mac(&self) -> Option<MacAddress> {
        self.values().find_map(|v| match v {
            BlockRepr::MacAddress(m) => Some(*m),
            _ => None,
        })
    }

    /// Every ControlResponse block as (option, suboption, BlockError), in order. A Set
    /// succeeded when the ServiceType is `Success` and every BlockError is
    /// [`block_error::OK`].
    pub fn set_result(&self) -> impl Iterator<Item = (u8, u8, u8)> + '_ {
        self.values().filter_map(|v| match v {
            BlockRepr::ControlResponse {
                option,
                suboption,
                error,
            } => Some((*option, *suboption, *error)),
            _ => None,
        })
    }
}

impl core::fmt::Display for Repr {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "DCP frame_id={:#06x} {} {} xid={:#010x} delay={}",
            self.frame_id, self.service_id, self.service_type, self.xid, self.response_delay
        )?;
        for b in &self.blocks {
            let (o, s) = b.value.code();
            write!(f, " [{o:02x}/{s:02x}")?;
            if b.prefix != 0 {
                write!(f, " prefix={:#06x}", b.prefix)?;
            }
            f.write_str("]")?;
        }
        Ok(())
    }
}

/// How long a device waits before answering an Identify request with this
/// ResponseDelayFactor: `((MAC[4] << 8 | MAC[5]) mod factor) × 10 ms`; 0 (immediate) when the
/// factor is 0, 1 or above [`MAX_RESPONSE_DELAY_FACTOR`].
pub fn response_delay_ns(mac: MacAddress, factor: u16) -> u64 {
    if factor <= 1 || factor > MAX_RESPONSE_DELAY_FACTOR {
        return 0;
    }
    let slot = u16::from_be_bytes([mac.0[4], mac.0[5]]) % factor;
    u64::from(slot) * 10_000_000
}
