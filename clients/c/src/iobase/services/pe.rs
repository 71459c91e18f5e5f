// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFIenergy on a controller (`PNIO_register_pe_cbf`, `PNIO_pe_cmd_req`): the command goes
//! to the server, which carries it over record 0x80A0 and confirms it; the worker hands the
//! confirmation to the PE callback as `PNIO_PE_CBE_PRM`.

use super::{JOB_TIMEOUT, ServiceWorker, Shared};
use crate::iobase::callbacks::invoke_call;
use crate::iobase::errors::*;
use crate::iobase::pe_types::*;
use crate::iobase::sync::lock;
use crate::iobase::types::{PNIO_ADDR, PNIO_ERR_STAT, PNIO_REF};
use procimg_client::RecordStatus;
use procimg_client::pe::{PeAnswer, PeCommand};
use std::time::Instant;

/// A PE command waiting for its confirmation.
#[derive(Clone, Copy)]
pub(super) struct PeJob {
    pub req_ref: PNIO_REF,
    pub addr: PNIO_ADDR,
    pub cmd_id: PNIO_PE_CMD_ENUM,
    pub deadline: Instant,
    pub generation: Option<u64>,
}

impl ServiceWorker {
    /// `PNIO_register_pe_cbf`.
    pub(crate) fn register_pe_cbf(&self, cbf: PNIO_PE_CBF) -> u32 {
        const WHAT: &str = "PNIO_register_pe_cbf";
        let s = &self.shared;
        let mut slot = lock(&s.pe_cbf);
        if slot.is_some() {
            return s.fail(
                WHAT,
                PNIO_ERR_ALREADY_DONE,
                "the PE callback is registered already",
            );
        }
        *slot = cbf;
        PNIO_OK
    }

    /// `PNIO_pe_cmd_req`: the command `prm` to the submodule at `addr`.
    pub(crate) fn pe_cmd_req(
        &self,
        addr: &PNIO_ADDR,
        req_ref: PNIO_REF,
        prm: &PNIO_PE_REQ_PRM,
    ) -> u32 {
        const WHAT: &str = "PNIO_pe_cmd_req";
        let s = &self.shared;
        if lock(&s.pe_cbf).is_none() {
            return s.fail(
                WHAT,
                PNIO_ERR_SEQUENCE,
                "register the PE callback first (PNIO_register_pe_cbf)",
            );
        }
        let command = match command_of(prm) {
            Ok(c) => c,
            Err(why) => return s.fail(WHAT, PNIO_ERR_PRM_INVALIDARG, why),
        };
        let target = match self.record_target(WHAT, addr, PE_SAP_DR_INDEX) {
            Ok(t) => t,
            Err(code) => return code,
        };
        let reference = {
            let mut jobs = lock(&s.jobs);
            if jobs.records.len() + jobs.pe.len() >= super::MAX_RECORD_JOBS {
                return s.fail(
                    WHAT,
                    PNIO_ERR_NO_RESOURCE,
                    "16 record jobs and PE commands are open: wait for a confirmation",
                );
            }
            let reference = jobs.reference();
            jobs.pe.insert(
                reference,
                PeJob {
                    req_ref,
                    addr: *addr,
                    cmd_id: prm.CmdId,
                    deadline: Instant::now() + JOB_TIMEOUT,
                    generation: None,
                },
            );
            reference
        };
        self.hand_over(
            WHAT,
            |jobs, generation| {
                if let Some(j) = jobs.pe.get_mut(&reference) {
                    j.generation = generation;
                }
            },
            |sv| sv.pe_command(target, command.clone(), reference),
            |jobs| {
                jobs.pe.remove(&reference);
            },
        )
    }
}

/// The command `prm` names, or why it names none.
fn command_of(prm: &PNIO_PE_REQ_PRM) -> Result<PeCommand, String> {
    let m = prm.CmdModifier;
    Ok(match (prm.CmdId, m) {
        (PNIO_PE_CMD_START_PAUSE, PE_CMD_MODIF_NOT_USED) => PeCommand::StartPause {
            // SAFETY: the member of this command; every bit pattern is a valid u32.
            pause_ms: unsafe { prm.rq.StartPause.time_ms },
        },
        (PNIO_PE_CMD_END_PAUSE, PE_CMD_MODIF_NOT_USED) => PeCommand::EndPause,
        (PNIO_PE_CMD_Q_MODES, PE_CMD_MODIF_Q_MODE_LIST_ALL) => PeCommand::ListModes,
        (PNIO_PE_CMD_Q_MODES, PE_CMD_MODIF_Q_MODE_GET_MODE) => PeCommand::GetMode {
            // SAFETY: the member of this command; plain bytes.
            mode: unsafe { prm.rq.ModeGet.peModeId },
        },
        (PNIO_PE_CMD_PEM_STATUS, PE_CMD_MODIF_NOT_USED) => PeCommand::PemStatus,
        (PNIO_PE_CMD_PE_IDENTIFY, PE_CMD_MODIF_NOT_USED) => PeCommand::Identify,
        (PNIO_PE_CMD_Q_MSRMT, PE_CMD_MODIF_Q_MSRMT_LIST_ALL) => PeCommand::MeasurementList,
        (PNIO_PE_CMD_Q_MSRMT, PE_CMD_MODIF_Q_MSRMT_GET_VAL) => {
            // SAFETY: the member of this command; plain bytes and words.
            let v = unsafe { prm.rq.MeasurementValue };
            let n = usize::from(v.num).min(PE_MSRMT_IDS_MAX as usize);
            PeCommand::MeasurementValues {
                ids: v.Measurement_ID[..n].to_vec(),
            }
        }
        (id, m) => {
            return Err(format!(
                "CmdId {id} with CmdModifier {m} is no PE command (Q_MODES and Q_MSRMT take a \
                 modifier 1 or 2, the others PE_CMD_MODIF_NOT_USED)"
            ));
        }
    })
}

