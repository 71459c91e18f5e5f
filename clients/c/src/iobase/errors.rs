// SPDX-License-Identifier: MIT OR Apache-2.0
//! The return codes of `pnioerrx.h`: `PNIO_OK`, the warnings `PNIO_WARN_*` and the errors
//! `PNIO_ERR_*`, with the values of the 2015 headers; and how an API function records why it failed.

/// Success.
pub const PNIO_OK: u32 = 0x000;
/// PROFIenergy: the device woke up online.
pub const PNIO_OK_PE_WAKE_ONLINE: u32 = 0x001;
/// PROFIenergy: the device woke up offline.
pub const PNIO_OK_PE_WAKE_OFFLINE: u32 = 0x002;

/// IRT data accessed outside the STARTOP..OPDONE window: it may be inconsistent.
pub const PNIO_WARN_IRT_INCONSISTENT: u32 = 0x010;
/// No submodules.
pub const PNIO_WARN_NO_SUBMODULES: u32 = 0x011;
/// The local state is BAD.
pub const PNIO_WARN_LOCAL_STATE_BAD: u32 = 0x012;
/// PN Driver: the configuration has no IO system of its own.
pub const PNIO_WARN_NO_DECENTRALIOSYSTEM: u32 = 0x013;

/// The handle pointer is NULL.
pub const PNIO_ERR_PRM_HND: u32 = 0x101;
/// The buffer pointer is NULL (or its length 0).
pub const PNIO_ERR_PRM_BUF: u32 = 0x102;
/// The length pointer is NULL.
pub const PNIO_ERR_PRM_LEN: u32 = 0x103;
/// The address is invalid.
pub const PNIO_ERR_PRM_ADD: u32 = 0x104;
/// The remote-state pointer is NULL.
pub const PNIO_ERR_PRM_RSTATE: u32 = 0x105;
/// The callback is invalid.
pub const PNIO_ERR_PRM_CALLBACK: u32 = 0x106;
/// The event type is invalid.
pub const PNIO_ERR_PRM_TYPE: u32 = 0x107;
/// ExtPar is invalid.
pub const PNIO_ERR_PRM_EXT_PAR: u32 = 0x108;
/// The IO data type does not fit the function.
pub const PNIO_ERR_PRM_IO_TYPE: u32 = 0x109;
/// The CpIndex is invalid.
pub const PNIO_ERR_PRM_CP_ID: u32 = 0x10A;
/// The local state is invalid.
pub const PNIO_ERR_PRM_LOC_STATE: u32 = 0x10B;
/// The record index is invalid.
pub const PNIO_ERR_PRM_REC_INDEX: u32 = 0x10C;
/// The timeout is invalid.
pub const PNIO_ERR_PRM_TIMEOUT: u32 = 0x10D;
/// The device annotation is invalid.
pub const PNIO_ERR_PRM_DEV_ANNOTATION: u32 = 0x10E;
/// The device state is invalid.
pub const PNIO_ERR_PRM_DEV_STATE: u32 = 0x10F;
/// The callback pointer is invalid.
pub const PNIO_ERR_PRM_PCBF: u32 = 0x110;
/// The max AR value is invalid.
pub const PNIO_ERR_PRM_MAX_AR_VALUE: u32 = 0x111;
/// The access type is invalid.
pub const PNIO_ERR_PRM_ACCESS_TYPE: u32 = 0x112;
/// A pointer is invalid.
pub const PNIO_ERR_PRM_POINTER: u32 = 0x113;
/// An argument is invalid.
pub const PNIO_ERR_PRM_INVALIDARG: u32 = 0x114;
/// The measurement number is invalid.
pub const PNIO_ERR_PRM_MEASURE_NUMBER: u32 = 0x115;
/// The cycle offset is invalid.
pub const PNIO_ERR_PRM_CYCLE_OFFSET: u32 = 0x116;
/// The router address is invalid.
pub const PNIO_ERR_PRM_ROUTER_ADD: u32 = 0x117;
/// PN Driver: the IP suite is invalid.
pub const PNIO_ERR_PRM_IP: u32 = 0x118;
/// PN Driver: the NameOfStation is invalid.
pub const PNIO_ERR_PRM_NOS: u32 = 0x119;
/// PN Driver: the NameOfStation is too long.
pub const PNIO_ERR_PRM_NOS_LEN: u32 = 0x11A;

