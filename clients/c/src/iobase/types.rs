// SPDX-License-Identifier: MIT OR Apache-2.0
//! Rust mirrors of the C types of `pniobase.h` and `pniousrx.h`, with the C names.
//!
//! Every struct is `#[repr(C)]` with the fields in the header's order. The headers declare
//! their structs `ATTR_PACKED`, which on GCC is `__attribute__((aligned(4)))`: natural layout,
//! alignment at least 4. Where that raises a struct's alignment (structs of bytes and 16-bit
//! words only) the mirror says `align(4)` too; `tests/iobase_header.rs` compares every size
//! and offset with the C compiler's.
//!
//! C enums are `int`-sized; their Rust mirrors are `u32` aliases with one constant per
//! value, so a value a C program passes that is no enumerator is still a valid Rust value
//! (and is refused with an error code instead of being undefined behaviour).
//!
//! C's `PNIO_CBE_PRM` has an anonymous union (`prm->ModeInd.Mode`); Rust has none, so the
//! mirror names it `u` (`prm.u.ModeInd.Mode`), at the same offset.
#![allow(non_camel_case_types, non_snake_case)]

/// `PNIO_UINT8`: 8 bits unsigned.
pub type PNIO_UINT8 = u8;
/// `PNIO_UINT16`: 16 bits unsigned.
pub type PNIO_UINT16 = u16;
/// `PNIO_UINT32`: 32 bits unsigned (the manual's `unsigned long` of 32-bit Windows).
pub type PNIO_UINT32 = u32;
/// `PNIO_REF`: a user reference echoed in a confirmation, 32 bits.
pub type PNIO_REF = u32;

// ---------------------------------------------------------------------------------------
// Limits

/// `PNIO_API_VERSION`: the interface version these headers describe.
pub const PNIO_API_VERSION: u32 = 230;
/// `PNIO_MAX_ALARM_DATA_LEN`: user data bytes of an alarm.
pub const PNIO_MAX_ALARM_DATA_LEN: u32 = 1472;
/// `PNIO_MAX_IO_LEN`: data bytes of one submodule.
pub const PNIO_MAX_IO_LEN: u32 = 254;
/// `PNIO_MAX_REC_LEN`: bytes of one record read.
pub const PNIO_MAX_REC_LEN: u32 = 4096;

// ---------------------------------------------------------------------------------------
// Enums

/// `PNIO_ADDR_TYPE`: how a `PNIO_ADDR` addresses.
pub type PNIO_ADDR_TYPE = u32;
/// Logical address (the only kind a controller uses).
pub const PNIO_ADDR_LOG: PNIO_ADDR_TYPE = 0;
/// Geographical address (not for the controller API).
pub const PNIO_ADDR_GEO: PNIO_ADDR_TYPE = 1;

/// `PNIO_IO_TYPE`: address space.
pub type PNIO_IO_TYPE = u32;
/// Inputs (I).
pub const PNIO_IO_IN: PNIO_IO_TYPE = 0;
/// Outputs (Q).
pub const PNIO_IO_OUT: PNIO_IO_TYPE = 1;

/// `PNIO_IOXS`: a data status (IOPS/IOCS).
pub type PNIO_IOXS = u32;
/// Valid.
pub const PNIO_S_GOOD: PNIO_IOXS = 0;
/// Invalid.
pub const PNIO_S_BAD: PNIO_IOXS = 1;

/// The status IO-Base value `v` names; `None` for a value that is neither GOOD nor BAD.
pub(crate) fn ioxs(v: PNIO_IOXS) -> Option<procimg_client::Ioxs> {
    match v {
        PNIO_S_GOOD => Some(procimg_client::Ioxs::Good),
        PNIO_S_BAD => Some(procimg_client::Ioxs::Bad),
        _ => None,
    }
}

/// Status `v` as IO-Base writes it.
pub(crate) fn pnio_ioxs(v: procimg_client::Ioxs) -> PNIO_IOXS {
    match v {
        procimg_client::Ioxs::Good => PNIO_S_GOOD,
        procimg_client::Ioxs::Bad => PNIO_S_BAD,
    }
}

/// `PNIO_MODE_TYPE`: the controller's mode.
pub type PNIO_MODE_TYPE = u32;
/// OFFLINE (stop): no IO data, records or alarms.
pub const PNIO_MODE_OFFLINE: PNIO_MODE_TYPE = 0;
/// CLEAR: IO data exchanged, outputs with status BAD.
pub const PNIO_MODE_CLEAR: PNIO_MODE_TYPE = 1;
/// OPERATE: normal operation.
pub const PNIO_MODE_OPERATE: PNIO_MODE_TYPE = 2;

/// `PNIO_DEV_ACT_TYPE`: deactivate or activate a device.
pub type PNIO_DEV_ACT_TYPE = u32;
/// Deactivate.
pub const PNIO_DA_FALSE: PNIO_DEV_ACT_TYPE = 0;
/// Activate.
pub const PNIO_DA_TRUE: PNIO_DEV_ACT_TYPE = 1;

/// `PNIO_DATA_TYPE`: RT or IRT data.
pub type PNIO_DATA_TYPE = u32;
/// Real-time data.
pub const PNIO_DATA_RT: PNIO_DATA_TYPE = 0;
/// Isochronous real-time data.
pub const PNIO_DATA_IRT: PNIO_DATA_TYPE = 1;

/// `PNIO_COM_TYPE`: how a submodule's data travels.
pub type PNIO_COM_TYPE = u32;
/// Between device and controller.
pub const PNIO_COM_UNICAST: PNIO_COM_TYPE = 0;
/// Direct data exchange.
pub const PNIO_COM_DIRECT_DATA_EX: PNIO_COM_TYPE = 1;

