// SPDX-License-Identifier: MIT OR Apache-2.0
//! Why an AR ended, as the program is told (`PNIO_AR_REASON` of `AR_ABORT_IND` and
//! `AR_OFFLINE_IND`). IO-Base's reasons 1 to 34 are the RTA abort codes of IEC 61158-6-10,
//! which procimgd sends with the AR's end.

/// `PNIO_AR_REASON_NONE`: no reason known.
pub const REASON_NONE: u32 = 0;
/// The highest RTA abort code IO-Base names (`PNIO_AR_REASON_IRDATA`); 1 is the lowest.
pub const REASON_HIGHEST_ABORT_CODE: u32 = 34;
/// `PNIO_AR_REASON_ABORT`: this station ended the AR on purpose.
pub const REASON_ABORT: u32 = 13;
/// `PNIO_AR_REASON_RERUN`: a new Connect of the PLC replaced the AR.
pub const REASON_RERUN: u32 = 14;
/// `PNIO_AR_REASON_REL`: the PLC released the AR.
pub const REASON_REL: u32 = 15;

/// Why an AR ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArEndReason {
    /// The PLC released it.
    Released,
    /// Aborted, with the RTA abort code if procimgd sent one (an older server does not);
    /// `planned` when this station ended it on purpose (stop, OFFLINE, the program's abort).
    Aborted {
        /// The RTA abort code.
        code: Option<u8>,
        /// This station ended it on purpose.
        planned: bool,
    },
    /// A new Connect of the PLC replaced it before its end was reported.
    Replaced,
    /// Its end was waited for in vain after this station ended it.
    Abandoned,
}

impl ArEndReason {
    /// From the station's report of the end.
    pub fn reported(abort_code: Option<u8>, aborted: bool, planned: bool) -> ArEndReason {
        if aborted {
            ArEndReason::Aborted {
                code: abort_code,
                planned,
            }
        } else {
            ArEndReason::Released
        }
    }

    /// IO-Base's `PNIO_AR_REASON`:
    ///
    /// * released by the PLC → `PNIO_AR_REASON_REL`;
    /// * an abort with code 0x01..=0x22 → that value (0x05 `MISS`, the PLC's frames
    ///   stopped; 0x10 `PAS`, the station went OFFLINE; 0x1f `DCP_NAME`; 0x20 `DCP_RESET`);
    /// * any other code, or none → `PNIO_AR_REASON_ABORT` when this station ended it on
    ///   purpose, else `PNIO_AR_REASON_NONE`;
    /// * replaced → `PNIO_AR_REASON_RERUN`; abandoned → `PNIO_AR_REASON_ABORT`.
    pub fn iobase_code(self) -> u32 {
        match self {
            ArEndReason::Released => REASON_REL,
            ArEndReason::Replaced => REASON_RERUN,
            ArEndReason::Abandoned => REASON_ABORT,
            ArEndReason::Aborted { code, planned } => match code.map(u32::from) {
                Some(c) if (1..=REASON_HIGHEST_ABORT_CODE).contains(&c) => c,
                _ if planned => REASON_ABORT,
                _ => REASON_NONE,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reasons_are_the_abort_codes() {
        let code = |c, aborted, planned| ArEndReason::reported(c, aborted, planned).iobase_code();
        assert_eq!(code(None, false, false), REASON_REL);
        assert_eq!(code(Some(0x05), true, false), 5, "MISS");
        assert_eq!(code(Some(0x10), true, true), 16, "PAS");
        assert_eq!(code(Some(0x7f), true, true), REASON_ABORT);
        assert_eq!(code(Some(0x00), true, false), REASON_NONE);
        // An older server sends no code.
        assert_eq!(code(None, true, true), REASON_ABORT);
        assert_eq!(ArEndReason::Replaced.iobase_code(), REASON_RERUN);
        assert_eq!(ArEndReason::Abandoned.iobase_code(), REASON_ABORT);
    }
}
