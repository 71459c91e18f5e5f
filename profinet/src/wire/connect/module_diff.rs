// SPDX-License-Identifier: MIT OR Apache-2.0
//! ModuleDiffBlock: where the plugged modules and submodules differ from the expected ones,
//! and the states that say how.

use super::*;

coded_enum! {
    /// ModuleState of a ModuleDiffBlock entry.
    pub enum ModuleState(u16) {
        /// 0: no module plugged.
        NoModule = 0 => "no module",
        /// 1: a wrong module (another ModuleIdentNumber).
        WrongModule = 1 => "wrong module",
        /// 2: the proper module, but at least one submodule is locked, wrong, missing or has
        /// diagnosis.
        ProperModule = 2 => "proper module",
        /// 3: a substitute the device adapts.
        Substitute = 3 => "substitute",
    }
}

coded_enum! {
    /// IdentInfo of a [`SubmoduleState`] (bits 11–14): how the real submodule matches the
    /// expected one. Values 4..=15 are reserved.
    pub enum IdentInfo(u8) {
        /// 0: the expected submodule.
        Ok = 0 => "ok",
        /// 1: a substitute.
        Substitute = 1 => "substitute",
        /// 2: a wrong submodule.
        Wrong = 2 => "wrong",
        /// 3: no submodule.
        NoSubmodule = 3 => "no submodule",
    }
}

coded_enum! {
    /// ARInfo of a [`SubmoduleState`] (bits 7–10): who owns the submodule. Values 5..=15 are
    /// reserved.
    pub enum ArInfo(u8) {
        /// 0: owned by this AR.
        Own = 0 => "own",
        /// 1: ApplicationReady pending (e.g. a parameter error).
        ApplicationReadyPending = 1 => "application ready pending",
        /// 2: locked by a superordinated function.
        SuperordinatedLocked = 2 => "superordinated locked",
        /// 3: locked by another IO controller.
        LockedByIoController = 3 => "locked by IO controller",
        /// 4: locked by an IO supervisor.
        LockedByIoSupervisor = 4 => "locked by IO supervisor",
    }
}

/// SubmoduleState of a ModuleDiffBlock entry (the FormatIndicator = 1 layout).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SubmoduleState(pub u16);

impl SubmoduleState {
    /// Bit 15: FormatIndicator; the fields below are valid only when it is set.
    pub const FORMAT_INDICATOR: u16 = 1 << 15;
    /// Bit 3: QualifiedInfo (qualified diagnosis available).
    pub const QUALIFIED_INFO: u16 = 1 << 3;
    /// Bit 4: MaintenanceRequired.
    pub const MAINTENANCE_REQUIRED: u16 = 1 << 4;
    /// Bit 5: MaintenanceDemanded.
    pub const MAINTENANCE_DEMANDED: u16 = 1 << 5;
    /// Bit 6: DiagInfo / fault: diagnosis data available.
    pub const DIAG_INFO: u16 = 1 << 6;

    /// Whether the FormatIndicator is set.
    pub const fn format_indicator(&self) -> bool {
        self.0 & SubmoduleState::FORMAT_INDICATOR != 0
    }

    /// Bits 0–2: AddInfo (1 = takeover not allowed).
    pub const fn add_info(&self) -> u8 {
        // Masked to 3 bits, so the cast keeps every bit.
        (self.0 & 0x7) as u8
    }

    /// Bit 3: QualifiedInfo.
    pub const fn qualified_info(&self) -> bool {
        self.0 & SubmoduleState::QUALIFIED_INFO != 0
    }

    /// Bit 4: MaintenanceRequired.
    pub const fn maintenance_required(&self) -> bool {
        self.0 & SubmoduleState::MAINTENANCE_REQUIRED != 0
    }

    /// Bit 5: MaintenanceDemanded.
    pub const fn maintenance_demanded(&self) -> bool {
        self.0 & SubmoduleState::MAINTENANCE_DEMANDED != 0
    }

    /// Bit 6: DiagInfo, i.e. a fault: diagnosis is available in the records.
    pub const fn fault(&self) -> bool {
        self.0 & SubmoduleState::DIAG_INFO != 0
    }

    /// Bits 7–10: ARInfo.
    pub const fn ar_info(&self) -> ArInfo {
        // Masked to 4 bits, so the cast keeps every bit.
        ArInfo::from_raw(((self.0 >> 7) & 0xf) as u8)
    }

    /// Bits 11–14: IdentInfo.
    pub const fn ident_info(&self) -> IdentInfo {
        // Masked to 4 bits, so the cast keeps every bit.
        IdentInfo::from_raw(((self.0 >> 11) & 0xf) as u8)
    }

    /// Whether the controller may exchange data with the submodule: the format is known, the
    /// submodule is the expected one or a substitute, and this AR owns it.
    pub const fn is_usable(&self) -> bool {
        self.format_indicator()
            && matches!(self.ident_info(), IdentInfo::Ok | IdentInfo::Substitute)
            && matches!(self.ar_info(), ArInfo::Own)
    }
}

