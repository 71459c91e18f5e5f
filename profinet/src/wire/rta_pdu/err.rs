// SPDX-License-Identifier: MIT OR Apache-2.0
//! ERR-RTA: the abort codes and the VarPart of an ERR-RTA PDU.

use crate::wire::cursor::{Reader, Writer};
use crate::wire::{EmitResult, PnioStatus, Result};

/// ErrorCode of an RTA error (ERR-RTA PNIOStatus).
pub const ERROR_CODE_RTA: u8 = 0xcf;
/// ErrorDecode "PNIO".
pub const ERROR_DECODE_PNIO: u8 = 0x81;
/// ErrorCode1 "RTA protocol" (ErrorCode2 then holds the [`AbortCode`]).
pub const ERROR_CODE1_RTA_PROTOCOL: u8 = 0xfd;

coded_enum! {
    /// The abort reason of an ERR-RTA: ErrorCode2 of a `CF 81 FD xx` PNIOStatus.
    pub enum AbortCode(u8) {
        /// 0x00: no reason given (p-net uses it for aborts it initiates).
        Unspecified = 0x00 => "unspecified",
        /// 0x01: sequence number error.
        SequenceError = 0x01 => "sequence number error",
        /// 0x02: instance closed.
        InstanceClosed = 0x02 => "instance closed",
        /// 0x03: AR out of memory.
        OutOfMemory = 0x03 => "AR out of memory",
        /// 0x04: adding a provider or consumer failed.
        AddProviderOrConsumerFailed = 0x04 => "AR add provider or consumer failed",
        /// 0x05: consumer data hold timer expired.
        ConsumerDhtExpired = 0x05 => "AR consumer data hold time expired",
        /// 0x06: CM initiator activity timeout.
        CmiTimeout = 0x06 => "AR CMI timeout",
        /// 0x07: alarm open failed.
        AlarmOpenFailed = 0x07 => "AR alarm open failed",
        /// 0x08: alarm send confirmed negatively.
        AlarmSendNegative = 0x08 => "AR alarm send.cnf(-)",
        /// 0x09: alarm ack send confirmed negatively.
        AlarmAckSendNegative = 0x09 => "AR alarm ack send.cnf(-)",
        /// 0x0A: alarm data too long.
        AlarmDataTooLong = 0x0a => "AR alarm data too long",
        /// 0x0B: alarm indication with error.
        AlarmIndicationError = 0x0b => "AR alarm.ind(err)",
        /// 0x0C: RPC client call confirmed negatively.
        RpcClientCallNegative = 0x0c => "AR RPC client call.cnf(-)",
        /// 0x0D: abort requested.
        AbortRequest = 0x0d => "AR abort.req",
        /// 0x0E: a re-run aborts the existing AR.
        RerunAbortsExisting = 0x0e => "AR re-run aborts existing",
        /// 0x0F: release indication received.
        ReleaseIndication = 0x0f => "AR release.ind received",
        /// 0x10: device deactivated.
        DeviceDeactivated = 0x10 => "AR device deactivated",
        /// 0x11: AR removed.
        ArRemoved = 0x11 => "AR removed",
        /// 0x12: protocol violation.
        ProtocolViolation = 0x12 => "AR protocol violation",
        /// 0x13: name resolution error.
        NameResolutionError = 0x13 => "AR name resolution error",
        /// 0x14: RPC bind error.
        RpcBindError = 0x14 => "AR RPC bind error",
        /// 0x15: RPC connect error.
        RpcConnectError = 0x15 => "AR RPC connect error",
        /// 0x16: RPC read error.
        RpcReadError = 0x16 => "AR RPC read error",
        /// 0x17: RPC write error.
        RpcWriteError = 0x17 => "AR RPC write error",
        /// 0x18: RPC control error.
        RpcControlError = 0x18 => "AR RPC control error",
        /// 0x19: forbidden pull or plug.
        ForbiddenPullOrPlug = 0x19 => "AR forbidden pull or plug",
        /// 0x1A: AP removed.
        ApRemoved = 0x1a => "AR AP removed",
        /// 0x1B: link down.
        LinkDown = 0x1b => "AR link down",
        /// 0x1C: multicast MAC registration failed.
        MulticastRegistrationFailed = 0x1c => "AR multicast MAC registration failed",
        /// 0x1D: not synchronized.
        NotSynchronized = 0x1d => "not synchronized",
        /// 0x1E: wrong topology.
        WrongTopology = 0x1e => "wrong topology",
        /// 0x1F: NameOfStation changed by DCP.
        StationNameChanged = 0x1f => "DCP station name changed",
        /// 0x20: reset to factory by DCP.
        ResetToFactory = 0x20 => "DCP reset to factory",
        /// 0x24: PDEV check failed (no port with the required speed/duplex).
        PdevCheckFailed = 0x24 => "PDEV check failed",
        /// 0x25: the IO controller's IP suite was changed (DCP or local engineering).
        IocIpChanged = 0x25 => "IOC IP suite changed",
    }
}

impl core::fmt::Display for AbortCode {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let code = u8::from(*self);
        match self.name() {
            Some(name) => write!(f, "{name} ({code:#04x})"),
            None => write!(f, "abort code {code:#04x}"),
        }
    }
}

/// The VarPart of an ERR-RTA.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ErrRta {
    /// PNIOStatus, `CF 81 FD <abort code>` for an abort.
    pub status: PnioStatus,
    /// Bytes after the PNIOStatus within VarPartLen (vendor error info; normally none).
    pub vendor_data: Vec<u8>,
}

impl ErrRta {
    /// An abort with this code: PNIOStatus `CF 81 FD <code>`.
    pub fn abort(code: AbortCode) -> ErrRta {
        ErrRta {
            status: PnioStatus {
                error_code: ERROR_CODE_RTA,
                error_decode: ERROR_DECODE_PNIO,
                error_code1: ERROR_CODE1_RTA_PROTOCOL,
                error_code2: code.into(),
            },
            vendor_data: Vec::new(),
        }
    }

    /// The abort code, when the status is `CF 81 FD xx`.
    pub fn abort_code(&self) -> Option<AbortCode> {
        let s = self.status;
        (s.error_code == ERROR_CODE_RTA
            && s.error_decode == ERROR_DECODE_PNIO
            && s.error_code1 == ERROR_CODE1_RTA_PROTOCOL)
            .then(|| AbortCode::from(s.error_code2))
    }

    /// Parses a VarPart (at least the 4 status bytes).
    pub fn parse(b: &[u8]) -> Result<ErrRta> {
        let mut r = Reader::new(b);
        let status = PnioStatus::from_u32(r.u32()?);
        Ok(ErrRta {
            status,
            vendor_data: r.rest().to_vec(),
        })
    }

    /// Bytes of the VarPart.
    pub fn buffer_len(&self) -> usize {
        self.vendor_data.len().saturating_add(4)
    }

    pub(super) fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u32(self.status.to_u32())?;
        w.put(&self.vendor_data)
    }
}

impl core::fmt::Display for ErrRta {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.abort_code() {
            Some(code) => write!(f, "abort: {code}"),
            None => write!(f, "{}", self.status),
        }
    }
}
