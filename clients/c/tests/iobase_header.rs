// SPDX-License-Identifier: MIT OR Apache-2.0
//! The hand-written IO-Base headers (`pniobase.h`, `pniousrx.h`, `pnioerrx.h`) must agree
//! with the Rust mirrors in `src/iobase`: every struct's size, alignment and field offsets,
//! every constant's value and every function's signature, as a C11 and a C++17 compiler see
//! them. A C program generated from the Rust facts checks them all and names each mismatch.

use procimg::iobase::api::*;
use procimg::iobase::errors;
use procimg::iobase::interface_api::*;
use procimg::iobase::interface_types::*;
use procimg::iobase::pe_api::*;
use procimg::iobase::pe_types::*;
use procimg::iobase::types::*;
use procimg::iobase::watchdog::*;
use std::mem::{align_of, offset_of, size_of};
#[macro_use]
mod layout_check;
mod header_program;
use layout_check::{Offsets, Sizes};

fn layout_facts() -> (Sizes, Offsets) {
    let mut sizes: Sizes = Vec::new();
    let mut offs: Offsets = Vec::new();
    macro_rules! ty {
        ($($layout:tt)*) => { record_layout!(sizes, offs, $($layout)*) };
    }
    ty!(PNIO_ADDR, [AddrType, IODataType, u]);
    ty!(
        PNIO_ERR_STAT,
        [ErrCode, ErrDecode, ErrCode1, ErrCode2, AddValue1, AddValue2]
    );
    ty!(
        PNIO_CYCLE_INFO,
        [CycleCount, ClockCount, CountSinceCycleStart]
    );
    ty!(
        PNIO_ALARM_TINFO,
        [
            CompatDevGeoaddr,
            ProfileType,
            AinfoType,
            ControllerFlags,
            DeviceFlag,
            PnioVendorIdent,
            PnioDevIdent,
            PnioDevInstance
        ]
    );
    ty!(
        PNIO_ALARM_INFO,
        [
            BlockType,
            BlockVersion,
            Api,
            AlarmSpecifier,
            ModIdent,
            SubIdent,
            UserStrucIdent,
            UserAlarmDataLen,
            UAData
        ]
    );
    ty!(
        PNIO_CTRL_ALARM_DATA,
        [
            AlarmType,
            AlarmPriority,
            DeviceNum,
            SlotNum,
            SubslotNum,
            CpuAlarmPriority,
            PnioCompatModtype,
            AlarmTinfo,
            DiagDs,
            PrAlarmInfo,
            AlarmAinfo
        ]
    );
    ty!(PNIO_CTRL_DIAG, [DiagService, u, ReqRef, Reserved2]);
    ty!(
        PNIO_CTRL_DIAG_CONFIG_SUBMODULE,
        [
            Address,
            DataLength,
            DataType,
            ComType,
            Api,
            ReductionFactor,
            Phase,
            CycleTime,
            Reserved1,
            StatNo,
            Slot,
            Subslot,
            Reserved2
        ]
    );
    ty!(PNIO_CTRL_DIAG_DEVICE, [Mode, DiagState, Reason, Reserved1]);
    ty!(
        PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE,
        [Address, BitOffset, BitLength]
    );
    ty!(
        PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO_DATA,
        [name, TypeOfStation, ip_addr, ip_mask, default_router]
    );
    ty!(
        PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC_DATA,
        [Mode, ErrorCause, ReasonCode, AdditionalInfo]
    );
    ty!(
        PNIO_CTRL_COMM_PORT_COUNTER_DATA,
        [
            SndNoError,
            SndCollision,
            SndOtherError,
            RcvNoError,
            RcvResError,
            RcvRejected
        ]
    );
    ty!(PNIO_CTRL_COMM_COUNTER_DATA, [Port, NumberOfPorts]);
    ty!(PNIO_CBE_PRM_MODE_IND, [Mode]);
    ty!(
        PNIO_CBE_PRM_REC_READ_CONF,
        [pAddr, RecordIndex, ReqRef, Err, Length, pBuffer]
    );
    ty!(
        PNIO_CBE_PRM_REC_WRITE_CONF,
        [pAddr, RecordIndex, ReqRef, Err]
    );
    ty!(PNIO_CBE_PRM_ALARM_IND, [pAddr, IndRef, pAlarmData]);
    ty!(PNIO_CBE_PRM_DEV_ACT_CONF, [pAddr, Mode, Result]);
    ty!(PNIO_CBE_PRM_LED_FLASH, [Frequency]);
    ty!(PNIO_CBE_PRM_IOSYS_CONF, [pAddr, Mode, Status]);
    ty!(
        PNIO_CBE_PRM_CTRL_DIAG_CONF,
        [pDiagData, DiagDataBufferLen, pDiagDataBuffer, ErrorCode]
    );
    ty!(PNIO_PE_PRM_START_PAUSE_REQ, [time_ms]);
    ty!(PNIO_PE_PRM_Q_MODE_GET_MODE_REQ, [peModeId, reserved]);
    ty!(
        PNIO_PE_PRM_Q_MSRMT_GET_VAL_REQ,
        [num, reserved, Measurement_ID]
    );
    ty!(PNIO_PE_REQ_PRM, [CmdId, CmdModifier, rq]);
    ty!(PNIO_PE_PRM_GENERIC_CONF_NEG, [err_code, reserved]);
    ty!(PNIO_PE_PRM_START_PAUSE_CONF, [pe_mode_id]);
    ty!(PNIO_PE_PRM_END_PAUSE_CONF, [time_ms]);
    ty!(PNIO_PE_PRM_PE_IDENTIFY_CONF, [numServices, serviceId]);
    ty!(
        PNIO_PE_PRM_PEM_STATUS_CONF,
        [
            PE_Mode_ID_Source,
            PE_Mode_ID_Destination,
            Time_to_operate,
            Remaining_time_to_destination,
            Mode_Power_Consumption,
            Energy_Consumption_to_Destination,
            Energy_Consumption_to_operate
        ]
    );
    ty!(PNIO_PE_PRM_Q_MODE_LIST_ALL_CONF, [numModeIds, peModeId]);
    ty!(
        PNIO_PE_PRM_Q_MODE_GET_MODE_CONF,
        [
            peModeId,
            PE_Mode_Attributes,
            Time_min_Pause,
            Time_to_Pause,
            Time_to_operate,
            Time_min_length_of_stay,
            Time_max_length_of_stay,
            Mode_Power_Consumption,
            Energy_Consumption_to_pause,
            Energy_Consumption_to_operate
        ]
    );
    ty!(
        PNIO_PE_PRM_Q_MSRMT_LIST_ELEM,
        [Measurement_ID, Accuracy_Domain, Accuracy_Class, Range]
    );
    ty!(
        PNIO_PE_PRM_Q_MSRMT_GET_LIST_CONF,
        [numMeasurementIds, reserved, elem]
    );
    ty!(
        PNIO_PE_PRM_Q_MSRMT_VAL_ELEM,
        [
            Measurement_ID,
            Status_of_Measurement_Value,
            Transmission_Data_Type,
            End_of_demand,
            reserved
        ]
    );
    ty!(
        PNIO_PE_PRM_Q_MSRMT_GET_VAL_CONF,
        [numMeasurementValues, reserved, value]
    );
    ty!(
        PE_CBE_HDR,
        [CmdId, Handle, Addr, Ref, Err, state, struct_id, length]
    );
    ty!(PNIO_PE_CBE_PRM, [pe_hdr, pe_prm]);
    ty!(PNIO_IPv4, [IpAddress, NetMask, Gateway, Remanent]);
    ty!(PNIO_NOS, [Nos, Length, Remanent]);
    ty!(
        PNIO_CBE_PRM_SET_ADDR_CONF,
        [
            Mode,
            pStationName,
            StationNameLen,
            LocalIPAddress,
            LocalSubnetMask,
            DefaultRouterAddr,
            Options,
            Err
        ]
    );
    ty!(
        PNIO_CBE_PRM_REMA_READ_IND,
        [RemaXMLBuffer, RemaXMLBufferLength, Err]
    );
    ty!(PNIO_CBE_PRM, [CbeType, Handle]);
    // The anonymous union of PNIO_CBE_PRM: each member at the union's offset.
    let u = offset_of!(PNIO_CBE_PRM, u);
    for m in [
        "ModeInd",
        "RecReadConf",
        "RecWriteConf",
        "AlarmInd",
        "DevActConf",
        "LedFlash",
        "CtrlDiagConf",
        "IoSystemReconf",
        "SetAddrConf",
        "RemaReadConf",
    ] {
        offs.push(("PNIO_CBE_PRM", m, u));
    }
    ty!(PNIO_CP_CBE_PRM_STARTOP_IND, [AppHandle, CycleInfo]);
    // The manual's name of the same field (an anonymous union in C).
    offs.push((
        "PNIO_CP_CBE_PRM_STARTOP_IND",
        "CpHandle",
        offset_of!(PNIO_CP_CBE_PRM_STARTOP_IND, AppHandle),
    ));
    sizes.push((
        "PNIO_CP_CBE_PRM_OPFAULT_IND",
        size_of::<PNIO_CP_CBE_PRM_OPFAULT_IND>(),
        align_of::<PNIO_CP_CBE_PRM_OPFAULT_IND>(),
    ));
    sizes.push((
        "PNIO_CP_CBE_PRM_NEWCYCLE_IND",
        size_of::<PNIO_CP_CBE_PRM_NEWCYCLE_IND>(),
        align_of::<PNIO_CP_CBE_PRM_NEWCYCLE_IND>(),
    ));
    ty!(PNIO_CP_CBE_PRM, [CbeType, CpIndex, u]);
    // Enums are int-sized.
    for e in [
        "PNIO_ADDR_TYPE",
        "PNIO_IO_TYPE",
        "PNIO_IOXS",
        "PNIO_MODE_TYPE",
        "PNIO_DEV_ACT_TYPE",
        "PNIO_DATA_TYPE",
        "PNIO_COM_TYPE",
        "PNIO_CP_CBE_TYPE",
        "PNIO_CBE_TYPE",
        "PNIO_IOS_RECONFIG_MODE",
        "PNIO_CTRL_DIAG_ENUM",
        "PNIO_ALARM_TYPE",
        "PNIO_APRIO_TYPE",
        "PNIO_SET_IP_NOS_MODE_TYPE",
        "PNIO_PE_CMD_ENUM",
        "PNIO_PE_CMD_MODIFIER_ENUM",
    ] {
        sizes.push((e, size_of::<u32>(), align_of::<u32>()));
    }
    for (t, s) in [
        ("PNIO_UINT8", 1),
        ("PNIO_BOOL", 1),
        ("PNIO_UINT16", 2),
        ("PNIO_UINT32", 4),
        ("PNIO_REF", 4),
    ] {
        sizes.push((t, s, s));
    }
    (sizes, offs)
}