/// Says what the state means: "the expected submodule, owned by this AR, diagnosis
/// available", "wrong submodule, locked by IO controller" and so on.
impl core::fmt::Display for SubmoduleState {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if !self.format_indicator() {
            return write!(f, "SubmoduleState {:#06x} in the old format", self.0);
        }
        match self.ident_info() {
            IdentInfo::Ok => f.write_str("the expected submodule")?,
            IdentInfo::Substitute => f.write_str("a substitute")?,
            IdentInfo::Wrong => f.write_str("a wrong submodule")?,
            IdentInfo::NoSubmodule => f.write_str("no submodule")?,
            IdentInfo::Unknown(raw) => write!(f, "reserved IdentInfo {raw}")?,
        }
        match self.ar_info() {
            ArInfo::Own => f.write_str(", owned by this AR")?,
            ArInfo::Unknown(raw) => write!(f, ", reserved ARInfo {raw}")?,
            other => write!(f, ", {}", other.name().unwrap_or("?"))?,
        }
        if self.fault() {
            f.write_str(", diagnosis available")?;
        }
        if self.maintenance_demanded() {
            f.write_str(", maintenance demanded")?;
        }
        if self.maintenance_required() {
            f.write_str(", maintenance required")?;
        }
        if self.qualified_info() {
            f.write_str(", qualified diagnosis")?;
        }
        if self.add_info() == 1 {
            f.write_str(", takeover not allowed")?;
        }
        Ok(())
    }
}

/// A submodule entry of a ModuleDiffBlock.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ModuleDiffSubmodule {
    /// SubslotNumber.
    pub subslot: u16,
    /// SubmoduleIdentNumber (the real one).
    pub submodule_ident: u32,
    /// SubmoduleState.
    pub state: SubmoduleState,
}

/// A module entry of a ModuleDiffBlock.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ModuleDiffModule {
    /// SlotNumber.
    pub slot: u16,
    /// ModuleIdentNumber (the real one).
    pub module_ident: u32,
    /// ModuleState.
    pub state: ModuleState,
    /// The submodules that differ.
    pub submodules: Vec<ModuleDiffSubmodule>,
}

/// The modules of one API in a ModuleDiffBlock.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ModuleDiffApi {
    /// API.
    pub api: u32,
    /// The modules that differ.
    pub modules: Vec<ModuleDiffModule>,
}

/// ModuleDiffBlock (0x8104): the modules and submodules whose real state differs from the
/// expected configuration. Not an error: the AR is up; submodules that are not
/// [usable](SubmoduleState::is_usable) must be treated as absent.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct ModuleDiffBlock {
    /// The APIs with differences.
    pub apis: Vec<ModuleDiffApi>,
}

impl ModuleDiffBlock {
    /// Every listed submodule as (API, slot, subslot, state).
    pub fn submodules(&self) -> impl Iterator<Item = (u32, u16, u16, SubmoduleState)> + '_ {
        self.apis.iter().flat_map(|a| {
            a.modules.iter().flat_map(move |m| {
                m.submodules
                    .iter()
                    .map(move |s| (a.api, m.slot, s.subslot, s.state))
            })
        })
    }
}

impl Body for ModuleDiffBlock {
    const BLOCK_TYPE: BlockType = BlockType::ModuleDiffBlock;

    fn body_len(&self) -> usize {
        self.apis.iter().fold(2usize, |n, a| {
            a.modules.iter().fold(n.saturating_add(6), |n, m| {
                n.saturating_add(10)
                    .saturating_add(m.submodules.len().saturating_mul(8))
            })
        })
    }

    fn read(r: &mut Reader<'_>) -> Result<Self> {
        let apis = r.list(|r| {
            Ok(ModuleDiffApi {
                api: r.u32()?,
                modules: r.list(|r| {
                    Ok(ModuleDiffModule {
                        slot: r.u16()?,
                        module_ident: r.u32()?,
                        state: ModuleState::from(r.u16()?),
                        submodules: r.list(|r| {
                            Ok(ModuleDiffSubmodule {
                                subslot: r.u16()?,
                                submodule_ident: r.u32()?,
                                state: SubmoduleState(r.u16()?),
                            })
                        })?,
                    })
                })?,
            })
        })?;
        Ok(ModuleDiffBlock { apis })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.count("NumberOfAPIs", self.apis.len())?;
        for a in &self.apis {
            w.u32(a.api)?;
            w.count("NumberOfModules", a.modules.len())?;
            for m in &a.modules {
                w.u16(m.slot)?;
                w.u32(m.module_ident)?;
                w.u16(m.state.into())?;
                w.count("NumberOfSubmodules", m.submodules.len())?;
                for s in &m.submodules {
                    w.u16(s.subslot)?;
                    w.u32(s.submodule_ident)?;
                    w.u16(s.state.0)?;
                }
            }
        }
        Ok(())
    }
}

block_api!(ModuleDiffBlock, "ModuleDiffBlock");
