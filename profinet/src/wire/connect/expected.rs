// SPDX-License-Identifier: MIT OR Apache-2.0
//! ExpectedSubmoduleBlockReq: the modules and submodules the controller expects, with their
//! data descriptions.

use super::*;

/// A DataDescription of an expected submodule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DataDescription {
    /// DataDescription ([`submodule::DATA_INPUT`] or [`submodule::DATA_OUTPUT`]).
    pub direction: u16,
    /// SubmoduleDataLength: IO data bytes.
    pub length: u16,
    /// LengthIOCS (1).
    pub length_iocs: u8,
    /// LengthIOPS (1).
    pub length_iops: u8,
}

impl DataDescription {
    /// An input description of `length` bytes with 1-byte IOCS and IOPS.
    pub const fn input(length: u16) -> DataDescription {
        DataDescription {
            direction: submodule::DATA_INPUT,
            length,
            length_iocs: 1,
            length_iops: 1,
        }
    }

    /// An output description of `length` bytes with 1-byte IOCS and IOPS.
    pub const fn output(length: u16) -> DataDescription {
        DataDescription {
            direction: submodule::DATA_OUTPUT,
            ..DataDescription::input(length)
        }
    }

    fn read(r: &mut Reader<'_>) -> Result<DataDescription> {
        Ok(DataDescription {
            direction: r.u16()?,
            length: r.u16()?,
            length_iocs: r.u8()?,
            length_iops: r.u8()?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u16(self.direction)?;
        w.u16(self.length)?;
        w.u8(self.length_iocs)?;
        w.u8(self.length_iops)
    }
}

/// An expected submodule.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ExpectedSubmodule {
    /// SubslotNumber.
    pub subslot: u16,
    /// SubmoduleIdentNumber.
    pub submodule_ident: u32,
    /// SubmoduleProperties ([`submodule`] bits; bits 0–1 the type).
    pub properties: u16,
    /// The data descriptions: two (input, then output) for
    /// [`TYPE_INPUT_OUTPUT`](submodule::TYPE_INPUT_OUTPUT), one otherwise (an input of length
    /// 0 for a submodule without IO data). Other counts do not emit.
    pub data_descriptions: Vec<DataDescription>,
}

impl ExpectedSubmodule {
    /// A submodule with `input_length` input and `output_length` output bytes, typed and
    /// described as the controller must: no IO data is an input of length 0.
    pub fn with_io(
        subslot: u16,
        submodule_ident: u32,
        input_length: u16,
        output_length: u16,
    ) -> ExpectedSubmodule {
        let (properties, data_descriptions) = match (input_length, output_length) {
            (0, 0) => (submodule::TYPE_NO_IO, vec![DataDescription::input(0)]),
            (i, 0) => (submodule::TYPE_INPUT, vec![DataDescription::input(i)]),
            (0, o) => (submodule::TYPE_OUTPUT, vec![DataDescription::output(o)]),
            (i, o) => (
                submodule::TYPE_INPUT_OUTPUT,
                vec![DataDescription::input(i), DataDescription::output(o)],
            ),
        };
        ExpectedSubmodule {
            subslot,
            submodule_ident,
            properties,
            data_descriptions,
        }
    }

    /// The type from the properties ([`submodule::TYPE_NO_IO`]..=[`submodule::TYPE_INPUT_OUTPUT`]).
    pub const fn submodule_type(&self) -> u16 {
        self.properties & submodule::TYPE_MASK
    }

    /// How many data descriptions the type calls for.
    pub(super) const fn description_count(properties: u16) -> usize {
        if properties & submodule::TYPE_MASK == submodule::TYPE_INPUT_OUTPUT {
            2
        } else {
            1
        }
    }

    fn length(&self, direction: u16) -> u16 {
        self.data_descriptions
            .iter()
            .find(|d| d.direction == direction)
            .map_or(0, |d| d.length)
    }

    /// Input bytes (0 without an input description).
    pub fn input_length(&self) -> u16 {
        self.length(submodule::DATA_INPUT)
    }

    /// Output bytes (0 without an output description).
    pub fn output_length(&self) -> u16 {
        self.length(submodule::DATA_OUTPUT)
    }

    fn wire_len(&self) -> usize {
        8usize.saturating_add(self.data_descriptions.len().saturating_mul(6))
    }

    fn read(r: &mut Reader<'_>) -> Result<ExpectedSubmodule> {
        let subslot = r.u16()?;
        let submodule_ident = r.u32()?;
        let properties = r.u16()?;
        let data_descriptions = (0..ExpectedSubmodule::description_count(properties))
            .map(|_| DataDescription::read(r))
            .collect::<Result<Vec<_>>>()?;
        Ok(ExpectedSubmodule {
            subslot,
            submodule_ident,
            properties,
            data_descriptions,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        if self.data_descriptions.len() != ExpectedSubmodule::description_count(self.properties) {
            return Err(EmitError::Inconsistent(
                "an expected submodule's data descriptions do not match its type",
            ));
        }
        w.u16(self.subslot)?;
        w.u32(self.submodule_ident)?;
        w.u16(self.properties)?;
        self.data_descriptions.iter().try_for_each(|d| d.write(w))
    }
}

/// An expected module: one API entry of an ExpectedSubmoduleBlockReq.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ExpectedModule {
    /// API.
    pub api: u32,
    /// SlotNumber.
    pub slot: u16,
    /// ModuleIdentNumber.
    pub module_ident: u32,
    /// ModuleProperties (0).
    pub properties: u16,
    /// The submodules expected in the slot.
    pub submodules: Vec<ExpectedSubmodule>,
}

impl ExpectedModule {
    fn wire_len(&self) -> usize {
        self.submodules
            .iter()
            .fold(14usize, |n, s| n.saturating_add(s.wire_len()))
    }

    fn read(r: &mut Reader<'_>) -> Result<ExpectedModule> {
        Ok(ExpectedModule {
            api: r.u32()?,
            slot: r.u16()?,
            module_ident: r.u32()?,
            properties: r.u16()?,
            submodules: r.list(ExpectedSubmodule::read)?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u32(self.api)?;
        w.u16(self.slot)?;
        w.u32(self.module_ident)?;
        w.u16(self.properties)?;
        w.count("NumberOfSubmodules", self.submodules.len())?;
        self.submodules.iter().try_for_each(|s| s.write(w))
    }
}

/// ExpectedSubmoduleBlockReq (0x0104): the modules and submodules the controller expects.
///
/// On the wire NumberOfAPIs counts entries of (API, slot, module, submodules), so each
/// [`ExpectedModule`] carries its API. The S7 sends one block per slot.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct ExpectedSubmoduleBlockReq {
    /// The module entries.
    pub modules: Vec<ExpectedModule>,
}

impl Body for ExpectedSubmoduleBlockReq {
    const BLOCK_TYPE: BlockType = BlockType::ExpectedSubmoduleBlockReq;

    fn body_len(&self) -> usize {
        self.modules
            .iter()
            .fold(2usize, |n, m| n.saturating_add(m.wire_len()))
    }

    fn read(r: &mut Reader<'_>) -> Result<Self> {
        Ok(ExpectedSubmoduleBlockReq {
            modules: r.list(ExpectedModule::read)?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.count("NumberOfAPIs", self.modules.len())?;
        self.modules.iter().try_for_each(|m| m.write(w))
    }
}

block_api!(ExpectedSubmoduleBlockReq, "ExpectedSubmoduleBlockReq");