/// The PE callback for the command with `reference`: its answer, or why it has none.
pub(super) fn pe_done(
    shared: &Shared,
    reference: u64,
    answer: Option<&PeAnswer>,
    status: RecordStatus,
) {
    let Some(job) = lock(&shared.jobs).pe.remove(&reference) else {
        return;
    };
    deliver(shared, &job, answer, status);
}

/// Calls the PE callback for `job`.
pub(super) fn deliver(
    shared: &Shared,
    job: &PeJob,
    answer: Option<&PeAnswer>,
    status: RecordStatus,
) {
    let Some(cbf) = *lock(&shared.pe_cbf) else {
        return;
    };
    // SAFETY: all-zero bytes are a valid PNIO_PE_CBE_PRM: integers, floats, arrays of them,
    // and a PNIO_ADDR, whose union of integers is valid zeroed too.
    let mut prm: PNIO_PE_CBE_PRM = unsafe { std::mem::zeroed() };
    prm.pe_hdr.CmdId = job.cmd_id;
    prm.pe_hdr.Handle = shared.handle;
    prm.pe_hdr.Addr = job.addr;
    prm.pe_hdr.Ref = job.req_ref;
    prm.pe_hdr.Err = PNIO_ERR_STAT {
        ErrCode: status.error_code,
        ErrDecode: status.error_decode,
        ErrCode1: status.error_code1,
        ErrCode2: status.error_code2,
        AddValue1: status.add_value1,
        AddValue2: status.add_value2,
    };
    let (state, struct_id, length) = match answer {
        None => (2, PE_CNF_STRUCT_ID_RESERVED, 0),
        Some(a) => fill(&mut prm.pe_prm, a),
    };
    prm.pe_hdr.state = state;
    prm.pe_hdr.struct_id = struct_id;
    prm.pe_hdr.length = length as u32;
    let p: *mut PNIO_PE_CBE_PRM = &mut prm;
    // SAFETY: the program registered `cbf`; `p` is a live, initialised PNIO_PE_CBE_PRM for
    // the duration of the call.
    invoke_call(|| unsafe { cbf(p) });
}