/// `PNIO_CP_CBE_TYPE`: the isochronous events of `PNIO_CP_register_cbf`.
pub type PNIO_CP_CBE_TYPE = u32;
/// No event.
pub const PNIO_CP_CBE_UNKNOWN: PNIO_CP_CBE_TYPE = 0;
/// STARTOP: this cycle's inputs are there, processing may start.
pub const PNIO_CP_CBE_STARTOP_IND: PNIO_CP_CBE_TYPE = 1;
/// OPFAULT: OPDONE came too late.
pub const PNIO_CP_CBE_OPFAULT_IND: PNIO_CP_CBE_TYPE = 2;
/// NEWCYCLE: a new bus cycle began.
pub const PNIO_CP_CBE_NEWCYCLE_IND: PNIO_CP_CBE_TYPE = 3;

/// `PNIO_CBE_TYPE`: the controller's callback events.
pub type PNIO_CBE_TYPE = u32;
/// Own mode changed.
pub const PNIO_CBE_MODE_IND: PNIO_CBE_TYPE = 1;
/// An alarm arrived (registered through `PNIO_controller_open` only).
pub const PNIO_CBE_ALARM_IND: PNIO_CBE_TYPE = 2;
/// A record read finished (registered through `PNIO_controller_open` only).
pub const PNIO_CBE_REC_READ_CONF: PNIO_CBE_TYPE = 3;
/// A record write finished (registered through `PNIO_controller_open` only).
pub const PNIO_CBE_REC_WRITE_CONF: PNIO_CBE_TYPE = 4;
/// A device (de)activation finished.
pub const PNIO_CBE_DEV_ACT_CONF: PNIO_CBE_TYPE = 5;
/// A remote download or reconfiguration request arrived.
pub const PNIO_CBE_CP_STOP_REQ: PNIO_CBE_TYPE = 6;
/// Start flashing the identification LED.
pub const PNIO_CBE_START_LED_FLASH: PNIO_CBE_TYPE = 7;
/// Stop flashing the identification LED.
pub const PNIO_CBE_STOP_LED_FLASH: PNIO_CBE_TYPE = 8;
/// A diagnosis request finished.
pub const PNIO_CBE_CTRL_DIAG_CONF: PNIO_CBE_TYPE = 9;
/// PN Driver: interface address set (not supported by procimg).
pub const PNIO_CBE_IFC_SET_ADDR_CONF: PNIO_CBE_TYPE = 10;
/// PN Driver: remanent data read (not supported by procimg).
pub const PNIO_CBE_REMA_READ_CONF: PNIO_CBE_TYPE = 11;
/// PN Driver: IO system reconfiguration (not supported by procimg).
pub const PNIO_CBE_IOSYSTEM_RECONFIG: PNIO_CBE_TYPE = 12;
/// PN Driver: interface record read (not supported by procimg).
pub const PNIO_CBE_IFC_REC_READ_CONF: PNIO_CBE_TYPE = 13;
/// PN Driver: interface alarm (not supported by procimg).
pub const PNIO_CBE_IFC_ALARM_IND: PNIO_CBE_TYPE = 14;

/// `PNIO_IOS_RECONFIG_MODE`: mode of `PNIO_iosystem_reconfig`.
pub type PNIO_IOS_RECONFIG_MODE = u32;
/// Deactivate all devices.
pub const PNIO_IOS_RECONFIG_MODE_DEACT: PNIO_IOS_RECONFIG_MODE = 1;
/// Tailor the IO system.
pub const PNIO_IOS_RECONFIG_MODE_TAILOR: PNIO_IOS_RECONFIG_MODE = 2;

/// `PNIO_CTRL_DIAG_ENUM`: the services of `PNIO_ctrl_diag_req`.
pub type PNIO_CTRL_DIAG_ENUM = u32;
/// Reserved.
pub const PNIO_CTRL_DIAG_RESERVED: PNIO_CTRL_DIAG_ENUM = 0;
/// The configured submodules (`PNIO_CTRL_DIAG_CONFIG_SUBMODULE[]`).
pub const PNIO_CTRL_DIAG_CONFIG_SUBMODULE_LIST: PNIO_CTRL_DIAG_ENUM = 1;
/// A device's state (`PNIO_CTRL_DIAG_DEVICE`).
pub const PNIO_CTRL_DIAG_DEVICE_STATE: PNIO_CTRL_DIAG_ENUM = 2;
/// Whether an IO router is configured (answer in `DiagDataBufferLen`).
pub const PNIO_CTRL_DIAG_CONFIG_IOROUTER_PRESENT: PNIO_CTRL_DIAG_ENUM = 3;
/// The output slices this program may write (`PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE[]`).
pub const PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE_LIST: PNIO_CTRL_DIAG_ENUM = 4;
/// The controller's name and address (`PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO_DATA`).
pub const PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO: PNIO_CTRL_DIAG_ENUM = 5;
/// Ethernet counters (`PNIO_CTRL_COMM_COUNTER_DATA`).
pub const PNIO_CTRL_DIAG_GET_COMM_COUNTER_DATA: PNIO_CTRL_DIAG_ENUM = 6;
/// Ethernet counters, then reset them.
pub const PNIO_CTRL_DIAG_RESET_COMM_COUNTERS: PNIO_CTRL_DIAG_ENUM = 7;
/// Why a device's AR ended (`PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC_DATA`).
pub const PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC: PNIO_CTRL_DIAG_ENUM = 8;