/// Every constant of the headers with its Rust value.
fn constants() -> Vec<(&'static str, u64)> {
    let mut v: Vec<(&'static str, u64)> = Vec::new();
    macro_rules! c {
        ($($n:ident),* $(,)?) => { $( v.push((stringify!($n), u64::from($n))); )* };
    }
    c!(
        PNIO_API_VERSION,
        PNIO_MAX_ALARM_DATA_LEN,
        PNIO_MAX_IO_LEN,
        PNIO_MAX_REC_LEN,
        PNIO_ADDR_LOG,
        PNIO_ADDR_GEO,
        PNIO_IO_IN,
        PNIO_IO_OUT,
        PNIO_S_GOOD,
        PNIO_S_BAD,
        PNIO_MODE_OFFLINE,
        PNIO_MODE_CLEAR,
        PNIO_MODE_OPERATE,
        PNIO_DA_FALSE,
        PNIO_DA_TRUE,
        PNIO_DATA_RT,
        PNIO_DATA_IRT,
        PNIO_COM_UNICAST,
        PNIO_COM_DIRECT_DATA_EX,
        PNIO_CP_CBE_UNKNOWN,
        PNIO_CP_CBE_STARTOP_IND,
        PNIO_CP_CBE_OPFAULT_IND,
        PNIO_CP_CBE_NEWCYCLE_IND,
        PNIO_CBE_MODE_IND,
        PNIO_CBE_ALARM_IND,
        PNIO_CBE_REC_READ_CONF,
        PNIO_CBE_REC_WRITE_CONF,
        PNIO_CBE_DEV_ACT_CONF,
        PNIO_CBE_CP_STOP_REQ,
        PNIO_CBE_START_LED_FLASH,
        PNIO_CBE_STOP_LED_FLASH,
        PNIO_CBE_CTRL_DIAG_CONF,
        PNIO_CBE_IFC_SET_ADDR_CONF,
        PNIO_CBE_REMA_READ_CONF,
        PNIO_CBE_IOSYSTEM_RECONFIG,
        PNIO_CBE_IFC_REC_READ_CONF,
        PNIO_CBE_IFC_ALARM_IND,
        PNIO_IOS_RECONFIG_MODE_DEACT,
        PNIO_IOS_RECONFIG_MODE_TAILOR,
        PNIO_CTRL_DIAG_RESERVED,
        PNIO_CTRL_DIAG_CONFIG_SUBMODULE_LIST,
        PNIO_CTRL_DIAG_DEVICE_STATE,
        PNIO_CTRL_DIAG_CONFIG_IOROUTER_PRESENT,
        PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE_LIST,
        PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO,
        PNIO_CTRL_DIAG_GET_COMM_COUNTER_DATA,
        PNIO_CTRL_DIAG_RESET_COMM_COUNTERS,
        PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC,
        PNIO_ALARM_DIAGNOSTIC,
        PNIO_ALARM_PROCESS,
        PNIO_ALARM_PULL,
        PNIO_ALARM_PLUG,
        PNIO_ALARM_STATUS,
        PNIO_ALARM_UPDATE,
        PNIO_ALARM_REDUNDANCY,
        PNIO_ALARM_CONTROLLED_BY_SUPERVISOR,
        PNIO_ALARM_RELEASED_BY_SUPERVISOR,
        PNIO_ALARM_PLUG_WRONG,
        PNIO_ALARM_RETURN_OF_SUBMODULE,
        PNIO_ALARM_DIAGNOSTIC_DISAPPEARS,
        PNIO_ALARM_MCR_MISMATCH,
        PNIO_ALARM_PORT_DATA_CHANGED,
        PNIO_ALARM_SYNC_DATA_CHANGED,
        PNIO_ALARM_ISOCHRONE_MODE_PROBLEM,
        PNIO_ALARM_NETWORK_COMPONENT_PROBLEM,
        PNIO_ALARM_UPLOAD_AND_STORAGE,
        PNIO_ALARM_PULL_MODULE,
        PNIO_ALARM_DEV_FAILURE,
        PNIO_ALARM_DEV_RETURN,
        PNIO_APRIO_LOW,
        PNIO_APRIO_HIGH,
        PNIO_CEP_MODE_CTRL,
        PNIO_CEP_DEV_MAXAR_BY_TYPE,
        PNIO_CEP_SLICE_ACCESS,
        PNIO_CEP_DEV_MAXAR_BY_TYPE_ADV,
        PNIO_CEP_PE_MODE_ENABLE,
        PNIO_CEP_SET_MRP_ROLE_OFF,
        PNIO_CTRL_DEV_DIAG_OFFLINE,
        PNIO_CTRL_DEV_DIAG_ADDR_INFO_OK,
        PNIO_CTRL_DEV_DIAG_AR_CONNECTING,
        PNIO_CTRL_DEV_DIAG_AR_IN_DATA,
        PNIO_CTRL_DEV_DIAG_AR_OFFLINE,
        PNIO_CTRL_DEV_DIAG_AR_RTC3_FOLLOWS,
        PNIO_SET_IP_MODE,
        PNIO_SET_NOS_MODE,
        PNIO_FALSE,
        PNIO_TRUE,
        PE_SAP_DR_INDEX,
        PE_MSRMT_IDS_MAX,
        PNIO_PE_SERVICE_REQ_LIFETIME_DEFAULT,
        PNIO_PE_CMD_RESERVED,
        PNIO_PE_CMD_START_PAUSE,
        PNIO_PE_CMD_END_PAUSE,
        PNIO_PE_CMD_Q_MODES,
        PNIO_PE_CMD_PEM_STATUS,
        PNIO_PE_CMD_PE_IDENTIFY,
        PNIO_PE_CMD_Q_MSRMT,
        PE_CMD_MODIF_NOT_USED,
        PE_CMD_MODIF_Q_MODE_LIST_ALL,
        PE_CMD_MODIF_Q_MODE_GET_MODE,
        PE_CMD_MODIF_Q_MSRMT_LIST_ALL,
        PE_CMD_MODIF_Q_MSRMT_GET_VAL,
        PE_CNF_STRUCT_ID_RESERVED,
        PE_CNF_STRUCT_ID_UNIQUE,
        PE_CNF_STRUCT_ID_QMODE_LIST_ALL,
        PE_CNF_STRUCT_ID_QMODE_GET_MODE,
        PE_CNF_STRUCT_ID_QMSRMT_LIST_ALL,
        PE_CNF_STRUCT_ID_QMSRMT_GET_VAL,
        PE_CNF_STRUCT_ID_ERROR,
    );
    for &(n, code) in PNIO_CTRL_REASONS.iter().chain(errors::ALL) {
        v.push((n, u64::from(code)));
    }
    v
}

/// `(function, C pointer type)`: the C side of each exported function's signature; the
/// Rust side is checked by [`rust_signatures_are_the_manuals`].
const FUNCTIONS: &[(&str, &str)] = &[
    (
        "PNIO_controller_open",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_UINT32, PNIO_CBF, PNIO_CBF, PNIO_CBF, PNIO_UINT32 *)",
    ),
    ("PNIO_controller_close", "PNIO_UINT32 (*)(PNIO_UINT32)"),
    (
        "PNIO_register_cbf",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_CBE_TYPE, PNIO_CBF)",
    ),
    (
        "PNIO_set_mode",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_MODE_TYPE)",
    ),
    (
        "PNIO_device_activate",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_ADDR *, PNIO_DEV_ACT_TYPE)",
    ),
    (
        "PNIO_data_read",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_ADDR *, PNIO_UINT32, PNIO_UINT32 *, PNIO_UINT8 *, PNIO_IOXS, PNIO_IOXS *)",
    ),
    (
        "PNIO_output_data_read",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_ADDR *, PNIO_UINT32, PNIO_UINT32 *, PNIO_UINT8 *, PNIO_IOXS *, PNIO_IOXS *)",
    ),
    (
        "PNIO_data_read_cache_refresh",
        "PNIO_UINT32 (*)(PNIO_UINT32)",
    ),
    (
        "PNIO_data_read_cache",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_ADDR *, PNIO_UINT32, PNIO_UINT32 *, PNIO_UINT8 *, PNIO_IOXS, PNIO_IOXS *)",
    ),
    (
        "PNIO_data_write",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_ADDR *, PNIO_UINT32, PNIO_UINT8 *, PNIO_IOXS, PNIO_IOXS *)",
    ),
    (
        "PNIO_data_write_cache",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_ADDR *, PNIO_UINT32, PNIO_UINT8 *, PNIO_IOXS, PNIO_IOXS *)",
    ),
    (
        "PNIO_data_write_cache_flush",
        "PNIO_UINT32 (*)(PNIO_UINT32)",
    ),
    (
        "PNIO_rec_read_req",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_ADDR *, PNIO_UINT32, PNIO_REF, PNIO_UINT32)",
    ),
    (
        "PNIO_rec_write_req",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_ADDR *, PNIO_UINT32, PNIO_REF, PNIO_UINT32, PNIO_UINT8 *)",
    ),
    (
        "PNIO_ctrl_diag_req",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_CTRL_DIAG *)",
    ),
    (
        "PNIO_iosystem_reconfig",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_IOS_RECONFIG_MODE, PNIO_UINT32, PNIO_ADDR *, PNIO_UINT32, PNIO_ADDR *)",
    ),
    (
        "PNIO_CP_register_cbf",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_CP_CBE_TYPE, PNIO_CP_CBF)",
    ),
    (
        "PNIO_CP_set_opdone",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_CYCLE_INFO *)",
    ),
    (
        "PNIO_CP_set_appl_watchdog",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_UINT32, PNIO_CBF_APPL_WATCHDOG)",
    ),
    ("PNIO_CP_trigger_watchdog", "PNIO_UINT32 (*)(PNIO_UINT32)"),
    (
        "PNIO_register_pe_cbf",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_PE_CBF)",
    ),
    (
        "PNIO_pe_cmd_req",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_ADDR *, PNIO_REF, PNIO_PE_REQ_PRM *)",
    ),
    (
        "PNIO_interface_open",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_CBF, PNIO_CBF, PNIO_UINT32 *)",
    ),
    (
        "PNIO_interface_register_cbf",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_CBE_TYPE, PNIO_CBF)",
    ),
    ("PNIO_interface_close", "PNIO_UINT32 (*)(PNIO_UINT32)"),
    (
        "PNIO_interface_set_ip_and_nos",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_SET_IP_NOS_MODE_TYPE, PNIO_IPv4, PNIO_NOS)",
    ),
    (
        "PNIO_interface_rec_read_req",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_ADDR *, PNIO_UINT32, PNIO_REF, PNIO_UINT32)",
    ),
];