/// Writes `a` into its member of `u`: the state, struct_id and the member's size.
fn fill(u: &mut PNIO_PE_CBE_PRM_pe_prm, a: &PeAnswer) -> (u16, u16, usize) {
    use std::mem::size_of;
    let bytes = |dst: &mut [u8; 254], src: &[u8]| {
        let n = src.len().min(254);
        dst[..n].copy_from_slice(&src[..n]);
        n as u8
    };
    match a {
        PeAnswer::StartPause { mode } => {
            u.StartPause = PNIO_PE_PRM_START_PAUSE_CONF {
                pe_mode_id: u32::from(*mode),
            };
            (
                1,
                PE_CNF_STRUCT_ID_UNIQUE,
                size_of::<PNIO_PE_PRM_START_PAUSE_CONF>(),
            )
        }
        PeAnswer::EndPause { time_to_operate } => {
            u.EndPause = PNIO_PE_PRM_END_PAUSE_CONF {
                time_ms: *time_to_operate,
            };
            (
                1,
                PE_CNF_STRUCT_ID_UNIQUE,
                size_of::<PNIO_PE_PRM_END_PAUSE_CONF>(),
            )
        }
        PeAnswer::Identify { services } => {
            let mut c = PNIO_PE_PRM_PE_IDENTIFY_CONF {
                numServices: 0,
                serviceId: [0; 254],
            };
            c.numServices = bytes(&mut c.serviceId, services);
            u.PeIdentify = c;
            (
                1,
                PE_CNF_STRUCT_ID_UNIQUE,
                size_of::<PNIO_PE_PRM_PE_IDENTIFY_CONF>(),
            )
        }
        PeAnswer::PemStatus(s) => {
            u.PemStatus = PNIO_PE_PRM_PEM_STATUS_CONF {
                PE_Mode_ID_Source: s.source,
                PE_Mode_ID_Destination: s.destination,
                Time_to_operate: s.time_to_operate,
                Remaining_time_to_destination: s.remaining_time_to_destination,
                Mode_Power_Consumption: s.power_kw,
                Energy_Consumption_to_Destination: s.energy_to_destination_kwh,
                Energy_Consumption_to_operate: s.energy_to_operate_kwh,
            };
            (
                1,
                PE_CNF_STRUCT_ID_UNIQUE,
                size_of::<PNIO_PE_PRM_PEM_STATUS_CONF>(),
            )
        }
        PeAnswer::ModeList { modes } => {
            let mut c = PNIO_PE_PRM_Q_MODE_LIST_ALL_CONF {
                numModeIds: 0,
                peModeId: [0; 254],
            };
            c.numModeIds = bytes(&mut c.peModeId, modes);
            u.ModeList = c;
            (
                1,
                PE_CNF_STRUCT_ID_QMODE_LIST_ALL,
                size_of::<PNIO_PE_PRM_Q_MODE_LIST_ALL_CONF>(),
            )
        }
        PeAnswer::Mode(m) => {
            u.ModeGet = PNIO_PE_PRM_Q_MODE_GET_MODE_CONF {
                peModeId: m.mode,
                PE_Mode_Attributes: m.attributes,
                Time_min_Pause: m.time_min_pause,
                Time_to_Pause: m.time_to_pause,
                Time_to_operate: m.time_to_operate,
                Time_min_length_of_stay: m.time_min_length_of_stay,
                Time_max_length_of_stay: m.time_max_length_of_stay,
                Mode_Power_Consumption: m.power_kw,
                Energy_Consumption_to_pause: m.energy_to_pause_kwh,
                Energy_Consumption_to_operate: m.energy_to_operate_kwh,
            };
            (
                1,
                PE_CNF_STRUCT_ID_QMODE_GET_MODE,
                size_of::<PNIO_PE_PRM_Q_MODE_GET_MODE_CONF>(),
            )
        }
        PeAnswer::MeasurementList { items } => {
            let mut c = PNIO_PE_PRM_Q_MSRMT_GET_LIST_CONF {
                numMeasurementIds: 0,
                reserved: 0,
                elem: [PNIO_PE_PRM_Q_MSRMT_LIST_ELEM::default(); PE_MSRMT_IDS_MAX as usize],
            };
            for (e, m) in c.elem.iter_mut().zip(items) {
                *e = PNIO_PE_PRM_Q_MSRMT_LIST_ELEM {
                    Measurement_ID: m.id,
                    Accuracy_Domain: m.accuracy_domain,
                    Accuracy_Class: m.accuracy_class,
                    Range: m.range,
                };
            }
            c.numMeasurementIds = items.len().min(PE_MSRMT_IDS_MAX as usize) as u8;
            u.MeasurementList = c;
            (
                1,
                PE_CNF_STRUCT_ID_QMSRMT_LIST_ALL,
                size_of::<PNIO_PE_PRM_Q_MSRMT_GET_LIST_CONF>(),
            )
        }
        PeAnswer::MeasurementValues { values } => {
            let mut c = PNIO_PE_PRM_Q_MSRMT_GET_VAL_CONF {
                numMeasurementValues: 0,
                reserved: 0,
                value: [PNIO_PE_PRM_Q_MSRMT_VAL_ELEM::default(); PE_MSRMT_IDS_MAX as usize],
            };
            for (e, v) in c.value.iter_mut().zip(values) {
                *e = PNIO_PE_PRM_Q_MSRMT_VAL_ELEM {
                    Measurement_ID: v.id,
                    Status_of_Measurement_Value: u16::from(v.status),
                    Transmission_Data_Type: v.value,
                    End_of_demand: 0,
                    reserved: 0,
                };
            }
            c.numMeasurementValues = values.len().min(PE_MSRMT_IDS_MAX as usize) as u8;
            u.MeasurementValue = c;
            (
                1,
                PE_CNF_STRUCT_ID_QMSRMT_GET_VAL,
                size_of::<PNIO_PE_PRM_Q_MSRMT_GET_VAL_CONF>(),
            )
        }
        PeAnswer::Error { code } => {
            u.RespNegative = PNIO_PE_PRM_GENERIC_CONF_NEG {
                err_code: *code,
                reserved: 0,
            };
            (
                2,
                PE_CNF_STRUCT_ID_ERROR,
                size_of::<PNIO_PE_PRM_GENERIC_CONF_NEG>(),
            )
        }
        // Query_Version and answers of other shapes have no member: the header only.
        PeAnswer::Version { .. } | PeAnswer::Other { .. } => (1, PE_CNF_STRUCT_ID_RESERVED, 0),
    }
}
