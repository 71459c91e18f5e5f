// SPDX-License-Identifier: MIT OR Apache-2.0
//! Rust mirrors of the C types of `pniousrd.h`, the IO device part of the IO-Base API, with
//! the C names; the types it shares with the controller part (`PNIO_UINT32`, `PNIO_IOXS`,
//! `PNIO_ERR_STAT`, …) are [`super::types`]'.
//!
//! The conventions are those of [`super::types`]: every struct is `#[repr(C)]` with the
//! header's fields in its order, `align(4)` where `ATTR_PACKED` raises a struct's alignment
//! (structs of bytes and 16-bit words only), and C enums are `u32` aliases with one constant
//! per value. Where the header offers two names for a field (an anonymous union of the
//! manual's name and IO-Base's), the mirror has IO-Base's.
//!
//! Nothing here is exported to C yet. The callback typedefs are `Option<unsafe extern "C"
//! fn>` aliases, the functions' types are aliases in [`prototypes`], and both are listed with
//! their C spelling in [`DEVICE_CALLBACKS`] and [`DEVICE_FUNCTIONS`]: from one declaration
//! each, so that `tests/iobase_device_header.rs` checks the header's prototypes against the
//! same facts the Rust types are made of.
#![allow(non_camel_case_types, non_snake_case)]

use super::types::{PNIO_ADDR_GEO, PNIO_ADDR_TYPE, PNIO_ERR_STAT, PNIO_IO_TYPE, PNIO_IOXS};
use super::types::{PNIO_UINT8, PNIO_UINT16, PNIO_UINT32};
use core::ffi::c_void;
use core::mem::size_of;

// ---------------------------------------------------------------------------------------
// Limits and encodings

/// `MAX_DEVICE_TYPE_LENGTH`: characters of `PNIO_ANNOTATION::deviceType` without the NUL.
pub const MAX_DEVICE_TYPE_LENGTH: u32 = 25;
/// `MAX_ORDER_ID_LENGTH`: characters of `PNIO_ANNOTATION::orderId` without the NUL.
pub const MAX_ORDER_ID_LENGTH: u32 = 20;

/// `PNIO_DEVICE_SET_MAXAR_BY_TYPE`: `MaxAr` of `PNIO_device_open` with
/// `PNIO_CEP_DEV_MAXAR_BY_TYPE`, 4 bits for each kind of AR.
pub const fn PNIO_DEVICE_SET_MAXAR_BY_TYPE(
    MaxArClass1_2: u32,
    MaxArClass3: u32,
    MaxArDeviceAccess: u32,
) -> u32 {
    ((MaxArDeviceAccess & 0xF) << 8) | ((MaxArClass3 & 0xF) << 4) | (MaxArClass1_2 & 0xF)
}

/// `PNIO_set_dev_state`: no problem.
pub const PNIO_DEVSTAT_OK: u32 = 1;
/// `PNIO_set_dev_state`: the station has a problem.
pub const PNIO_DEVSTAT_STATION_PROBLEM: u32 = 2;

// ---------------------------------------------------------------------------------------
// Enums

/// `PNIO_ACCESS_ENUM`: which IO data `PNIO_initiate_data_*_ext` visit.
pub type PNIO_ACCESS_ENUM = u32;
/// All data, consistent: not supported by IO-Base.
pub const PNIO_ACCESS_ALL_WITH_LOCK: PNIO_ACCESS_ENUM = 0;
/// RT and IRT data; IRT consistent only inside the isochronous window.
pub const PNIO_ACCESS_ALL_WITHOUT_LOCK: PNIO_ACCESS_ENUM = 1;
/// RT data, consistent.
pub const PNIO_ACCESS_RT_WITH_LOCK: PNIO_ACCESS_ENUM = 2;
/// RT data, consistency not guaranteed.
pub const PNIO_ACCESS_RT_WITHOUT_LOCK: PNIO_ACCESS_ENUM = 3;
/// IRT data with a lock: not supported by IO-Base.
pub const PNIO_ACCESS_IRT_WITH_LOCK: PNIO_ACCESS_ENUM = 4;
/// IRT data, consistent only inside the isochronous window.
pub const PNIO_ACCESS_IRT_WITHOUT_LOCK: PNIO_ACCESS_ENUM = 5;

/// `PNIO_DEV_ACTION`: what a `PNIO_CBF_PULL_PLUG_CONF` confirms.
pub type PNIO_DEV_ACTION = u32;
/// `PNIO_mod_pull`.
pub const PNIO_MOD_PULL: PNIO_DEV_ACTION = 1;
/// `PNIO_mod_plug`.
pub const PNIO_MOD_PLUG: PNIO_DEV_ACTION = 2;
/// `PNIO_sub_pull`.
pub const PNIO_SUB_PULL: PNIO_DEV_ACTION = 3;
/// `PNIO_sub_plug`, `PNIO_sub_plug_ext`, `PNIO_sub_plug_ext_IM`.
pub const PNIO_SUB_PLUG: PNIO_DEV_ACTION = 4;

/// `PNIO_PLUG_IM0_BITS`: a submodule's entry in I&M0FilterData (record 0xF840).
pub type PNIO_PLUG_IM0_BITS = u32;
/// No I&M data.
pub const PNIO_PLUG_IM0_BITS_NOTHING: PNIO_PLUG_IM0_BITS = 0x00;
/// I&M data of its own.
pub const PNIO_PLUG_IM0_BITS_SUBMODULE: PNIO_PLUG_IM0_BITS = 0x01;
/// I&M data that also speaks for its module.
pub const PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MODULE: PNIO_PLUG_IM0_BITS = 0x03;
/// I&M data that also speaks for its module and the device (the DAP's submodule).
pub const PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MOD_DEV: PNIO_PLUG_IM0_BITS = 0x07;

/// `PNIO_AR_TYPE_ENUM`: `ArType` of `PNIO_CBF_AR_CHECK_IND`.
pub type PNIO_AR_TYPE_ENUM = u32;
/// An IO AR.
pub const PNIO_AR_TYPE_SINGLE: PNIO_AR_TYPE_ENUM = 0x01;
/// A supervisor AR.
pub const PNIO_AR_TYPE_SUPERVISOR: PNIO_AR_TYPE_ENUM = 0x06;
/// An IO AR with RT class 3.
pub const PNIO_AR_TYPE_SINGLE_RTC3: PNIO_AR_TYPE_ENUM = 0x10;

