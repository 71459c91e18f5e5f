// SPDX-License-Identifier: MIT OR Apache-2.0
//! The program's alarms (`PNIO_process_alarm_send`, `PNIO_diag_alarm_send`,
//! `PNIO_ret_of_sub_alarm_send`) and their `PNIO_CBF_REQ_DONE`.
//!
//! An alarm needs the AR the program called `PNIO_set_appl_state_ready` for, named by its
//! ArNumber and SessionKey, and a submodule the program plugged; its data is at most
//! [`MAX_ALARM_DATA`] bytes. procimgd sends it on the AR at once (the call returns
//! `PNIO_OK` then) and tells the library thread of the PLC's AlarmAck, which gives
//! `PNIO_CBF_REQ_DONE` with the UserHndl: Status `PNIO_OK` and a zero `PNIO_ERR_STAT` when
//! the PLC accepted it, `PNIO_ERR_ALARM_DATA_FORMAT` with the AlarmAck's PNIOStatus when it
//! did not, `PNIO_ERR_ABORT` when the AR ended before the acknowledgement came.
//! `PNIO_diag_alarm_send` and `PNIO_ret_of_sub_alarm_send` for a submodule the AR does not
//! hold return `PNIO_OK`, as the manual has it, and `PNIO_CBF_REQ_DONE` follows with
//! `PNIO_ERR_UNKNOWN_ADDR`.

use super::Pos;
use super::jobs::Job;
use super::session_failure;
use super::state::{Device, Life};
use crate::iobase::callbacks::invoke_device;
use crate::iobase::errors::*;
use crate::iobase::sync::lock;
use crate::iobase::types::PNIO_ERR_STAT;
use procimg_client::iobase::ArId;
use procimg_client::{AlarmRefusal, ControlError, Refusal, StationAlarmKind};

/// The most alarm data: the AlarmNotification PDU's 200 bytes less its 28-byte header, which
/// every PLC takes (a CP 1616 as a controller takes no more either).
pub(crate) const MAX_ALARM_DATA: u32 = 172;

/// One alarm of the program, as the functions give it here.
pub(crate) struct AlarmCall<'a> {
    /// The function, for error texts.
    pub f: &'a str,
    /// ArNumber and SessionKey.
    pub ar: (u16, u16),
    /// Where.
    pub at: Pos,
    /// What alarm.
    pub kind: StationAlarmKind,
    /// UserStructIdent.
    pub usi: u16,
    /// The data (after the USI).
    pub data: &'a [u8],
    /// The program's UserHndl.
    pub user: u32,
}

/// Sends `call`'s alarm; `PNIO_OK` once it went out.
pub(crate) fn send(dev: &Device, call: AlarmCall<'_>) -> u32 {
    let f = call.f;
    let life = lock(&dev.config).life;
    if life != Life::Started {
        return fail(
            f,
            PNIO_ERR_SEQUENCE,
            format_args!("the device is {}: alarms need an AR", life.name()),
        );
    }
    let ar = ArId {
        number: call.ar.0,
        session_key: call.ar.1,
    };
    match dev.iobase.check(ar) {
        Err(e) => return session_failure(f, e),
        Ok(current) if !current.is_ready() => {
            return fail(
                f,
                PNIO_ERR_SEQUENCE,
                format_args!(
                    "AR {} is not ready: alarms go after PNIO_set_appl_state_ready",
                    ar.number
                ),
            );
        }
        Ok(_) => {}
    }
    if call.data.len() > MAX_ALARM_DATA as usize {
        return fail(
            f,
            PNIO_ERR_VALUE_LEN,
            format_args!(
                "DataLen {} is more than the {MAX_ALARM_DATA} bytes of alarm data every PLC takes",
                call.data.len()
            ),
        );
    }
    let forgiving = call.kind != StationAlarmKind::Process;
    if !lock(&dev.config).subs.contains_key(&call.at) {
        if forgiving {
            return later(dev, f, call.user, PNIO_ERR_UNKNOWN_ADDR);
        }
        return fail(
            f,
            PNIO_ERR_UNKNOWN_ADDR,
            format_args!(
                "the program has no submodule plugged at API {} slot {} subslot {:#06x}",
                call.at.0, call.at.1, call.at.2
            ),
        );
    }
    let tag = {
        let mut a = lock(&dev.alarms);
        a.next_tag += 1;
        let tag = a.next_tag;
        a.waiting.insert(tag, call.user);
        tag
    };
    let sent = dev
        .iobase
        .services()
        .send_alarm(call.at, call.kind, call.usi, call.data, tag);
    match sent {
        Ok(()) => PNIO_OK,
        Err(e) => {
            lock(&dev.alarms).waiting.remove(&tag);
            let code = code_of(&e);
            if forgiving && code == PNIO_ERR_UNKNOWN_ADDR {
                return later(dev, f, call.user, code);
            }
            fail(f, code, format_args!("{e}"))
        }
    }
}

/// Returns `PNIO_OK` and has the library thread give `PNIO_CBF_REQ_DONE` with `status`.
fn later(dev: &Device, f: &str, user: u32, status: u32) -> u32 {
    match dev.send(Job::AlarmDone { user, status }) {
        Ok(()) => PNIO_OK,
        Err(code) => fail(f, code, "the device's thread has ended"),
    }
}

/// The IO-Base code of a refused alarm.
fn code_of(e: &ControlError) -> u32 {
    match e {
        ControlError::Refused(Refusal::StationAlarm { refused, .. }) => match refused {
            AlarmRefusal::NotInDataExchange => PNIO_ERR_SEQUENCE,
            AlarmRefusal::NotInAr => PNIO_ERR_UNKNOWN_ADDR,
            AlarmRefusal::InvalidUsi => PNIO_ERR_PRM_INVALIDARG,
            AlarmRefusal::TooLong => PNIO_ERR_VALUE_LEN,
        },
        ControlError::Refused(_) | ControlError::NotDevice { .. } => PNIO_ERR_INTERNAL,
        _ => PNIO_ERR_NO_FW_COMMUNICATION,
    }
}

/// procimgd's word on alarm `tag`: the PLC's AlarmAck status, or none (the AR ended).
pub(crate) fn acknowledged(dev: &Device, tag: u64, status: Option<[u8; 4]>) {
    let Some(user) = lock(&dev.alarms).waiting.remove(&tag) else {
        return;
    };
    let (code, state) = match status {
        Some([0, 0, 0, 0]) => (PNIO_OK, PNIO_ERR_STAT::default()),
        Some([c, d, c1, c2]) => (
            PNIO_ERR_ALARM_DATA_FORMAT,
            PNIO_ERR_STAT {
                ErrCode: c,
                ErrDecode: d,
                ErrCode1: c1,
                ErrCode2: c2,
                ..PNIO_ERR_STAT::default()
            },
        ),
        None => (PNIO_ERR_ABORT, PNIO_ERR_STAT::default()),
    };
    done(dev, user, code, state);
}

/// Gives `PNIO_CBF_REQ_DONE`.
pub(crate) fn done(dev: &Device, user: u32, status: u32, mut state: PNIO_ERR_STAT) {
    if let Some(f) = dev.cbf.cbf_alarm_done {
        let ps: *mut PNIO_ERR_STAT = &mut state;
        // SAFETY: a PNIO_CBF_REQ_DONE the program gave PNIO_device_open, callable until
        // PNIO_device_close (which waits for this thread); `ps` points to a local that
        // outlives the call.
        invoke_device(|| unsafe { f(dev.handle, user, status, ps) });
    }
}
