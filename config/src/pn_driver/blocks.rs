// SPDX-License-Identifier: MIT OR Apache-2.0
//! The PN Driver configuration's data blocks, as Siemens' "PROFINET Driver Engineering
//! Interface" manual (v3.1.0, chapter "Description of PNIO data blocks") lays them out: an
//! 8-byte header (type, length, version high, version low, two reserved bytes), then the
//! fields at fixed big-endian offsets. They carry what a connect needs (identity, IOCRs,
//! expected submodules) in a padded layout of their own, not as IEC 61158-6-10 blocks:
//! procimg reads the fields it plans with and computes its own wire blocks.
//!
//! Each reader takes a field's bytes and never panics: a block too short for what it
//! claims, or of another type, is a [`BlockError`].

use std::net::Ipv4Addr;

/// A block that cannot be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct BlockError(pub String);

type Result<T> = core::result::Result<T, BlockError>;

/// Bytes of the header every block starts with.
const HEADER_LEN: usize = 8;

/// A checked view of one block: its type is the expected one, and every read is in bounds.
struct View<'a> {
    bytes: &'a [u8],
    name: &'static str,
}

impl<'a> View<'a> {
    /// `bytes` as block `name` of type `block_type`.
    fn new(bytes: &'a [u8], block_type: u16, name: &'static str) -> Result<View<'a>> {
        let view = View { bytes, name };
        let found = view.u16(0)?;
        if found != block_type {
            return Err(BlockError(format!(
                "the {name} block should have block type 0x{block_type:04X}, this one has \
                 0x{found:04X}"
            )));
        }
        Ok(view)
    }

    fn slice(&self, at: usize, len: usize) -> Result<&'a [u8]> {
        self.bytes
            .get(at..at.saturating_add(len))
            .filter(|s| s.len() == len)
            .ok_or_else(|| {
                BlockError(format!(
                    "the {} block ends at byte {}, before the field at byte {at} ({len} \
                     bytes): the block is cut short",
                    self.name,
                    self.bytes.len()
                ))
            })
    }

    fn u16(&self, at: usize) -> Result<u16> {
        let s = self.slice(at, 2)?;
        Ok(u16::from_be_bytes([s[0], s[1]]))
    }

    fn u32(&self, at: usize) -> Result<u32> {
        let s = self.slice(at, 4)?;
        Ok(u32::from_be_bytes([s[0], s[1], s[2], s[3]]))
    }

    fn ip(&self, at: usize) -> Result<Ipv4Addr> {
        Ok(Ipv4Addr::from(self.u32(at)?))
    }
}

/// Block 0x3000: an IP suite.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct IpSuite {
    pub ip: Ipv4Addr,
    pub mask: Ipv4Addr,
    pub gateway: Ipv4Addr,
}

impl IpSuite {
    pub const BLOCK_TYPE: u16 = 0x3000;

    pub fn parse(bytes: &[u8]) -> Result<IpSuite> {
        let v = View::new(bytes, Self::BLOCK_TYPE, "IP suite")?;
        Ok(IpSuite {
            ip: v.ip(HEADER_LEN)?,
            mask: v.ip(HEADER_LEN + 4)?,
            gateway: v.ip(HEADER_LEN + 8)?,
        })
    }
}

/// Block 0xA201: a NameOfStation (length at 8, the name from 12).
pub(super) struct NameOfStation;

impl NameOfStation {
    pub const BLOCK_TYPE: u16 = 0xA201;

    pub fn parse(bytes: &[u8]) -> Result<String> {
        let v = View::new(bytes, Self::BLOCK_TYPE, "NameOfStation")?;
        let len = usize::from(v.u16(HEADER_LEN)?);
        let name = v.slice(HEADER_LEN + 4, len)?;
        String::from_utf8(name.to_vec())
            .map_err(|_| BlockError("the NameOfStation is not text (UTF-8)".to_owned()))
    }
}

/// Blocks 0x3006 (IP address validation) and 0x3009 (NameOfStation validation) of the
/// controller's interface, and 0x3011 (remote IP address validation) of a device: whether
/// the value is the project's, or is "set directly at the device" (0xFFFF: by a program,
/// DCP or the retentive data; a device's by whoever commissions it).
pub(super) struct SetAtDevice;

impl SetAtDevice {
    pub const IP_BLOCK_TYPE: u16 = 0x3006;
    pub const NAME_BLOCK_TYPE: u16 = 0x3009;
    pub const REMOTE_IP_BLOCK_TYPE: u16 = 0x3011;

    pub fn parse(bytes: &[u8], block_type: u16) -> Result<bool> {
        let v = View::new(bytes, block_type, "validation")?;
        Ok(v.u16(HEADER_LEN)? == 0xFFFF)
    }
}

/// Block 0x3060, PNIOD_PROPERTIES: the device's identity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct DeviceProperties {
    pub vendor_id: u16,
    pub device_id: u16,
    pub instance: u16,
}

impl DeviceProperties {
    pub const BLOCK_TYPE: u16 = 0x3060;

    pub fn parse(bytes: &[u8]) -> Result<DeviceProperties> {
        let v = View::new(bytes, Self::BLOCK_TYPE, "PNIOD_PROPERTIES")?;
        Ok(DeviceProperties {
            vendor_id: v.u16(HEADER_LEN)?,
            device_id: v.u16(HEADER_LEN + 2)?,
            instance: v.u16(HEADER_LEN + 4)?,
        })
    }
}

