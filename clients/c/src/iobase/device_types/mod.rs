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

mod signatures;
mod structs;

pub use signatures::*;
pub use structs::*;

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