/// `PNIO_AR_REASON`: why an AR ended.
pub type PNIO_AR_REASON = u32;
/// None.
pub const PNIO_AR_REASON_NONE: PNIO_AR_REASON = 0;
/// Internal.
pub const PNIO_AR_REASON_RESERVED1: PNIO_AR_REASON = 1;
/// Internal.
pub const PNIO_AR_REASON_RESERVED2: PNIO_AR_REASON = 2;
/// Out of memory.
pub const PNIO_AR_REASON_MEM: PNIO_AR_REASON = 3;
/// Adding a provider or consumer failed.
pub const PNIO_AR_REASON_FRAME: PNIO_AR_REASON = 4;
/// The consumer missed the PLC's frames.
pub const PNIO_AR_REASON_MISS: PNIO_AR_REASON = 5;
/// CMI timeout.
pub const PNIO_AR_REASON_TIMER: PNIO_AR_REASON = 6;
/// Opening the alarm channel failed.
pub const PNIO_AR_REASON_ALARM: PNIO_AR_REASON = 7;
/// Sending an alarm failed.
pub const PNIO_AR_REASON_ALSND: PNIO_AR_REASON = 8;
/// Sending an alarm acknowledgement failed.
pub const PNIO_AR_REASON_ALACK: PNIO_AR_REASON = 9;
/// Alarm data too long.
pub const PNIO_AR_REASON_ALLEN: PNIO_AR_REASON = 10;
/// Alarm indication error.
pub const PNIO_AR_REASON_ASRT: PNIO_AR_REASON = 11;
/// An RPC client call failed.
pub const PNIO_AR_REASON_RPC: PNIO_AR_REASON = 12;
/// AR abort requested.
pub const PNIO_AR_REASON_ABORT: PNIO_AR_REASON = 13;
/// A new AR replaced this one.
pub const PNIO_AR_REASON_RERUN: PNIO_AR_REASON = 14;
/// The PLC released the AR.
pub const PNIO_AR_REASON_REL: PNIO_AR_REASON = 15;
/// The device was passivated.
pub const PNIO_AR_REASON_PAS: PNIO_AR_REASON = 16;
/// The device or AR was removed.
pub const PNIO_AR_REASON_RMV: PNIO_AR_REASON = 17;
/// Protocol violation.
pub const PNIO_AR_REASON_PROT: PNIO_AR_REASON = 18;
/// Name and address resolution error.
pub const PNIO_AR_REASON_NARE: PNIO_AR_REASON = 19;
/// RPC bind error.
pub const PNIO_AR_REASON_BIND: PNIO_AR_REASON = 20;
/// RPC connect error.
pub const PNIO_AR_REASON_CONNECT: PNIO_AR_REASON = 21;
/// RPC read error.
pub const PNIO_AR_REASON_READ: PNIO_AR_REASON = 22;
/// RPC write error.
pub const PNIO_AR_REASON_WRITE: PNIO_AR_REASON = 23;
/// RPC control error.
pub const PNIO_AR_REASON_CONTROL: PNIO_AR_REASON = 24;
/// Pull or plug between the AR check and the end of parameterisation.
pub const PNIO_AR_REASON_PULLPLUG: PNIO_AR_REASON = 25;
/// Deprecated: AP removed.
pub const PNIO_AR_REASON_AP_RMV: PNIO_AR_REASON = 26;
/// Link down.
pub const PNIO_AR_REASON_LNK_DWN: PNIO_AR_REASON = 27;
/// A multicast MAC could not be registered.
pub const PNIO_AR_REASON_MMAC: PNIO_AR_REASON = 28;
/// Not synchronised (no companion AR).
pub const PNIO_AR_REASON_SYNC: PNIO_AR_REASON = 29;
/// Wrong topology (no companion AR).
pub const PNIO_AR_REASON_TOPO: PNIO_AR_REASON = 30;
/// DCP changed the station name.
pub const PNIO_AR_REASON_DCP_NAME: PNIO_AR_REASON = 31;
/// DCP reset to factory settings.
pub const PNIO_AR_REASON_DCP_RESET: PNIO_AR_REASON = 32;
/// Deprecated: companion AR blocked by a port or interface submodule of the first AR.
pub const PNIO_AR_REASON_PRM: PNIO_AR_REASON = 33;
/// No IR data record yet.
pub const PNIO_AR_REASON_IRDATA: PNIO_AR_REASON = 34;
/// The largest value.
pub const PNIO_AR_REASON_MAX: PNIO_AR_REASON = 255;

/// `PNIO_APDU_STATUS_IND`: the PLC's state, bits.
pub type PNIO_APDU_STATUS_IND = u32;
/// The PLC is in STOP.
pub const PNIO_EVENT_APDU_STATUS_STOP: PNIO_APDU_STATUS_IND = 0x01;
/// The PLC is in RUN.
pub const PNIO_EVENT_APDU_STATUS_RUN: PNIO_APDU_STATUS_IND = 0x02;
/// No station problem.
pub const PNIO_EVENT_APDU_STATUS_STATION_OK: PNIO_APDU_STATUS_IND = 0x04;
/// Station problem.
pub const PNIO_EVENT_APDU_STATUS_STATION_PROBLEM: PNIO_APDU_STATUS_IND = 0x08;
/// Primary (redundancy).
pub const PNIO_EVENT_APDU_STATUS_PRIMARY: PNIO_APDU_STATUS_IND = 0x10;
/// Backup (redundancy).
pub const PNIO_EVENT_APDU_STATUS_BACKUP: PNIO_APDU_STATUS_IND = 0x20;

/// `PNIO_IOCR_TYPE_ENUM`: an IOCR's direction, named from the PLC's side.
pub type PNIO_IOCR_TYPE_ENUM = u32;
/// Reserved.
pub const PNIO_IOCR_TYPE_RESERVED_0: PNIO_IOCR_TYPE_ENUM = 0;
/// Input frame: the device sends.
pub const PNIO_IOCR_TYPE_INPUT: PNIO_IOCR_TYPE_ENUM = 1;
/// Output frame: the device receives.
pub const PNIO_IOCR_TYPE_OUTPUT: PNIO_IOCR_TYPE_ENUM = 2;
/// Multicast provider (an input frame).
pub const PNIO_IOCR_TYPE_MULTICAST_PROVIDER: PNIO_IOCR_TYPE_ENUM = 3;
/// Multicast consumer (an output frame).
pub const PNIO_IOCR_TYPE_MULTICAST_CONSUMER: PNIO_IOCR_TYPE_ENUM = 4;

/// `PNIO_IOCR_PROP_ENUM`: an IOCR's properties.
pub type PNIO_IOCR_PROP_ENUM = u32;
/// The RT class bits.
pub const PNIO_IOCR_PROP_RT_CLASS_MASK: PNIO_IOCR_PROP_ENUM = 0x0F;
/// RT class 1 (RT).
pub const PNIO_IOCR_PROP_RT_CLASS_1: PNIO_IOCR_PROP_ENUM = 0x01;
/// RT class 2 (RT).
pub const PNIO_IOCR_PROP_RT_CLASS_2: PNIO_IOCR_PROP_ENUM = 0x02;
/// RT class 3 (IRT).
pub const PNIO_IOCR_PROP_RT_CLASS_3: PNIO_IOCR_PROP_ENUM = 0x03;
/// RT class 1 over UDP.
pub const PNIO_IOCR_PROP_RT_CLASS_1_UDP: PNIO_IOCR_PROP_ENUM = 0x04;

/// `PNIO_MODULE_STATE`: `*pModState` of `PNIO_CBF_CHECK_IND`.
pub type PNIO_MODULE_STATE = u32;
/// No module.
pub const PNIO_MOD_STATE_NO_MODULE: PNIO_MODULE_STATE = 0;
/// A wrong module.
pub const PNIO_MOD_STATE_WRONG_MODULE: PNIO_MODULE_STATE = 1;
/// The module expected.
pub const PNIO_MOD_STATE_PROPER_MODULE: PNIO_MODULE_STATE = 2;
/// A substitute of the module expected.
pub const PNIO_MOD_STATE_SUBSTITUTED_MODULE: PNIO_MODULE_STATE = 3;

