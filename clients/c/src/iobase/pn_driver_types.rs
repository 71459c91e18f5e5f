// SPDX-License-Identifier: MIT OR Apache-2.0
//! Rust mirrors of the C types of `servusrx.h`, PN Driver's start-up, with the C names, as
//! [`types`](super::types) says for the other headers; `tests/pndriver_header.rs` compares
//! them with the C compiler's view.
#![allow(non_camel_case_types, non_snake_case)]

use super::types::{
    PNIO_ALARM_INFO, PNIO_ALARM_TINFO, PNIO_ALARM_TYPE, PNIO_APRIO_TYPE, PNIO_IO_TYPE, PNIO_UINT8,
    PNIO_UINT16, PNIO_UINT32,
};

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

/// `SERV_CP_INFO_TYPE`: the info interface's events.
pub type SERV_CP_INFO_TYPE = u32;
/// The procimgd is to restart.
pub const SERV_CP_INFO_STOP_REQ: SERV_CP_INFO_TYPE = 1;
/// An alarm of the controller's port.
pub const SERV_CP_INFO_PDEV_DATA: SERV_CP_INFO_TYPE = 2;
/// The ports' states.
pub const SERV_CP_INFO_PDEV_INIT_DATA: SERV_CP_INFO_TYPE = 3;
/// An LED changed.
pub const SERV_CP_INFO_LED_STATE: SERV_CP_INFO_TYPE = 4;

/// `SERV_CIB_PDEV_EXTCHNL_DIAG`: a port alarm's extended channel diagnosis.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SERV_CIB_PDEV_EXTCHNL_DIAG {
    /// ChannelNumber.
    pub Channel: PNIO_UINT16,
    /// ChannelProperties.
    pub Properties: PNIO_UINT16,
    /// ChannelErrorType.
    pub ErrType: PNIO_UINT16,
    /// ExtChannelErrorType.
    pub ExtErrType: PNIO_UINT16,
    /// ExtChannelAddValue, low word.
    pub ExtAdvAlLo: PNIO_UINT16,
    /// ExtChannelAddValue, high word.
    pub ExtAdvAlHi: PNIO_UINT16,
}

/// `SERV_CIB_PDEV_DATA`: an alarm of the controller's port.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct SERV_CIB_PDEV_DATA {
    /// 0.
    pub Version: PNIO_UINT32,
    /// `PNIO_IO_IN`.
    pub IODataType: PNIO_IO_TYPE,
    /// The submodule's diagnostic address.
    pub LogAddr: PNIO_UINT32,
    /// Slot.
    pub Slot: PNIO_UINT32,
    /// Subslot.
    pub Subslot: PNIO_UINT32,
    /// AlarmType.
    pub AlarmType: PNIO_ALARM_TYPE,
    /// Priority.
    pub AlarmPriority: PNIO_APRIO_TYPE,
    /// The AlarmSpecifier's sequence number.
    pub AlarmSequence: PNIO_UINT32,
    /// 0: the controller's own station.
    pub StationNr: PNIO_UINT32,
    /// Reserved.
    pub Reserved1: [PNIO_UINT8; 4],
    /// Reserved.
    pub Reserved2: [PNIO_UINT8; 48],
    /// Station details.
    pub AlarmTinfo: PNIO_ALARM_TINFO,
    /// The extended channel diagnosis.
    pub Diagnostics: SERV_CIB_PDEV_EXTCHNL_DIAG,
    /// OB82-style bytes.
    pub DiagDs: [PNIO_UINT8; 4],
    /// The alarm notification.
    pub AlarmAinfo: PNIO_ALARM_INFO,
}

