// SPDX-License-Identifier: MIT OR Apache-2.0
//! The ARs of a device as its program knows them: the ArNumber the program gets for each
//! PLC's Connect (1, 2, … per device), the station's SessionKey, how far the current AR got
//! in the IO-Base manual's per-AR order, and the checks of the calls that name an AR.
//!
//! Only the current AR is known. A call naming an ArNumber this device never gave is out of
//! sequence ([`SessionError::NeverGiven`]); the ArNumber of an AR that has ended, or the
//! current one's with another SessionKey, is a session error.

use procimg_control::ArState;

/// An AR as the program names it in its calls.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ArId {
    /// ArNumber: 1 for the first AR of the device, then counting up (wrapping to 1).
    pub number: u16,
    /// The SessionKey of the PLC's Connect.
    pub session_key: u16,
}

/// How far an AR got, in the manual's per-AR order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum ArPhase {
    /// The Connect was checked (`AR_CHECK_IND`, `AR_INFO_IND`).
    Checked,
    /// The PLC ended its parameters (`PRM_END_IND`): the program's ApplicationReady may
    /// come.
    PrmEnd,
    /// The program said it is ready (`PNIO_set_appl_state_ready`).
    ApplReady,
    /// The PLC confirmed the ApplicationReady (`AR_INDATA_IND`): data exchange.
    InData,
}

/// The DataStatus of the PLC's output frames, as `APDU_STATUS_IND` reports it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ApduStatus {
    /// RUN (else STOP).
    pub running: bool,
    /// The PLC reports a station problem.
    pub station_problem: bool,
    /// The PLC's provider is the backup, not the primary.
    pub backup: bool,
}

/// The current AR of a device.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProgramAr {
    /// ArNumber and SessionKey.
    pub id: ArId,
    /// ARUUID, as procimgd writes it.
    pub uuid: String,
    /// How far it got.
    pub phase: ArPhase,
    /// A change of the PLC's status before data exchange, given after `AR_INDATA_IND`.
    apdu_pending: Option<ApduStatus>,
    /// Submodules plugged in data exchange whose `PRM_END_IND` was given and whose
    /// ApplicationReady has not come yet.
    plug_prm_ends: u32,
}

impl ProgramAr {
    /// Whether the program said it is ready for this AR (alarms may go).
    pub fn is_ready(&self) -> bool {
        self.phase >= ArPhase::ApplReady
    }

    /// Whether the AR takes the program's IO data: from `PRM_END_IND` on, as the manual's
    /// order has it (the I data written then is what the PLC gets with the
    /// ApplicationReady, which follows).
    pub fn takes_data(&self) -> bool {
        self.phase >= ArPhase::PrmEnd
    }
}

/// Why a call naming an AR is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SessionError {
    /// The ArNumber is the current AR's, the SessionKey is not.
    #[error(
        "SessionKey {given} is not AR {number}'s ({current}): use the one the AR check \
         (AR_CHECK_IND) gave"
    )]
    WrongSessionKey {
        /// The ArNumber.
        number: u16,
        /// The SessionKey given.
        given: u16,
        /// The current AR's.
        current: u16,
    },
    /// The AR has ended.
    #[error("AR {number} has ended")]
    Ended {
        /// The ArNumber.
        number: u16,
    },
    /// This device never gave the ArNumber.
    #[error("ArNumber {number} was never given by the AR check (AR_CHECK_IND) of this device")]
    NeverGiven {
        /// The ArNumber.
        number: u16,
    },
}

/// Why the program's ApplicationReady is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ReadyError {
    /// The AR named is not the current one.
    #[error(transparent)]
    Session(#[from] SessionError),
    /// The PLC has not ended its parameters yet.
    #[error("not now for AR {number}: PRM_END_IND has not come yet")]
    NoPrmEnd {
        /// The ArNumber.
        number: u16,
    },
    /// The program said it already.
    #[error("not now for AR {number}: it was called for this AR already")]
    Already {
        /// The ArNumber.
        number: u16,
    },
}

/// What an accepted ApplicationReady is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ready {
    /// The AR's: its phase is [`ArPhase::ApplReady`] now (undone by
    /// [`ArSessions::not_ready`] when procimgd does not take it).
    Ar,
    /// A submodule's plugged in data exchange (its PlugApplicationReady).
    Plug,
}

