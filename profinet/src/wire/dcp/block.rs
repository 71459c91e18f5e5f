// SPDX-License-Identifier: MIT OR Apache-2.0
//! DCP blocks: the options and suboptions of a PDU, how a PDU's service decides their
//! encoding, and their values.

use super::*;

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
    fn emit_value(&self, prefixed: bool, w: &mut Writer<'_>) -> EmitResult<()> {
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
    pub(super) fn parse(
        ctx: BlockContext,
        option: u8,
        suboption: u8,
        body: &[u8],
    ) -> Result<Block> {
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
    pub(super) fn emit(&self, ctx: BlockContext, w: &mut Writer<'_>) -> EmitResult<()> {
        let (option, suboption) = self.value.code();
        if ctx == BlockContext::GetRequest {
            return w.put(&[option, suboption]);
        }
        let prefixed = ctx.has_prefix(option, suboption);
        let len = self.block_length(ctx);
        let len16 =
            u16::try_from(len).map_err(|_| EmitError::too_long_u16("DCPBlockLength", len))?;
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