/// `PNIO_SUBMODULE_STATE`: the ident bits (11-14) of a submodule state.
pub type PNIO_SUBMODULE_STATE = u32;
/// The ident bits.
pub const PNIO_SUB_STATE_IDENT_MASK: PNIO_SUBMODULE_STATE = 0x7800;
/// No submodule.
pub const PNIO_SUB_STATE_IDENT_NO_SUBMODULE: PNIO_SUBMODULE_STATE = 0x1800;
/// A wrong submodule.
pub const PNIO_SUB_STATE_IDENT_WRONG: PNIO_SUBMODULE_STATE = 0x1000;
/// A substitute.
pub const PNIO_SUB_STATE_IDENT_SUBSTITUTE: PNIO_SUBMODULE_STATE = 0x0800;
/// The submodule expected.
pub const PNIO_SUB_STATE_IDENT_OK: PNIO_SUBMODULE_STATE = 0x0000;
/// Bit 15 of a submodule state: format 1.
pub const PNIO_SUB_STATE_FORMAT_1: u32 = 0x8000;

/// `PNIO_SUB_CHECK_STATE`: `*pSubState` of `PNIO_CBF_CHECK_IND`.
pub type PNIO_SUB_CHECK_STATE = u32;
/// No submodule.
pub const PNIO_SUB_CHECK_NO_SUBMODULE: PNIO_SUB_CHECK_STATE =
    PNIO_SUB_STATE_FORMAT_1 | PNIO_SUB_STATE_IDENT_NO_SUBMODULE;
/// A wrong submodule.
pub const PNIO_SUB_CHECK_WRONG_SUBMODULE: PNIO_SUB_CHECK_STATE =
    PNIO_SUB_STATE_FORMAT_1 | PNIO_SUB_STATE_IDENT_WRONG;
/// A substitute.
pub const PNIO_SUB_CHECK_SUBSTITUTED_SUBMODULE: PNIO_SUB_CHECK_STATE =
    PNIO_SUB_STATE_FORMAT_1 | PNIO_SUB_STATE_IDENT_SUBSTITUTE;
/// The submodule expected.
pub const PNIO_SUB_CHECK_PROPER_SUBMODULE: PNIO_SUB_CHECK_STATE =
    PNIO_SUB_STATE_FORMAT_1 | PNIO_SUB_STATE_IDENT_OK;

/// `enum PNIO_SUB_PROPERTIES_ENUM_USER`: `PNIO_SUBMOD_TYPE::SubMProperties`, the type bits.
pub const CM_SUB_PROP_USER_TYPE_MASK: u32 = 0x03;
/// No IO data.
pub const CM_SUB_PROP_USER_TYPE_NO_DATA: u32 = 0x00;
/// Inputs only.
pub const CM_SUB_PROP_USER_TYPE_INPUT: u32 = 0x01;
/// Outputs only.
pub const CM_SUB_PROP_USER_TYPE_OUTPUT: u32 = 0x02;
/// Inputs and outputs.
pub const CM_SUB_PROP_USER_TYPE_INPUT_OUTPUT: u32 = 0x03;
/// Shared input.
pub const CM_SUB_PROP_USER_SHARED_INP_MASK: u32 = 0x04;
/// Input data length reduced to 0.
pub const CM_SUB_PROP_USER_REDUCE_INP_LEN_MASK: u32 = 0x08;
/// Output data length reduced to 0.
pub const CM_SUB_PROP_USER_REDUCE_OUT_LEN_MASK: u32 = 0x10;
/// IOxS length treated as 0.
pub const CM_SUB_PROP_USER_DISCARD_IOXS_MASK: u32 = 0x20;
/// The manual's name of [`CM_SUB_PROP_USER_TYPE_MASK`].
pub const PNIO_SUB_PROP_TYPE_MASK: u32 = CM_SUB_PROP_USER_TYPE_MASK;
/// The manual's name of [`CM_SUB_PROP_USER_TYPE_NO_DATA`].
pub const PNIO_SUB_PROP_TYPE_NO_DATA: u32 = CM_SUB_PROP_USER_TYPE_NO_DATA;
/// The manual's name of [`CM_SUB_PROP_USER_TYPE_INPUT`].
pub const PNIO_SUB_PROP_TYPE_INPUT: u32 = CM_SUB_PROP_USER_TYPE_INPUT;
/// The manual's name of [`CM_SUB_PROP_USER_TYPE_OUTPUT`].
pub const PNIO_SUB_PROP_TYPE_OUTPUT: u32 = CM_SUB_PROP_USER_TYPE_OUTPUT;
/// The manual's name of [`CM_SUB_PROP_USER_TYPE_INPUT_OUTPUT`].
pub const PNIO_SUB_PROP_TYPE_INPUT_OUTPUT: u32 = CM_SUB_PROP_USER_TYPE_INPUT_OUTPUT;

// ---------------------------------------------------------------------------------------
// Alarms

/// `AlarmType` of the plug functions: the submodule the PLC expects.
pub const PNIO_ALARM_TYPE_PLUG: u32 = 0x0004;
/// `AlarmType` of the plug functions: another, incompatible one.
pub const PNIO_ALARM_TYPE_PLUG_WRONG: u32 = 0x000A;

/// `AlarmState` of `PNIO_diag_alarm_send`: the diagnosis appears.
pub const PNIO_STATE_ALARM_APPEARS: u32 = 1;
/// `AlarmState` of `PNIO_diag_alarm_send`: the diagnosis disappears.
pub const PNIO_STATE_ALARM_DISAPPEARS: u32 = 2;

/// UserStructIdent: channel diagnosis.
pub const PNIO_USR_STRUC_ID_CHANNEL_DIAG: u32 = 0x8000;
/// UserStructIdent: several diagnoses (not allowed in an alarm).
pub const PNIO_USR_STRUC_ID_MULTI_MANUFAC_DIAG: u32 = 0x8001;
/// UserStructIdent: extended channel diagnosis.
pub const PNIO_USR_STRUC_ID_EXTCHANNEL_DIAG: u32 = 0x8002;

// ---------------------------------------------------------------------------------------
// Diagnosis

/// ChannelProperties.Type: the whole submodule.
pub const PNIO_DIAG_CHANPROP_TYPE_SUBMOD: u32 = 0x00;
/// ChannelProperties.Type: 1 bit.
pub const PNIO_DIAG_CHANPROP_TYPE_1BIT: u32 = 0x01;
/// ChannelProperties.Type: 2 bits.
pub const PNIO_DIAG_CHANPROP_TYPE_2BIT: u32 = 0x02;
/// ChannelProperties.Type: 4 bits.
pub const PNIO_DIAG_CHANPROP_TYPE_4BIT: u32 = 0x03;
/// ChannelProperties.Type: a byte.
pub const PNIO_DIAG_CHANPROP_TYPE_BYTE: u32 = 0x04;
/// ChannelProperties.Type: a word.
pub const PNIO_DIAG_CHANPROP_TYPE_WORD: u32 = 0x05;
/// ChannelProperties.Type: a double word.
pub const PNIO_DIAG_CHANPROP_TYPE_DWORD: u32 = 0x06;
/// ChannelProperties.Type: a long word.
pub const PNIO_DIAG_CHANPROP_TYPE_LWORD: u32 = 0x07;

/// ChannelProperties.Specifier: appears.
pub const PNIO_DIAG_CHAN_SPEC_ERROR_APPEARS: u32 = 0x0001;
/// ChannelProperties.Specifier: disappears, no other error remains.
pub const PNIO_DIAG_CHAN_SPEC_ERROR_DISAPP_FREE: u32 = 0x0002;
/// ChannelProperties.Specifier: disappears, others remain (alarms only).
pub const PNIO_DIAG_CHAN_SPEC_ERROR_DISAPP_REMAIN: u32 = 0x0003;

