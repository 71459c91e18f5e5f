// SPDX-License-Identifier: MIT OR Apache-2.0
//! Which modules and submodules are where: ExpectedIdentificationData (block 0x0012, records
//! 0x8000, 0xC000, 0xE000), RealIdentificationData (block 0x0013, records 0x8001, 0xC001,
//! 0xE001, 0xF000) and I&M0FilterData (record 0xF840: blocks 0x0030 submodule, 0x0031
//! module, 0x0032 device).
//!
//! All of them list slots with their ModuleIdentNumber and subslots with their
//! SubmoduleIdentNumber:
//!
//! ```text
//! identification v1.0:  NumberOfSlots (Slot ModuleIdent NumberOfSubslots (Subslot SubmoduleIdent)*)*
//! identification v1.1:  NumberOfAPIs (API NumberOfSlots (...)*)*
//! I&M0 filter (v1.0):   NumberOfAPIs (API NumberOfSlots (...)*)*
//! ```
//!
//! Version 1.0 of the identification blocks predates APIs: it describes API 0 alone, and has
//! no field for it. The I&M0 filter blocks carry the API level in their version 1.0 already.

use super::super::common::{BLOCK_HEADER_LEN, blocks};
use super::super::cursor::{Reader, Writer};
use super::{
    BlockHeader, BlockType, EmitError, EmitResult, Error, RecordVersion, Result, emit_block,
};

/// A subslot of an identification list.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct IdentSubmodule {
    /// SubslotNumber.
    pub subslot: u16,
    /// SubmoduleIdentNumber.
    pub submodule_ident: u32,
}

/// A slot of an identification list and its subslots.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct IdentModule {
    /// SlotNumber.
    pub slot: u16,
    /// ModuleIdentNumber.
    pub module_ident: u32,
    /// The subslots, in order.
    pub submodules: Vec<IdentSubmodule>,
}

/// An API of an identification list and its slots.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct IdentApi {
    /// API.
    pub api: u32,
    /// The slots, in order.
    pub modules: Vec<IdentModule>,
}

impl IdentApi {
    /// The list of `(api, slot, module_ident, subslot, submodule_ident)` submodules, grouped
    /// by API and then by slot in the order each first appears.
    pub fn group(submodules: impl IntoIterator<Item = (u32, u16, u32, u16, u32)>) -> Vec<IdentApi> {
        let mut apis: Vec<IdentApi> = Vec::new();
        for (api, slot, module_ident, subslot, submodule_ident) in submodules {
            let a = match apis.iter().position(|a| a.api == api) {
                Some(i) => i,
                None => {
                    apis.push(IdentApi {
                        api,
                        modules: Vec::new(),
                    });
                    apis.len() - 1
                }
            };
            let modules = &mut apis[a].modules;
            let m = match modules.iter().position(|m| m.slot == slot) {
                Some(i) => i,
                None => {
                    modules.push(IdentModule {
                        slot,
                        module_ident,
                        submodules: Vec::new(),
                    });
                    modules.len() - 1
                }
            };
            modules[m].submodules.push(IdentSubmodule {
                subslot,
                submodule_ident,
            });
        }
        apis
    }

    /// Every listed submodule as `(api, slot, module_ident, subslot, submodule_ident)`.
    pub fn flatten(apis: &[IdentApi]) -> impl Iterator<Item = (u32, u16, u32, u16, u32)> + '_ {
        apis.iter().flat_map(|a| {
            a.modules.iter().flat_map(move |m| {
                m.submodules
                    .iter()
                    .map(move |s| (a.api, m.slot, m.module_ident, s.subslot, s.submodule_ident))
            })
        })
    }
}

/// Bytes of a slot list (its count included).
fn modules_len(modules: &[IdentModule]) -> usize {
    modules.iter().fold(2usize, |n, m| {
        n.saturating_add(8)
            .saturating_add(m.submodules.len().saturating_mul(6))
    })
}

/// Bytes of an API list (its count included).
fn apis_len(apis: &[IdentApi]) -> usize {
    apis.iter().fold(2usize, |n, a| {
        n.saturating_add(4).saturating_add(modules_len(&a.modules))
    })
}

fn read_modules(r: &mut Reader<'_>) -> Result<Vec<IdentModule>> {
    r.list(|r| {
        Ok(IdentModule {
            slot: r.u16()?,
            module_ident: r.u32()?,
            submodules: r.list(|r| {
                Ok(IdentSubmodule {
                    subslot: r.u16()?,
                    submodule_ident: r.u32()?,
                })
            })?,
        })
    })
}

