// SPDX-License-Identifier: MIT OR Apache-2.0
//! Why a device left data exchange or could not be brought up.

use crate::wire::rta_pdu::AbortCode;

/// The kinds of failure a program tells apart (IO-Base's `PNIO_CTRL_REASON_*`); the words go
/// with them in the failure text.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FailureCause {
    /// No failure (running, or never tried).
    #[default]
    None,
    /// No device of its name answered DCP Identify.
    NotFound,
    /// Giving it its IP address (DCP Set) failed, or it has none.
    IpSetFailed,
    /// It did not answer an RPC call (Connect, Write, PrmEnd, Release) in time.
    RpcTimeout,
    /// Its RPC layer refused a call, or answered with something unreadable.
    RpcError,
    /// It refused the configuration: a negative PNIO status to Connect, Write or PrmEnd.
    Refused,
    /// It sent no ApplicationReady after the parameters.
    NoApplicationReady,
    /// Its cyclic data stopped coming (the watchdog expired).
    NoCyclicData,
    /// It aborted the AR.
    DeviceAborted,
    /// The controller aborted the AR (its alarm channel failed).
    ControllerAborted,
    /// The controller released it, going OFFLINE.
    Released,
    /// A client deactivated it.
    Deactivated,
    /// The controller could not build a request for it (a configuration it cannot carry).
    Internal,
}

impl FailureCause {
    /// The code of the ERR-RTA abort that tells the device of an AR ended for this cause
    /// (the PNIO status ErrorCode2 with ErrorCode1 "RTA error"), so that it frees the AR at
    /// once and says why in its own diagnosis.
    pub const fn abort_code(self) -> AbortCode {
        match self {
            FailureCause::NoCyclicData => AbortCode::ConsumerDhtExpired,
            FailureCause::NoApplicationReady => AbortCode::CmiTimeout,
            FailureCause::RpcTimeout | FailureCause::RpcError => AbortCode::RpcClientCallNegative,
            FailureCause::Refused => AbortCode::ProtocolViolation,
            FailureCause::Deactivated => AbortCode::DeviceDeactivated,
            FailureCause::Released => AbortCode::ReleaseIndication,
            FailureCause::None
            | FailureCause::NotFound
            | FailureCause::IpSetFailed
            | FailureCause::DeviceAborted
            | FailureCause::ControllerAborted
            | FailureCause::Internal => AbortCode::AbortRequest,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lost_ar_is_aborted_with_why() {
        assert_eq!(
            FailureCause::NoCyclicData.abort_code(),
            AbortCode::ConsumerDhtExpired
        );
        assert_eq!(
            FailureCause::RpcTimeout.abort_code(),
            AbortCode::RpcClientCallNegative
        );
        assert_eq!(FailureCause::Internal.abort_code(), AbortCode::AbortRequest);
    }
}
