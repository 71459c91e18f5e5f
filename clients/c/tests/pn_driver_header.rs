// SPDX-License-Identifier: MIT OR Apache-2.0
//! The hand-written `servusrx.h` (PN Driver's start-up) must agree with its Rust mirrors in
//! `src/iobase/pn_driver_types.rs` and the functions of `src/iobase/pn_driver.rs`: every
//! struct's size, alignment and field offsets, every constant's value and every function's
//! signature, as a C11 and a C++17 compiler see them.

use procimg::iobase::pn_driver::*;
use procimg::iobase::pn_driver_types::*;
use procimg::iobase::types::{PNIO_UINT8, PNIO_UINT32};
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
    ty!(PNIO_PCI_LOCATION_TYPE, [BusNr, DeviceNr, FunctionNr]);
    ty!(PNIO_DEBUG_SETTINGS_TYPE, [CbfPntrcBufferFull, TraceLevels]);
    ty!(
        PNIO_CP_ID_TYPE,
        [CpSelection, CpMacAddr, CpPciLocation, Description]
    );
    ty!(
        PNIO_SW_VERSION_TYPE,
        [
            revision_prefix,
            functional_enhancement,
            bug_fix,
            internal_change
        ]
    );
    ty!(
        PNIO_SYSTEM_DESCR,
        [
            Vendor,
            ProductFamily,
            ProductSerialNr,
            IM_DeviceType,
            IM_OrderId,
            IM_HwRevision,
            IM_SwVersion,
            IM_RevisionCounter,
            IM_Version,
            IM_Supported,
            IM_ProfileSpecificType,
            IM_ProfileId
        ]
    );
    ty!(SERV_FW_VERS_TYPE, [v1, v2, v3, v4, v5, reserved]);
    ty!(
        SERV_CP_FW_INFO_TYPE,
        [
            fw_version,
            cp_ser_nr,
            mlfb,
            hw_version,
            mac,
            ip_addr,
            ip_mask,
            default_router,
            name,
            TypeOfStation
        ]
    );
    ty!(
        SERV_CIB_PDEV_EXTCHNL_DIAG,
        [
            Channel, Properties, ErrType, ExtErrType, ExtAdvAlLo, ExtAdvAlHi
        ]
    );
    ty!(
        SERV_CIB_PDEV_DATA,
        [
            Version,
            IODataType,
            LogAddr,
            Slot,
            Subslot,
            AlarmType,
            AlarmPriority,
            AlarmSequence,
            StationNr,
            Reserved1,
            Reserved2,
            AlarmTinfo,
            Diagnostics,
            DiagDs,
            AlarmAinfo
        ]
    );
    ty!(
        SERV_CIB_PDEV_INIT_STATE,
        [
            Reserved1, Reserved2, Reserved3, IODataType, LogAddr, Slot, Subslot, PortState,
            Reserved4
        ]
    );
    ty!(SERV_CIB_PDEV_INIT_DATA, [ItemNumber, InitState]);
    ty!(SERV_CIB_LED, [LedType, LedState, Reserved1]);
    ty!(SERV_CP_INFO_PRM, [Version, Handle, CpIndex, InfoType, u]);
    for e in [
        "SERV_CP_INFO_TYPE",
        "SERV_CIB_LED_TYPE",
        "SERV_CIB_LED_STATE",
        "PNIO_CP_SELECT_TYPE",
        "pnio_stack_comp",
        "pnio_trace_level",
        "PNIO_CP_DLD_TYPE",
        "PNIO_CP_RESET_TYPE",
    ] {
        sizes.push((e, size_of::<u32>(), align_of::<u32>()));
    }
    sizes.push(("PNIO_MAC_ADDR_TYPE", 6, 1));
    (sizes, offs)
}

