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
use super::{Error, Field, MacAddress, Rest, Result, be16, be32};

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

/// DCP ServiceID.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ServiceId {
    /// 3: Get.
    Get,
    /// 4: Set.
    Set,
    /// 5: Identify.
    Identify,
    /// 6: Hello.
    Hello,
    /// Any other value (never 3..=6).
    Unknown(u8),
}

impl From<u8> for ServiceId {
    fn from(v: u8) -> ServiceId {
        match v {
            3 => ServiceId::Get,
            4 => ServiceId::Set,
            5 => ServiceId::Identify,
            6 => ServiceId::Hello,
            other => ServiceId::Unknown(other),
        }
    }
}

impl From<ServiceId> for u8 {
    fn from(v: ServiceId) -> u8 {
        match v {
            ServiceId::Get => 3,
            ServiceId::Set => 4,
            ServiceId::Identify => 5,
            ServiceId::Hello => 6,
            ServiceId::Unknown(other) => other,
        }
    }
}

impl core::fmt::Display for ServiceId {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ServiceId::Get => f.write_str("Get"),
            ServiceId::Set => f.write_str("Set"),
            ServiceId::Identify => f.write_str("Identify"),
            ServiceId::Hello => f.write_str("Hello"),
            ServiceId::Unknown(v) => write!(f, "Service({v:#04x})"),
        }
    }
}

/// DCP ServiceType.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ServiceType {
    /// 0x00: request.
    Request,
    /// 0x01: response, success.
    Success,
    /// 0x05: response, request not supported.
    NotSupported,
    /// Any other value (never 0x00, 0x01 or 0x05).
    Unknown(u8),
}

impl From<u8> for ServiceType {
    fn from(v: u8) -> ServiceType {
        match v {
            0x00 => ServiceType::Request,
            0x01 => ServiceType::Success,
            0x05 => ServiceType::NotSupported,
            other => ServiceType::Unknown(other),
        }
    }
}

impl From<ServiceType> for u8 {
    fn from(v: ServiceType) -> u8 {
        match v {
            ServiceType::Request => 0x00,
            ServiceType::Success => 0x01,
            ServiceType::NotSupported => 0x05,
            ServiceType::Unknown(other) => other,
        }
    }
}

impl core::fmt::Display for ServiceType {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ServiceType::Request => f.write_str("Request"),
            ServiceType::Success => f.write_str("Success"),
            ServiceType::NotSupported => f.write_str("NotSupported"),
            ServiceType::Unknown(v) => write!(f, "Type({v:#04x})"),
        }
    }
}

/// How the blocks of a PDU are encoded; follows from its ServiceID and ServiceType.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BlockContext {
    /// Identify request filter blocks: no prefix. Also used for requests of unknown services,
    /// as the plainest, lossless reading.
    IdentifyFilter,
    /// Set request: every value is prefixed by a BlockQualifier.
    SetRequest,
    /// Identify/Get/Set responses, any non-request ServiceType, and Hello requests: every
    /// value is prefixed by a BlockInfo (except ControlResponse blocks).
    Response,
    /// Get request: a bare list of (option, suboption) pairs.
    GetRequest,
}

impl BlockContext {
    /// The context of a PDU with these service fields.
    pub const fn of(service_id: ServiceId, service_type: ServiceType) -> BlockContext {
        match (service_id, service_type) {
            (ServiceId::Set, ServiceType::Request) => BlockContext::SetRequest,
            (ServiceId::Get, ServiceType::Request) => BlockContext::GetRequest,
            (ServiceId::Hello, ServiceType::Request) => BlockContext::Response,
            (_, ServiceType::Request) => BlockContext::IdentifyFilter,
            _ => BlockContext::Response,
        }
    }

    /// Whether a block with this code carries a BlockInfo/BlockQualifier in this context.
    pub const fn has_prefix(self, option: u8, suboption: u8) -> bool {
        let control_response =
            option == code::CONTROL_RESPONSE.0 && suboption == code::CONTROL_RESPONSE.1;
        matches!(self, BlockContext::SetRequest | BlockContext::Response) && !control_response
    }
}