/// `PNIO_ALARM_TYPE`: the kind of an alarm.
pub type PNIO_ALARM_TYPE = u32;
/// Diagnosis appears.
pub const PNIO_ALARM_DIAGNOSTIC: PNIO_ALARM_TYPE = 0x01;
/// Process alarm.
pub const PNIO_ALARM_PROCESS: PNIO_ALARM_TYPE = 0x02;
/// Module pulled.
pub const PNIO_ALARM_PULL: PNIO_ALARM_TYPE = 0x03;
/// Module plugged.
pub const PNIO_ALARM_PLUG: PNIO_ALARM_TYPE = 0x04;
/// Status alarm.
pub const PNIO_ALARM_STATUS: PNIO_ALARM_TYPE = 0x05;
/// Update alarm.
pub const PNIO_ALARM_UPDATE: PNIO_ALARM_TYPE = 0x06;
/// Redundancy alarm.
pub const PNIO_ALARM_REDUNDANCY: PNIO_ALARM_TYPE = 0x07;
/// Controlled by a supervisor.
pub const PNIO_ALARM_CONTROLLED_BY_SUPERVISOR: PNIO_ALARM_TYPE = 0x08;
/// Released by a supervisor.
pub const PNIO_ALARM_RELEASED_BY_SUPERVISOR: PNIO_ALARM_TYPE = 0x09;
/// A wrong module was plugged.
pub const PNIO_ALARM_PLUG_WRONG: PNIO_ALARM_TYPE = 0x0A;
/// A submodule returned.
pub const PNIO_ALARM_RETURN_OF_SUBMODULE: PNIO_ALARM_TYPE = 0x0B;
/// Diagnosis disappears.
pub const PNIO_ALARM_DIAGNOSTIC_DISAPPEARS: PNIO_ALARM_TYPE = 0x0C;
/// Multicast communication mismatch.
pub const PNIO_ALARM_MCR_MISMATCH: PNIO_ALARM_TYPE = 0x0D;
/// Port data changed.
pub const PNIO_ALARM_PORT_DATA_CHANGED: PNIO_ALARM_TYPE = 0x0E;
/// Synchronisation data changed.
pub const PNIO_ALARM_SYNC_DATA_CHANGED: PNIO_ALARM_TYPE = 0x0F;
/// Isochronous mode problem.
pub const PNIO_ALARM_ISOCHRONE_MODE_PROBLEM: PNIO_ALARM_TYPE = 0x10;
/// Network component problem.
pub const PNIO_ALARM_NETWORK_COMPONENT_PROBLEM: PNIO_ALARM_TYPE = 0x11;
/// Upload and storage.
pub const PNIO_ALARM_UPLOAD_AND_STORAGE: PNIO_ALARM_TYPE = 0x1E;
/// Pull of a whole module.
pub const PNIO_ALARM_PULL_MODULE: PNIO_ALARM_TYPE = 0x1F;
/// The device failed (its AR ended): made by the controller.
pub const PNIO_ALARM_DEV_FAILURE: PNIO_ALARM_TYPE = 0x0001_0000;
/// The device returned (its AR is in data exchange): made by the controller.
pub const PNIO_ALARM_DEV_RETURN: PNIO_ALARM_TYPE = 0x0001_0001;

/// `PNIO_APRIO_TYPE`: alarm priority.
pub type PNIO_APRIO_TYPE = u32;
/// Low.
pub const PNIO_APRIO_LOW: PNIO_APRIO_TYPE = 0;
/// High.
pub const PNIO_APRIO_HIGH: PNIO_APRIO_TYPE = 1;

// ---------------------------------------------------------------------------------------
// Flags and bit fields

/// ExtPar: the program may change the controller's mode.
pub const PNIO_CEP_MODE_CTRL: u32 = 0x02;
/// ExtPar (device side): max ARs by device type.
pub const PNIO_CEP_DEV_MAXAR_BY_TYPE: u32 = 0x04;
/// ExtPar: slice (partial) access to submodules.
pub const PNIO_CEP_SLICE_ACCESS: u32 = 0x08;
/// ExtPar (device side): max ARs by device type, advanced.
pub const PNIO_CEP_DEV_MAXAR_BY_TYPE_ADV: u32 = 0x10;
/// ExtPar (device side): PROFIenergy.
pub const PNIO_CEP_PE_MODE_ENABLE: u32 = 0x20;
/// ExtPar: switch the MRP role off.
pub const PNIO_CEP_SET_MRP_ROLE_OFF: u32 = 0x40;

/// `PNIO_CTRL_DIAG_DEVICE::DiagState`: the device is offline.
pub const PNIO_CTRL_DEV_DIAG_OFFLINE: u32 = 0x0000_0001;
/// The device's address was resolved.
pub const PNIO_CTRL_DEV_DIAG_ADDR_INFO_OK: u32 = 0x0000_0010;
/// The AR is being set up.
pub const PNIO_CTRL_DEV_DIAG_AR_CONNECTING: u32 = 0x0000_0100;
/// The AR is in data exchange.
pub const PNIO_CTRL_DEV_DIAG_AR_IN_DATA: u32 = 0x0000_0200;
/// The AR is offline (see `Reason`).
pub const PNIO_CTRL_DEV_DIAG_AR_OFFLINE: u32 = 0x0000_0400;
/// The AR waits for RTC3 (IRT) data.
pub const PNIO_CTRL_DEV_DIAG_AR_RTC3_FOLLOWS: u32 = 0x0000_1000;

