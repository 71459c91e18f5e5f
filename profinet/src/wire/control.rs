// SPDX-License-Identifier: MIT OR Apache-2.0
//! Control blocks of the CM protocol: PrmBegin, PrmEnd, ApplicationReady, Release and their
//! responses.
//!
//! Every control block has the same 32 bytes: the [`BlockHeader`] (BlockLength 0x001C,
//! version 1.0) and a fixed body, all big-endian whatever the RPC DREP:
//!
//! ```text
//! BlockType(2) BlockLength(2)=0x001C Version(2)=0x0100 Reserved(2)=0 ARUUID(16) SessionKey(2)
//! Reserved-or-AlarmSequenceNumber(2) ControlCommand(2) ControlBlockProperties(2)
//! ```
//!
//! The second reserved field carries the AlarmSequenceNumber in the plug variants (0x0111,
//! 0x0113 and their responses). The sequence is Connect → PrmEnd (IOC → IOD, opnum 4) →
//! ApplicationReady (IOD → IOC, opnum 4) → data exchange → Release (IOC → IOD, opnum 1); every
//! request is answered by the block type with bit 15 set ([`BlockType::response`]) and
//! [`command::DONE`].

use super::common::BLOCK_HEADER_LEN;
use super::{BlockHeader, BlockType, EmitError, EmitResult, Error, Field, Result, Uuid, be16};

/// Whether `t` is a control block type: PrmEnd, PlugPrmEnd, ApplicationReady,
/// PlugApplicationReady, Release or PrmBegin, request or response.
pub const fn is_control(t: BlockType) -> bool {
    matches!(
        t.request(),
        BlockType::PrmEndReq
            | BlockType::PlugPrmEndReq
            | BlockType::ApplicationReadyReq
            | BlockType::PlugApplicationReadyReq
            | BlockType::ReleaseReq
            | BlockType::PrmBeginReq
    )
}

/// ControlCommand bits.
pub mod command {
    /// PrmEnd: the controller has written all parameters.
    pub const PRM_END: u16 = 0x0001;
    /// ApplicationReady: the device is ready for data exchange.
    pub const APPLICATION_READY: u16 = 0x0002;
    /// Release: the controller ends the AR.
    pub const RELEASE: u16 = 0x0004;
    /// Done: the answer to any of the above.
    pub const DONE: u16 = 0x0008;
    /// ReadyForCompanion.
    pub const READY_FOR_COMPANION: u16 = 0x0010;
    /// ReadyForRT_CLASS_3.
    pub const READY_FOR_RT_CLASS_3: u16 = 0x0020;
    /// PrmBegin: the controller starts re-parameterizing.
    pub const PRM_BEGIN: u16 = 0x0040;
}

mod field {
    use super::Field;
    pub const RESERVED: Field = 6..8;
    pub const AR_UUID: Field = 8..24;
    pub const SESSION_KEY: Field = 24..26;
    pub const ALARM_SEQUENCE_NUMBER: Field = 26..28;
    pub const CONTROL_COMMAND: Field = 28..30;
    pub const PROPERTIES: Field = 30..32;
}

/// Bytes of a control block, header included.
pub const BLOCK_LEN: usize = field::PROPERTIES.end;
/// BlockLength of a control block (total − 4).
// 28: the fixed layout above, far below u16::MAX, so the cast keeps every bit.
pub const BLOCK_LENGTH: u16 = (BLOCK_LEN - 4) as u16;