/// A view of a DCP PDU, from the FrameID on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Packet<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// Wraps a buffer without checking it.
    pub const fn new_unchecked(buffer: T) -> Packet<T> {
        Packet { buffer }
    }

    /// Wraps a buffer after [`check_len`](Self::check_len).
    pub fn new_checked(buffer: T) -> Result<Packet<T>> {
        let p = Packet::new_unchecked(buffer);
        p.check_len()?;
        Ok(p)
    }

    /// Checks the buffer holds the header and the DCPDataLength bytes of blocks it announces.
    /// Bytes after them (Ethernet padding) are allowed and ignored.
    pub fn check_len(&self) -> Result<()> {
        let b = self.buffer.as_ref();
        let Some(len) = b.get(field::DATA_LENGTH) else {
            return Err(Error);
        };
        if b.len() < HEADER_LEN + usize::from(be16(len)) {
            Err(Error)
        } else {
            Ok(())
        }
    }

    /// The buffer.
    pub fn into_inner(self) -> T {
        self.buffer
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

/// The value of one DCP block.
///
/// Strings (DeviceVendor, NameOfStation, AliasName) are kept byte for byte; bytes that are not
/// UTF-8 make the block parse as [`BlockRepr::Unknown`], so parsing stays lossless and never
/// fails on them. Likewise a known option/suboption whose value has the wrong length parses as
/// `Unknown`; `Unknown` otherwise means an option/suboption this module does not model.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum BlockRepr {
    /// 01/01 MAC address.
    MacAddress(MacAddress),
    /// 01/02 IP parameter. In responses, BlockInfo bit 0 = IP set, bit 1 = via DHCP,
    /// bit 7 = IP conflict. A gateway equal to the IP means "no gateway".
    IpParameter {
        /// IP address.
        ip: [u8; 4],
        /// Subnet mask.
        mask: [u8; 4],
        /// Default gateway.
        gateway: [u8; 4],
    },
    /// 01/03 full IP suite.
    FullIpSuite {
        /// IP address.
        ip: [u8; 4],
        /// Subnet mask.
        mask: [u8; 4],
        /// Default gateway.
        gateway: [u8; 4],
        /// DNS servers.
        dns: [[u8; 4]; 4],
    },
    /// 02/01 device vendor (TypeOfStation).
    DeviceVendor(String),
    /// 02/02 NameOfStation (DNS-compatible ASCII, at most 240 characters; not enforced here).
    NameOfStation(String),
    /// 02/03 VendorID and DeviceID.
    DeviceId {
        /// VendorID.
        vendor_id: u16,
        /// DeviceID.
        device_id: u16,
    },
    /// 02/04 device role: bit 0 IO device, bit 1 IO controller, bit 2 multidevice,
    /// bit 3 supervisor. The reserved byte is kept because p-net sends it non-zero (0x01).
    DeviceRole {
        /// Role bits.
        role: u8,
        /// The reserved byte after them, as received.
        reserved: u8,
    },
    /// 02/05 the (option, suboption) pairs the device supports.
    DeviceOptions(Vec<(u8, u8)>),
    /// 02/06 alias name (`port-xyz.name`), Identify filter only.
    AliasName(String),
    /// 02/07 device instance.
    DeviceInstance {
        /// High byte.
        high: u8,
        /// Low byte.
        low: u8,
    },
    /// 05/01 start transaction (Set).
    ControlStart,
    /// 05/02 stop transaction (Set).
    ControlStop,
    /// 05/03 signal (Set): SignalValue, 0x0100 = flash once.
    ControlSignal(u16),
    /// 05/04 result of one block of a Set/Get request. Never has a BlockInfo/BlockQualifier.
    ControlResponse {
        /// Option of the block answered.
        option: u8,
        /// Suboption of the block answered.
        suboption: u8,
        /// BlockError, see [`block_error`].
        error: u8,
    },
    /// 05/05 factory reset. The block holds 2 bytes in total: in a Set request (and in
    /// responses) they are the BlockQualifier, so the u16 *is* the qualifier and
    /// [`Block::prefix`] mirrors it ([`Repr::emit`] writes the u16, ignoring `prefix`); in an
    /// Identify filter they are the plain value.
    FactoryReset(u16),
    /// 05/06 reset to factory; the u16 is the BlockQualifier carrying the reset mode. Encoded
    /// like [`BlockRepr::FactoryReset`].
    ResetToFactory(u16),
    /// 06/01 device initiative: bit 0 = the device sends Hello.
    DeviceInitiative(u16),
    /// FF/FF all selector (Identify All): empty value.
    AllSelector,
    /// One (option, suboption) pair of a Get request. Only meaningful in
    /// [`BlockContext::GetRequest`] (elsewhere it is emitted as a block with an empty value);
    /// in a Get request every other variant is emitted as its bare (option, suboption) pair.
    Requested {
        /// Option.
        option: u8,
        /// Suboption.
        suboption: u8,
    },
    /// Any other block, or a known one whose value does not decode; `data` is the value after
    /// the prefix (if the context has one).
    Unknown {
        /// Option.
        option: u8,
        /// Suboption.
        suboption: u8,
        /// The value bytes.
        data: Vec<u8>,
    },
}

impl BlockRepr {
    /// The (option, suboption) of this block.
    pub fn code(&self) -> (u8, u8) {
        match self {
            BlockRepr::MacAddress(_) => code::MAC_ADDRESS,
            BlockRepr::IpParameter { .. } => code::IP_PARAMETER,
            BlockRepr::FullIpSuite { .. } => code::FULL_IP_SUITE,
            BlockRepr::DeviceVendor(_) => code::DEVICE_VENDOR,
            BlockRepr::NameOfStation(_) => code::NAME_OF_STATION,
            BlockRepr::DeviceId { .. } => code::DEVICE_ID,
            BlockRepr::DeviceRole { .. } => code::DEVICE_ROLE,
            BlockRepr::DeviceOptions(_) => code::DEVICE_OPTIONS,
            BlockRepr::AliasName(_) => code::ALIAS_NAME,
            BlockRepr::DeviceInstance { .. } => code::DEVICE_INSTANCE,
            BlockRepr::ControlStart => code::CONTROL_START,
            BlockRepr::ControlStop => code::CONTROL_STOP,
            BlockRepr::ControlSignal(_) => code::CONTROL_SIGNAL,
            BlockRepr::ControlResponse { .. } => code::CONTROL_RESPONSE,
            BlockRepr::FactoryReset(_) => code::FACTORY_RESET,
            BlockRepr::ResetToFactory(_) => code::RESET_TO_FACTORY,
            BlockRepr::DeviceInitiative(_) => code::DEVICE_INITIATIVE,
            BlockRepr::AllSelector => code::ALL_SELECTOR,
            BlockRepr::Requested { option, suboption }
            | BlockRepr::Unknown {
                option, suboption, ..
            } => (*option, *suboption),
        }
    }