/// Why a device is not in data exchange (`PNIO_CTRL_DIAG_DEVICE::Reason`), name and value.
pub const PNIO_CTRL_REASONS: &[(&str, u32)] = &[
    ("PNIO_CTRL_REASON_NONE", 0x0000),
    ("PNIO_CTRL_REASON_NARE_ERR_MULTIPLE_IP_USE", 0x0101),
    ("PNIO_CTRL_REASON_NARE_ERR_IP_IN_USE", 0x0102),
    ("PNIO_CTRL_REASON_NARE_ERR_DCP_MULTIPLE_STATIONS", 0x0103),
    ("PNIO_CTRL_REASON_NARE_ERR_DCP_SET_FAILED", 0x0104),
    ("PNIO_CTRL_REASON_NARE_ERR_DCP_SET_TIMEOUT", 0x0105),
    ("PNIO_CTRL_REASON_NARE_ERR_DCP_STATION_NOT_FOUND", 0x0106),
    ("PNIO_CTRL_REASON_NARE_ERR_OPCODE", 0x0107),
    ("PNIO_CTRL_REASON_NARE_ERR_CHANNEL_USE", 0x0108),
    ("PNIO_CTRL_REASON_NARE_ERR_DNS_FAILED", 0x0109),
    ("PNIO_CTRL_REASON_NARE_ERR_LL", 0x010A),
    ("PNIO_CTRL_REASON_NARE_ERR_NO_OWN_IP", 0x010B),
    ("PNIO_CTRL_REASON_NARE_ERR_DCP_IDENT_TLV_ERROR", 0x010C),
    ("PNIO_CTRL_REASON_NARE_ERR_IP_RESOLVE_NO_ANSWER", 0x010D),
    ("PNIO_CTRL_REASON_CLRPC_ERR_FAULTED", 0x0201),
    ("PNIO_CTRL_REASON_CLRPC_ERR_REJECTED", 0x0202),
    ("PNIO_CTRL_REASON_CLRPC_ERR_IN_ARGS", 0x0203),
    ("PNIO_CTRL_REASON_CLRPC_ERR_OUT_ARGS", 0x0204),
    ("PNIO_CTRL_REASON_CLRPC_ERR_DECODE", 0x0205),
    ("PNIO_CTRL_REASON_CLRPC_ERR_PNIO_OUT_ARGS", 0x0206),
    ("PNIO_CTRL_REASON_CLRPC_ERR_TIMEOUT", 0x0207),
    ("PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_LINK", 0x0301),
    ("PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_MISS", 0x0401),
    ("PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_COMPANION", 0x0501),
    ("PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_OTHER", 0x0601),
    ("PNIO_CTRL_REASON_ERR_MULTIPLE_IP_USE", 0x0700),
    ("PNIO_CTRL_REASON_ERR_MULTIPLE_STATIONS", 0x0701),
    ("PNIO_CTRL_REASON_REASON_LINK_DOWN", 0x0702),
    ("PNIO_CTRL_REASON_MAU_MISMATCH", 0x0703),
    ("PNIO_CTRL_REASON_RPC_ERROR", 0x0704),
    ("PNIO_CTRL_REASON_PNIO_CONFIGURATION", 0x0705),
    ("PNIO_CTRL_REASON_RPC_TIMEOUT", 0x0706),
    ("PNIO_CTRL_REASON_IP_SET_ABORTED", 0x0707),
    ("PNIO_CTRL_REASON_IOD_NOT_FOUND", 0x0708),
    ("PNIO_CTRL_REASON_OUT_OF_RESOURCES", 0x0709),
    ("PNIO_CTRL_REASON_MISS", 0x070A),
    ("PNIO_CTRL_REASON_NOS_SET_ABORTED", 0x070B),
    ("PNIO_CTRL_REASON_IOC_ABORTED", 0x070C),
    ("PNIO_CTRL_REASON_IOD_ABORTED", 0x070D),
    ("PNIO_CTRL_REASON_VENDORID_ABORTED", 0x070E),
    ("PNIO_CTRL_REASON_MP_IN_PROGRESS", 0x070F),
    ("PNIO_CTRL_REASON_MP_NOS_MISSING", 0x0710),
    ("PNIO_CTRL_REASON_MP_IPv4_MISSING", 0x0711),
    ("PNIO_CTRL_REASON_MP_NOS_INVALID", 0x0712),
    ("PNIO_CTRL_REASON_MP_IPv4_INVALID", 0x0713),
    ("PNIO_CTRL_REASON_MP_TAILORING_MISSING", 0x0714),
    ("PNIO_CTRL_REASON_MP_PDEV_ERROR", 0x0715),
    ("PNIO_CTRL_REASON_MP_DEVICE_DISABLED", 0x0716),
];

/// No reason: the device is in data exchange (or was never connected).
pub const PNIO_CTRL_REASON_NONE: u32 = 0x0000;
/// The device's station was not found on the network.
pub const PNIO_CTRL_REASON_NARE_ERR_DCP_STATION_NOT_FOUND: u32 = 0x0106;
/// The connect RPC timed out.
pub const PNIO_CTRL_REASON_CLRPC_ERR_TIMEOUT: u32 = 0x0207;
/// The link is down.
pub const PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_LINK: u32 = 0x0301;
/// The device is missing.
pub const PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_MISS: u32 = 0x0401;
/// The device aborted the AR.
pub const PNIO_CTRL_REASON_IOD_ABORTED: u32 = 0x070D;
/// The controller aborted the AR.
pub const PNIO_CTRL_REASON_IOC_ABORTED: u32 = 0x070C;
/// The device was not found.
pub const PNIO_CTRL_REASON_IOD_NOT_FOUND: u32 = 0x0708;
/// The RPC timed out.
pub const PNIO_CTRL_REASON_RPC_TIMEOUT: u32 = 0x0706;
/// The device was deactivated.
pub const PNIO_CTRL_REASON_MP_DEVICE_DISABLED: u32 = 0x0716;
/// The device's RPC layer refused a call.
pub const PNIO_CTRL_REASON_RPC_ERROR: u32 = 0x0704;
/// The device refused the configuration.
pub const PNIO_CTRL_REASON_PNIO_CONFIGURATION: u32 = 0x0705;
/// Giving the device its IP address failed.
pub const PNIO_CTRL_REASON_IP_SET_ABORTED: u32 = 0x0707;
/// The device's cyclic data stopped coming.
pub const PNIO_CTRL_REASON_MISS: u32 = 0x070A;

// ---------------------------------------------------------------------------------------
// Structs