/// What the station's report of an AR's state means to the program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Step {
    /// `PRM_END_IND`.
    PrmEnd(ArId),
    /// `AR_INDATA_IND`, then the PLC's status if it changed before.
    InData(ArId, Option<ApduStatus>),
}

/// The ARs of a device: the current one and the next ArNumber.
#[derive(Clone, Debug)]
pub struct ArSessions {
    next_number: u16,
    current: Option<ProgramAr>,
}

impl Default for ArSessions {
    fn default() -> ArSessions {
        ArSessions::new()
    }
}

impl ArSessions {
    /// No AR yet; the first gets ArNumber 1.
    pub fn new() -> ArSessions {
        ArSessions {
            next_number: 1,
            current: None,
        }
    }

    /// The current AR, if one is up.
    pub fn current(&self) -> Option<&ProgramAr> {
        self.current.as_ref()
    }

    /// Checks the ArNumber and SessionKey of a call; the current AR.
    pub fn check(&self, id: ArId) -> Result<&ProgramAr, SessionError> {
        match &self.current {
            Some(ar) if ar.id == id => Ok(ar),
            Some(ar) if ar.id.number == id.number => Err(SessionError::WrongSessionKey {
                number: id.number,
                given: id.session_key,
                current: ar.id.session_key,
            }),
            _ if id.number != 0 && id.number < self.next_number => {
                Err(SessionError::Ended { number: id.number })
            }
            _ => Err(SessionError::NeverGiven { number: id.number }),
        }
    }

    /// The current AR if it is the one procimgd names `uuid`.
    pub fn by_uuid(&self, uuid: &str) -> Option<&ProgramAr> {
        self.current.as_ref().filter(|a| a.uuid == uuid)
    }

    /// A PLC's Connect: the new AR's id, and the AR it replaces (whose end was not reported).
    pub(crate) fn begin(&mut self, session_key: u16, uuid: &str) -> (ArId, Option<ProgramAr>) {
        let id = ArId {
            number: self.next_number,
            session_key,
        };
        self.next_number = self.next_number.checked_add(1).unwrap_or(1);
        let replaced = self.current.replace(ProgramAr {
            id,
            uuid: uuid.to_owned(),
            phase: ArPhase::Checked,
            apdu_pending: None,
            plug_prm_ends: 0,
        });
        (id, replaced)
    }

    /// The station reports the AR `uuid` at `state`: the indication that brings, if any
    /// (each once, in order).
    pub(crate) fn advance(&mut self, uuid: &str, state: ArState) -> Option<Step> {
        let target = match state {
            ArState::Parameterized => ArPhase::PrmEnd,
            ArState::Data => ArPhase::InData,
            // No indication of their own: the Connect's came with the AR check, and the
            // ApplicationReady going out is the program's doing.
            ArState::Connected | ArState::WaitingForApplicationReadyConfirm | ArState::Unknown => {
                return None;
            }
        };
        let ar = self.current.as_mut().filter(|a| a.uuid == uuid)?;
        if ar.phase >= target {
            return None;
        }
        ar.phase = target;
        Some(match target {
            ArPhase::PrmEnd => Step::PrmEnd(ar.id),
            _ => Step::InData(ar.id, ar.apdu_pending.take()),
        })
    }

    /// The PLC's status changed: the AR to tell now (in data exchange); before, the change
    /// is kept for after `AR_INDATA_IND`.
    pub(crate) fn plc_status(&mut self, status: ApduStatus) -> Option<ArId> {
        let ar = self.current.as_mut()?;
        if ar.phase == ArPhase::InData {
            return Some(ar.id);
        }
        ar.apdu_pending = Some(status);
        None
    }

    /// The PLC ended the parameters of a submodule plugged in data exchange: the AR whose
    /// `PRM_END_IND` it is.
    pub(crate) fn plug_parameterized(&mut self) -> Option<ArId> {
        let ar = self
            .current
            .as_mut()
            .filter(|a| a.phase == ArPhase::InData)?;
        ar.plug_prm_ends += 1;
        Some(ar.id)
    }

    /// The AR `uuid` ended: it, if it was the current one.
    pub(crate) fn end(&mut self, uuid: &str) -> Option<ProgramAr> {
        match &self.current {
            Some(ar) if ar.uuid == uuid => self.current.take(),
            _ => None,
        }
    }