/// ChannelProperties.Direction: vendor specific.
pub const PNIO_DIAG_CHAN_DIRECTION_MANUFACTURE: u32 = 0x0000;
/// ChannelProperties.Direction: input.
pub const PNIO_DIAG_CHAN_DIRECTION_INPUT: u32 = 0x0001;
/// ChannelProperties.Direction: output.
pub const PNIO_DIAG_CHAN_DIRECTION_OUTPUT: u32 = 0x0002;
/// ChannelProperties.Direction: both.
pub const PNIO_DIAG_CHAN_DIRECTION_BIDIRECT: u32 = 0x0003;

/// ChannelProperties: maintenance required (bit 9).
pub const PNIO_CHAN_PROP_MAINT_REQUIRED_BIT: u32 = 0x0200;
/// ChannelProperties: maintenance demanded (bit 10).
pub const PNIO_CHAN_PROP_MAINT_DEMANDED_BIT: u32 = 0x0400;

/// The channel error types (`ChannelErrType`), name and value.
pub const PNIO_DIAG_CHAN_ERRORS: &[(&str, u32)] = &[
    ("PNIO_DIAG_CHAN_ERROR_SHORT_CIRCUIT", 0x0001),
    ("PNIO_DIAG_CHAN_ERROR_UNDERVOLTAGE", 0x0002),
    ("PNIO_DIAG_CHAN_ERROR_OVERVOLTAGE", 0x0003),
    ("PNIO_DIAG_CHAN_ERROR_OVERLOAD", 0x0004),
    ("PNIO_DIAG_CHAN_ERROR_OVERTEMPERATURE", 0x0005),
    ("PNIO_DIAG_CHAN_ERROR_LINE_BREAK", 0x0006),
    ("PNIO_DIAG_CHAN_ERROR_UPPER_LIMIT_VALUE_EXCEEDED", 0x0007),
    ("PNIO_DIAG_CHAN_ERROR_LOWER_LIMIT_VALUE_EXCEEDED", 0x0008),
    ("PNIO_DIAG_CHAN_ERROR", 0x0009),
    ("PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_PARAM", 0x0010),
    ("PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_SUPPLY", 0x0011),
    ("PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_FUSE", 0x0012),
    ("PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_MANUF", 0x0013),
    ("PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_GROUND", 0x0014),
    (
        "PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_REF_POINT",
        0x0015,
    ),
    ("PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_PROCESS", 0x0016),
    ("PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_THRES", 0x0017),
    ("PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_OUTPUT", 0x0018),
    ("PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_SAFETY", 0x0019),
    (
        "PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_EXTERNAL",
        0x001A,
    ),
    ("PNIO_DIAG_CHAN_ERROR_DATA_TRANSMISSION", 0x8000),
    ("PNIO_DIAG_CHAN_ERROR_REMOTE_MISMATCH", 0x8001),
    ("PNIO_DIAG_CHAN_ERROR_MEDIA_REDUND", 0x8002),
    ("PNIO_DIAG_CHAN_ERROR_SYNC_MISMATCH", 0x8003),
    ("PNIO_DIAG_CHAN_ERROR_ISOCH_MISMATCH", 0x8004),
    ("PNIO_DIAG_CHAN_ERROR_MULTICAST_CR", 0x8005),
    ("PNIO_DIAG_CHAN_ERROR_MULTICAST_PROV", 0x8006),
];

// ---------------------------------------------------------------------------------------
// Structs

/// The geographical address of `PNIO_DEV_ADDR::u` (an unnamed struct in C).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_DEV_ADDR_Geo {
    /// Reserved.
    pub RESERVED1: [PNIO_UINT32; 2],
    /// Slot.
    pub Slot: PNIO_UINT32,
    /// Subslot.
    pub Subslot: PNIO_UINT32,
    /// Reserved.
    pub RESERVED2: [PNIO_UINT32; 1],
}

/// `PNIO_DEV_ADDR::u`.
#[repr(C)]
#[derive(Clone, Copy)]
pub union PNIO_DEV_ADDR_u {
    /// Reserved.
    pub RESERVED: PNIO_UINT32,
    /// The geographical address.
    pub Geo: PNIO_DEV_ADDR_Geo,
}

/// `PNIO_DEV_ADDR`: a device address, always geographical.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PNIO_DEV_ADDR {
    /// `PNIO_ADDR_GEO`.
    pub AddrType: PNIO_ADDR_TYPE,
    /// `PNIO_IO_IN` or `PNIO_IO_OUT`.
    pub IODataType: PNIO_IO_TYPE,
    /// The slot and subslot.
    pub u: PNIO_DEV_ADDR_u,
}

impl PNIO_DEV_ADDR {
    /// The geographical address of slot and subslot, for data of `IODataType`.
    pub fn geo(IODataType: PNIO_IO_TYPE, Slot: u32, Subslot: u32) -> PNIO_DEV_ADDR {
        PNIO_DEV_ADDR {
            AddrType: PNIO_ADDR_GEO,
            IODataType,
            u: PNIO_DEV_ADDR_u {
                Geo: PNIO_DEV_ADDR_Geo {
                    Slot,
                    Subslot,
                    ..PNIO_DEV_ADDR_Geo::default()
                },
            },
        }
    }

    /// The geographical address (`u.Geo`).
    pub fn geo_addr(&self) -> PNIO_DEV_ADDR_Geo {
        // SAFETY: every bit pattern is a valid `PNIO_DEV_ADDR_Geo`, and `Geo` spans the whole
        // union, all of it initialised (built by `geo` or read from C memory of its size).
        unsafe { self.u.Geo }
    }
}

impl core::fmt::Debug for PNIO_DEV_ADDR {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let geo = self.geo_addr();
        f.debug_struct("PNIO_DEV_ADDR")
            .field("AddrType", &self.AddrType)
            .field("IODataType", &self.IODataType)
            .field("Slot", &geo.Slot)
            .field("Subslot", &geo.Subslot)
            .finish()
    }
}

/// `PNIO_ANNOTATION`: what the PLC's engineering shows of the device.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PNIO_ANNOTATION {
    /// ProductFamily, NUL-terminated.
    pub deviceType: [PNIO_UINT8; MAX_DEVICE_TYPE_LENGTH as usize + 1],
    /// OrderNumber, NUL-terminated.
    pub orderId: [PNIO_UINT8; MAX_ORDER_ID_LENGTH as usize + 1],
    /// HardwareRelease.
    pub hwRevision: PNIO_UINT16,
    /// The prefix of SoftwareRelease (`'V'` of "V1.2.3").
    pub swRevisionPrefix: PNIO_UINT8,
    /// The first number of SoftwareRelease.
    pub swRevision1: PNIO_UINT16,
    /// The second.
    pub swRevision2: PNIO_UINT16,
    /// The third.
    pub swRevision3: PNIO_UINT16,
}

/// `PNIO_UUID_TYPE`: a UUID, passed by value.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_UUID_TYPE {
    /// time_low.
    pub TimeLow: PNIO_UINT32,
    /// time_mid.
    pub TimeMid: PNIO_UINT16,
    /// time_hi_and_version.
    pub TimeHiAndVersion: PNIO_UINT16,
    /// clock_seq_hi_and_reserved.
    pub ClockSeqHiAndReserved: PNIO_UINT8,
    /// clock_seq_low.
    pub ClockSeqLow: PNIO_UINT8,
    /// node.
    pub Node: [PNIO_UINT8; 6],
}