/// `PNIO_ADDR::u`: the logical address, or reserved words.
#[repr(C)]
#[derive(Clone, Copy)]
pub union PNIO_ADDR_u {
    /// The logical address (`AddrType == PNIO_ADDR_LOG`).
    pub Addr: PNIO_UINT32,
    /// Reserved.
    pub Reserved: [PNIO_UINT32; 5],
}

/// `PNIO_ADDR`: an address in the I or Q space.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PNIO_ADDR {
    /// Must be `PNIO_ADDR_LOG` for the controller.
    pub AddrType: PNIO_ADDR_TYPE,
    /// `PNIO_IO_IN` or `PNIO_IO_OUT`.
    pub IODataType: PNIO_IO_TYPE,
    /// The address.
    pub u: PNIO_ADDR_u,
}

impl PNIO_ADDR {
    /// A logical address in the given space.
    pub fn logical(io: PNIO_IO_TYPE, addr: u32) -> PNIO_ADDR {
        let mut u = PNIO_ADDR_u { Reserved: [0; 5] };
        u.Addr = addr;
        PNIO_ADDR {
            AddrType: PNIO_ADDR_LOG,
            IODataType: io,
            u,
        }
    }

    /// The logical address (`u.Addr`).
    pub fn addr(&self) -> u32 {
        // SAFETY: every bit pattern is a valid u32, and the union is at least 4 bytes, all of
        // them initialised (it is built from 5 words or read from C memory of its size).
        unsafe { self.u.Addr }
    }
}

impl core::fmt::Debug for PNIO_ADDR {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("PNIO_ADDR")
            .field("AddrType", &self.AddrType)
            .field("IODataType", &self.IODataType)
            .field("Addr", &self.addr())
            .finish()
    }
}

/// `PNIO_ERR_STAT`: a PROFINET IO status (IEC 61158-6 PNIOStatus) and two additional values.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_ERR_STAT {
    /// ErrorCode.
    pub ErrCode: PNIO_UINT8,
    /// ErrorDecode.
    pub ErrDecode: PNIO_UINT8,
    /// ErrorCode1.
    pub ErrCode1: PNIO_UINT8,
    /// ErrorCode2.
    pub ErrCode2: PNIO_UINT8,
    /// AdditionalValue1 (record read: 1 = more data than was read).
    pub AddValue1: PNIO_UINT16,
    /// AdditionalValue2.
    pub AddValue2: PNIO_UINT16,
}

/// `PNIO_CYCLE_INFO`: timing of the current cycle.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_CYCLE_INFO {
    /// Grows by the cycle time per cycle, in 31.25 µs units, 16 bits (32 per 1 ms cycle).
    pub CycleCount: PNIO_UINT32,
    /// Free-running clock, 10 ns units, 32 bits.
    pub ClockCount: PNIO_UINT32,
    /// Time since the start of the cycle, 10 ns units.
    pub CountSinceCycleStart: PNIO_UINT32,
}

/// `PNIO_ALARM_TINFO`: the alarm's configuration details (layout from the manual's
/// SERV_CIB_PDEV_DATA chapter).
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_ALARM_TINFO {
    /// Bits 0-10 device number, 11-14 IO subsystem number, 15 = 1 (PNIO).
    pub CompatDevGeoaddr: PNIO_UINT16,
    /// 0x08: bits 0-3 PNIO, 4-7 DP.
    pub ProfileType: PNIO_UINT8,
    /// Bits 0-3: alarm info type (0 = transparent).
    pub AinfoType: PNIO_UINT8,
    /// Bit 0: external DP interface.
    pub ControllerFlags: PNIO_UINT8,
    /// Bit 0: APDU status failure.
    pub DeviceFlag: PNIO_UINT8,
    /// The device's vendor ID.
    pub PnioVendorIdent: PNIO_UINT16,
    /// The device ID.
    pub PnioDevIdent: PNIO_UINT16,
    /// The device instance.
    pub PnioDevInstance: PNIO_UINT16,
}

/// `PNIO_ALARM_INFO::u`: the alarm's user data.
#[repr(C)]
#[derive(Clone, Copy)]
pub union PNIO_ALARM_INFO_u {
    /// User data (`UserAlarmDataLen` bytes valid).
    pub UserAlarmData: [PNIO_UINT8; PNIO_MAX_ALARM_DATA_LEN as usize],
}

/// `PNIO_ALARM_INFO`: the alarm notification's fields (IEC 61158-6 AlarmNotification).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PNIO_ALARM_INFO {
    /// BlockType (0x0001 high, 0x0002 low priority alarm).
    pub BlockType: PNIO_UINT16,
    /// BlockVersion.
    pub BlockVersion: PNIO_UINT16,
    /// API.
    pub Api: PNIO_UINT32,
    /// AlarmSpecifier (sequence number, diagnosis flags).
    pub AlarmSpecifier: PNIO_UINT16,
    /// ModuleIdentNumber.
    pub ModIdent: PNIO_UINT32,
    /// SubmoduleIdentNumber.
    pub SubIdent: PNIO_UINT32,
    /// UserStructureIdentifier.
    pub UserStrucIdent: PNIO_UINT16,
    /// Bytes of user data.
    pub UserAlarmDataLen: PNIO_UINT16,
    /// The user data.
    pub UAData: PNIO_ALARM_INFO_u,
}