/// The handle is unknown or closed.
pub const PNIO_ERR_WRONG_HND: u32 = 0x201;
/// No more instances.
pub const PNIO_ERR_MAX_REACHED: u32 = 0x202;
/// The instance could not be created.
pub const PNIO_ERR_CREATE_INSTANCE: u32 = 0x203;
/// Not allowed in the current mode, or the mode value is invalid.
pub const PNIO_ERR_MODE_VALUE: u32 = 0x204;
/// STARTOP registered before OPFAULT.
pub const PNIO_ERR_OPFAULT_NOT_REG: u32 = 0x205;
/// NEWCYCLE registered in the wrong order.
pub const PNIO_ERR_NEWCYCLE_SEQUENCE_REG: u32 = 0x206;
/// The network protocol is not available.
pub const PNIO_ERR_NETWORK_PROT_NOT_AVAILABLE: u32 = 0x207;
/// PN Driver: the stack is not available yet; try again later.
pub const PNIO_ERR_RETRY: u32 = 0x208;

/// No connection to the device (or the server).
pub const PNIO_ERR_NO_CONNECTION: u32 = 0x301;
/// An operating-system resource failed.
pub const PNIO_ERR_OS_RES: u32 = 0x302;
/// Already done (registered before).
pub const PNIO_ERR_ALREADY_DONE: u32 = 0x303;
/// The manual's spelling of [`PNIO_ERR_ALREADY_DONE`].
pub const PNIO_ERR_ALLREADY_DONE: u32 = PNIO_ERR_ALREADY_DONE;
/// No configuration (no server for this CP).
pub const PNIO_ERR_NO_CONFIG: u32 = 0x304;
/// `PNIO_set_mode` is not allowed (open without `PNIO_CEP_MODE_CTRL`).
pub const PNIO_ERR_SET_MODE_NOT_ALLOWED: u32 = 0x305;
/// `PNIO_device_activate` is not allowed (open without `PNIO_CEP_MODE_CTRL`).
pub const PNIO_ERR_DEV_ACT_NOT_ALLOWED: u32 = 0x306;
/// No licence server.
pub const PNIO_ERR_NO_LIC_SERVER: u32 = 0x307;
/// The length does not fit.
pub const PNIO_ERR_VALUE_LEN: u32 = 0x308;
/// The call is out of sequence.
pub const PNIO_ERR_SEQUENCE: u32 = 0x309;
/// The configuration is invalid.
pub const PNIO_ERR_INVALID_CONFIG: u32 = 0x30A;
/// The address is not configured.
pub const PNIO_ERR_UNKNOWN_ADDR: u32 = 0x30B;
/// Out of resources.
pub const PNIO_ERR_NO_RESOURCE: u32 = 0x30C;
/// The configuration is being updated.
pub const PNIO_ERR_CONFIG_IN_UPDATE: u32 = 0x30D;
/// No communication with the firmware (the server).
pub const PNIO_ERR_NO_FW_COMMUNICATION: u32 = 0x30E;
/// STARTOP is not registered.
pub const PNIO_ERR_STARTOP_NOT_REGISTERED: u32 = 0x30F;
/// Owned by another program.
pub const PNIO_ERR_OWNED: u32 = 0x310;
/// A thread could not be started.
pub const PNIO_ERR_START_THREAD_FAILED: u32 = 0x311;
/// A real-time thread could not be started.
pub const PNIO_ERR_START_RT_THREAD_FAILED: u32 = 0x312;
/// A driver call failed.
pub const PNIO_ERR_DRIVER_IOCTL_FAILED: u32 = 0x313;
/// After an exception.
pub const PNIO_ERR_AFTER_EXCEPTION: u32 = 0x314;
/// No cycle information.
pub const PNIO_ERR_NO_CYCLE_INFO_DATA: u32 = 0x315;
/// Session error.
pub const PNIO_ERR_SESSION: u32 = 0x316;
/// Alarm data format error.
pub const PNIO_ERR_ALARM_DATA_FORMAT: u32 = 0x317;
/// Aborted.
pub const PNIO_ERR_ABORT: u32 = 0x318;
/// Corrupted data.
pub const PNIO_ERR_CORRUPTED_DATA: u32 = 0x319;
/// Flash access failed.
pub const PNIO_ERR_FLASH_ACCESS: u32 = 0x31A;
/// Wrong request block length.
pub const PNIO_ERR_WRONG_RQB_LEN: u32 = 0x31B;
/// No reset verification.
pub const PNIO_ERR_NO_RESET_VERIFICATION: u32 = 0x31C;
/// PN Driver: the configuration does not let the program set the IP suite or NameOfStation.
pub const PNIO_ERR_SET_IP_NOS_NOT_ALLOWED: u32 = 0x31D;
/// PN Driver: the retentive data cannot be read.
pub const PNIO_ERR_INVALID_REMA: u32 = 0x31E;
/// PN Driver: the previous job of this kind has not ended.
pub const PNIO_ERR_NOT_REENTERABLE: u32 = 0x31F;
/// PN Driver: the station is not configured as optional (tailoring).
pub const PNIO_ERR_INVALID_STATION: u32 = 0x320;
/// PN Driver: the port has no programmable peer (tailoring).
pub const PNIO_ERR_INVALID_PORT: u32 = 0x321;
/// PN Driver: no network adapter found.
pub const PNIO_ERR_NO_ADAPTER_FOUND: u32 = 0x322;
/// PN Driver: access denied.
pub const PNIO_ERR_ACCESS_DENIED: u32 = 0x323;
/// Internal error.
pub const PNIO_ERR_INTERNAL: u32 = 0x3FF;