    /// Decodes a value (the bytes after the prefix). `prefix` is `Some` when the context
    /// has one. Never fails: what does not decode becomes `Unknown`.
    fn parse(option: u8, suboption: u8, prefix: Option<u16>, v: &[u8]) -> BlockRepr {
        let ip4 = |at: usize| -> [u8; 4] {
            let mut a = [0u8; 4];
            if let Some(s) = v.get(at..at + 4) {
                a.copy_from_slice(s);
            }
            a
        };
        let string = |v: &[u8]| core::str::from_utf8(v).ok().map(String::from);
        let decoded = match ((option, suboption), v.len()) {
            (code::MAC_ADDRESS, 6) => Some(BlockRepr::MacAddress(MacAddress::from_slice(v))),
            (code::IP_PARAMETER, 12) => Some(BlockRepr::IpParameter {
                ip: ip4(0),
                mask: ip4(4),
                gateway: ip4(8),
            }),
            (code::FULL_IP_SUITE, 28) => Some(BlockRepr::FullIpSuite {
                ip: ip4(0),
                mask: ip4(4),
                gateway: ip4(8),
                dns: [ip4(12), ip4(16), ip4(20), ip4(24)],
            }),
            (code::DEVICE_VENDOR, _) => string(v).map(BlockRepr::DeviceVendor),
            (code::NAME_OF_STATION, _) => string(v).map(BlockRepr::NameOfStation),
            (code::DEVICE_ID, 4) => Some(BlockRepr::DeviceId {
                vendor_id: be16(&v[0..2]),
                device_id: be16(&v[2..4]),
            }),
            (code::DEVICE_ROLE, 2) => Some(BlockRepr::DeviceRole {
                role: v[0],
                reserved: v[1],
            }),
            (code::DEVICE_OPTIONS, n) if n % 2 == 0 => Some(BlockRepr::DeviceOptions(
                v.chunks_exact(2).map(|p| (p[0], p[1])).collect(),
            )),
            (code::ALIAS_NAME, _) => string(v).map(BlockRepr::AliasName),
            (code::DEVICE_INSTANCE, 2) => Some(BlockRepr::DeviceInstance {
                high: v[0],
                low: v[1],
            }),
            (code::CONTROL_START, 0) => Some(BlockRepr::ControlStart),
            (code::CONTROL_STOP, 0) => Some(BlockRepr::ControlStop),
            (code::CONTROL_SIGNAL, 2) => Some(BlockRepr::ControlSignal(be16(v))),
            (code::CONTROL_RESPONSE, 3) => Some(BlockRepr::ControlResponse {
                option: v[0],
                suboption: v[1],
                error: v[2],
            }),
            (code::FACTORY_RESET, n) => qualifier_value(prefix, v, n).map(BlockRepr::FactoryReset),
            (code::RESET_TO_FACTORY, n) => {
                qualifier_value(prefix, v, n).map(BlockRepr::ResetToFactory)
            }
            (code::DEVICE_INITIATIVE, 2) => Some(BlockRepr::DeviceInitiative(be16(v))),
            (code::ALL_SELECTOR, 0) => Some(BlockRepr::AllSelector),
            _ => None,
        };
        decoded.unwrap_or_else(|| BlockRepr::Unknown {
            option,
            suboption,
            data: v.to_vec(),
        })
    }

    /// Bytes of the value after the prefix.
    fn value_len(&self, prefixed: bool) -> usize {
        match self {
            BlockRepr::MacAddress(_) => 6,
            BlockRepr::IpParameter { .. } => 12,
            BlockRepr::FullIpSuite { .. } => 28,
            BlockRepr::DeviceVendor(s) | BlockRepr::NameOfStation(s) | BlockRepr::AliasName(s) => {
                s.len()
            }
            BlockRepr::DeviceId { .. } => 4,
            BlockRepr::DeviceRole { .. }
            | BlockRepr::DeviceInstance { .. }
            | BlockRepr::ControlSignal(_)
            | BlockRepr::DeviceInitiative(_) => 2,
            BlockRepr::DeviceOptions(o) => o.len().saturating_mul(2),
            BlockRepr::ControlStart
            | BlockRepr::ControlStop
            | BlockRepr::AllSelector
            | BlockRepr::Requested { .. } => 0,
            BlockRepr::ControlResponse { .. } => 3,
            BlockRepr::FactoryReset(_) | BlockRepr::ResetToFactory(_) => {
                if prefixed {
                    0
                } else {
                    2
                }
            }
            BlockRepr::Unknown { data, .. } => data.len(),
        }
    }