buffer_view! {
    /// A view of a control block, from its BlockType on.
    pub struct Packet;
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// Checks the buffer holds the [`BLOCK_LEN`] bytes of a control block (bytes after them
    /// are allowed and ignored).
    pub fn check_len(&self) -> Result<()> {
        if self.buffer.as_ref().len() < BLOCK_LEN {
            Err(Error)
        } else {
            Ok(())
        }
    }

    /// The block header.
    pub fn header(&self) -> BlockHeader {
        let b = self.buffer.as_ref();
        BlockHeader {
            block_type: BlockType::from_raw(be16(&b[0..2])),
            length: be16(&b[2..4]),
            version_high: b[4],
            version_low: b[5],
        }
    }

    /// The reserved field after the header (0).
    pub fn reserved(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::RESERVED])
    }

    /// ARUUID.
    pub fn ar_uuid(&self) -> Uuid {
        let mut u = [0u8; 16];
        u.copy_from_slice(&self.buffer.as_ref()[field::AR_UUID]);
        Uuid(u)
    }

    /// SessionKey.
    pub fn session_key(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::SESSION_KEY])
    }

    /// AlarmSequenceNumber in the plug variants; reserved (0) otherwise.
    pub fn alarm_sequence_number(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::ALARM_SEQUENCE_NUMBER])
    }

    /// ControlCommand ([`command`] bits).
    pub fn control_command(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::CONTROL_COMMAND])
    }

    /// ControlBlockProperties (0).
    pub fn control_block_properties(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::PROPERTIES])
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Packet<T> {
    /// Writes the block header.
    pub fn set_header(&mut self, h: BlockHeader) {
        self.buffer.as_mut()[..BLOCK_HEADER_LEN].copy_from_slice(&h.to_bytes());
    }

    /// Sets the reserved field after the header.
    pub fn set_reserved(&mut self, v: u16) {
        self.buffer.as_mut()[field::RESERVED].copy_from_slice(&v.to_be_bytes());
    }

    /// Sets the ARUUID.
    pub fn set_ar_uuid(&mut self, v: Uuid) {
        self.buffer.as_mut()[field::AR_UUID].copy_from_slice(&v.0);
    }

    /// Sets the SessionKey.
    pub fn set_session_key(&mut self, v: u16) {
        self.buffer.as_mut()[field::SESSION_KEY].copy_from_slice(&v.to_be_bytes());
    }

    /// Sets the AlarmSequenceNumber / reserved field.
    pub fn set_alarm_sequence_number(&mut self, v: u16) {
        self.buffer.as_mut()[field::ALARM_SEQUENCE_NUMBER].copy_from_slice(&v.to_be_bytes());
    }

    /// Sets the ControlCommand.
    pub fn set_control_command(&mut self, v: u16) {
        self.buffer.as_mut()[field::CONTROL_COMMAND].copy_from_slice(&v.to_be_bytes());
    }

    /// Sets the ControlBlockProperties.
    pub fn set_control_block_properties(&mut self, v: u16) {
        self.buffer.as_mut()[field::PROPERTIES].copy_from_slice(&v.to_be_bytes());
    }
}

/// A control block.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ControlBlock {
    /// BlockType (a control block type, see [`is_control`]).
    pub block_type: BlockType,
    /// ARUUID of the AR the block controls.
    pub ar_uuid: Uuid,
    /// SessionKey of the AR (from the ARBlockReq).
    pub session_key: u16,
    /// AlarmSequenceNumber in the plug variants; 0 otherwise.
    pub alarm_sequence_number: u16,
    /// ControlCommand ([`command`] bits).
    pub command: u16,
    /// ControlBlockProperties (0).
    pub properties: u16,
}

impl ControlBlock {
    const fn new(
        block_type: BlockType,
        ar_uuid: Uuid,
        session_key: u16,
        command: u16,
    ) -> ControlBlock {
        ControlBlock {
            block_type,
            ar_uuid,
            session_key,
            alarm_sequence_number: 0,
            command,
            properties: 0,
        }
    }

    /// A block of a plug variant, which carries the AlarmSequenceNumber of the plug alarm it
    /// answers.
    const fn for_plug_alarm(
        block_type: BlockType,
        ar_uuid: Uuid,
        session_key: u16,
        alarm_sequence_number: u16,
        command: u16,
    ) -> ControlBlock {
        ControlBlock {
            alarm_sequence_number,
            ..ControlBlock::new(block_type, ar_uuid, session_key, command)
        }
    }