/// The Rust functions have the manual's parameter types (as the C types map to Rust).
#[test]
fn rust_signatures_are_the_manuals() {
    type U = PNIO_UINT32;
    let _: unsafe extern "C" fn(U, U, PNIO_CBF, PNIO_CBF, PNIO_CBF, *mut U) -> U =
        PNIO_controller_open;
    let _: unsafe extern "C" fn(U) -> U = PNIO_controller_close;
    let _: unsafe extern "C" fn(U, PNIO_CBE_TYPE, PNIO_CBF) -> U = PNIO_register_cbf;
    let _: unsafe extern "C" fn(U, PNIO_MODE_TYPE) -> U = PNIO_set_mode;
    let _: unsafe extern "C" fn(U, *mut PNIO_ADDR, PNIO_DEV_ACT_TYPE) -> U = PNIO_device_activate;
    let _: unsafe extern "C" fn(
        U,
        *mut PNIO_ADDR,
        U,
        *mut U,
        *mut u8,
        PNIO_IOXS,
        *mut PNIO_IOXS,
    ) -> U = PNIO_data_read;
    let _: unsafe extern "C" fn(
        U,
        *mut PNIO_ADDR,
        U,
        *mut U,
        *mut u8,
        *mut PNIO_IOXS,
        *mut PNIO_IOXS,
    ) -> U = PNIO_output_data_read;
    let _: unsafe extern "C" fn(U) -> U = PNIO_data_read_cache_refresh;
    let _: unsafe extern "C" fn(
        U,
        *mut PNIO_ADDR,
        U,
        *mut U,
        *mut u8,
        PNIO_IOXS,
        *mut PNIO_IOXS,
    ) -> U = PNIO_data_read_cache;
    let _: unsafe extern "C" fn(U, *mut PNIO_ADDR, U, *mut u8, PNIO_IOXS, *mut PNIO_IOXS) -> U =
        PNIO_data_write;
    let _: unsafe extern "C" fn(U, *mut PNIO_ADDR, U, *mut u8, PNIO_IOXS, *mut PNIO_IOXS) -> U =
        PNIO_data_write_cache;
    let _: unsafe extern "C" fn(U) -> U = PNIO_data_write_cache_flush;
    let _: unsafe extern "C" fn(U, *mut PNIO_ADDR, U, PNIO_REF, U) -> U = PNIO_rec_read_req;
    let _: unsafe extern "C" fn(U, *mut PNIO_ADDR, U, PNIO_REF, U, *mut u8) -> U =
        PNIO_rec_write_req;
    let _: unsafe extern "C" fn(U, *mut PNIO_CTRL_DIAG) -> U = PNIO_ctrl_diag_req;
    let _: unsafe extern "C" fn(
        U,
        PNIO_IOS_RECONFIG_MODE,
        U,
        *mut PNIO_ADDR,
        U,
        *mut PNIO_ADDR,
    ) -> U = PNIO_iosystem_reconfig;
    let _: unsafe extern "C" fn(U, PNIO_CP_CBE_TYPE, PNIO_CP_CBF) -> U = PNIO_CP_register_cbf;
    let _: unsafe extern "C" fn(U, *mut PNIO_CYCLE_INFO) -> U = PNIO_CP_set_opdone;
    let _: unsafe extern "C" fn(U, U, PNIO_CBF_APPL_WATCHDOG) -> U = PNIO_CP_set_appl_watchdog;
    let _: unsafe extern "C" fn(U) -> U = PNIO_CP_trigger_watchdog;
    // The callback's type is the manual's: void (*)(PNIO_UINT32).
    let _: PNIO_CBF_APPL_WATCHDOG = None::<unsafe extern "C" fn(U)>;
    let _: unsafe extern "C" fn(U, PNIO_CBF, PNIO_CBF, *mut U) -> U = PNIO_interface_open;
    let _: unsafe extern "C" fn(U, PNIO_CBE_TYPE, PNIO_CBF) -> U = PNIO_interface_register_cbf;
    let _: unsafe extern "C" fn(U) -> U = PNIO_interface_close;
    let _: unsafe extern "C" fn(U, PNIO_SET_IP_NOS_MODE_TYPE, PNIO_IPv4, PNIO_NOS) -> U =
        PNIO_interface_set_ip_and_nos;
    let _: unsafe extern "C" fn(U, *mut PNIO_ADDR, U, PNIO_REF, U) -> U =
        PNIO_interface_rec_read_req;
    let _: unsafe extern "C" fn(U, PNIO_PE_CBF) -> U = PNIO_register_pe_cbf;
    let _: unsafe extern "C" fn(U, *mut PNIO_ADDR, PNIO_REF, *mut PNIO_PE_REQ_PRM) -> U =
        PNIO_pe_cmd_req;
    let _: PNIO_PE_CBF = None::<unsafe extern "C" fn(*mut PNIO_PE_CBE_PRM)>;
    assert_eq!(FUNCTIONS.len(), 27);
}

