// SPDX-License-Identifier: MIT OR Apache-2.0
//! Rust mirrors of the PROFIenergy types of `pniousrx.h`, with the C names; laid out as
//! [`super::types`] says (structs of bytes and 16-bit words take `align(4)`).
#![allow(non_camel_case_types, non_snake_case)]

use super::types::{PNIO_ADDR, PNIO_ERR_STAT, PNIO_REF, PNIO_UINT8, PNIO_UINT16, PNIO_UINT32};

/// `PE_SAP_DR_INDEX`: PE's record.
pub const PE_SAP_DR_INDEX: u32 = 0x80a0;
/// `PE_MSRMT_IDS_MAX`.
pub const PE_MSRMT_IDS_MAX: u32 = 254;
/// `PNIO_PE_SERVICE_REQ_LIFETIME_DEFAULT`, seconds.
pub const PNIO_PE_SERVICE_REQ_LIFETIME_DEFAULT: u32 = 10;

/// `PNIO_PE_CMD_ENUM`.
pub type PNIO_PE_CMD_ENUM = u32;
/// Reserved.
pub const PNIO_PE_CMD_RESERVED: PNIO_PE_CMD_ENUM = 0;
/// Start_Pause.
pub const PNIO_PE_CMD_START_PAUSE: PNIO_PE_CMD_ENUM = 1;
/// End_Pause.
pub const PNIO_PE_CMD_END_PAUSE: PNIO_PE_CMD_ENUM = 2;
/// Query_Modes.
pub const PNIO_PE_CMD_Q_MODES: PNIO_PE_CMD_ENUM = 3;
/// PEM_Status.
pub const PNIO_PE_CMD_PEM_STATUS: PNIO_PE_CMD_ENUM = 4;
/// PE_Identify.
pub const PNIO_PE_CMD_PE_IDENTIFY: PNIO_PE_CMD_ENUM = 5;
/// Query_Measurement.
pub const PNIO_PE_CMD_Q_MSRMT: PNIO_PE_CMD_ENUM = 16;

/// `PNIO_PE_CMD_MODIFIER_ENUM`.
pub type PNIO_PE_CMD_MODIFIER_ENUM = u32;
/// No modifier.
pub const PE_CMD_MODIF_NOT_USED: PNIO_PE_CMD_MODIFIER_ENUM = 0;
/// Query_Modes: the list.
pub const PE_CMD_MODIF_Q_MODE_LIST_ALL: PNIO_PE_CMD_MODIFIER_ENUM = 1;
/// Query_Modes: one mode.
pub const PE_CMD_MODIF_Q_MODE_GET_MODE: PNIO_PE_CMD_MODIFIER_ENUM = 2;
/// Query_Measurement: the list.
pub const PE_CMD_MODIF_Q_MSRMT_LIST_ALL: PNIO_PE_CMD_MODIFIER_ENUM = 1;
/// Query_Measurement: values.
pub const PE_CMD_MODIF_Q_MSRMT_GET_VAL: PNIO_PE_CMD_MODIFIER_ENUM = 2;

/// `PE_CNF_STRUCT_ID_RESERVED`.
pub const PE_CNF_STRUCT_ID_RESERVED: u16 = 0;
/// `PE_CNF_STRUCT_ID_UNIQUE`.
pub const PE_CNF_STRUCT_ID_UNIQUE: u16 = 1;
/// `PE_CNF_STRUCT_ID_QMODE_LIST_ALL`.
pub const PE_CNF_STRUCT_ID_QMODE_LIST_ALL: u16 = 1;
/// `PE_CNF_STRUCT_ID_QMODE_GET_MODE`.
pub const PE_CNF_STRUCT_ID_QMODE_GET_MODE: u16 = 2;
/// `PE_CNF_STRUCT_ID_QMSRMT_LIST_ALL`.
pub const PE_CNF_STRUCT_ID_QMSRMT_LIST_ALL: u16 = 1;
/// `PE_CNF_STRUCT_ID_QMSRMT_GET_VAL`.
pub const PE_CNF_STRUCT_ID_QMSRMT_GET_VAL: u16 = 2;
/// `PE_CNF_STRUCT_ID_ERROR`.
pub const PE_CNF_STRUCT_ID_ERROR: u16 = 0xff;

/// `PNIO_PE_PRM_START_PAUSE_REQ`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_PE_PRM_START_PAUSE_REQ {
    /// The pause expected, ms.
    pub time_ms: PNIO_UINT32,
}

/// `PNIO_PE_PRM_Q_MODE_GET_MODE_REQ`.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_PE_PRM_Q_MODE_GET_MODE_REQ {
    /// PE_Mode_ID.
    pub peModeId: PNIO_UINT8,
    /// Reserved.
    pub reserved: PNIO_UINT8,
}