/// `PNIO_IOCS_TYPE`: a submodule in an IOCR.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_IOCS_TYPE {
    /// Slot.
    pub SlotNum: PNIO_UINT32,
    /// Subslot.
    pub SubslotNum: PNIO_UINT32,
    /// Reserved.
    pub reserved: PNIO_UINT32,
}

/// `PNIO_IOCR_TYPE`: one input or output frame of an AR.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_IOCR_TYPE {
    /// SendClock × 31.25 µs × ReductioFactor.
    pub CycleTime: PNIO_UINT32,
    /// `PNIO_IOCR_TYPE_*`.
    pub Direction: PNIO_IOCR_TYPE_ENUM,
    /// `PNIO_IOCR_PROP_*`.
    pub IOCRProperties: PNIO_IOCR_PROP_ENUM,
    /// Send clock in 31.25 µs units.
    pub SendClock: PNIO_UINT32,
    /// Sent every ReductioFactor send clocks.
    pub ReductioFactor: PNIO_UINT32,
    /// Phase.
    pub Phase: PNIO_UINT32,
    /// Elements of `pIoCsList`.
    pub NumOfIoCs: PNIO_UINT32,
    /// The submodules in this frame.
    pub pIoCsList: *mut PNIO_IOCS_TYPE,
    /// Reserved.
    pub reserved: [PNIO_UINT32; 3],
}

/// `PNIO_SUBMOD_TYPE`: a submodule of an AR.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_SUBMOD_TYPE {
    /// Slot.
    pub SlotNum: PNIO_UINT32,
    /// Subslot.
    pub SubSlotNum: PNIO_UINT32,
    /// `PNIO_SUB_PROP_TYPE_*` under `PNIO_SUB_PROP_TYPE_MASK`.
    pub SubMProperties: PNIO_UINT32,
    /// SubmoduleIdentNumber.
    pub SubMIdent: PNIO_UINT32,
    /// Input data bytes (the device sends).
    pub InDatLen: PNIO_UINT32,
    /// Bytes of the device's IOPS of the inputs.
    pub InIopsLen: PNIO_UINT32,
    /// Bytes of the PLC's IOCS of the inputs.
    pub InIocsLen: PNIO_UINT32,
    /// Output data bytes (the device receives).
    pub OutDatLen: PNIO_UINT32,
    /// Bytes of the PLC's IOPS of the outputs.
    pub OutIopsLen: PNIO_UINT32,
    /// Bytes of the device's IOCS of the outputs.
    pub OutIocsLen: PNIO_UINT32,
    /// Reserved.
    pub reserved: [PNIO_UINT32; 8],
}

/// `PNIO_MODULE_TYPE`: a module of an AR. C also names `Api` as the manual does, `API`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_MODULE_TYPE {
    /// API.
    pub Api: PNIO_UINT32,
    /// Slot.
    pub SlotNum: PNIO_UINT32,
    /// Elements of `pSubList`.
    pub NumOfSubmod: PNIO_UINT32,
    /// Reserved, 0.
    pub ModProperties: PNIO_UINT32,
    /// ModuleIdentNumber.
    pub ModIdent: PNIO_UINT32,
    /// Its submodules.
    pub pSubList: *mut PNIO_SUBMOD_TYPE,
}

/// `PNIO_AR_TYPE`: an AR. C also names `pNextAr` as the manual does, `pReserved`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_AR_TYPE {
    /// Don't care.
    pub pNextAr: *mut c_void,
    /// The AR's number.
    pub ArNumber: PNIO_UINT16,
    /// Grows with every AR.
    pub SessionKey: PNIO_UINT16,
    /// Elements of `pIoCrList`.
    pub NumOfIocr: PNIO_UINT32,
    /// Its IOCRs.
    pub pIoCrList: *mut PNIO_IOCR_TYPE,
    /// Elements of `pModList`.
    pub NumOfMod: PNIO_UINT32,
    /// Its modules.
    pub pModList: *mut PNIO_MODULE_TYPE,
}

/// `PNIO_LIST_ENTRY_TYPE`: a link of a doubly linked list; a head whose `Flink` is NULL or
/// the head itself is an empty list.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_LIST_ENTRY_TYPE {
    /// Next.
    pub Flink: *mut PNIO_LIST_ENTRY_TYPE,
    /// Previous.
    pub Blink: *mut PNIO_LIST_ENTRY_TYPE,
}

/// `PNIO_APPL_READY_LIST_TYPE`: the submodules that are not ready.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_APPL_READY_LIST_TYPE {
    /// Of `PNIO_APPL_READY_AP_TYPE`.
    pub ap_list: PNIO_LIST_ENTRY_TYPE,
}

/// `PNIO_APPL_READY_AP_TYPE`: an API of that list.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_APPL_READY_AP_TYPE {
    /// The list entry (first: a pointer to it is one to the element).
    pub link: PNIO_LIST_ENTRY_TYPE,
    /// API.
    pub api: PNIO_UINT32,
    /// Of `PNIO_APPL_READY_MODULE_TYPE`.
    pub module_list: PNIO_LIST_ENTRY_TYPE,
}

/// `PNIO_APPL_READY_MODULE_TYPE`: a slot of that list.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_APPL_READY_MODULE_TYPE {
    /// The list entry.
    pub link: PNIO_LIST_ENTRY_TYPE,
    /// Slot.
    pub slot_nr: PNIO_UINT16,
    /// Of `PNIO_APPL_READY_SUBMODULE_TYPE`.
    pub submodule_list: PNIO_LIST_ENTRY_TYPE,
}

/// `PNIO_APPL_READY_SUBMODULE_TYPE`: a subslot of that list.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_APPL_READY_SUBMODULE_TYPE {
    /// The list entry.
    pub link: PNIO_LIST_ENTRY_TYPE,
    /// Subslot.
    pub subslot_nr: PNIO_UINT16,
}

/// `PNIO_BLOCK_HEADER`: the header of an I&M record, a plain struct of 6 bytes (not
/// `ATTR_PACKED`, so that the records keep their wire layout).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_BLOCK_HEADER {
    /// 0x0020 + n for I&Mn.
    pub BlockType: PNIO_UINT16,
    /// Bytes after BlockType and BlockLength.
    pub BlockLength: PNIO_UINT16,
    /// 1.
    pub BlockVersionHigh: PNIO_UINT8,
    /// 0.
    pub BlockVersionLow: PNIO_UINT8,
}

/// `PNIO_IM0_TYPE`: I&M0 (record 0xAFF0); 16-bit fields big-endian.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_IM0_TYPE {
    /// BlockType 0x0020.
    pub BlockHeader: PNIO_BLOCK_HEADER,
    /// VendorID, high byte.
    pub VendorIDHigh: PNIO_UINT8,
    /// VendorID, low byte.
    pub VendorIDLow: PNIO_UINT8,
    /// Order number, blank-padded.
    pub OrderID: [PNIO_UINT8; 20],
    /// Serial number, blank-padded.
    pub IM_Serial_Number: [PNIO_UINT8; 16],
    /// Hardware revision.
    pub IM_Hardware_Revision: PNIO_UINT16,
    /// Prefix, functional, bug fix, internal.
    pub IM_Software_Revision: [PNIO_UINT8; 4],
    /// Revision counter (after 0xFFFF comes 1).
    pub IM_Revision_Counter: PNIO_UINT16,
    /// Profile (0xF600: generic device).
    pub IM_Profile_ID: PNIO_UINT16,
    /// Profile specific type.
    pub IM_Profile_Specific_Type: PNIO_UINT16,
    /// 1.
    pub IM_Version_Major: PNIO_UINT8,
    /// 1.
    pub IM_Version_Minor: PNIO_UINT8,
    /// Bit n: I&Mn supported.
    pub IM_Supported: PNIO_UINT16,
}

