// SPDX-License-Identifier: MIT OR Apache-2.0
//! Rust mirrors of the C types of `servusrx.h`, PN Driver's start-up, with the C names, as
//! [`types`](super::types) says for the other headers; `tests/pndriver_header.rs` compares
//! them with the C compiler's view.
#![allow(non_camel_case_types, non_snake_case)]

use super::types::{PNIO_UINT8, PNIO_UINT16, PNIO_UINT32};

/// `PROCIMG_MAX_NETWORK_ADAPTERS`: most entries `SERV_CP_get_network_adapters` writes.
pub const PROCIMG_MAX_NETWORK_ADAPTERS: u32 = 50;
/// `PROCIMG_TRACE_BUFFER_SIZE`: bytes of trace gathered before `CbfPntrcBufferFull`.
pub const PROCIMG_TRACE_BUFFER_SIZE: u32 = 65536;

/// `pnio_stack_comp`: a component of the stack's trace.
pub type pnio_stack_comp = u32;
/// `PNIO_TRACE_COMP_PND`: PN Driver itself, procimgd's log.
pub const PNIO_TRACE_COMP_PND: pnio_stack_comp = 17;
/// `PNIO_TRACE_COMP_NUM`: the number of components.
pub const PNIO_TRACE_COMP_NUM: pnio_stack_comp = 18;
/// The components, in value order (for the header test).
pub const PNIO_TRACE_COMPONENTS: [&str; 18] = [
    "PNIO_TRACE_COMP_ACP",
    "PNIO_TRACE_COMP_CLRPC",
    "PNIO_TRACE_COMP_CM",
    "PNIO_TRACE_COMP_DCP",
    "PNIO_TRACE_COMP_EDDI",
    "PNIO_TRACE_COMP_EDDS",
    "PNIO_TRACE_COMP_EPS",
    "PNIO_TRACE_COMP_GSY",
    "PNIO_TRACE_COMP_HIF",
    "PNIO_TRACE_COMP_LLDP",
    "PNIO_TRACE_COMP_NARE",
    "PNIO_TRACE_COMP_OHA",
    "PNIO_TRACE_COMP_PNTRC",
    "PNIO_TRACE_COMP_PSI",
    "PNIO_TRACE_COMP_SNMPX",
    "PNIO_TRACE_COMP_SOCK",
    "PNIO_TRACE_COMP_TCIP",
    "PNIO_TRACE_COMP_PND",
];

/// `pnio_trace_level`: how much a component traces.
pub type pnio_trace_level = u32;
/// `PNIO_TRACE_LEVEL_OFF`.
pub const PNIO_TRACE_LEVEL_OFF: pnio_trace_level = 0;
/// `PNIO_TRACE_LEVEL_FATAL`.
pub const PNIO_TRACE_LEVEL_FATAL: pnio_trace_level = 1;
/// `PNIO_TRACE_LEVEL_ERROR`.
pub const PNIO_TRACE_LEVEL_ERROR: pnio_trace_level = 2;
/// `PNIO_TRACE_LEVEL_UNEXP`.
pub const PNIO_TRACE_LEVEL_UNEXP: pnio_trace_level = 3;
/// `PNIO_TRACE_LEVEL_WARN`.
pub const PNIO_TRACE_LEVEL_WARN: pnio_trace_level = 4;
/// `PNIO_TRACE_LEVEL_NOTE_HIGH`.
pub const PNIO_TRACE_LEVEL_NOTE_HIGH: pnio_trace_level = 5;
/// `PNIO_TRACE_LEVEL_NOTE`.
pub const PNIO_TRACE_LEVEL_NOTE: pnio_trace_level = 6;
/// `PNIO_TRACE_LEVEL_NOTE_LOW`.
pub const PNIO_TRACE_LEVEL_NOTE_LOW: pnio_trace_level = 7;
/// `PNIO_TRACE_LEVEL_CHAT`.
pub const PNIO_TRACE_LEVEL_CHAT: pnio_trace_level = 8;
/// `PNIO_TRACE_LEVEL_NUM`: the number of levels.
pub const PNIO_TRACE_LEVEL_NUM: pnio_trace_level = 9;

/// `PNIO_CP_SELECT_TYPE`: how a `PNIO_CP_ID_TYPE` names its adapter.
pub type PNIO_CP_SELECT_TYPE = u32;
/// `PNIO_CP_SELECT_WITH_PCI_LOCATION`: by `CpPciLocation`.
pub const PNIO_CP_SELECT_WITH_PCI_LOCATION: PNIO_CP_SELECT_TYPE = 1;
/// `PNIO_CP_SELECT_WITH_MAC_ADDRESS`: by `CpMacAddr`.
pub const PNIO_CP_SELECT_WITH_MAC_ADDRESS: PNIO_CP_SELECT_TYPE = 2;

/// `PNIO_MAC_ADDR_SIZE`.
pub const PNIO_MAC_ADDR_SIZE: u32 = 6;
/// `PNIO_MAC_ADDR_TYPE`.
pub type PNIO_MAC_ADDR_TYPE = [PNIO_UINT8; 6];

/// `PNIO_PCI_LOCATION_TYPE`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_PCI_LOCATION_TYPE {
    /// The bus.
    pub BusNr: PNIO_UINT16,
    /// The device on the bus.
    pub DeviceNr: PNIO_UINT16,
    /// The function of the device.
    pub FunctionNr: PNIO_UINT16,
}

/// `PNIO_PNTRC_BUFFER_FULL`: receives a full trace buffer.
pub type PNIO_PNTRC_BUFFER_FULL =
    Option<unsafe extern "C" fn(pBuffer: *mut PNIO_UINT8, BufferSize: PNIO_UINT32)>;