/// `PNIO_PE_PRM_Q_MSRMT_GET_VAL_REQ`.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_PE_PRM_Q_MSRMT_GET_VAL_REQ {
    /// Measurement_IDs used.
    pub num: PNIO_UINT8,
    /// Reserved.
    pub reserved: PNIO_UINT8,
    /// Measurement_IDs.
    pub Measurement_ID: [PNIO_UINT16; PE_MSRMT_IDS_MAX as usize],
}

/// The union of `PNIO_PE_REQ_PRM`.
#[repr(C)]
#[derive(Clone, Copy)]
pub union PNIO_PE_REQ_PRM_rq {
    /// Start_Pause.
    pub StartPause: PNIO_PE_PRM_START_PAUSE_REQ,
    /// Query_Modes Get_Mode.
    pub ModeGet: PNIO_PE_PRM_Q_MODE_GET_MODE_REQ,
    /// Query_Measurement values.
    pub MeasurementValue: PNIO_PE_PRM_Q_MSRMT_GET_VAL_REQ,
}

/// `PNIO_PE_REQ_PRM`: a PE command.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PNIO_PE_REQ_PRM {
    /// The command.
    pub CmdId: PNIO_PE_CMD_ENUM,
    /// Its modifier.
    pub CmdModifier: PNIO_PE_CMD_MODIFIER_ENUM,
    /// Its parameters.
    pub rq: PNIO_PE_REQ_PRM_rq,
}

/// `PNIO_PE_PRM_GENERIC_CONF_NEG`.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_PE_PRM_GENERIC_CONF_NEG {
    /// The device's PE Error_Code.
    pub err_code: PNIO_UINT8,
    /// Reserved.
    pub reserved: PNIO_UINT8,
}

/// `PNIO_PE_PRM_START_PAUSE_CONF`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_PE_PRM_START_PAUSE_CONF {
    /// The mode reached.
    pub pe_mode_id: PNIO_UINT32,
}

/// `PNIO_PE_PRM_END_PAUSE_CONF`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_PE_PRM_END_PAUSE_CONF {
    /// Until ready to operate, ms.
    pub time_ms: PNIO_UINT32,
}

/// `PNIO_PE_PRM_PE_IDENTIFY_CONF`.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_PE_PRM_PE_IDENTIFY_CONF {
    /// Services listed.
    pub numServices: PNIO_UINT8,
    /// Service_Request_IDs.
    pub serviceId: [PNIO_UINT8; 254],
}

/// `PNIO_PE_PRM_PEM_STATUS_CONF`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PNIO_PE_PRM_PEM_STATUS_CONF {
    /// PE_Mode_ID_Source.
    pub PE_Mode_ID_Source: PNIO_UINT8,
    /// PE_Mode_ID_Destination.
    pub PE_Mode_ID_Destination: PNIO_UINT8,
    /// Time_to_operate, ms.
    pub Time_to_operate: PNIO_UINT32,
    /// Remaining_time_to_destination, ms.
    pub Remaining_time_to_destination: PNIO_UINT32,
    /// Mode_Power_Consumption, kW.
    pub Mode_Power_Consumption: f32,
    /// Energy_Consumption_to_Destination, kWh.
    pub Energy_Consumption_to_Destination: f32,
    /// Energy_Consumption_to_operate, kWh.
    pub Energy_Consumption_to_operate: f32,
}

/// `PNIO_PE_PRM_Q_MODE_LIST_ALL_CONF`.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_PE_PRM_Q_MODE_LIST_ALL_CONF {
    /// Modes listed.
    pub numModeIds: PNIO_UINT8,
    /// PE_Mode_IDs.
    pub peModeId: [PNIO_UINT8; 254],
}

/// `PNIO_PE_PRM_Q_MODE_GET_MODE_CONF`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PNIO_PE_PRM_Q_MODE_GET_MODE_CONF {
    /// PE_Mode_ID.
    pub peModeId: PNIO_UINT8,
    /// PE_Mode_Attributes.
    pub PE_Mode_Attributes: PNIO_UINT8,
    /// Time_min_Pause, ms.
    pub Time_min_Pause: PNIO_UINT32,
    /// Time_to_Pause, ms.
    pub Time_to_Pause: PNIO_UINT32,
    /// Time_to_operate, ms.
    pub Time_to_operate: PNIO_UINT32,
    /// Time_min_length_of_stay, ms.
    pub Time_min_length_of_stay: PNIO_UINT32,
    /// Time_max_length_of_stay, ms.
    pub Time_max_length_of_stay: PNIO_UINT32,
    /// Mode_Power_Consumption, kW.
    pub Mode_Power_Consumption: f32,
    /// Energy_Consumption_to_pause, kWh.
    pub Energy_Consumption_to_pause: f32,
    /// Energy_Consumption_to_operate, kWh.
    pub Energy_Consumption_to_operate: f32,
}