    /// Writes the value after the prefix.
    fn emit_value(&self, prefixed: bool, w: &mut Writer<'_>) -> Result<()> {
        match self {
            BlockRepr::MacAddress(m) => w.put(&m.0),
            BlockRepr::IpParameter { ip, mask, gateway } => {
                w.put(ip)?;
                w.put(mask)?;
                w.put(gateway)
            }
            BlockRepr::FullIpSuite {
                ip,
                mask,
                gateway,
                dns,
            } => {
                w.put(ip)?;
                w.put(mask)?;
                w.put(gateway)?;
                dns.iter().try_for_each(|d| w.put(d))
            }
            BlockRepr::DeviceVendor(s) | BlockRepr::NameOfStation(s) | BlockRepr::AliasName(s) => {
                w.put(s.as_bytes())
            }
            BlockRepr::DeviceId {
                vendor_id,
                device_id,
            } => {
                w.put(&vendor_id.to_be_bytes())?;
                w.put(&device_id.to_be_bytes())
            }
            BlockRepr::DeviceRole { role, reserved } => w.put(&[*role, *reserved]),
            BlockRepr::DeviceOptions(o) => o.iter().try_for_each(|(a, b)| w.put(&[*a, *b])),
            BlockRepr::DeviceInstance { high, low } => w.put(&[*high, *low]),
            BlockRepr::ControlStart
            | BlockRepr::ControlStop
            | BlockRepr::AllSelector
            | BlockRepr::Requested { .. } => Ok(()),
            BlockRepr::ControlSignal(v) | BlockRepr::DeviceInitiative(v) => w.put(&v.to_be_bytes()),
            BlockRepr::ControlResponse {
                option,
                suboption,
                error,
            } => w.put(&[*option, *suboption, *error]),
            BlockRepr::FactoryReset(v) | BlockRepr::ResetToFactory(v) => {
                if prefixed {
                    Ok(())
                } else {
                    w.put(&v.to_be_bytes())
                }
            }
            BlockRepr::Unknown { data, .. } => w.put(data),
        }
    }
}

/// FactoryReset/ResetToFactory: 2 bytes in all, the prefix if the context has one.
fn qualifier_value(prefix: Option<u16>, v: &[u8], n: usize) -> Option<u16> {
    match (prefix, n) {
        (Some(q), 0) => Some(q),
        (None, 2) => Some(be16(v)),
        _ => None,
    }
}

/// One block with its context-dependent prefix.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Block {
    /// BlockInfo (responses) or BlockQualifier (Set requests); 0 where the context has none
    /// (Identify filters, Get requests, ControlResponse blocks).
    pub prefix: u16,
    /// The value.
    pub value: BlockRepr,
}

impl Block {
    /// A block.
    pub const fn new(prefix: u16, value: BlockRepr) -> Block {
        Block { prefix, value }
    }

    /// A block without prefix (Identify filter, Get request, ControlResponse).
    pub const fn bare(value: BlockRepr) -> Block {
        Block { prefix: 0, value }
    }

    /// Bytes on the wire in `ctx`, header and pad included.
    pub fn buffer_len(&self, ctx: BlockContext) -> usize {
        if ctx == BlockContext::GetRequest {
            return 2;
        }
        let len = self.block_length(ctx);
        BLOCK_HEADER_LEN.saturating_add(len).saturating_add(len % 2)
    }

    /// DCPBlockLength in `ctx` (prefix + value; may exceed u16, which `emit` refuses).
    fn block_length(&self, ctx: BlockContext) -> usize {
        let (option, suboption) = self.value.code();
        let prefixed = ctx.has_prefix(option, suboption);
        let prefix = if prefixed { PREFIX_LEN } else { 0 };
        prefix.saturating_add(self.value.value_len(prefixed))
    }

    /// Parses one block's DCPBlockLength bytes (after the 4-byte header).
    fn parse(ctx: BlockContext, option: u8, suboption: u8, body: &[u8]) -> Result<Block> {
        if ctx.has_prefix(option, suboption) {
            let (p, v) = body.split_at_checked(PREFIX_LEN).ok_or(Error)?;
            let prefix = be16(p);
            Ok(Block::new(
                prefix,
                BlockRepr::parse(option, suboption, Some(prefix), v),
            ))
        } else {
            Ok(Block::bare(BlockRepr::parse(option, suboption, None, body)))
        }
    }