    /// The PrmEnd request the controller sends after the Connect (and its record writes).
    pub const fn prm_end(ar_uuid: Uuid, session_key: u16) -> ControlBlock {
        ControlBlock::new(BlockType::PrmEndReq, ar_uuid, session_key, command::PRM_END)
    }

    /// The ApplicationReady request a device sends to the controller.
    pub const fn application_ready(ar_uuid: Uuid, session_key: u16) -> ControlBlock {
        ControlBlock::new(
            BlockType::ApplicationReadyReq,
            ar_uuid,
            session_key,
            command::APPLICATION_READY,
        )
    }

    /// The controller's answer to a device's ApplicationReady: 0x8112 with Done.
    pub const fn application_ready_done(ar_uuid: Uuid, session_key: u16) -> ControlBlock {
        ControlBlock::new(
            BlockType::ApplicationReadyRes,
            ar_uuid,
            session_key,
            command::DONE,
        )
    }

    /// The PlugPrmEnd request (0x0111) the controller sends when it has written the
    /// parameters of a submodule the device announced with the plug alarm numbered
    /// `alarm_sequence_number`.
    pub const fn plug_prm_end(
        ar_uuid: Uuid,
        session_key: u16,
        alarm_sequence_number: u16,
    ) -> ControlBlock {
        ControlBlock::for_plug_alarm(
            BlockType::PlugPrmEndReq,
            ar_uuid,
            session_key,
            alarm_sequence_number,
            command::PRM_END,
        )
    }

    /// The PlugApplicationReady request (0x0113) a device sends when the submodule of the
    /// plug alarm numbered `alarm_sequence_number` is ready for data exchange.
    pub const fn plug_application_ready(
        ar_uuid: Uuid,
        session_key: u16,
        alarm_sequence_number: u16,
    ) -> ControlBlock {
        ControlBlock::for_plug_alarm(
            BlockType::PlugApplicationReadyReq,
            ar_uuid,
            session_key,
            alarm_sequence_number,
            command::APPLICATION_READY,
        )
    }

    /// The Release request that ends an AR (RPC opnum 1).
    pub const fn release(ar_uuid: Uuid, session_key: u16) -> ControlBlock {
        ControlBlock::new(
            BlockType::ReleaseReq,
            ar_uuid,
            session_key,
            command::RELEASE,
        )
    }

    /// The PrmBegin request that starts a re-parameterization (advanced startup).
    pub const fn prm_begin(ar_uuid: Uuid, session_key: u16) -> ControlBlock {
        ControlBlock::new(
            BlockType::PrmBeginReq,
            ar_uuid,
            session_key,
            command::PRM_BEGIN,
        )
    }

    /// The Done response to `request`: its block type with bit 15 set, its ARUUID, SessionKey
    /// and AlarmSequenceNumber, [`command::DONE`]. `None` if `request` is not a control
    /// request.
    pub const fn done_response_for(request: &ControlBlock) -> Option<ControlBlock> {
        if !request.is_request() {
            return None;
        }
        Some(ControlBlock {
            block_type: request.block_type.response(),
            ar_uuid: request.ar_uuid,
            session_key: request.session_key,
            alarm_sequence_number: request.alarm_sequence_number,
            command: command::DONE,
            properties: 0,
        })
    }

    /// Whether the block type is a control request.
    pub const fn is_request(&self) -> bool {
        is_control(self.block_type) && !self.block_type.is_response()
    }

    /// Whether the block type is a control response.
    pub const fn is_response(&self) -> bool {
        is_control(self.block_type) && self.block_type.is_response()
    }

    /// Whether the command has the Done bit (what a valid response carries).
    pub const fn is_done(&self) -> bool {
        self.command & command::DONE != 0
    }

    /// Whether `self` is the Done response to `request`: the matching response type, the same
    /// ARUUID, SessionKey and AlarmSequenceNumber (0 outside the plug variants), and Done.
    pub fn answers(&self, request: &ControlBlock) -> bool {
        request.is_request()
            && self.block_type == request.block_type.response()
            && self.ar_uuid == request.ar_uuid
            && self.session_key == request.session_key
            && self.alarm_sequence_number == request.alarm_sequence_number
            && self.is_done()
    }