/// `SERV_CIB_PDEV_MAX_PORT_ITEMS`.
pub const SERV_CIB_PDEV_MAX_PORT_ITEMS: u32 = 8;
/// A diagnosis is pending.
pub const SERV_CIB_PDEV_PORT_STATE_DISTURBED: u16 = 0x0001;
/// The submodule exists.
pub const SERV_CIB_PDEV_PORT_STATE_EXISTS: u16 = 0x0002;
/// It is not available.
pub const SERV_CIB_PDEV_PORT_STATE_NOT_AVAILABLE: u16 = 0x0004;
/// Maintenance required.
pub const SERV_CIB_PDEV_PORT_STATE_MAINTENANCE_REQUIRED: u16 = 0x0100;
/// Maintenance demanded.
pub const SERV_CIB_PDEV_PORT_STATE_MAINTENANCE_DEMANDED: u16 = 0x0200;

/// `SERV_CIB_PDEV_INIT_STATE`: one submodule's state.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SERV_CIB_PDEV_INIT_STATE {
    /// Reserved.
    pub Reserved1: PNIO_UINT8,
    /// Reserved.
    pub Reserved2: PNIO_UINT8,
    /// Reserved.
    pub Reserved3: PNIO_UINT16,
    /// `PNIO_IO_IN`.
    pub IODataType: PNIO_IO_TYPE,
    /// Diagnostic address.
    pub LogAddr: PNIO_UINT32,
    /// Slot.
    pub Slot: PNIO_UINT32,
    /// Subslot.
    pub Subslot: PNIO_UINT32,
    /// `SERV_CIB_PDEV_PORT_STATE_*`.
    pub PortState: PNIO_UINT16,
    /// Reserved.
    pub Reserved4: PNIO_UINT16,
}

/// `SERV_CIB_PDEV_INIT_DATA`: the interface's and ports' states.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SERV_CIB_PDEV_INIT_DATA {
    /// Entries used.
    pub ItemNumber: PNIO_UINT32,
    /// The entries.
    pub InitState: [SERV_CIB_PDEV_INIT_STATE; SERV_CIB_PDEV_MAX_PORT_ITEMS as usize],
}

/// `SERV_CIB_LED_TYPE`.
pub type SERV_CIB_LED_TYPE = u32;
/// Bus fault.
pub const SERV_CIB_LED_BF: SERV_CIB_LED_TYPE = 1;
/// Group fault.
pub const SERV_CIB_LED_SF: SERV_CIB_LED_TYPE = 2;
/// `SERV_CIB_LED_STATE`.
pub type SERV_CIB_LED_STATE = u32;
/// Off.
pub const SERV_CIB_LED_OFF: SERV_CIB_LED_STATE = 1;
/// On.
pub const SERV_CIB_LED_ON: SERV_CIB_LED_STATE = 2;

/// `SERV_CIB_LED`: an LED's state.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SERV_CIB_LED {
    /// Which LED.
    pub LedType: SERV_CIB_LED_TYPE,
    /// On or off.
    pub LedState: SERV_CIB_LED_STATE,
    /// Reserved.
    pub Reserved1: [PNIO_UINT8; 4],
}

/// The union of `SERV_CP_INFO_PRM`.
#[repr(C)]
#[derive(Clone, Copy)]
pub union SERV_CP_INFO_PRM_u {
    /// `SERV_CP_INFO_PDEV_DATA`.
    pub PdevData: SERV_CIB_PDEV_DATA,
    /// `SERV_CP_INFO_PDEV_INIT_DATA`.
    pub PdevInitData: SERV_CIB_PDEV_INIT_DATA,
    /// `SERV_CP_INFO_LED_STATE`.
    pub LedInfo: SERV_CIB_LED,
}

/// `SERV_CP_INFO_PRM`: what an info callback receives.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct SERV_CP_INFO_PRM {
    /// 0.
    pub Version: PNIO_UINT32,
    /// From `SERV_CP_info_open`.
    pub Handle: PNIO_UINT32,
    /// The CP.
    pub CpIndex: PNIO_UINT32,
    /// The event.
    pub InfoType: SERV_CP_INFO_TYPE,
    /// Its parameters.
    pub u: SERV_CP_INFO_PRM_u,
}

/// `SERV_CP_INFO_CBF`: an info callback.
pub type SERV_CP_INFO_CBF = Option<unsafe extern "C" fn(pCbfPrm: *mut SERV_CP_INFO_PRM)>;