/// `PNIO_IM1_TYPE`: I&M1 (record 0xAFF1).
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PNIO_IM1_TYPE {
    /// BlockType 0x0021.
    pub BlockHeader: PNIO_BLOCK_HEADER,
    /// Tag function.
    pub IM_Tag_Function: [PNIO_UINT8; 32],
    /// Tag location.
    pub IM_Tag_Location: [PNIO_UINT8; 22],
}

/// `PNIO_IM2_TYPE`: I&M2 (record 0xAFF2).
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_IM2_TYPE {
    /// BlockType 0x0022.
    pub BlockHeader: PNIO_BLOCK_HEADER,
    /// "YYYY-MM-DD hh:mm".
    pub IM_Date: [PNIO_UINT8; 16],
}

/// `PNIO_IM3_TYPE`: I&M3 (record 0xAFF3).
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PNIO_IM3_TYPE {
    /// BlockType 0x0023.
    pub BlockHeader: PNIO_BLOCK_HEADER,
    /// Descriptor.
    pub IM_Descriptor: [PNIO_UINT8; 54],
}

/// `PNIO_IM4_TYPE`: I&M4 (record 0xAFF4).
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PNIO_IM4_TYPE {
    /// BlockType 0x0024.
    pub BlockHeader: PNIO_BLOCK_HEADER,
    /// Signature.
    pub IM_Signature: [PNIO_UINT8; 54],
}

// ---------------------------------------------------------------------------------------
// Signatures

/// A C type in a signature: as the header spells it, with the size of its Rust mirror.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CType {
    /// The C spelling, e.g. `"PNIO_DEV_ADDR *"`.
    pub c: &'static str,
    /// The size of the Rust type (0 for `void`).
    pub size: usize,
}

/// A function or callback type of `pniousrd.h`.
#[derive(Clone, Copy, Debug)]
pub struct CSignature {
    /// The function's or the typedef's name.
    pub name: &'static str,
    /// The result.
    pub result: CType,
    /// The parameters, name and type.
    pub params: &'static [(&'static str, CType)],
}

impl CSignature {
    /// The C pointer type, e.g. `PNIO_UINT32 (*)(PNIO_UINT32, PNIO_DEV_ADDR *)`.
    pub fn c_pointer_type(&self) -> String {
        let params: Vec<&str> = self.params.iter().map(|(_, t)| t.c).collect();
        format!("{} (*)({})", self.result.c, params.join(", "))
    }
}

/// The result of a signature: `void` without a type.
macro_rules! c_result {
    () => {
        CType { c: "void", size: 0 }
    };
    ($r:ty => $rc:literal) => {
        CType {
            c: $rc,
            size: size_of::<$r>(),
        }
    };
}

/// One `CSignature` from a declaration `name(param: RustType => "C type", …) -> …`.
macro_rules! c_signature {
    ($name:ident($($p:ident: $t:ty => $c:literal),*) $($r:ty => $rc:literal)?) => {
        CSignature {
            name: stringify!($name),
            result: c_result!($($r => $rc)?),
            params: &[$((stringify!($p), CType { c: $c, size: size_of::<$t>() })),*],
        }
    };
}