    /// The program's ApplicationReady for `id`.
    pub fn ready(&mut self, id: ArId) -> Result<Ready, ReadyError> {
        self.check(id)?;
        let Some(ar) = self.current.as_mut() else {
            return Err(SessionError::NeverGiven { number: id.number }.into());
        };
        match ar.phase {
            ArPhase::InData if ar.plug_prm_ends > 0 => {
                ar.plug_prm_ends -= 1;
                Ok(Ready::Plug)
            }
            ArPhase::PrmEnd => {
                ar.phase = ArPhase::ApplReady;
                Ok(Ready::Ar)
            }
            ArPhase::Checked => Err(ReadyError::NoPrmEnd { number: id.number }),
            ArPhase::ApplReady | ArPhase::InData => Err(ReadyError::Already { number: id.number }),
        }
    }

    /// procimgd did not take the ApplicationReady [`ready`](Self::ready) accepted for the
    /// AR: it may come again.
    pub fn not_ready(&mut self, id: ArId) {
        if let Some(ar) = self.current.as_mut()
            && ar.id == id
            && ar.phase == ArPhase::ApplReady
        {
            ar.phase = ArPhase::PrmEnd;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn id(number: u16, session_key: u16) -> ArId {
        ArId {
            number,
            session_key,
        }
    }

    #[test]
    fn ar_numbers_count_per_device_and_sessions_are_checked() {
        let mut s = ArSessions::new();
        assert_eq!(
            s.check(id(1, 5)),
            Err(SessionError::NeverGiven { number: 1 })
        );
        let (first, replaced) = s.begin(5, "a");
        assert_eq!((first, replaced), (id(1, 5), None));
        assert!(s.check(id(1, 5)).is_ok());
        assert_eq!(
            s.check(id(1, 6)),
            Err(SessionError::WrongSessionKey {
                number: 1,
                given: 6,
                current: 5
            })
        );
        let (second, replaced) = s.begin(9, "b");
        assert_eq!(second, id(2, 9));
        assert_eq!(
            replaced.map(|a| a.id),
            Some(first),
            "a Connect replaces the AR"
        );
        assert_eq!(s.check(first), Err(SessionError::Ended { number: 1 }));
        assert!(s.end("a").is_none(), "not the current AR");
        assert_eq!(s.end("b").map(|a| a.id), Some(second));
        assert_eq!(s.check(second), Err(SessionError::Ended { number: 2 }));
    }

    #[test]
    fn indications_come_once_and_in_order() {
        let mut s = ArSessions::new();
        let (ar, _) = s.begin(1, "u");
        assert_eq!(s.advance("u", ArState::Connected), None);
        assert_eq!(s.ready(ar), Err(ReadyError::NoPrmEnd { number: 1 }));
        let run = ApduStatus {
            running: true,
            station_problem: false,
            backup: false,
        };
        assert_eq!(s.plc_status(run), None, "kept for after IN_DATA");
        assert_eq!(
            s.advance("u", ArState::Parameterized),
            Some(Step::PrmEnd(ar))
        );
        assert_eq!(s.advance("u", ArState::Parameterized), None);
        assert_eq!(s.advance("other", ArState::Data), None);
        assert_eq!(s.ready(ar), Ok(Ready::Ar));
        assert_eq!(s.ready(ar), Err(ReadyError::Already { number: 1 }));
        s.not_ready(ar);
        assert_eq!(
            s.ready(ar),
            Ok(Ready::Ar),
            "again after procimgd refused it"
        );
        assert!(s.current().is_some_and(ProgramAr::is_ready));
        assert_eq!(
            s.advance("u", ArState::Data),
            Some(Step::InData(ar, Some(run)))
        );
        assert_eq!(s.plc_status(run), Some(ar));
        assert_eq!(s.plug_parameterized(), Some(ar));
        assert_eq!(s.ready(ar), Ok(Ready::Plug));
        assert_eq!(s.ready(ar), Err(ReadyError::Already { number: 1 }));
    }

    #[test]
    fn ar_numbers_wrap_to_one() {
        let mut s = ArSessions {
            next_number: u16::MAX,
            current: None,
        };
        assert_eq!(s.begin(1, "a").0.number, u16::MAX);
        assert_eq!(s.begin(1, "b").0.number, 1);
    }
}