/// Every constant of the header with its Rust value.
fn constants() -> Vec<(&'static str, u64)> {
    let mut v: Vec<(&'static str, u64)> = Vec::new();
    macro_rules! c {
        ($($n:ident),* $(,)?) => { $( v.push((stringify!($n), u64::from($n))); )* };
    }
    c!(
        PROCIMG_MAX_NETWORK_ADAPTERS,
        PROCIMG_TRACE_BUFFER_SIZE,
        PNIO_TRACE_COMP_PND,
        PNIO_TRACE_COMP_NUM,
        PNIO_TRACE_LEVEL_OFF,
        PNIO_TRACE_LEVEL_FATAL,
        PNIO_TRACE_LEVEL_ERROR,
        PNIO_TRACE_LEVEL_UNEXP,
        PNIO_TRACE_LEVEL_WARN,
        PNIO_TRACE_LEVEL_NOTE_HIGH,
        PNIO_TRACE_LEVEL_NOTE,
        PNIO_TRACE_LEVEL_NOTE_LOW,
        PNIO_TRACE_LEVEL_CHAT,
        PNIO_TRACE_LEVEL_NUM,
        PNIO_CP_SELECT_WITH_PCI_LOCATION,
        PNIO_CP_SELECT_WITH_MAC_ADDRESS,
        PNIO_MAC_ADDR_SIZE,
        PNIO_CP_DLD_FIRMWARE,
        PNIO_CP_DLD_CONFIG,
        PNIO_CP_RESET_SAFE,
        PNIO_CP_RESET_FORCE,
        SERV_CP_INFO_STOP_REQ,
        SERV_CP_INFO_PDEV_DATA,
        SERV_CP_INFO_PDEV_INIT_DATA,
        SERV_CP_INFO_LED_STATE,
        SERV_CIB_PDEV_MAX_PORT_ITEMS,
        SERV_CIB_PDEV_PORT_STATE_DISTURBED,
        SERV_CIB_PDEV_PORT_STATE_EXISTS,
        SERV_CIB_PDEV_PORT_STATE_NOT_AVAILABLE,
        SERV_CIB_PDEV_PORT_STATE_MAINTENANCE_REQUIRED,
        SERV_CIB_PDEV_PORT_STATE_MAINTENANCE_DEMANDED,
        SERV_CIB_LED_BF,
        SERV_CIB_LED_SF,
        SERV_CIB_LED_OFF,
        SERV_CIB_LED_ON,
    );
    for (value, name) in PNIO_TRACE_COMPONENTS.iter().enumerate() {
        v.push((name, value as u64));
    }
    v
}

/// `(function, C pointer type)`.
const FUNCTIONS: &[(&str, &str)] = &[
    (
        "SERV_CP_init",
        "PNIO_UINT32 (*)(PNIO_DEBUG_SETTINGS_PTR_TYPE)",
    ),
    ("SERV_CP_undo_init", "PNIO_UINT32 (*)(void)"),
    (
        "SERV_CP_get_network_adapters",
        "PNIO_UINT32 (*)(PNIO_CP_ID_PTR_TYPE, PNIO_UINT8 *)",
    ),
    (
        "SERV_CP_startup",
        "PNIO_UINT32 (*)(PNIO_CP_ID_PTR_TYPE, PNIO_UINT32, PNIO_UINT8 *, PNIO_UINT32, PNIO_UINT8 *, PNIO_UINT32, PNIO_SYSTEM_DESCR *)",
    ),
    ("SERV_CP_shutdown", "PNIO_UINT32 (*)(void)"),
    (
        "SERV_CP_set_trace_level",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_UINT32, PNIO_PNTRC_SET_TRACE_LEVEL_DONE)",
    ),
    (
        "SERV_CP_get_fw_info",
        "PNIO_UINT32 (*)(PNIO_UINT32, SERV_CP_FW_INFO_TYPE *)",
    ),
    (
        "SERV_CP_set_type_of_station",
        "PNIO_UINT32 (*)(PNIO_UINT32, char *)",
    ),
    (
        "SERV_CP_download",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_CP_DLD_TYPE, PNIO_UINT8 *, PNIO_UINT32)",
    ),
    (
        "SERV_CP_reset",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_CP_RESET_TYPE)",
    ),
    (
        "SERV_CP_info_open",
        "PNIO_UINT32 (*)(PNIO_UINT32, PNIO_UINT32 *, PNIO_UINT32)",
    ),
    ("SERV_CP_info_close", "PNIO_UINT32 (*)(PNIO_UINT32)"),
    (
        "SERV_CP_info_register_cbf",
        "PNIO_UINT32 (*)(PNIO_UINT32, SERV_CP_INFO_TYPE, SERV_CP_INFO_CBF, PNIO_UINT32)",
    ),
];