    /// Parses the control block at the start of `b` (bytes after its 32 are ignored). A block
    /// type that is not a control block, a BlockLength other than 0x001C or a version other
    /// than 1.0 give [`Error`]. The leading reserved field is not checked.
    pub fn parse(b: &[u8]) -> Result<ControlBlock> {
        let p = Packet::new_checked(b)?;
        let h = p.header();
        if !is_control(h.block_type)
            || h.length != BLOCK_LENGTH
            || (h.version_high, h.version_low) != (1, 0)
        {
            return Err(Error);
        }
        Ok(ControlBlock {
            block_type: h.block_type,
            ar_uuid: p.ar_uuid(),
            session_key: p.session_key(),
            alarm_sequence_number: p.alarm_sequence_number(),
            command: p.control_command(),
            properties: p.control_block_properties(),
        })
    }

    /// Bytes of the block: always [`BLOCK_LEN`].
    pub const fn buffer_len(&self) -> usize {
        BLOCK_LEN
    }

    /// Writes the block into the first [`BLOCK_LEN`] bytes of `buf`;
    /// [`EmitError::BufferTooShort`] if `buf` is shorter. The block type is written as it is
    /// (only control types parse back).
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        let len = buf.len();
        let b = buf.get_mut(..BLOCK_LEN).ok_or(EmitError::BufferTooShort {
            what: "control block",
            needed: BLOCK_LEN,
            len,
        })?;
        let mut p = Packet::new_unchecked(b);
        p.set_header(BlockHeader {
            block_type: self.block_type,
            length: BLOCK_LENGTH,
            version_high: 1,
            version_low: 0,
        });
        p.set_reserved(0);
        p.set_ar_uuid(self.ar_uuid);
        p.set_session_key(self.session_key);
        p.set_alarm_sequence_number(self.alarm_sequence_number);
        p.set_control_command(self.command);
        p.set_control_block_properties(self.properties);
        Ok(())
    }

    /// The block's bytes.
    pub fn to_bytes(&self) -> [u8; BLOCK_LEN] {
        let mut b = [0u8; BLOCK_LEN];
        // Cannot fail: the array has exactly BLOCK_LEN bytes.
        let _ = self.emit(&mut b);
        b
    }
}