/// The kind of an IOCR (IOCRType).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum IocrType {
    Input,
    Output,
    /// Multicast provider or consumer (3, 4) or another value.
    Other(u16),
}

/// One IOCR of block 0x3102, IOCR_DATA: what procimg plans the device's exchange with.
/// The frame ID, phase, sequence and frame offsets are TIA's plan for PN Driver; procimg
/// computes its own, as any RT controller does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Iocr {
    pub kind: IocrType,
    /// IOCRProperties bits 0..3.
    pub rt_class: u8,
    pub send_clock_factor: u16,
    pub reduction_ratio: u16,
    pub watchdog_factor: u16,
}

/// Block 0x3102.
pub(super) struct IocrData;

impl IocrData {
    pub const BLOCK_TYPE: u16 = 0x3102;
    /// Bytes of an IOCR entry up to its watchdog factor, the last field read.
    const ENTRY_MIN: usize = 34;

    pub fn parse(bytes: &[u8]) -> Result<Vec<Iocr>> {
        let v = View::new(bytes, Self::BLOCK_TYPE, "IOCR_DATA")?;
        let count = v.u16(HEADER_LEN)?;
        let mut at = HEADER_LEN + 2;
        let mut iocrs = Vec::new();
        for n in 0..count {
            let len = usize::from(v.u16(at)?);
            if len < Self::ENTRY_MIN {
                return Err(BlockError(format!(
                    "IOCR {n} of the IOCR_DATA block claims {len} bytes, less than an IOCR \
                     entry's {}",
                    Self::ENTRY_MIN
                )));
            }
            v.slice(at, len)?;
            iocrs.push(Iocr {
                kind: match v.u16(at + 4)? {
                    1 => IocrType::Input,
                    2 => IocrType::Output,
                    other => IocrType::Other(other),
                },
                rt_class: (v.u32(at + 12)? & 0x0F) as u8,
                send_clock_factor: v.u16(at + 20)?,
                reduction_ratio: v.u16(at + 22)?,
                watchdog_factor: v.u16(at + 32)?,
            });
            at += len;
        }
        Ok(iocrs)
    }
}

/// One submodule of block 0x3101, EXPECTED_SUBMODULE_DATA.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Expected {
    pub api: u32,
    pub slot: u16,
    pub module_ident: u32,
    pub subslot: u16,
    pub submodule_ident: u32,
    /// SubmoduleProperties.
    pub properties: u16,
    pub input_length: u16,
    pub output_length: u16,
    /// The IOPS and IOCS lengths of its data descriptions (1 each in every PROFINET
    /// device procimg knows).
    pub status_lengths: [u16; 2],
}

/// Block 0x3101.
pub(super) struct ExpectedSubmodules;

impl ExpectedSubmodules {
    pub const BLOCK_TYPE: u16 = 0x3101;
    const API_LEN: usize = 8;
    const SLOT_LEN: usize = 20;
    const SUBMODULE_LEN: usize = 12;
    const DESCRIPTION_LEN: usize = 12;

    pub fn parse(bytes: &[u8]) -> Result<Vec<Expected>> {
        let v = View::new(bytes, Self::BLOCK_TYPE, "EXPECTED_SUBMODULE_DATA")?;
        let apis = v.u16(HEADER_LEN)?;
        let mut at = HEADER_LEN + 2;
        let mut out = Vec::new();
        for _ in 0..apis {
            let api = v.u32(at)?;
            let slots = v.u16(at + 6)?;
            at += Self::API_LEN;
            for _ in 0..slots {
                let slot = v.u16(at + 4)?;
                let module_ident = v.u32(at + 8)?;
                let submodules = v.u16(at + 18)?;
                at += Self::SLOT_LEN;
                for _ in 0..submodules {
                    let subslot = v.u16(at)?;
                    let submodule_ident = v.u32(at + 4)?;
                    let properties = v.u16(at + 8)?;
                    at += Self::SUBMODULE_LEN;
                    // One data description, two for a submodule with inputs and outputs.
                    let descriptions = if properties & 3 == 3 { 2 } else { 1 };
                    let mut expected = Expected {
                        api,
                        slot,
                        module_ident,
                        subslot,
                        submodule_ident,
                        properties,
                        input_length: 0,
                        output_length: 0,
                        status_lengths: [1, 1],
                    };
                    for _ in 0..descriptions {
                        let length = v.u16(at + 2)?;
                        let status_lengths = [v.u16(at + 4)?, v.u16(at + 6)?];
                        // 1 is the input description; TIA Portal writes an output
                        // submodule's as 0, and PN Driver takes any other value as output.
                        if v.u16(at)? == 1 {
                            expected.input_length = length;
                        } else {
                            expected.output_length = length;
                        }
                        if status_lengths != [1, 1] {
                            expected.status_lengths = status_lengths;
                        }
                        at += Self::DESCRIPTION_LEN;
                    }
                    out.push(expected);
                }
            }
        }
        Ok(out)
    }
}

/// A big-endian list of u32 record indices (the DataRecordsTransferSequence).
pub(super) fn index_list(bytes: &[u8]) -> Result<Vec<u32>> {
    if !bytes.len().is_multiple_of(4) {
        return Err(BlockError(format!(
            "{} bytes are not a list of 4-byte record indices",
            bytes.len()
        )));
    }
    Ok(bytes
        .chunks_exact(4)
        .map(|c| u32::from_be_bytes([c[0], c[1], c[2], c[3]]))
        .collect())
}