fn read_apis(r: &mut Reader<'_>) -> Result<Vec<IdentApi>> {
    r.list(|r| {
        Ok(IdentApi {
            api: r.u32()?,
            modules: read_modules(r)?,
        })
    })
}

fn write_modules(w: &mut Writer<'_>, modules: &[IdentModule]) -> EmitResult<()> {
    w.count("NumberOfSlots", modules.len())?;
    for m in modules {
        w.u16(m.slot)?;
        w.u32(m.module_ident)?;
        w.count("NumberOfSubslots", m.submodules.len())?;
        for s in &m.submodules {
            w.u16(s.subslot)?;
            w.u32(s.submodule_ident)?;
        }
    }
    Ok(())
}

fn write_apis(w: &mut Writer<'_>, apis: &[IdentApi]) -> EmitResult<()> {
    w.count("NumberOfAPIs", apis.len())?;
    for a in apis {
        w.u32(a.api)?;
        write_modules(w, &a.modules)?;
    }
    Ok(())
}

/// Which identification a block gives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum IdentificationKind {
    /// ExpectedIdentificationData (0x0012): what the AR expects.
    Expected,
    /// RealIdentificationData (0x0013): what is plugged.
    Real,
}

impl IdentificationKind {
    /// The BlockType.
    pub const fn block_type(self) -> BlockType {
        match self {
            IdentificationKind::Expected => BlockType::ExpectedIdentificationData,
            IdentificationKind::Real => BlockType::RealIdentificationData,
        }
    }
}

/// ExpectedIdentificationData or RealIdentificationData.
///
/// In [`RecordVersion::V1_0`] the block describes API 0 alone: `apis` holds exactly that one
/// API (parsing makes it so; emitting anything else gives [`EmitError::Inconsistent`]).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct IdentificationData {
    /// Expected or real.
    pub kind: IdentificationKind,
    /// BlockVersion 1.0 (API 0 only, no API field) or 1.1.
    pub version: RecordVersion,
    /// The APIs with their slots and subslots.
    pub apis: Vec<IdentApi>,
}

impl IdentificationData {
    /// Parses the block at the start of `b` (bytes after it are ignored). Another block type
    /// or version, or lists that do not fill the block exactly, give [`Error`].
    pub fn parse(b: &[u8]) -> Result<IdentificationData> {
        let h = BlockHeader::parse(b)?;
        let kind = match h.block_type {
            BlockType::ExpectedIdentificationData => IdentificationKind::Expected,
            BlockType::RealIdentificationData => IdentificationKind::Real,
            _ => return Err(Error),
        };
        let version = RecordVersion::of(&h).ok_or(Error)?;
        let mut r = Reader::new(h.body(b));
        let apis = match version {
            RecordVersion::V1_0 => vec![IdentApi {
                api: 0,
                modules: read_modules(&mut r)?,
            }],
            RecordVersion::V1_1 => read_apis(&mut r)?,
        };
        r.end()?;
        Ok(IdentificationData {
            kind,
            version,
            apis,
        })
    }

    /// The slots of the one API 0 a version 1.0 block may describe.
    fn v1_0_modules(&self) -> EmitResult<&[IdentModule]> {
        match &self.apis[..] {
            [a] if a.api == 0 => Ok(&a.modules),
            _ => Err(EmitError::Inconsistent(
                "identification data of version 1.0 describes API 0 alone",
            )),
        }
    }

    fn body_len(&self) -> usize {
        match self.version {
            RecordVersion::V1_0 => self.v1_0_modules().map_or(0, modules_len),
            RecordVersion::V1_1 => apis_len(&self.apis),
        }
    }

    /// Bytes of the block, header included.
    pub fn buffer_len(&self) -> usize {
        BLOCK_HEADER_LEN.saturating_add(self.body_len())
    }

    /// Writes the block into the first [`buffer_len`](Self::buffer_len) bytes of `buf`. A
    /// shorter buffer, a list longer than its count or block allow, or version 1.0 with
    /// other APIs than API 0 give [`EmitError`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        let what = "identification data";
        let (block_type, version_low) = (self.kind.block_type(), self.version.low());
        match self.version {
            RecordVersion::V1_0 => {
                let modules = self.v1_0_modules()?;
                emit_block(
                    what,
                    block_type,
                    version_low,
                    modules_len(modules),
                    buf,
                    |w| write_modules(w, modules),
                )?;
            }
            RecordVersion::V1_1 => {
                let len = apis_len(&self.apis);
                emit_block(what, block_type, version_low, len, buf, |w| {
                    write_apis(w, &self.apis)
                })?;
            }
        }
        Ok(())
    }

    /// The block as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b))
    }
}