/// `PNIO_CTRL_ALARM_DATA`: an alarm as `PNIO_CBE_ALARM_IND` delivers it.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PNIO_CTRL_ALARM_DATA {
    /// The alarm type (`PNIO_ALARM_*`).
    pub AlarmType: PNIO_ALARM_TYPE,
    /// Priority.
    pub AlarmPriority: PNIO_APRIO_TYPE,
    /// Device (station) number.
    pub DeviceNum: PNIO_UINT16,
    /// Slot.
    pub SlotNum: PNIO_UINT16,
    /// Subslot.
    pub SubslotNum: PNIO_UINT16,
    /// Priority as a CPU would see it.
    pub CpuAlarmPriority: PNIO_UINT16,
    /// Compatible module type.
    pub PnioCompatModtype: PNIO_UINT32,
    /// Configuration details.
    pub AlarmTinfo: PNIO_ALARM_TINFO,
    /// Diagnosis bytes as in OB82.
    pub DiagDs: [PNIO_UINT8; 4],
    /// Process alarm bytes.
    pub PrAlarmInfo: [PNIO_UINT8; 4],
    /// The alarm notification.
    pub AlarmAinfo: PNIO_ALARM_INFO,
}

/// `PNIO_CTRL_DIAG::u`: reserved words, or the address of a device.
#[repr(C)]
#[derive(Clone, Copy)]
pub union PNIO_CTRL_DIAG_u {
    /// Reserved.
    pub Reserved1: [PNIO_UINT32; 8],
    /// For DEVICE_STATE and DEVICE_DIAGNOSTIC: an address of the device.
    pub Addr: PNIO_ADDR,
}

/// `PNIO_CTRL_DIAG`: a diagnosis request.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PNIO_CTRL_DIAG {
    /// The service (`PNIO_CTRL_DIAG_*`).
    pub DiagService: PNIO_CTRL_DIAG_ENUM,
    /// Its parameter.
    pub u: PNIO_CTRL_DIAG_u,
    /// User reference.
    pub ReqRef: PNIO_REF,
    /// Reserved.
    pub Reserved2: PNIO_UINT32,
}

/// `PNIO_CTRL_DIAG_CONFIG_SUBMODULE`: one element of the CONFIG_SUBMODULE_LIST answer.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PNIO_CTRL_DIAG_CONFIG_SUBMODULE {
    /// The logical address (input length 0: the diagnostic address).
    pub Address: PNIO_ADDR,
    /// Data length.
    pub DataLength: PNIO_UINT32,
    /// RT or IRT.
    pub DataType: PNIO_DATA_TYPE,
    /// Unicast or direct data exchange.
    pub ComType: PNIO_COM_TYPE,
    /// API.
    pub Api: PNIO_UINT32,
    /// Sent every ReductionFactor cycles.
    pub ReductionFactor: PNIO_UINT32,
    /// Phase, 0..ReductionFactor-1.
    pub Phase: PNIO_UINT32,
    /// Send clock in 31.25 µs units.
    pub CycleTime: PNIO_UINT32,
    /// Reserved.
    pub Reserved1: [PNIO_UINT32; 2],
    /// Station number.
    pub StatNo: PNIO_UINT32,
    /// Slot.
    pub Slot: PNIO_UINT32,
    /// Subslot.
    pub Subslot: PNIO_UINT32,
    /// Reserved.
    pub Reserved2: [PNIO_UINT32; 2],
}

/// `PNIO_CTRL_DIAG_DEVICE`: the DEVICE_STATE answer.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_CTRL_DIAG_DEVICE {
    /// Activated or not.
    pub Mode: PNIO_DEV_ACT_TYPE,
    /// Bit field of `PNIO_CTRL_DEV_DIAG_*`.
    pub DiagState: PNIO_UINT32,
    /// A `PNIO_CTRL_REASON_*`.
    pub Reason: PNIO_UINT32,
    /// Reserved.
    pub Reserved1: [PNIO_UINT32; 12],
}

/// `PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE`: one element of the CONFIG_OUTPUT_SLICE_LIST answer.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE {
    /// The submodule's address.
    pub Address: PNIO_ADDR,
    /// First bit this program may write.
    pub BitOffset: PNIO_UINT16,
    /// Bits it may write.
    pub BitLength: PNIO_UINT16,
}

/// `PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO_DATA`: the CONFIG_NAME_ADDR_INFO answer.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO_DATA {
    /// Station name, NUL-terminated.
    pub name: [PNIO_UINT8; 256],
    /// Type of station, NUL-terminated.
    pub TypeOfStation: [PNIO_UINT8; 256],
    /// IP address.
    pub ip_addr: PNIO_UINT32,
    /// Network mask.
    pub ip_mask: PNIO_UINT32,
    /// Default router.
    pub default_router: PNIO_UINT32,
}

/// `PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC_DATA`: the DEVICE_DIAGNOSTIC answer.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC_DATA {
    /// Activated or not.
    pub Mode: PNIO_DEV_ACT_TYPE,
    /// The cause (big-endian, as PN Driver gives it).
    pub ErrorCause: PNIO_UINT16,
    /// Reason code.
    pub ReasonCode: PNIO_UINT8,
    /// More detail.
    pub AdditionalInfo: [PNIO_UINT8; 10],
}

/// `PNIO_CTRL_COMM_PORT_COUNTER_DATA`: one port's Ethernet counters.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_CTRL_COMM_PORT_COUNTER_DATA {
    /// Frames sent without error.
    pub SndNoError: PNIO_UINT32,
    /// Sends failed by collision.
    pub SndCollision: PNIO_UINT32,
    /// Sends failed otherwise.
    pub SndOtherError: PNIO_UINT32,
    /// Frames received without error.
    pub RcvNoError: PNIO_UINT32,
    /// Frames received with errors.
    pub RcvResError: PNIO_UINT32,
    /// Frames rejected.
    pub RcvRejected: PNIO_UINT32,
}

/// `PNIO_CTRL_COMM_COUNTER_DATA`: the GET/RESET_COMM_COUNTER answer.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_CTRL_COMM_COUNTER_DATA {
    /// Per port.
    pub Port: [PNIO_CTRL_COMM_PORT_COUNTER_DATA; 4],
    /// Ports in use.
    pub NumberOfPorts: PNIO_UINT16,
}

