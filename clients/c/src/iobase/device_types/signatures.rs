// SPDX-License-Identifier: MIT OR Apache-2.0
//! The C spelling of every callback typedef and function prototype of `pniousrd.h`, and the
//! Rust types they are made of, as the [module above](super) says.

#![allow(non_camel_case_types, non_snake_case)]

use super::*;
use crate::iobase::types::{PNIO_ERR_STAT, PNIO_IOXS};
use crate::iobase::types::{PNIO_UINT8, PNIO_UINT16, PNIO_UINT32};
use core::mem::size_of;

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
/// `PNIO_device_open`. In C the members `cbf_cp_stop_req` and `cbf_device_stopped` have the
/// manual's names, `pnio_cbf_cp_stop_req` and `pnio_cbf_device_stopped`, and IO-Base's
/// header's names are macros for them: a plain struct, initialised positionally or by
/// designators.
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