/// The Rust side of each exported function has the manual's signature.
#[test]
fn rust_signatures_are_the_manuals() {
    type U = PNIO_UINT32;
    let _: unsafe extern "C" fn(*mut PNIO_DEBUG_SETTINGS_TYPE) -> U = SERV_CP_init;
    let _: unsafe extern "C" fn() -> U = SERV_CP_undo_init;
    let _: unsafe extern "C" fn(*mut PNIO_CP_ID_TYPE, *mut PNIO_UINT8) -> U =
        SERV_CP_get_network_adapters;
    let _: unsafe extern "C" fn(
        *mut PNIO_CP_ID_TYPE,
        U,
        *mut PNIO_UINT8,
        U,
        *mut PNIO_UINT8,
        U,
        *mut PNIO_SYSTEM_DESCR,
    ) -> U = SERV_CP_startup;
    let _: unsafe extern "C" fn() -> U = SERV_CP_shutdown;
    let _: unsafe extern "C" fn(U, U, PNIO_PNTRC_SET_TRACE_LEVEL_DONE) -> U =
        SERV_CP_set_trace_level;
    let _: unsafe extern "C" fn(U, *mut SERV_CP_FW_INFO_TYPE) -> U =
        procimg::iobase::cp_services::SERV_CP_get_fw_info;
    let _: unsafe extern "C" fn(U, *mut core::ffi::c_char) -> U =
        procimg::iobase::cp_services::SERV_CP_set_type_of_station;
    let _: unsafe extern "C" fn(U, PNIO_CP_DLD_TYPE, *mut PNIO_UINT8, U) -> U =
        procimg::iobase::cp_services::SERV_CP_download;
    let _: unsafe extern "C" fn(U, PNIO_CP_RESET_TYPE) -> U =
        procimg::iobase::cp_services::SERV_CP_reset;
    let _: unsafe extern "C" fn(U, *mut U, U) -> U = procimg::iobase::cp_info::SERV_CP_info_open;
    let _: unsafe extern "C" fn(U) -> U = procimg::iobase::cp_info::SERV_CP_info_close;
    let _: unsafe extern "C" fn(U, SERV_CP_INFO_TYPE, SERV_CP_INFO_CBF, U) -> U =
        procimg::iobase::cp_info::SERV_CP_info_register_cbf;
    let _: SERV_CP_INFO_CBF = None::<unsafe extern "C" fn(*mut SERV_CP_INFO_PRM)>;
    let _: PNIO_PNTRC_BUFFER_FULL = None::<unsafe extern "C" fn(*mut PNIO_UINT8, U)>;
    assert_eq!(FUNCTIONS.len(), 13);
}

fn program(cpp: bool) -> String {
    let (sizes, offsets) = layout_facts();
    header_program::header_program(
        cpp,
        &header_program::HeaderFacts {
            header: "servusrx.h",
            functions: FUNCTIONS,
            callbacks: &[
                (
                    "void (*)(PNIO_UINT8 *, PNIO_UINT32)",
                    "PNIO_PNTRC_BUFFER_FULL",
                ),
                ("void (*)(void)", "PNIO_PNTRC_SET_TRACE_LEVEL_DONE"),
                ("void (*)(SERV_CP_INFO_PRM *)", "SERV_CP_INFO_CBF"),
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
    layout_check::build_and_run_c11_and_cpp17("pn-driver-header", program, "src/iobase");
}

/// The header stands alone, and beside the controller's.
#[test]
fn the_header_compiles_alone_and_with_pniousrx() {
    layout_check::headers_compile_alone(
        "pn-driver-alone",
        &[&["servusrx.h", "servusrx.h"], &["pniousrx.h", "servusrx.h"]],
    );
}