/// `PNIO_CBE_PRM_MODE_IND`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_CBE_PRM_MODE_IND {
    /// The new mode.
    pub Mode: PNIO_MODE_TYPE,
}

/// `PNIO_CBE_PRM_REC_READ_CONF` (the header's field order).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_CBE_PRM_REC_READ_CONF {
    /// The address the job was sent to.
    pub pAddr: *mut PNIO_ADDR,
    /// Record index.
    pub RecordIndex: PNIO_UINT32,
    /// As given to `PNIO_rec_read_req`.
    pub ReqRef: PNIO_REF,
    /// The job's status.
    pub Err: PNIO_ERR_STAT,
    /// Bytes in `pBuffer`.
    pub Length: PNIO_UINT32,
    /// The record, valid during the callback only.
    pub pBuffer: *const PNIO_UINT8,
}

/// `PNIO_CBE_PRM_REC_WRITE_CONF`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_CBE_PRM_REC_WRITE_CONF {
    /// The address the job was sent to.
    pub pAddr: *mut PNIO_ADDR,
    /// Record index.
    pub RecordIndex: PNIO_UINT32,
    /// As given to `PNIO_rec_write_req`.
    pub ReqRef: PNIO_REF,
    /// The job's status.
    pub Err: PNIO_ERR_STAT,
}

/// `PNIO_CBE_PRM_ALARM_IND`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_CBE_PRM_ALARM_IND {
    /// Source: a device's diagnostic address, or a module's address.
    pub pAddr: *mut PNIO_ADDR,
    /// Internal, reserved.
    pub IndRef: PNIO_REF,
    /// The alarm, valid during the callback only.
    pub pAlarmData: *const PNIO_CTRL_ALARM_DATA,
}

/// `PNIO_CBE_PRM_DEV_ACT_CONF`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_CBE_PRM_DEV_ACT_CONF {
    /// The address the job was sent to.
    pub pAddr: *mut PNIO_ADDR,
    /// The device's connection state now.
    pub Mode: PNIO_DEV_ACT_TYPE,
    /// `PNIO_OK`, or why the (de)activation failed.
    pub Result: PNIO_UINT32,
}

/// `PNIO_CBE_PRM_IOSYS_CONF`: the end of a `PNIO_iosystem_reconfig`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_CBE_PRM_IOSYS_CONF {
    /// The address of the device or port that made it fail (as the program gave it); all
    /// zero when none did.
    pub pAddr: *mut PNIO_ADDR,
    /// `PNIO_DA_TRUE` after a tailoring (the devices wanted are activated), `PNIO_DA_FALSE`
    /// after a deactivation.
    pub Mode: PNIO_DEV_ACT_TYPE,
    /// `PNIO_OK`, `PNIO_ERR_INVALID_STATION` or `PNIO_ERR_INVALID_PORT`.
    pub Status: PNIO_UINT32,
}

/// `PNIO_CBE_PRM_LED_FLASH`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_CBE_PRM_LED_FLASH {
    /// Flash frequency in Hz.
    pub Frequency: PNIO_UINT32,
}

/// `PNIO_CBE_PRM_CTRL_DIAG_CONF`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_CBE_PRM_CTRL_DIAG_CONF {
    /// The request given to `PNIO_ctrl_diag_req` (the caller's again from now on).
    pub pDiagData: *mut PNIO_CTRL_DIAG,
    /// Bytes of the answer.
    pub DiagDataBufferLen: PNIO_UINT32,
    /// The answer, valid during the callback only.
    pub pDiagDataBuffer: *mut PNIO_UINT8,
    /// The service's result.
    pub ErrorCode: PNIO_UINT32,
}

/// `PNIO_SET_IP_NOS_MODE_TYPE`: what `PNIO_interface_set_ip_and_nos` changes (bits).
pub type PNIO_SET_IP_NOS_MODE_TYPE = u32;
/// The IP suite.
pub const PNIO_SET_IP_MODE: PNIO_SET_IP_NOS_MODE_TYPE = 0x0001;
/// The NameOfStation.
pub const PNIO_SET_NOS_MODE: PNIO_SET_IP_NOS_MODE_TYPE = 0x0002;

/// `PNIO_CBE_PRM_SET_ADDR_CONF`: the end of a `PNIO_interface_set_ip_and_nos`, or a change
/// by DCP; the station as it is now.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_CBE_PRM_SET_ADDR_CONF {
    /// What was to change.
    pub Mode: PNIO_SET_IP_NOS_MODE_TYPE,
    /// The station's name, `StationNameLen` bytes, valid during the callback only.
    pub pStationName: *mut core::ffi::c_void,
    /// Bytes of the name.
    pub StationNameLen: PNIO_UINT16,
    /// The address.
    pub LocalIPAddress: [PNIO_UINT8; 4],
    /// The netmask.
    pub LocalSubnetMask: [PNIO_UINT8; 4],
    /// The gateway.
    pub DefaultRouterAddr: [PNIO_UINT8; 4],
    /// Reserved: 0.
    pub Options: PNIO_UINT32,
    /// `PNIO_OK`, or why not.
    pub Err: PNIO_UINT32,
}

/// `PNIO_CBE_PRM_REMA_READ_IND`: the interface's retentive data.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_CBE_PRM_REMA_READ_IND {
    /// The text, valid during the callback only.
    pub RemaXMLBuffer: *mut PNIO_UINT8,
    /// Its length in bytes (no terminating NUL).
    pub RemaXMLBufferLength: PNIO_UINT32,
    /// `PNIO_OK`.
    pub Err: PNIO_UINT32,
}