/// The callback typedefs: an `Option<unsafe extern "C" fn>` alias each, and
/// [`DEVICE_CALLBACKS`].
macro_rules! callbacks {
    ($(
        $(#[$m:meta])*
        $name:ident($($p:ident: $t:ty => $c:literal),* $(,)?) $(-> $r:ty => $rc:literal)?;
    )*) => {
        $(
            $(#[$m])*
            pub type $name = Option<unsafe extern "C" fn($($p: $t),*) $(-> $r)?>;
        )*

        /// Every callback typedef of `pniousrd.h`, as C spells it.
        pub const DEVICE_CALLBACKS: &[CSignature] =
            &[$(c_signature!($name($($p: $t => $c),*) $($r => $rc)?)),*];
    };
}

/// The functions: an `unsafe extern "C" fn` alias each in [`prototypes`], and
/// [`DEVICE_FUNCTIONS`].
macro_rules! functions {
    ($(
        $(#[$m:meta])*
        $name:ident($($p:ident: $t:ty => $c:literal),* $(,)?) -> $r:ty => $rc:literal;
    )*) => {
        /// The type of each function of `pniousrd.h`, named as the function: what its
        /// implementation (`#[unsafe(no_mangle)] pub unsafe extern "C" fn`) must coerce to.
        pub mod prototypes {
            #[allow(clippy::wildcard_imports)]
            use super::*;
            $(
                $(#[$m])*
                pub type $name = unsafe extern "C" fn($($p: $t),*) -> $r;
            )*
        }

        /// Every function of `pniousrd.h`, as C spells it.
        pub const DEVICE_FUNCTIONS: &[CSignature] =
            &[$(c_signature!($name($($p: $t => $c),*) $r => $rc)),*];
    };
}

callbacks! {
    /// `PNIO_CBF_DATA_WRITE`: copy the inputs of a submodule into `pBuffer`; returns the IOPS.
    PNIO_CBF_DATA_WRITE(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        BufLen: PNIO_UINT32 => "PNIO_UINT32",
        pBuffer: *mut PNIO_UINT8 => "PNIO_UINT8 *",
        IOremState: PNIO_IOXS => "PNIO_IOXS",
    ) -> PNIO_IOXS => "PNIO_IOXS";
    /// `PNIO_CBF_DATA_READ`: take the outputs of a submodule from `pBuffer`; returns the IOCS.
    PNIO_CBF_DATA_READ(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        BufLen: PNIO_UINT32 => "PNIO_UINT32",
        pBuffer: *mut PNIO_UINT8 => "PNIO_UINT8 *",
        IOremState: PNIO_IOXS => "PNIO_IOXS",
    ) -> PNIO_IOXS => "PNIO_IOXS";
    /// `PNIO_CBF_REC_READ`: a record read.
    PNIO_CBF_REC_READ(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
        SequenceNum: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        RecordIndex: PNIO_UINT32 => "PNIO_UINT32",
        pBufLen: *mut PNIO_UINT32 => "PNIO_UINT32 *",
        pBuffer: *mut PNIO_UINT8 => "PNIO_UINT8 *",
        pPnioState: *mut PNIO_ERR_STAT => "PNIO_ERR_STAT *",
    );
    /// `PNIO_CBF_REC_WRITE`: a record write.
    PNIO_CBF_REC_WRITE(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
        SequenceNum: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        RecordIndex: PNIO_UINT32 => "PNIO_UINT32",
        pBufLen: *mut PNIO_UINT32 => "PNIO_UINT32 *",
        pBuffer: *mut PNIO_UINT8 => "PNIO_UINT8 *",
        pPnioState: *mut PNIO_ERR_STAT => "PNIO_ERR_STAT *",
    );
    /// `PNIO_CBF_REQ_DONE`: the PLC acknowledged an alarm.
    PNIO_CBF_REQ_DONE(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        UserHndl: PNIO_UINT32 => "PNIO_UINT32",
        Status: PNIO_UINT32 => "PNIO_UINT32",
        pPnioState: *mut PNIO_ERR_STAT => "PNIO_ERR_STAT *",
    );
    /// `PNIO_CBF_CHECK_IND`: the PLC expects something else at `pAddr`.
    PNIO_CBF_CHECK_IND(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        pModIdent: *mut PNIO_UINT32 => "PNIO_UINT32 *",
        pModState: *mut PNIO_UINT16 => "PNIO_UINT16 *",
        pSubIdent: *mut PNIO_UINT32 => "PNIO_UINT32 *",
        pSubState: *mut PNIO_UINT16 => "PNIO_UINT16 *",
    );
    /// `PNIO_CBF_AR_CHECK_IND`: a PLC connects (the UUIDs by value).
    PNIO_CBF_AR_CHECK_IND(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        HostIp: PNIO_UINT32 => "PNIO_UINT32",
        ArType: PNIO_UINT16 => "PNIO_UINT16",
        ArUUID: PNIO_UUID_TYPE => "PNIO_UUID_TYPE",
        ArProperties: PNIO_UINT32 => "PNIO_UINT32",
        CmiObjUUID: PNIO_UUID_TYPE => "PNIO_UUID_TYPE",
        CmiStationNameLength: PNIO_UINT16 => "PNIO_UINT16",
        pCmiStationName: *mut PNIO_UINT8 => "PNIO_UINT8 *",
        pAr: *mut PNIO_AR_TYPE => "PNIO_AR_TYPE *",
    );
    /// `PNIO_CBF_AR_INFO_IND`: the AR's IOCRs, modules and submodules.
    PNIO_CBF_AR_INFO_IND(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
        pAR: *mut PNIO_AR_TYPE => "PNIO_AR_TYPE *",
    );
    /// `PNIO_CBF_AR_INDATA_IND`: cyclic data exchange began.
    PNIO_CBF_AR_INDATA_IND(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
    );
    /// `PNIO_CBF_AR_ABORT_IND`: the AR ended before data exchange.
    PNIO_CBF_AR_ABORT_IND(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
        ReasonCode: PNIO_AR_REASON => "PNIO_AR_REASON",
    );
    /// `PNIO_CBF_AR_OFFLINE_IND`: the AR ended after data exchange had begun.
    PNIO_CBF_AR_OFFLINE_IND(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
        ReasonCode: PNIO_AR_REASON => "PNIO_AR_REASON",
    );
    /// `PNIO_CBF_APDU_STATUS_IND`: the PLC's state changed.
    PNIO_CBF_APDU_STATUS_IND(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
        ApduStatus: PNIO_APDU_STATUS_IND => "PNIO_APDU_STATUS_IND",
    );
    /// `PNIO_CBF_PRM_END_IND`: the PLC ended parameterising (16-bit slot and subslot, as in
    /// IO-Base's header; the manual says 32).
    PNIO_CBF_PRM_END_IND(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        SlotNum: PNIO_UINT16 => "PNIO_UINT16",
        SubslotNum: PNIO_UINT16 => "PNIO_UINT16",
    );
    /// `PNIO_CBF_CP_STOP_REQ`: a remote download asks the program to close the device.
    PNIO_CBF_CP_STOP_REQ(DevHndl: PNIO_UINT32 => "PNIO_UINT32");
    /// `PNIO_CBF_DEVICE_STOPPED`: `PNIO_device_stop` finished.
    PNIO_CBF_DEVICE_STOPPED(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        ErrorCode: PNIO_UINT32 => "PNIO_UINT32",
    );
    /// `PNIO_CBF_START_LED_FLASH`: flash at `Frequency` Hz.
    PNIO_CBF_START_LED_FLASH(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Frequency: PNIO_UINT32 => "PNIO_UINT32",
    );
    /// `PNIO_CBF_STOP_LED_FLASH`: stop flashing.
    PNIO_CBF_STOP_LED_FLASH(DevHndl: PNIO_UINT32 => "PNIO_UINT32");
    /// `PNIO_CBF_PULL_PLUG_CONF`: a plug or pull finished (void and `PNIO_DEV_ACTION`, as in
    /// IO-Base's header).
    PNIO_CBF_PULL_PLUG_CONF(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        Action: PNIO_DEV_ACTION => "PNIO_DEV_ACTION",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        ErrorCode: PNIO_UINT32 => "PNIO_UINT32",
    );
}

/// `PNIO_CBF_FUNCTIONS` (the manual's `PNIO_CFB_FUNCTIONS`): the callbacks given to
/// `PNIO_device_open`. C also names `cbf_cp_stop_req` and `cbf_device_stopped` as the manual
/// does, `pnio_cbf_cp_stop_req` and `pnio_cbf_device_stopped`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct PNIO_CBF_FUNCTIONS {
    /// `sizeof(PNIO_CBF_FUNCTIONS)`: the version of the table.
    pub size: PNIO_UINT32,
    /// Mandatory.
    pub cbf_data_write: PNIO_CBF_DATA_WRITE,
    /// Mandatory.
    pub cbf_data_read: PNIO_CBF_DATA_READ,
    /// Mandatory.
    pub cbf_rec_read: PNIO_CBF_REC_READ,
    /// Mandatory.
    pub cbf_rec_write: PNIO_CBF_REC_WRITE,
    /// Mandatory.
    pub cbf_alarm_done: PNIO_CBF_REQ_DONE,
    /// Mandatory.
    pub cbf_check_ind: PNIO_CBF_CHECK_IND,
    /// Mandatory.
    pub cbf_ar_check_ind: PNIO_CBF_AR_CHECK_IND,
    /// Mandatory.
    pub cbf_ar_info_ind: PNIO_CBF_AR_INFO_IND,
    /// Mandatory.
    pub cbf_ar_indata_ind: PNIO_CBF_AR_INDATA_IND,
    /// Mandatory.
    pub cbf_ar_abort_ind: PNIO_CBF_AR_ABORT_IND,
    /// Mandatory.
    pub cbf_ar_offline_ind: PNIO_CBF_AR_OFFLINE_IND,
    /// Mandatory.
    pub cbf_apdu_status_ind: PNIO_CBF_APDU_STATUS_IND,
    /// Mandatory.
    pub cbf_prm_end_ind: PNIO_CBF_PRM_END_IND,
    /// Mandatory.
    pub cbf_cp_stop_req: PNIO_CBF_CP_STOP_REQ,
    /// Mandatory.
    pub cbf_device_stopped: PNIO_CBF_DEVICE_STOPPED,
    /// Optional.
    pub cbf_start_led_flash: PNIO_CBF_START_LED_FLASH,
    /// Optional.
    pub cbf_stop_led_flash: PNIO_CBF_STOP_LED_FLASH,
    /// Optional; needed to plug and pull after `PNIO_device_start`.
    pub cbf_pull_plug_conf: PNIO_CBF_PULL_PLUG_CONF,
}

/// The manual's name of [`PNIO_CBF_FUNCTIONS`].
pub type PNIO_CFB_FUNCTIONS = PNIO_CBF_FUNCTIONS;

functions! {
    /// `PNIO_device_open`: opens the device and registers its callbacks.
    PNIO_device_open(
        CpIndex: PNIO_UINT32 => "PNIO_UINT32",
        ExtPar: PNIO_UINT32 => "PNIO_UINT32",
        VendorId: PNIO_UINT16 => "PNIO_UINT16",
        DeviceId: PNIO_UINT16 => "PNIO_UINT16",
        InstanceId: PNIO_UINT16 => "PNIO_UINT16",
        MaxAr: PNIO_UINT32 => "PNIO_UINT32",
        pDevAnnotation: *mut PNIO_ANNOTATION => "PNIO_ANNOTATION *",
        pCbf: *mut PNIO_CBF_FUNCTIONS => "PNIO_CBF_FUNCTIONS *",
        pDevHndl: *mut PNIO_UINT32 => "PNIO_UINT32 *",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_device_open_ext`: with the highest slot and subslot numbers.
    PNIO_device_open_ext(
        CpIndex: PNIO_UINT32 => "PNIO_UINT32",
        ExtPar: PNIO_UINT32 => "PNIO_UINT32",
        VendorId: PNIO_UINT16 => "PNIO_UINT16",
        DeviceId: PNIO_UINT16 => "PNIO_UINT16",
        InstanceId: PNIO_UINT16 => "PNIO_UINT16",
        MaxAr: PNIO_UINT32 => "PNIO_UINT32",
        pDevAnnotation: *mut PNIO_ANNOTATION => "PNIO_ANNOTATION *",
        pCbf: *mut PNIO_CBF_FUNCTIONS => "PNIO_CBF_FUNCTIONS *",
        highSlotNum: PNIO_UINT16 => "PNIO_UINT16",
        highSubslotNum: PNIO_UINT16 => "PNIO_UINT16",
        pDevHndl: *mut PNIO_UINT32 => "PNIO_UINT32 *",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_device_close`.
    PNIO_device_close(DevHndl: PNIO_UINT32 => "PNIO_UINT32") -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_device_start`.
    PNIO_device_start(DevHndl: PNIO_UINT32 => "PNIO_UINT32") -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_device_stop`.
    PNIO_device_stop(DevHndl: PNIO_UINT32 => "PNIO_UINT32") -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_set_dev_state`.
    PNIO_set_dev_state(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        DevState: PNIO_UINT32 => "PNIO_UINT32",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_api_add`.
    PNIO_api_add(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        MaxSlots: PNIO_UINT16 => "PNIO_UINT16",
        MaxSubslots: PNIO_UINT16 => "PNIO_UINT16",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_api_add_ext`.
    PNIO_api_add_ext(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_api_remove`.
    PNIO_api_remove(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_mod_plug`.
    PNIO_mod_plug(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        ModIdent: PNIO_UINT32 => "PNIO_UINT32",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_mod_pull`.
    PNIO_mod_pull(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_sub_plug` (deprecated).
    PNIO_sub_plug(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        SubIdent: PNIO_UINT32 => "PNIO_UINT32",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_sub_plug_ext` (deprecated).
    PNIO_sub_plug_ext(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        SubIdent: PNIO_UINT32 => "PNIO_UINT32",
        AlarmType: PNIO_UINT32 => "PNIO_UINT32",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_sub_plug_ext_IM`.
    PNIO_sub_plug_ext_IM(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        SubIdent: PNIO_UINT32 => "PNIO_UINT32",
        AlarmType: PNIO_UINT32 => "PNIO_UINT32",
        IM0_bits: PNIO_PLUG_IM0_BITS => "PNIO_PLUG_IM0_BITS",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_sub_pull`.
    PNIO_sub_pull(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_initiate_data_write`.
    PNIO_initiate_data_write(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_initiate_data_write_ext`.
    PNIO_initiate_data_write_ext(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        AccessType: PNIO_ACCESS_ENUM => "PNIO_ACCESS_ENUM",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_initiate_data_read`.
    PNIO_initiate_data_read(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_initiate_data_read_ext`.
    PNIO_initiate_data_read_ext(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        AccessType: PNIO_ACCESS_ENUM => "PNIO_ACCESS_ENUM",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_set_appl_state_ready`.
    PNIO_set_appl_state_ready(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
        pList: *mut PNIO_APPL_READY_LIST_TYPE => "PNIO_APPL_READY_LIST_TYPE *",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_device_ar_abort`.
    PNIO_device_ar_abort(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_build_channel_properties`: returns the ChannelProperties word.
    PNIO_build_channel_properties(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Type: PNIO_UINT16 => "PNIO_UINT16",
        Spec: PNIO_UINT16 => "PNIO_UINT16",
        Dir: PNIO_UINT16 => "PNIO_UINT16",
    ) -> PNIO_UINT16 => "PNIO_UINT16";
    /// `PNIO_diag_channel_add`.
    PNIO_diag_channel_add(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        ChannelNum: PNIO_UINT16 => "PNIO_UINT16",
        ChannelProp: PNIO_UINT16 => "PNIO_UINT16",
        ChannelErrType: PNIO_UINT32 => "PNIO_UINT32",
        DiagTag: PNIO_UINT16 => "PNIO_UINT16",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_diag_channel_remove`.
    PNIO_diag_channel_remove(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        DiagTag: PNIO_UINT16 => "PNIO_UINT16",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_diag_ext_channel_add` (its `ChannelErrType` is 16 bits).
    PNIO_diag_ext_channel_add(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        ChannelNum: PNIO_UINT16 => "PNIO_UINT16",
        ChannelProp: PNIO_UINT16 => "PNIO_UINT16",
        ChannelErrType: PNIO_UINT16 => "PNIO_UINT16",
        ExtChannelErrType: PNIO_UINT16 => "PNIO_UINT16",
        ExtChannelAddValue: PNIO_UINT32 => "PNIO_UINT32",
        DiagTag: PNIO_UINT16 => "PNIO_UINT16",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_diag_ext_channel_remove`.
    PNIO_diag_ext_channel_remove(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        DiagTag: PNIO_UINT16 => "PNIO_UINT16",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_diag_generic_add`.
    PNIO_diag_generic_add(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        ChannelNum: PNIO_UINT16 => "PNIO_UINT16",
        ChannelProp: PNIO_UINT16 => "PNIO_UINT16",
        DiagTag: PNIO_UINT16 => "PNIO_UINT16",
        UserStructIdent: PNIO_UINT16 => "PNIO_UINT16",
        pInfoData: *mut PNIO_UINT8 => "PNIO_UINT8 *",
        InfoDataLen: PNIO_UINT32 => "PNIO_UINT32",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_diag_generic_remove`.
    PNIO_diag_generic_remove(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        DiagTag: PNIO_UINT16 => "PNIO_UINT16",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_process_alarm_send`.
    PNIO_process_alarm_send(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        pData: *mut PNIO_UINT8 => "PNIO_UINT8 *",
        DataLen: PNIO_UINT32 => "PNIO_UINT32",
        UserStructIdent: PNIO_UINT16 => "PNIO_UINT16",
        UserHndl: PNIO_UINT32 => "PNIO_UINT32",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_diag_alarm_send`.
    PNIO_diag_alarm_send(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
        AlarmState: PNIO_UINT32 => "PNIO_UINT32",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        pData: *mut PNIO_UINT8 => "PNIO_UINT8 *",
        DataLen: PNIO_UINT32 => "PNIO_UINT32",
        UserStructIdent: PNIO_UINT16 => "PNIO_UINT16",
        UserHndl: PNIO_UINT32 => "PNIO_UINT32",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
    /// `PNIO_ret_of_sub_alarm_send`.
    PNIO_ret_of_sub_alarm_send(
        DevHndl: PNIO_UINT32 => "PNIO_UINT32",
        Api: PNIO_UINT32 => "PNIO_UINT32",
        ArNumber: PNIO_UINT16 => "PNIO_UINT16",
        SessionKey: PNIO_UINT16 => "PNIO_UINT16",
        pAddr: *mut PNIO_DEV_ADDR => "PNIO_DEV_ADDR *",
        UserHndl: PNIO_UINT32 => "PNIO_UINT32",
    ) -> PNIO_UINT32 => "PNIO_UINT32";
}