fn program(cpp: bool) -> String {
    let (sizes, offsets) = layout_facts();
    header_program::header_program(
        cpp,
        &header_program::HeaderFacts {
            header: "pniousrx.h",
            functions: FUNCTIONS,
            // The watchdog's callback type has the manual's shape.
            callbacks: &[
                ("void (*)(PNIO_UINT32)", "PNIO_CBF_APPL_WATCHDOG"),
                ("void (*)(PNIO_PE_CBE_PRM *)", "PNIO_PE_CBF"),
            ],
            sizes: &sizes,
            offsets: &offsets,
            constants: &constants(),
        },
    )
}

/// Linked with the library: every function the header declares must be exported.
#[test]
fn c11_and_cpp17_agree_with_rust() {
    layout_check::build_and_run_c11_and_cpp17("iobase-header", program, "src/iobase");
}

/// Each header stands alone: a program may include just one of them.
#[test]
fn each_header_compiles_alone() {
    // Each twice: the include guards hold.
    layout_check::headers_compile_alone(
        "iobase-alone",
        &[
            &["pnioerrx.h", "pnioerrx.h"],
            &["pniobase.h", "pniobase.h"],
            &["pniousrx.h", "pniousrx.h"],
        ],
    );
}

/// The named reason constants of the Rust side are the table's.
#[test]
fn reason_constants_match_their_table() {
    for (n, v) in [
        ("PNIO_CTRL_REASON_NONE", PNIO_CTRL_REASON_NONE),
        (
            "PNIO_CTRL_REASON_NARE_ERR_DCP_STATION_NOT_FOUND",
            PNIO_CTRL_REASON_NARE_ERR_DCP_STATION_NOT_FOUND,
        ),
        (
            "PNIO_CTRL_REASON_CLRPC_ERR_TIMEOUT",
            PNIO_CTRL_REASON_CLRPC_ERR_TIMEOUT,
        ),
        (
            "PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_LINK",
            PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_LINK,
        ),
        (
            "PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_MISS",
            PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_MISS,
        ),
        ("PNIO_CTRL_REASON_IOD_ABORTED", PNIO_CTRL_REASON_IOD_ABORTED),
        ("PNIO_CTRL_REASON_IOC_ABORTED", PNIO_CTRL_REASON_IOC_ABORTED),
        (
            "PNIO_CTRL_REASON_IOD_NOT_FOUND",
            PNIO_CTRL_REASON_IOD_NOT_FOUND,
        ),
        ("PNIO_CTRL_REASON_RPC_TIMEOUT", PNIO_CTRL_REASON_RPC_TIMEOUT),
        (
            "PNIO_CTRL_REASON_MP_DEVICE_DISABLED",
            PNIO_CTRL_REASON_MP_DEVICE_DISABLED,
        ),
        ("PNIO_CTRL_REASON_RPC_ERROR", PNIO_CTRL_REASON_RPC_ERROR),
        (
            "PNIO_CTRL_REASON_PNIO_CONFIGURATION",
            PNIO_CTRL_REASON_PNIO_CONFIGURATION,
        ),
        (
            "PNIO_CTRL_REASON_IP_SET_ABORTED",
            PNIO_CTRL_REASON_IP_SET_ABORTED,
        ),
        ("PNIO_CTRL_REASON_MISS", PNIO_CTRL_REASON_MISS),
    ] {
        assert_eq!(
            PNIO_CTRL_REASONS
                .iter()
                .find(|(name, _)| *name == n)
                .map(|x| x.1),
            Some(v),
            "{n}"
        );
    }
}
