// SPDX-License-Identifier: MIT OR Apache-2.0
//! The ARs of an open device as the program knows them: ArNumber, SessionKey and how far
//! the current one got, and the checks of the per-AR calls.

use crate::iobase::errors::*;

/// How far an AR got, in the manual's per-AR order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Phase {
    /// `AR_CHECK_IND` (and `AR_INFO_IND`) given.
    Checked,
    /// `PRM_END_IND` given: `PNIO_set_appl_state_ready` may come.
    PrmEnd,
    /// `PNIO_set_appl_state_ready` called.
    ApplReady,
    /// `AR_INDATA_IND` given.
    InData,
}

/// The current AR of a device.
#[derive(Clone, Debug)]
pub(crate) struct Ar {
    /// ArNumber.
    pub number: u16,
    /// SessionKey.
    pub session_key: u16,
    /// ARUUID, as procimgd writes it.
    pub uuid: String,
    /// How far it got.
    pub phase: Phase,
    /// A RUN/STOP change before data exchange, given after `AR_INDATA_IND`.
    pub apdu_pending: Option<bool>,
    /// Submodules plugged in data exchange whose `PRM_END_IND` was given and whose
    /// `PNIO_set_appl_state_ready` has not come yet.
    pub plug_prm_ends: u32,
}

/// The ARs of an open device.
pub(crate) struct Ars {
    /// The ArNumber the next AR gets.
    pub next_number: u16,
    /// The AR, if one is up.
    pub current: Option<Ar>,
}

impl Ars {
    /// No AR yet.
    pub(crate) fn new() -> Ars {
        Ars {
            next_number: 1,
            current: None,
        }
    }

    /// Checks ArNumber and SessionKey of a per-AR call of function `f`; the current AR.
    pub(crate) fn check(&self, f: &str, number: u16, session_key: u16) -> Result<Ar, u32> {
        match &self.current {
            Some(ar) if ar.number == number && ar.session_key == session_key => Ok(ar.clone()),
            Some(ar) if ar.number == number => Err(fail(
                f,
                PNIO_ERR_SESSION,
                format_args!(
                    "SessionKey {session_key} is not AR {number}'s ({}): use the one \
                     PNIO_CBF_AR_CHECK_IND gave",
                    ar.session_key
                ),
            )),
            _ if number != 0 && number < self.next_number => Err(fail(
                f,
                PNIO_ERR_SESSION,
                format_args!("AR {number} has ended"),
            )),
            _ => Err(fail(
                f,
                PNIO_ERR_SEQUENCE,
                format_args!(
                    "ArNumber {number} was never given by PNIO_CBF_AR_CHECK_IND of this device"
                ),
            )),
        }
    }
}