/// `PNIO_PE_PRM_Q_MSRMT_LIST_ELEM`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PNIO_PE_PRM_Q_MSRMT_LIST_ELEM {
    /// Measurement_ID.
    pub Measurement_ID: PNIO_UINT16,
    /// Accuracy_Domain.
    pub Accuracy_Domain: PNIO_UINT8,
    /// Accuracy_Class.
    pub Accuracy_Class: PNIO_UINT8,
    /// Range.
    pub Range: f32,
}

/// `PNIO_PE_PRM_Q_MSRMT_GET_LIST_CONF`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_PE_PRM_Q_MSRMT_GET_LIST_CONF {
    /// Measurements listed.
    pub numMeasurementIds: PNIO_UINT8,
    /// Reserved.
    pub reserved: PNIO_UINT8,
    /// Them.
    pub elem: [PNIO_PE_PRM_Q_MSRMT_LIST_ELEM; PE_MSRMT_IDS_MAX as usize],
}

/// `PNIO_PE_PRM_Q_MSRMT_VAL_ELEM`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PNIO_PE_PRM_Q_MSRMT_VAL_ELEM {
    /// Measurement_ID.
    pub Measurement_ID: PNIO_UINT16,
    /// Status_of_Measurement_Value.
    pub Status_of_Measurement_Value: PNIO_UINT16,
    /// The value.
    pub Transmission_Data_Type: f32,
    /// End_of_demand.
    pub End_of_demand: PNIO_UINT32,
    /// Reserved.
    pub reserved: PNIO_UINT32,
}

/// `PNIO_PE_PRM_Q_MSRMT_GET_VAL_CONF`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_PE_PRM_Q_MSRMT_GET_VAL_CONF {
    /// Values listed.
    pub numMeasurementValues: PNIO_UINT8,
    /// Reserved.
    pub reserved: PNIO_UINT8,
    /// Them.
    pub value: [PNIO_PE_PRM_Q_MSRMT_VAL_ELEM; PE_MSRMT_IDS_MAX as usize],
}

/// `PE_CBE_HDR`.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PE_CBE_HDR {
    /// The command.
    pub CmdId: PNIO_PE_CMD_ENUM,
    /// The controller's handle.
    pub Handle: PNIO_UINT32,
    /// The address the command went to.
    pub Addr: PNIO_ADDR,
    /// The caller's reference.
    pub Ref: PNIO_REF,
    /// The record jobs' status.
    pub Err: PNIO_ERR_STAT,
    /// 1 answered, 2 refused or not carried out.
    pub state: PNIO_UINT16,
    /// Which member of `pe_prm`.
    pub struct_id: PNIO_UINT16,
    /// Bytes of that member.
    pub length: PNIO_UINT32,
}

/// The union of `PNIO_PE_CBE_PRM`.
#[repr(C)]
#[derive(Clone, Copy)]
pub union PNIO_PE_CBE_PRM_pe_prm {
    /// A refusal.
    pub RespNegative: PNIO_PE_PRM_GENERIC_CONF_NEG,
    /// Start_Pause.
    pub StartPause: PNIO_PE_PRM_START_PAUSE_CONF,
    /// End_Pause.
    pub EndPause: PNIO_PE_PRM_END_PAUSE_CONF,
    /// PE_Identify.
    pub PeIdentify: PNIO_PE_PRM_PE_IDENTIFY_CONF,
    /// PEM_Status.
    pub PemStatus: PNIO_PE_PRM_PEM_STATUS_CONF,
    /// Query_Modes list.
    pub ModeList: PNIO_PE_PRM_Q_MODE_LIST_ALL_CONF,
    /// Query_Modes one mode.
    pub ModeGet: PNIO_PE_PRM_Q_MODE_GET_MODE_CONF,
    /// Query_Measurement list.
    pub MeasurementList: PNIO_PE_PRM_Q_MSRMT_GET_LIST_CONF,
    /// Query_Measurement values.
    pub MeasurementValue: PNIO_PE_PRM_Q_MSRMT_GET_VAL_CONF,
}

/// `PNIO_PE_CBE_PRM`: what the PE callback receives.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PNIO_PE_CBE_PRM {
    /// The header.
    pub pe_hdr: PE_CBE_HDR,
    /// The answer.
    pub pe_prm: PNIO_PE_CBE_PRM_pe_prm,
}

/// `PNIO_PE_CBF`: the PE confirmation callback.
pub type PNIO_PE_CBF = Option<unsafe extern "C" fn(pPeCbfPrm: *mut PNIO_PE_CBE_PRM)>;