impl core::fmt::Display for ControlBlock {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let name = match self.block_type.request() {
            BlockType::PrmEndReq => "PrmEnd",
            BlockType::PlugPrmEndReq => "PlugPrmEnd",
            BlockType::ApplicationReadyReq => "ApplicationReady",
            BlockType::PlugApplicationReadyReq => "PlugApplicationReady",
            BlockType::ReleaseReq => "Release",
            BlockType::PrmBeginReq => "PrmBegin",
            _ => "Control",
        };
        let dir = if self.block_type.is_response() {
            "res"
        } else {
            "req"
        };
        write!(
            f,
            "{name} {dir} ({:#06x}) AR {} key {} cmd {:#06x}",
            self.block_type.raw(),
            self.ar_uuid,
            self.session_key,
            self.command
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::test_captures::capture_blocks;
    use proptest::prelude::*;

    // The four frames come from the test data of the `pnio` crate 0.1.0
    // (core-engineering/pnio-rs, MIT OR Apache-2.0): an S7-1515 talking to the p-net sample
    // device (captures/cm/*.hex).

    /// S7 Control PrmEnd (frame 57, DREP LE).
    const PRM_END_REQ: &str = "cm/prmend_req";
    /// p-net PrmEnd Done (frame 58, DREP BE).
    const PRM_END_RES: &str = "cm/prmend_res";
    /// p-net ApplicationReady to the S7 (frame 59, DREP BE).
    const APP_READY_REQ: &str = "cm/appready_req";
    /// S7 ApplicationReady Done (frame 60, DREP LE).
    const APP_READY_RES: &str = "cm/appready_res";

    /// AR of the captured connection, e5e1aecc-b133-4b4d-b187-cc68b0211ed2.
    const AR: Uuid = Uuid([
        0xe5, 0xe1, 0xae, 0xcc, 0xb1, 0x33, 0x4b, 0x4d, 0xb1, 0x87, 0xcc, 0x68, 0xb0, 0x21, 0x1e,
        0xd2,
    ]);

    /// Parses the single block of a capture and checks it emits back byte for byte.
    fn round_trip_capture(name: &str) -> ControlBlock {
        let bytes = &capture_blocks(name)[..];
        let c = ControlBlock::parse(bytes).unwrap();
        assert_eq!(c.buffer_len(), bytes.len());
        let mut out = [0xa5u8; BLOCK_LEN];
        c.emit(&mut out).unwrap();
        assert_eq!(&out[..], bytes);
        assert_eq!(c.to_bytes(), out);
        c
    }

    #[test]
    fn prm_end_capture() {
        let req = round_trip_capture(PRM_END_REQ);
        assert_eq!(req.block_type, BlockType::PrmEndReq);
        assert_eq!(req.ar_uuid, AR);
        assert_eq!(
            req.ar_uuid.to_string(),
            "e5e1aecc-b133-4b4d-b187-cc68b0211ed2"
        );
        assert_eq!(req.session_key, 2);
        assert_eq!(req.command, command::PRM_END);
        assert_eq!((req.alarm_sequence_number, req.properties), (0, 0));
        assert!(req.is_request() && !req.is_response() && !req.is_done());
        assert_eq!(req, ControlBlock::prm_end(AR, 2));

        let res = round_trip_capture(PRM_END_RES);
        assert_eq!(res.block_type, BlockType::PrmEndRes);
        assert_eq!(res.command, command::DONE);
        assert!(res.is_response() && res.is_done());
        assert_eq!(ControlBlock::done_response_for(&req), Some(res));
        assert!(res.answers(&req));
        assert!(!req.answers(&req));
        assert!(!res.answers(&ControlBlock::prm_end(AR, 3)));
    }

    #[test]
    fn application_ready_capture() {
        let req = round_trip_capture(APP_READY_REQ);
        assert_eq!(req.block_type, BlockType::ApplicationReadyReq);
        assert_eq!((req.ar_uuid, req.session_key), (AR, 2));
        assert_eq!(req.command, command::APPLICATION_READY);
        assert_eq!(req, ControlBlock::application_ready(AR, 2));

        let res = round_trip_capture(APP_READY_RES);
        assert_eq!(res, ControlBlock::application_ready_done(AR, 2));
        assert_eq!(ControlBlock::done_response_for(&req), Some(res));
        assert_eq!(ControlBlock::done_response_for(&res), None);
        assert!(res.answers(&req));
    }

    #[test]
    fn release_and_prm_begin() {
        let rel = ControlBlock::release(AR, 7);
        let b = rel.to_bytes();
        assert_eq!(&b[..6], &[0x01, 0x14, 0x00, 0x1c, 0x01, 0x00]);
        assert_eq!(&b[28..], &[0x00, 0x04, 0x00, 0x00]);
        assert_eq!(ControlBlock::parse(&b), Ok(rel));
        let done = ControlBlock::done_response_for(&rel).unwrap();
        assert_eq!(
            (done.block_type, done.command),
            (BlockType::ReleaseRes, command::DONE)
        );
        let begin = ControlBlock::prm_begin(AR, 7);
        assert_eq!(
            ControlBlock::done_response_for(&begin).map(|d| d.block_type),
            Some(BlockType::PrmBeginRes)
        );
        assert_eq!(
            rel.to_string(),
            "Release req (0x0114) AR e5e1aecc-b133-4b4d-b187-cc68b0211ed2 key 7 cmd 0x0004"
        );
    }

    #[test]
    fn plug_variants_keep_the_alarm_sequence_number() {
        let req = ControlBlock {
            block_type: BlockType::PlugPrmEndReq,
            alarm_sequence_number: 0x0123,
            ..ControlBlock::prm_end(AR, 1)
        };
        let res = ControlBlock::done_response_for(&req).unwrap();
        assert_eq!(res.block_type, BlockType::PlugPrmEndRes);
        assert_eq!(res.alarm_sequence_number, 0x0123);
        assert_eq!(ControlBlock::parse(&res.to_bytes()), Ok(res));
    }

    #[test]
    fn malformed() {
        let good = ControlBlock::prm_end(AR, 2).to_bytes();
        assert!(ControlBlock::parse(&good[..31]).is_err());
        assert!(ControlBlock::parse(&[]).is_err());
        let mut b = good;
        b[1] = 0x15; // 0x0115 is not a control block
        assert!(ControlBlock::parse(&b).is_err());
        let mut b = good;
        b[3] = 0x1d; // BlockLength 29
        assert!(ControlBlock::parse(&b).is_err());
        let mut b = good;
        b[5] = 1; // version 1.1
        assert!(ControlBlock::parse(&b).is_err());
        let mut short = [0u8; 31];
        assert_eq!(
            ControlBlock::prm_end(AR, 2).emit(&mut short),
            Err(EmitError::BufferTooShort {
                what: "control block",
                needed: 32,
                len: 31
            })
        );
        // Trailing bytes after the block are ignored.
        let mut long = good.to_vec();
        long.extend_from_slice(&[1, 2, 3]);
        assert_eq!(ControlBlock::parse(&long), Ok(ControlBlock::prm_end(AR, 2)));
    }

    fn control_type() -> impl Strategy<Value = BlockType> {
        prop::sample::select(vec![
            BlockType::PrmEndReq,
            BlockType::PlugPrmEndReq,
            BlockType::ApplicationReadyReq,
            BlockType::PlugApplicationReadyReq,
            BlockType::ReleaseReq,
            BlockType::PrmBeginReq,
            BlockType::PrmEndRes,
            BlockType::PlugPrmEndRes,
            BlockType::ApplicationReadyRes,
            BlockType::PlugApplicationReadyRes,
            BlockType::ReleaseRes,
            BlockType::PrmBeginRes,
        ])
    }

    fn control_block() -> impl Strategy<Value = ControlBlock> {
        (control_type(), any::<[u8; 16]>(), any::<[u16; 4]>()).prop_map(|(t, u, [k, a, c, p])| {
            ControlBlock {
                block_type: t,
                ar_uuid: Uuid(u),
                session_key: k,
                alarm_sequence_number: a,
                command: c,
                properties: p,
            }
        })
    }

    proptest! {
        #[test]
        fn parse_never_panics(b in proptest::collection::vec(any::<u8>(), 0..64)) {
            let _ = ControlBlock::parse(&b);
            if let Ok(p) = Packet::new_checked(&b[..]) {
                let _ = (p.header(), p.reserved(), p.ar_uuid(), p.session_key());
                let _ = (p.alarm_sequence_number(), p.control_command(), p.control_block_properties());
            }
        }

        #[test]
        fn parse_never_panics_on_plausible_blocks(t in control_type(), body in proptest::collection::vec(any::<u8>(), 0..40)) {
            let mut b = t.raw().to_be_bytes().to_vec();
            b.extend_from_slice(&[0x00, 0x1c, 0x01, 0x00]);
            b.extend_from_slice(&body);
            let r = ControlBlock::parse(&b);
            prop_assert_eq!(r.is_ok(), b.len() >= BLOCK_LEN);
        }

        #[test]
        fn round_trip(c in control_block()) {
            let b = c.to_bytes();
            prop_assert_eq!(ControlBlock::parse(&b), Ok(c));
            if let Some(res) = ControlBlock::done_response_for(&c) {
                prop_assert!(res.answers(&c));
                prop_assert_eq!(ControlBlock::parse(&res.to_bytes()), Ok(res));
            }
        }
    }
}