/// `PNIO_PNTRC_SET_TRACE_LEVEL_DONE`: a trace level holds.
pub type PNIO_PNTRC_SET_TRACE_LEVEL_DONE = Option<unsafe extern "C" fn()>;

/// `PNIO_DEBUG_SETTINGS_TYPE` (the manual's layout, PN Driver V1.0).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_DEBUG_SETTINGS_TYPE {
    /// Receives the trace; `None`: no trace.
    pub CbfPntrcBufferFull: PNIO_PNTRC_BUFFER_FULL,
    /// The first level of each component.
    pub TraceLevels: [PNIO_UINT8; 18],
}

/// `PNIO_CP_ID_TYPE`: one adapter.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_CP_ID_TYPE {
    /// How the entry names its adapter.
    pub CpSelection: PNIO_CP_SELECT_TYPE,
    /// The adapter's MAC address.
    pub CpMacAddr: PNIO_MAC_ADDR_TYPE,
    /// The adapter's PCI location.
    pub CpPciLocation: PNIO_PCI_LOCATION_TYPE,
    /// A NUL-terminated description: procimg writes the interface name.
    pub Description: [PNIO_UINT8; 300],
}

/// `PNIO_SW_VERSION_TYPE`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct PNIO_SW_VERSION_TYPE {
    /// 'V', 'R', 'P', 'U' or 'T'.
    pub revision_prefix: PNIO_UINT8,
    /// The functional enhancement.
    pub functional_enhancement: PNIO_UINT8,
    /// The bug fix.
    pub bug_fix: PNIO_UINT8,
    /// The internal change.
    pub internal_change: PNIO_UINT8,
}

/// `PNIO_SYSTEM_DESCR`: the PC station's identity (PN Driver's public headers).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_SYSTEM_DESCR {
    /// The vendor.
    pub Vendor: [PNIO_UINT8; 128],
    /// The product family.
    pub ProductFamily: [PNIO_UINT8; 128],
    /// The serial number.
    pub ProductSerialNr: [PNIO_UINT8; 128],
    /// I&M: the device type.
    pub IM_DeviceType: [PNIO_UINT8; 26],
    /// I&M: the order number.
    pub IM_OrderId: [PNIO_UINT8; 21],
    /// I&M: the hardware revision.
    pub IM_HwRevision: PNIO_UINT16,
    /// I&M: the software revision.
    pub IM_SwVersion: PNIO_SW_VERSION_TYPE,
    /// I&M: the revision counter.
    pub IM_RevisionCounter: PNIO_UINT16,
    /// I&M: the I&M version.
    pub IM_Version: PNIO_UINT16,
    /// I&M: the I&M records supported.
    pub IM_Supported: PNIO_UINT16,
    /// I&M: the profile-specific type.
    pub IM_ProfileSpecificType: PNIO_UINT16,
    /// I&M: the profile.
    pub IM_ProfileId: PNIO_UINT16,
}

/// `SERV_FW_VERS_TYPE`: a firmware version, V`v1`.`v2`.`v3`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SERV_FW_VERS_TYPE {
    /// Major.
    pub v1: PNIO_UINT16,
    /// Minor.
    pub v2: PNIO_UINT16,
    /// Patch.
    pub v3: PNIO_UINT16,
    /// Build.
    pub v4: PNIO_UINT16,
    /// Build increment (reserved).
    pub v5: PNIO_UINT16,
    /// Reserved.
    pub reserved: PNIO_UINT16,
}

/// `SERV_CP_FW_INFO_TYPE`: what `SERV_CP_get_fw_info` tells of a CP.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct SERV_CP_FW_INFO_TYPE {
    /// The firmware's (procimgd's) version.
    pub fw_version: SERV_FW_VERS_TYPE,
    /// The serial number, NUL-terminated: procimg writes the instance name.
    pub cp_ser_nr: [PNIO_UINT8; 16],
    /// The order number, NUL-terminated.
    pub mlfb: [PNIO_UINT8; 32],
    /// The hardware version.
    pub hw_version: PNIO_UINT16,
    /// The interface's MAC address.
    pub mac: [PNIO_UINT8; 6],
    /// IPv4 address, network byte order.
    pub ip_addr: PNIO_UINT32,
    /// Subnet mask, network byte order.
    pub ip_mask: PNIO_UINT32,
    /// Default router, network byte order.
    pub default_router: PNIO_UINT32,
    /// NameOfStation, NUL-terminated.
    pub name: [PNIO_UINT8; 256],
    /// Type of station, NUL-terminated.
    pub TypeOfStation: [PNIO_UINT8; 256],
}

/// `PNIO_CP_DLD_TYPE`: what `SERV_CP_download` carries.
pub type PNIO_CP_DLD_TYPE = u32;
/// A firmware file.
pub const PNIO_CP_DLD_FIRMWARE: PNIO_CP_DLD_TYPE = 1;
/// A configuration.
pub const PNIO_CP_DLD_CONFIG: PNIO_CP_DLD_TYPE = 2;

/// `PNIO_CP_RESET_TYPE`: how `SERV_CP_reset` treats attached programs.
pub type PNIO_CP_RESET_TYPE = u32;
/// Only with no program attached.
pub const PNIO_CP_RESET_SAFE: PNIO_CP_RESET_TYPE = 0;
/// Whoever is attached (after asking them to stop).
pub const PNIO_CP_RESET_FORCE: PNIO_CP_RESET_TYPE = 1;