/// The anonymous union of `PNIO_CBE_PRM`.
#[repr(C)]
#[derive(Clone, Copy)]
pub union PNIO_CBE_PRM_u {
    /// `PNIO_CBE_MODE_IND`.
    pub ModeInd: PNIO_CBE_PRM_MODE_IND,
    /// `PNIO_CBE_REC_READ_CONF`.
    pub RecReadConf: PNIO_CBE_PRM_REC_READ_CONF,
    /// `PNIO_CBE_REC_WRITE_CONF`.
    pub RecWriteConf: PNIO_CBE_PRM_REC_WRITE_CONF,
    /// `PNIO_CBE_ALARM_IND`.
    pub AlarmInd: PNIO_CBE_PRM_ALARM_IND,
    /// `PNIO_CBE_DEV_ACT_CONF`.
    pub DevActConf: PNIO_CBE_PRM_DEV_ACT_CONF,
    /// `PNIO_CBE_START_LED_FLASH`.
    pub LedFlash: PNIO_CBE_PRM_LED_FLASH,
    /// `PNIO_CBE_CTRL_DIAG_CONF`.
    pub CtrlDiagConf: PNIO_CBE_PRM_CTRL_DIAG_CONF,
    /// `PNIO_CBE_IOSYSTEM_RECONFIG`.
    pub IoSystemReconf: PNIO_CBE_PRM_IOSYS_CONF,
    /// `PNIO_CBE_IFC_SET_ADDR_CONF`.
    pub SetAddrConf: PNIO_CBE_PRM_SET_ADDR_CONF,
    /// `PNIO_CBE_REMA_READ_CONF`.
    pub RemaReadConf: PNIO_CBE_PRM_REMA_READ_IND,
}

/// `PNIO_CBE_PRM`: what a controller callback receives.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PNIO_CBE_PRM {
    /// The event.
    pub CbeType: PNIO_CBE_TYPE,
    /// The controller's handle.
    pub Handle: PNIO_UINT32,
    /// The event's parameters (anonymous in C).
    pub u: PNIO_CBE_PRM_u,
}

impl PNIO_CBE_PRM {
    /// An event with zeroed parameters.
    pub fn new(CbeType: PNIO_CBE_TYPE, Handle: PNIO_UINT32) -> PNIO_CBE_PRM {
        PNIO_CBE_PRM {
            CbeType,
            Handle,
            // The largest member, so every byte of the union is initialised.
            u: PNIO_CBE_PRM_u {
                RecReadConf: PNIO_CBE_PRM_REC_READ_CONF {
                    pAddr: core::ptr::null_mut(),
                    RecordIndex: 0,
                    ReqRef: 0,
                    Err: PNIO_ERR_STAT::default(),
                    Length: 0,
                    pBuffer: core::ptr::null(),
                },
            },
        }
    }
}

/// `PNIO_CBF`: a controller callback.
pub type PNIO_CBF = Option<unsafe extern "C" fn(pCbfPrm: *mut PNIO_CBE_PRM)>;

/// `PNIO_CP_CBE_PRM_STARTOP_IND` (and OPFAULT, NEWCYCLE: the same fields). The manual calls
/// the first field `CpHandle`; the C header offers both names.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_CP_CBE_PRM_STARTOP_IND {
    /// The controller's handle.
    pub AppHandle: PNIO_UINT32,
    /// This cycle's timing.
    pub CycleInfo: PNIO_CYCLE_INFO,
}

/// `PNIO_CP_CBE_PRM_OPFAULT_IND`.
pub type PNIO_CP_CBE_PRM_OPFAULT_IND = PNIO_CP_CBE_PRM_STARTOP_IND;
/// `PNIO_CP_CBE_PRM_NEWCYCLE_IND`.
pub type PNIO_CP_CBE_PRM_NEWCYCLE_IND = PNIO_CP_CBE_PRM_STARTOP_IND;

/// `PNIO_CP_CBE_PRM::u`.
#[repr(C)]
#[derive(Clone, Copy)]
pub union PNIO_CP_CBE_PRM_u {
    /// `PNIO_CP_CBE_STARTOP_IND`.
    pub StartOp: PNIO_CP_CBE_PRM_STARTOP_IND,
    /// `PNIO_CP_CBE_OPFAULT_IND`.
    pub OpFault: PNIO_CP_CBE_PRM_OPFAULT_IND,
    /// `PNIO_CP_CBE_NEWCYCLE_IND`.
    pub NewCycle: PNIO_CP_CBE_PRM_NEWCYCLE_IND,
}

/// `PNIO_CP_CBE_PRM`: what an isochronous callback receives.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PNIO_CP_CBE_PRM {
    /// The event.
    pub CbeType: PNIO_CP_CBE_TYPE,
    /// The CpIndex given to `PNIO_controller_open`.
    pub CpIndex: PNIO_UINT32,
    /// The event's parameters.
    pub u: PNIO_CP_CBE_PRM_u,
}

impl PNIO_CP_CBE_PRM {
    /// An event for controller `handle` with this cycle's timing.
    pub fn new(
        CbeType: PNIO_CP_CBE_TYPE,
        CpIndex: PNIO_UINT32,
        handle: PNIO_UINT32,
        info: PNIO_CYCLE_INFO,
    ) -> PNIO_CP_CBE_PRM {
        PNIO_CP_CBE_PRM {
            CbeType,
            CpIndex,
            u: PNIO_CP_CBE_PRM_u {
                StartOp: PNIO_CP_CBE_PRM_STARTOP_IND {
                    AppHandle: handle,
                    CycleInfo: info,
                },
            },
        }
    }
}

/// `PNIO_CP_CBF`: an isochronous callback.
pub type PNIO_CP_CBF = Option<unsafe extern "C" fn(pCbfPrm: *mut PNIO_CP_CBE_PRM)>;

/// `PNIO_CBF_APPL_WATCHDOG`: called once when the CP application watchdog expires, with
/// the CPIndex it was registered for.
pub type PNIO_CBF_APPL_WATCHDOG = Option<unsafe extern "C" fn(CPIndex: PNIO_UINT32)>;