/// Every code with its name, for the header test and for error texts.
pub const ALL: &[(&str, u32)] = &[
    ("PNIO_OK", PNIO_OK),
    ("PNIO_OK_PE_WAKE_ONLINE", PNIO_OK_PE_WAKE_ONLINE),
    ("PNIO_OK_PE_WAKE_OFFLINE", PNIO_OK_PE_WAKE_OFFLINE),
    ("PNIO_WARN_IRT_INCONSISTENT", PNIO_WARN_IRT_INCONSISTENT),
    ("PNIO_WARN_NO_SUBMODULES", PNIO_WARN_NO_SUBMODULES),
    ("PNIO_WARN_LOCAL_STATE_BAD", PNIO_WARN_LOCAL_STATE_BAD),
    (
        "PNIO_WARN_NO_DECENTRALIOSYSTEM",
        PNIO_WARN_NO_DECENTRALIOSYSTEM,
    ),
    ("PNIO_ERR_PRM_HND", PNIO_ERR_PRM_HND),
    ("PNIO_ERR_PRM_BUF", PNIO_ERR_PRM_BUF),
    ("PNIO_ERR_PRM_LEN", PNIO_ERR_PRM_LEN),
    ("PNIO_ERR_PRM_ADD", PNIO_ERR_PRM_ADD),
    ("PNIO_ERR_PRM_RSTATE", PNIO_ERR_PRM_RSTATE),
    ("PNIO_ERR_PRM_CALLBACK", PNIO_ERR_PRM_CALLBACK),
    ("PNIO_ERR_PRM_TYPE", PNIO_ERR_PRM_TYPE),
    ("PNIO_ERR_PRM_EXT_PAR", PNIO_ERR_PRM_EXT_PAR),
    ("PNIO_ERR_PRM_IO_TYPE", PNIO_ERR_PRM_IO_TYPE),
    ("PNIO_ERR_PRM_CP_ID", PNIO_ERR_PRM_CP_ID),
    ("PNIO_ERR_PRM_LOC_STATE", PNIO_ERR_PRM_LOC_STATE),
    ("PNIO_ERR_PRM_REC_INDEX", PNIO_ERR_PRM_REC_INDEX),
    ("PNIO_ERR_PRM_TIMEOUT", PNIO_ERR_PRM_TIMEOUT),
    ("PNIO_ERR_PRM_DEV_ANNOTATION", PNIO_ERR_PRM_DEV_ANNOTATION),
    ("PNIO_ERR_PRM_DEV_STATE", PNIO_ERR_PRM_DEV_STATE),
    ("PNIO_ERR_PRM_PCBF", PNIO_ERR_PRM_PCBF),
    ("PNIO_ERR_PRM_MAX_AR_VALUE", PNIO_ERR_PRM_MAX_AR_VALUE),
    ("PNIO_ERR_PRM_ACCESS_TYPE", PNIO_ERR_PRM_ACCESS_TYPE),
    ("PNIO_ERR_PRM_POINTER", PNIO_ERR_PRM_POINTER),
    ("PNIO_ERR_PRM_INVALIDARG", PNIO_ERR_PRM_INVALIDARG),
    ("PNIO_ERR_PRM_MEASURE_NUMBER", PNIO_ERR_PRM_MEASURE_NUMBER),
    ("PNIO_ERR_PRM_CYCLE_OFFSET", PNIO_ERR_PRM_CYCLE_OFFSET),
    ("PNIO_ERR_PRM_ROUTER_ADD", PNIO_ERR_PRM_ROUTER_ADD),
    ("PNIO_ERR_PRM_IP", PNIO_ERR_PRM_IP),
    ("PNIO_ERR_PRM_NOS", PNIO_ERR_PRM_NOS),
    ("PNIO_ERR_PRM_NOS_LEN", PNIO_ERR_PRM_NOS_LEN),
    ("PNIO_ERR_WRONG_HND", PNIO_ERR_WRONG_HND),
    ("PNIO_ERR_MAX_REACHED", PNIO_ERR_MAX_REACHED),
    ("PNIO_ERR_CREATE_INSTANCE", PNIO_ERR_CREATE_INSTANCE),
    ("PNIO_ERR_MODE_VALUE", PNIO_ERR_MODE_VALUE),
    ("PNIO_ERR_OPFAULT_NOT_REG", PNIO_ERR_OPFAULT_NOT_REG),
    (
        "PNIO_ERR_NEWCYCLE_SEQUENCE_REG",
        PNIO_ERR_NEWCYCLE_SEQUENCE_REG,
    ),
    (
        "PNIO_ERR_NETWORK_PROT_NOT_AVAILABLE",
        PNIO_ERR_NETWORK_PROT_NOT_AVAILABLE,
    ),
    ("PNIO_ERR_RETRY", PNIO_ERR_RETRY),
    ("PNIO_ERR_NO_CONNECTION", PNIO_ERR_NO_CONNECTION),
    ("PNIO_ERR_OS_RES", PNIO_ERR_OS_RES),
    ("PNIO_ERR_ALREADY_DONE", PNIO_ERR_ALREADY_DONE),
    ("PNIO_ERR_ALLREADY_DONE", PNIO_ERR_ALLREADY_DONE),
    ("PNIO_ERR_NO_CONFIG", PNIO_ERR_NO_CONFIG),
    (
        "PNIO_ERR_SET_MODE_NOT_ALLOWED",
        PNIO_ERR_SET_MODE_NOT_ALLOWED,
    ),
    ("PNIO_ERR_DEV_ACT_NOT_ALLOWED", PNIO_ERR_DEV_ACT_NOT_ALLOWED),
    ("PNIO_ERR_NO_LIC_SERVER", PNIO_ERR_NO_LIC_SERVER),
    ("PNIO_ERR_VALUE_LEN", PNIO_ERR_VALUE_LEN),
    ("PNIO_ERR_SEQUENCE", PNIO_ERR_SEQUENCE),
    ("PNIO_ERR_INVALID_CONFIG", PNIO_ERR_INVALID_CONFIG),
    ("PNIO_ERR_UNKNOWN_ADDR", PNIO_ERR_UNKNOWN_ADDR),
    ("PNIO_ERR_NO_RESOURCE", PNIO_ERR_NO_RESOURCE),
    ("PNIO_ERR_CONFIG_IN_UPDATE", PNIO_ERR_CONFIG_IN_UPDATE),
    ("PNIO_ERR_NO_FW_COMMUNICATION", PNIO_ERR_NO_FW_COMMUNICATION),
    (
        "PNIO_ERR_STARTOP_NOT_REGISTERED",
        PNIO_ERR_STARTOP_NOT_REGISTERED,
    ),
    ("PNIO_ERR_OWNED", PNIO_ERR_OWNED),
    ("PNIO_ERR_START_THREAD_FAILED", PNIO_ERR_START_THREAD_FAILED),
    (
        "PNIO_ERR_START_RT_THREAD_FAILED",
        PNIO_ERR_START_RT_THREAD_FAILED,
    ),
    ("PNIO_ERR_DRIVER_IOCTL_FAILED", PNIO_ERR_DRIVER_IOCTL_FAILED),
    ("PNIO_ERR_AFTER_EXCEPTION", PNIO_ERR_AFTER_EXCEPTION),
    ("PNIO_ERR_NO_CYCLE_INFO_DATA", PNIO_ERR_NO_CYCLE_INFO_DATA),
    ("PNIO_ERR_SESSION", PNIO_ERR_SESSION),
    ("PNIO_ERR_ALARM_DATA_FORMAT", PNIO_ERR_ALARM_DATA_FORMAT),
    ("PNIO_ERR_ABORT", PNIO_ERR_ABORT),
    ("PNIO_ERR_CORRUPTED_DATA", PNIO_ERR_CORRUPTED_DATA),
    ("PNIO_ERR_FLASH_ACCESS", PNIO_ERR_FLASH_ACCESS),
    ("PNIO_ERR_WRONG_RQB_LEN", PNIO_ERR_WRONG_RQB_LEN),
    (
        "PNIO_ERR_NO_RESET_VERIFICATION",
        PNIO_ERR_NO_RESET_VERIFICATION,
    ),
    (
        "PNIO_ERR_SET_IP_NOS_NOT_ALLOWED",
        PNIO_ERR_SET_IP_NOS_NOT_ALLOWED,
    ),
    ("PNIO_ERR_INVALID_REMA", PNIO_ERR_INVALID_REMA),
    ("PNIO_ERR_NOT_REENTERABLE", PNIO_ERR_NOT_REENTERABLE),
    ("PNIO_ERR_INVALID_STATION", PNIO_ERR_INVALID_STATION),
    ("PNIO_ERR_INVALID_PORT", PNIO_ERR_INVALID_PORT),
    ("PNIO_ERR_NO_ADAPTER_FOUND", PNIO_ERR_NO_ADAPTER_FOUND),
    ("PNIO_ERR_ACCESS_DENIED", PNIO_ERR_ACCESS_DENIED),
    ("PNIO_ERR_INTERNAL", PNIO_ERR_INTERNAL),
];

/// The name of a return code ("unknown code" for others), for error texts.
pub fn name(code: u32) -> &'static str {
    ALL.iter()
        .find(|(_, c)| *c == code)
        .map_or("unknown code", |(n, _)| n)
}

/// Records the failure text of an API function for the calling thread and returns `code`.
pub(crate) fn fail(function: &str, code: u32, detail: impl std::fmt::Display) -> u32 {
    crate::ffi::set_last_error(format!("{function}: {detail} ({})", name(code)));
    code
}