/// Which I&M0FilterData block a list is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Im0FilterKind {
    /// 0x0030 I&M0FilterDataSubmodule: every submodule with I&M data of its own.
    Submodule,
    /// 0x0031 I&M0FilterDataModule: the submodules whose I&M data stands for their module.
    Module,
    /// 0x0032 I&M0FilterDataDevice: the submodule whose I&M data stands for the device.
    Device,
}

impl Im0FilterKind {
    /// The BlockType.
    pub const fn block_type(self) -> BlockType {
        match self {
            Im0FilterKind::Submodule => BlockType::Im0FilterDataSubmodule,
            Im0FilterKind::Module => BlockType::Im0FilterDataModule,
            Im0FilterKind::Device => BlockType::Im0FilterDataDevice,
        }
    }

    const fn of(block_type: BlockType) -> Option<Im0FilterKind> {
        match block_type {
            BlockType::Im0FilterDataSubmodule => Some(Im0FilterKind::Submodule),
            BlockType::Im0FilterDataModule => Some(Im0FilterKind::Module),
            BlockType::Im0FilterDataDevice => Some(Im0FilterKind::Device),
            _ => None,
        }
    }
}

/// The I&M0FilterData record (index 0xF840): which submodules carry I&M data, as up to three
/// blocks (version 1.0) in the order submodule, module, device. An empty list has no block.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Im0FilterData {
    /// I&M0FilterDataSubmodule.
    pub submodules: Vec<IdentApi>,
    /// I&M0FilterDataModule.
    pub modules: Vec<IdentApi>,
    /// I&M0FilterDataDevice.
    pub device: Vec<IdentApi>,
}

impl Im0FilterData {
    fn lists(&self) -> [(Im0FilterKind, &Vec<IdentApi>); 3] {
        [
            (Im0FilterKind::Submodule, &self.submodules),
            (Im0FilterKind::Module, &self.modules),
            (Im0FilterKind::Device, &self.device),
        ]
    }

    /// Parses the whole record: its blocks in any order, each kind at most once. Another
    /// block, another version, a repeated kind or bytes that are not whole blocks give
    /// [`Error`].
    pub fn parse(b: &[u8]) -> Result<Im0FilterData> {
        let mut out = Im0FilterData::default();
        let mut seen = [false; 3];
        for block in blocks(b) {
            let (h, bytes) = block?;
            let kind = Im0FilterKind::of(h.block_type).ok_or(Error)?;
            if (h.version_high, h.version_low) != (1, 0) {
                return Err(Error);
            }
            let mut r = Reader::new(h.body(bytes));
            let apis = read_apis(&mut r)?;
            r.end()?;
            let (slot, list) = match kind {
                Im0FilterKind::Submodule => (0, &mut out.submodules),
                Im0FilterKind::Module => (1, &mut out.modules),
                Im0FilterKind::Device => (2, &mut out.device),
            };
            if seen[slot] {
                return Err(Error);
            }
            seen[slot] = true;
            *list = apis;
        }
        Ok(out)
    }

    /// Bytes of the record.
    pub fn buffer_len(&self) -> usize {
        self.lists()
            .iter()
            .filter(|(_, l)| !l.is_empty())
            .fold(0usize, |n, (_, l)| {
                n.saturating_add(BLOCK_HEADER_LEN)
                    .saturating_add(apis_len(l))
            })
    }

    /// Writes the record into the first [`buffer_len`](Self::buffer_len) bytes of `buf`; a
    /// shorter buffer or a list too long for its count or block gives [`EmitError`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        EmitError::check_len("I&M0FilterData", self.buffer_len(), buf.len())?;
        let mut at = 0;
        for (kind, list) in self.lists() {
            if list.is_empty() {
                continue;
            }
            let rest = buf.get_mut(at..).unwrap_or_default();
            let what = "I&M0FilterData";
            at += emit_block(what, kind.block_type(), 0, apis_len(list), rest, |w| {
                write_apis(w, list)
            })?;
        }
        Ok(())
    }

    /// The record as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b))
    }
}