    /// Writes the block, pad included.
    fn emit(&self, ctx: BlockContext, w: &mut Writer<'_>) -> Result<()> {
        let (option, suboption) = self.value.code();
        if ctx == BlockContext::GetRequest {
            return w.put(&[option, suboption]);
        }
        let prefixed = ctx.has_prefix(option, suboption);
        let len = self.block_length(ctx);
        let len16 = u16::try_from(len).map_err(|_| Error)?;
        w.put(&[option, suboption])?;
        w.put(&len16.to_be_bytes())?;
        if prefixed {
            let prefix = match self.value {
                BlockRepr::FactoryReset(q) | BlockRepr::ResetToFactory(q) => q,
                _ => self.prefix,
            };
            w.put(&prefix.to_be_bytes())?;
        }
        self.value.emit_value(prefixed, w)?;
        if len % 2 == 1 {
            w.put(&[0])?;
        }
        Ok(())
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
    /// 65535 bytes or DCPDataLength above 65535 give [`Error`].
    pub fn emit(&self, buf: &mut [u8]) -> Result<()> {
        let ctx = self.context();
        let data_len = u16::try_from(self.data_len()).map_err(|_| Error)?;
        let total = self.buffer_len();
        let pdu = buf.get_mut(..total).ok_or(Error)?;
        let (header, blocks) = pdu.split_at_mut(HEADER_LEN);
        let mut p = Packet::new_unchecked(header);
        p.set_frame_id(self.frame_id);
        p.set_service_id(self.service_id);
        p.set_service_type(self.service_type);
        p.set_xid(self.xid);
        p.set_response_delay(self.response_delay);
        p.set_data_length(data_len);
        let mut w = Writer::new(blocks);
        self.blocks.iter().try_for_each(|b| b.emit(ctx, &mut w))?;
        w.finish()
    }

    /// The PDU as a new vector of [`buffer_len`](Self::buffer_len) bytes.
    pub fn to_vec(&self) -> Result<Vec<u8>> {
        let mut v = vec![0u8; self.buffer_len()];
        self.emit(&mut v)?;
        Ok(v)
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

#[cfg(test)]
mod tests {
    use super::super::ethernet::{ETHERTYPE_PROFINET, Frame};
    use super::*;
    use proptest::prelude::*;

    // The three captures below come from the test data of the `pnio` crate 0.1.0
    // (core-engineering/pnio-rs, MIT OR Apache-2.0): an S7-1515 talking to the p-net sample
    // device. Bytes from the Ethernet header; trailing Ethernet padding included.

    /// captures/cm/dcp_set_req.hex: S7 DCP Set IP (VLAN tagged, Xid 0x0300012d), 64 bytes.
    static SET_REQ: [u8; 64] = [
        0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8, 0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f, 0x81, 0x00, 0x00,
        0x00, 0x88, 0x92, 0xfe, 0xfd, 0x04, 0x00, 0x03, 0x00, 0x01, 0x2d, 0x00, 0x00, 0x00, 0x12,
        0x01, 0x02, 0x00, 0x0e, 0x00, 0x00, 0xac, 0x10, 0x02, 0x0a, 0xff, 0xff, 0xff, 0x00, 0xac,
        0x10, 0x02, 0x0a, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00,
    ];

    /// captures/cm/dcp_set_res.hex: p-net DCP Set Ok, 34 bytes.
    static SET_RES: [u8; 34] = [
        0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f, 0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8, 0x88, 0x92, 0xfe,
        0xfd, 0x04, 0x01, 0x03, 0x00, 0x01, 0x2d, 0x00, 0x00, 0x00, 0x08, 0x05, 0x04, 0x00, 0x03,
        0x01, 0x02, 0x00, 0x00,
    ];

    /// captures/cm/ident_ok_pnet.hex: p-net DCP Identify response (Xid 0x0300012c), 144 bytes.
    static IDENT_RES: [u8; 144] = [
        0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f, 0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8, 0x88, 0x92, 0xfe,
        0xff, 0x05, 0x01, 0x03, 0x00, 0x01, 0x2c, 0x00, 0x00, 0x00, 0x76, 0x01, 0x02, 0x00, 0x0e,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02,
        0x01, 0x00, 0x1a, 0x00, 0x00, 0x50, 0x2d, 0x4e, 0x65, 0x74, 0x20, 0x53, 0x61, 0x6d, 0x70,
        0x6c, 0x65, 0x20, 0x41, 0x70, 0x70, 0x6c, 0x69, 0x63, 0x61, 0x74, 0x69, 0x6f, 0x6e, 0x02,
        0x02, 0x00, 0x0d, 0x00, 0x00, 0x72, 0x74, 0x2d, 0x6c, 0x61, 0x62, 0x73, 0x2d, 0x64, 0x65,
        0x76, 0x00, 0x02, 0x03, 0x00, 0x06, 0x00, 0x00, 0x04, 0x93, 0x00, 0x02, 0x02, 0x04, 0x00,
        0x04, 0x00, 0x00, 0x01, 0x01, 0x02, 0x05, 0x00, 0x1e, 0x00, 0x00, 0x01, 0x02, 0x01, 0x01,
        0x02, 0x01, 0x02, 0x02, 0x02, 0x03, 0x02, 0x04, 0x02, 0x05, 0x02, 0x06, 0x05, 0x01, 0x05,
        0x02, 0x05, 0x03, 0x05, 0x05, 0x05, 0x06, 0xff, 0xff,
    ];

    /// The DCP PDU of a captured frame, Ethernet padding included.
    fn pdu(frame: &[u8]) -> &[u8] {
        let f = Frame::new_checked(frame).unwrap();
        assert_eq!(f.ethertype(), ETHERTYPE_PROFINET);
        f.payload()
    }

    /// Parses a capture, checks that the Repr emits back to the PDU without padding.
    fn round_trip_capture(frame: &[u8]) -> Repr {
        let bytes = pdu(frame);
        let packet = Packet::new_checked(bytes).unwrap();
        let repr = Repr::parse(&packet).unwrap();
        let len = HEADER_LEN + usize::from(packet.data_length());
        assert_eq!(repr.buffer_len(), len);
        let mut buf = vec![0xa5u8; len];
        repr.emit(&mut buf).unwrap();
        assert_eq!(&buf[..], &bytes[..len]);
        repr
    }

    #[test]
    fn set_request_capture() {
        let repr = round_trip_capture(&SET_REQ);
        assert_eq!(repr.frame_id, FRAME_ID_GET_SET);
        assert_eq!(repr.service_id, ServiceId::Set);
        assert_eq!(repr.service_type, ServiceType::Request);
        assert_eq!(repr.context(), BlockContext::SetRequest);
        assert_eq!(repr.xid, 0x0300_012d);
        assert_eq!(repr.response_delay, 0);
        let ip = [172, 16, 2, 10];
        let mask = [255, 255, 255, 0];
        assert_eq!(
            repr.blocks,
            vec![Block::new(
                QUALIFIER_TEMPORARY,
                BlockRepr::IpParameter {
                    ip,
                    mask,
                    gateway: ip
                }
            )]
        );
        assert_eq!(repr, Repr::set_ip(0x0300_012d, ip, mask, ip, false));
        assert_eq!(repr.ip(), Some((ip, mask, ip)));
    }

    #[test]
    fn set_response_capture() {
        let repr = round_trip_capture(&SET_RES);
        assert_eq!(repr.frame_id, FRAME_ID_GET_SET);
        assert_eq!(repr.service_id, ServiceId::Set);
        assert_eq!(repr.service_type, ServiceType::Success);
        assert_eq!(repr.xid, 0x0300_012d);
        assert_eq!(
            repr.blocks,
            vec![Block::bare(BlockRepr::ControlResponse {
                option: 1,
                suboption: 2,
                error: block_error::OK
            })]
        );
        assert_eq!(repr.set_result().collect::<Vec<_>>(), vec![(1, 2, 0)]);
        // The pad after the last (odd) block is counted in DCPDataLength.
        assert_eq!(Packet::new_checked(pdu(&SET_RES)).unwrap().data_length(), 8);
    }

    #[test]
    fn identify_response_capture() {
        let repr = round_trip_capture(&IDENT_RES);
        assert_eq!(repr.frame_id, FRAME_ID_IDENTIFY_RESPONSE);
        assert_eq!(repr.service_id, ServiceId::Identify);
        assert_eq!(repr.service_type, ServiceType::Success);
        assert_eq!(repr.context(), BlockContext::Response);
        assert_eq!(repr.xid, 0x0300_012c);
        assert_eq!(repr.name_of_station(), Some("rt-labs-dev"));
        assert_eq!(repr.device_vendor(), Some("P-Net Sample Application"));
        assert_eq!(repr.device_id(), Some((0x0493, 0x0002)));
        assert_eq!(repr.ip(), Some(([0; 4], [0; 4], [0; 4])));
        assert_eq!(repr.mac(), None);
        let options = vec![
            (1, 2),
            (1, 1),
            (2, 1),
            (2, 2),
            (2, 3),
            (2, 4),
            (2, 5),
            (2, 6),
            (5, 1),
            (5, 2),
            (5, 3),
            (5, 5),
            (5, 6),
            (0xff, 0xff),
        ];
        let expected = vec![
            Block::new(
                0,
                BlockRepr::IpParameter {
                    ip: [0; 4],
                    mask: [0; 4],
                    gateway: [0; 4],
                },
            ),
            Block::new(
                0,
                BlockRepr::DeviceVendor("P-Net Sample Application".into()),
            ),
            Block::new(0, BlockRepr::NameOfStation("rt-labs-dev".into())),
            Block::new(
                0,
                BlockRepr::DeviceId {
                    vendor_id: 0x0493,
                    device_id: 0x0002,
                },
            ),
            Block::new(
                0,
                BlockRepr::DeviceRole {
                    role: 1,
                    reserved: 1,
                },
            ),
            Block::new(0, BlockRepr::DeviceOptions(options)),
        ];
        assert_eq!(repr.blocks, expected);
    }

    #[test]
    fn identify_by_name_s7() {
        let repr = Repr::identify_by_name(0x0300_012b, 1, "i-device");
        let mut expected = vec![
            0xfe, 0xfe, 0x05, 0x00, 0x03, 0x00, 0x01, 0x2b, 0x00, 0x01, 0x00, 0x0c, 0x02, 0x02,
            0x00, 0x08,
        ];
        expected.extend_from_slice(b"i-device");
        assert_eq!(repr.to_vec().unwrap(), expected);
        let back = Repr::parse(&Packet::new_checked(&expected[..]).unwrap()).unwrap();
        assert_eq!(back, repr);
        assert_eq!(back.context(), BlockContext::IdentifyFilter);
    }

    #[test]
    fn constructors() {
        let all = Repr::identify_all(7, 0x80).to_vec().unwrap();
        assert_eq!(
            all,
            [
                0xfe, 0xfe, 5, 0, 0, 0, 0, 7, 0, 0x80, 0, 4, 0xff, 0xff, 0, 0
            ]
        );
        // Odd name: DCPBlockLength 2 + 3, one pad counted in DCPDataLength.
        let name = Repr::set_name(1, "abc", true).to_vec().unwrap();
        assert_eq!(
            name,
            [
                0xfe, 0xfd, 4, 0, 0, 0, 0, 1, 0, 0, 0, 10, 2, 2, 0, 5, 0, 1, b'a', b'b', b'c', 0
            ]
        );
        let signal = Repr::signal(2).to_vec().unwrap();
        assert_eq!(
            signal,
            [
                0xfe, 0xfd, 4, 0, 0, 0, 0, 2, 0, 0, 0, 8, 5, 3, 0, 4, 0, 0, 1, 0
            ]
        );
        let get = Repr::get(3, &[code::NAME_OF_STATION, code::IP_PARAMETER])
            .to_vec()
            .unwrap();
        assert_eq!(get, [0xfe, 0xfd, 3, 0, 0, 0, 0, 3, 0, 0, 0, 4, 2, 2, 1, 2]);
    }

    #[test]
    fn factory_reset_uses_the_qualifier() {
        let r = Repr::set(9, Block::new(4, BlockRepr::ResetToFactory(4)));
        let bytes = r.to_vec().unwrap();
        assert_eq!(&bytes[HEADER_LEN..], [5, 6, 0, 2, 0, 4]);
        assert_eq!(Repr::parse(&Packet::new_unchecked(&bytes[..])).unwrap(), r);
    }

    #[test]
    fn malformed() {
        // Short header, DCPDataLength past the buffer, block past DCPDataLength, odd Get.
        let bad: [&[u8]; 5] = [
            &[0xfe, 0xfe, 5, 0],
            &[0xfe, 0xfe, 5, 0, 0, 0, 0, 1, 0, 0, 0, 4, 0xff, 0xff],
            &[0xfe, 0xfe, 5, 0, 0, 0, 0, 1, 0, 0, 0, 4, 2, 2, 0, 1, b'a'],
            &[0xfe, 0xfd, 3, 0, 0, 0, 0, 1, 0, 0, 0, 3, 2, 2, 1],
            // Response block too short for its BlockInfo.
            &[0xfe, 0xff, 5, 1, 0, 0, 0, 1, 0, 0, 0, 6, 2, 2, 0, 1, 0, 0],
        ];
        for b in bad {
            assert_eq!(Repr::parse(&Packet::new_unchecked(b)), Err(Error));
        }
        // Non-UTF-8 name is kept as Unknown, losslessly.
        let b: &[u8] = &[
            0xfe, 0xfe, 5, 0, 0, 0, 0, 1, 0, 0, 0, 6, 2, 2, 0, 2, 0xff, 0xfe,
        ];
        let r = Repr::parse(&Packet::new_unchecked(b)).unwrap();
        assert_eq!(
            r.blocks[0].value,
            BlockRepr::Unknown {
                option: 2,
                suboption: 2,
                data: vec![0xff, 0xfe]
            }
        );
        assert_eq!(r.to_vec().unwrap(), b);
        // A last odd block without its pad is accepted.
        let b: &[u8] = &[0xfe, 0xfe, 5, 0, 0, 0, 0, 1, 0, 0, 0, 5, 2, 2, 0, 1, b'a'];
        let r = Repr::parse(&Packet::new_unchecked(b)).unwrap();
        assert_eq!(r.name_of_station(), Some("a"));
        // Too short a buffer for emit.
        let r = Repr::identify_all(1, 1);
        let mut buf = vec![0u8; r.buffer_len() - 1];
        assert_eq!(r.emit(&mut buf), Err(Error));
    }

    #[test]
    fn response_delay() {
        let mac = MacAddress([0, 0x0e, 0xcf, 0, 0x01, 0x2c]); // 0x012c = 300
        assert_eq!(response_delay_ns(mac, 0), 0);
        assert_eq!(response_delay_ns(mac, 1), 0);
        assert_eq!(response_delay_ns(mac, 7), (300 % 7) * 10_000_000);
        assert_eq!(response_delay_ns(mac, 6400), 300 * 10_000_000);
        assert_eq!(response_delay_ns(mac, 6401), 0);
    }

    fn ip4() -> impl Strategy<Value = [u8; 4]> {
        any::<[u8; 4]>()
    }

    fn name() -> impl Strategy<Value = String> {
        "[a-z0-9-]{1,60}"
    }

    /// Any block value that parses back to itself in a context with (`prefixed`) or without
    /// a prefix; `Unknown` only with codes this module does not model.
    fn block_value() -> impl Strategy<Value = BlockRepr> {
        prop_oneof![
            any::<[u8; 6]>().prop_map(|m| BlockRepr::MacAddress(MacAddress(m))),
            (ip4(), ip4(), ip4()).prop_map(|(ip, mask, gateway)| BlockRepr::IpParameter {
                ip,
                mask,
                gateway
            }),
            (ip4(), ip4(), ip4(), any::<[[u8; 4]; 4]>()).prop_map(|(ip, mask, gateway, dns)| {
                BlockRepr::FullIpSuite {
                    ip,
                    mask,
                    gateway,
                    dns,
                }
            }),
            "[ -~]{0,40}".prop_map(BlockRepr::DeviceVendor),
            name().prop_map(BlockRepr::NameOfStation),
            (any::<u16>(), any::<u16>()).prop_map(|(vendor_id, device_id)| BlockRepr::DeviceId {
                vendor_id,
                device_id
            }),
            (any::<u8>(), any::<u8>())
                .prop_map(|(role, reserved)| BlockRepr::DeviceRole { role, reserved }),
            proptest::collection::vec(any::<(u8, u8)>(), 0..20).prop_map(BlockRepr::DeviceOptions),
            name().prop_map(BlockRepr::AliasName),
            (any::<u8>(), any::<u8>())
                .prop_map(|(high, low)| BlockRepr::DeviceInstance { high, low }),
            Just(BlockRepr::ControlStart),
            Just(BlockRepr::ControlStop),
            any::<u16>().prop_map(BlockRepr::ControlSignal),
            (any::<u8>(), any::<u8>(), any::<u8>()).prop_map(|(option, suboption, error)| {
                BlockRepr::ControlResponse {
                    option,
                    suboption,
                    error,
                }
            }),
            any::<u16>().prop_map(BlockRepr::FactoryReset),
            any::<u16>().prop_map(BlockRepr::ResetToFactory),
            any::<u16>().prop_map(BlockRepr::DeviceInitiative),
            Just(BlockRepr::AllSelector),
            (
                0x80u8..0xff,
                any::<u8>(),
                proptest::collection::vec(any::<u8>(), 0..50)
            )
                .prop_map(|(option, suboption, data)| BlockRepr::Unknown {
                    option,
                    suboption,
                    data
                }),
        ]
    }

    /// A block as `parse` would return it in `ctx`.
    fn block(ctx: BlockContext) -> impl Strategy<Value = Block> {
        (any::<u16>(), block_value()).prop_map(move |(prefix, value)| {
            let (o, s) = value.code();
            let prefix = match value {
                _ if !ctx.has_prefix(o, s) => 0,
                BlockRepr::FactoryReset(q) | BlockRepr::ResetToFactory(q) => q,
                _ => prefix,
            };
            Block { prefix, value }
        })
    }

    fn service() -> impl Strategy<Value = (ServiceId, ServiceType, BlockContext)> {
        use ServiceId::*;
        use ServiceType::*;
        prop_oneof![
            Just((Identify, Request, BlockContext::IdentifyFilter)),
            Just((Set, Request, BlockContext::SetRequest)),
            Just((Get, Request, BlockContext::GetRequest)),
            Just((Hello, Request, BlockContext::Response)),
            Just((Identify, Success, BlockContext::Response)),
            Just((Get, Success, BlockContext::Response)),
            Just((Set, Success, BlockContext::Response)),
            Just((Set, NotSupported, BlockContext::Response)),
            (7u8..).prop_map(|v| (ServiceId::Unknown(v), Request, BlockContext::IdentifyFilter)),
            (6u8..).prop_map(|v| (Get, ServiceType::Unknown(v), BlockContext::Response)),
        ]
    }

    fn repr() -> impl Strategy<Value = Repr> {
        (service(), any::<u16>(), any::<u32>(), any::<u16>()).prop_flat_map(
            |((service_id, service_type, ctx), frame_id, xid, response_delay)| {
                let blocks = if ctx == BlockContext::GetRequest {
                    proptest::collection::vec(
                        any::<(u8, u8)>().prop_map(|(option, suboption)| {
                            Block::bare(BlockRepr::Requested { option, suboption })
                        }),
                        0..20,
                    )
                    .boxed()
                } else {
                    proptest::collection::vec(block(ctx), 0..8).boxed()
                };
                blocks.prop_map(move |blocks| Repr {
                    frame_id,
                    service_id,
                    service_type,
                    xid,
                    response_delay,
                    blocks,
                })
            },
        )
    }

    proptest! {
        #[test]
        fn parse_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..1500)) {
            let p = Packet::new_unchecked(&bytes[..]);
            if let Ok(r) = Repr::parse(&p) {
                // What parses emits again, to the same length or one pad more.
                let v = r.to_vec().unwrap();
                prop_assert!(v.len() <= HEADER_LEN + usize::from(p.data_length()) + 1);
            }
            let _ = p.to_string();
        }

        #[test]
        fn parse_never_panics_on_plausible_blocks(
            sid in 0u8..8,
            st in prop_oneof![Just(0u8), Just(1u8), Just(5u8)],
            blocks in proptest::collection::vec(any::<u8>(), 0..300),
        ) {
            let mut bytes = vec![0xfe, 0xfd, sid, st, 0, 0, 0, 1, 0, 0];
            bytes.extend_from_slice(&(blocks.len() as u16).to_be_bytes());
            bytes.extend_from_slice(&blocks);
            let _ = Repr::parse(&Packet::new_unchecked(&bytes[..]));
        }

        #[test]
        fn round_trip(r in repr()) {
            let bytes = r.to_vec().unwrap();
            prop_assert_eq!(bytes.len(), r.buffer_len());
            let p = Packet::new_checked(&bytes[..]).unwrap();
            prop_assert_eq!(usize::from(p.data_length()) % 2, 0);
            let back = Repr::parse(&p).unwrap();
            prop_assert_eq!(back, r);
        }
    }
}
