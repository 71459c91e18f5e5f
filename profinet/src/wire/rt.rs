// SPDX-License-Identifier: MIT OR Apache-2.0
//! Cyclic real-time frames (RT class 1/2): FrameID, C_SDU, CycleCounter, DataStatus,
//! TransferStatus.
//!
//! The view starts at the FrameID (the Ethernet payload behind EtherType 0x8892). The APDU
//! status (CycleCounter, DataStatus, TransferStatus) follows the C_SDU of `DataLength` bytes,
//! which the IOCR defines; it is located from that length, not from the end of the buffer,
//! because Ethernet may pad a frame.

use super::{EmitError, EmitResult, Error, Field, Result, be16};

/// Smallest C_SDU: shorter IO data is padded up to it, so a frame is never shorter than the
/// Ethernet minimum.
pub const MIN_DATA_LENGTH: usize = 40;
/// Largest C_SDU.
pub const MAX_DATA_LENGTH: usize = 1440;

/// The RT time unit, 31.25 µs: the send clock is SendClockFactor of them, and the
/// CycleCounter counts them. The one definition of the unit in the workspace.
pub const TIME_UNIT_NS: u64 = 31_250;

/// The CycleCounter of a frame scheduled at `time_ns`: the time in [`TIME_UNIT_NS`] modulo
/// 2^16, so consecutive frames of a CR step by SendClockFactor × ReductionRatio.
pub const fn cycle_counter_at(time_ns: u64) -> u16 {
    // Truncation intended: the counter runs modulo 2^16.
    (time_ns / TIME_UNIT_NS) as u16
}

mod field {
    use super::Field;
    pub const FRAME_ID: Field = 0..2;
    pub const DATA_START: usize = 2;
    /// The APDU status after `n` bytes of C_SDU.
    pub const fn apdu_status(n: usize) -> Field {
        DATA_START + n..DATA_START + n + 4
    }
}

/// DataStatus bits.
pub mod data_status {
    /// Primary (1) or backup (0).
    pub const STATE_PRIMARY: u8 = 0x01;
    /// Redundancy (with State, system redundancy).
    pub const REDUNDANCY: u8 = 0x02;
    /// The data is valid.
    pub const DATA_VALID: u8 = 0x04;
    /// The provider runs (1) or is stopped (0).
    pub const PROVIDER_RUN: u8 = 0x10;
    /// No problem (1) or the station has a diagnosis (0).
    pub const STATION_OK: u8 = 0x20;
    /// Ignore DataStatus (dynamic frame packing subframes).
    pub const IGNORE: u8 = 0x80;
    /// Primary, valid, run, no problem: 0x35, what a provider in OPERATE sends.
    pub const OPERATE: u8 = STATE_PRIMARY | DATA_VALID | PROVIDER_RUN | STATION_OK;
    /// Primary, valid, stopped, no problem: 0x25, what a controller in CLEAR sends.
    pub const CLEAR: u8 = STATE_PRIMARY | DATA_VALID | STATION_OK;
}

/// The class of a FrameID.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameIdClass {
    /// 0x0100–0x7FFF: RT class 3 (IRT).
    RtClass3,
    /// 0x8000–0xBBFF: cyclic unicast, IOCRProperties.RTClass 2.
    RtClass2Unicast,
    /// 0xBC00–0xBFFF: cyclic multicast, RTClass 2.
    RtClass2Multicast,
    /// 0xC000–0xF7FF: cyclic unicast, RTClass 1 (legacy).
    RtClass1Unicast,
    /// 0xF800–0xFBFF: cyclic multicast, RTClass 1.
    RtClass1Multicast,
    /// 0xFC01: alarm, high priority.
    AlarmHigh,
    /// 0xFE01: alarm, low priority.
    AlarmLow,
    /// 0xFEFC–0xFEFF: DCP.
    Dcp,
    /// Anything else (PTCP, fragmentation, reserved).
    Other,
}

impl FrameIdClass {
    /// The class of `frame_id`.
    pub const fn of(frame_id: u16) -> FrameIdClass {
        match frame_id {
            0x0100..=0x7fff => FrameIdClass::RtClass3,
            0x8000..=0xbbff => FrameIdClass::RtClass2Unicast,
            0xbc00..=0xbfff => FrameIdClass::RtClass2Multicast,
            0xc000..=0xf7ff => FrameIdClass::RtClass1Unicast,
            0xf800..=0xfbff => FrameIdClass::RtClass1Multicast,
            0xfc01 => FrameIdClass::AlarmHigh,
            0xfe01 => FrameIdClass::AlarmLow,
            0xfefc..=0xfeff => FrameIdClass::Dcp,
            _ => FrameIdClass::Other,
        }
    }

    /// Whether frames of this class carry cyclic IO data.
    pub const fn is_cyclic(self) -> bool {
        matches!(
            self,
            FrameIdClass::RtClass2Unicast
                | FrameIdClass::RtClass2Multicast
                | FrameIdClass::RtClass1Unicast
                | FrameIdClass::RtClass1Multicast
        )
    }
}

/// A view of a cyclic RT frame whose C_SDU is `data_length` bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Packet<T: AsRef<[u8]>> {
    buffer: T,
    data_length: usize,
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// Wraps a buffer without checking it.
    pub const fn new_unchecked(buffer: T, data_length: usize) -> Packet<T> {
        Packet {
            buffer,
            data_length,
        }
    }

    /// Wraps a buffer after checking it holds the FrameID, the C_SDU and the APDU status.
    pub fn new_checked(buffer: T, data_length: usize) -> Result<Packet<T>> {
        let p = Packet::new_unchecked(buffer, data_length);
        p.check_len()?;
        Ok(p)
    }

    /// Checks the lengths: `data_length` within 40..=1440 and the buffer long enough.
    pub fn check_len(&self) -> Result<()> {
        if !(MIN_DATA_LENGTH..=MAX_DATA_LENGTH).contains(&self.data_length)
            || self.buffer.as_ref().len() < field::apdu_status(self.data_length).end
        {
            return Err(Error);
        }
        Ok(())
    }

    /// Bytes the frame occupies from the FrameID to the TransferStatus.
    pub const fn frame_len(&self) -> usize {
        field::apdu_status(self.data_length).end
    }

    /// The FrameID.
    pub fn frame_id(&self) -> u16 {
        be16(&self.buffer.as_ref()[field::FRAME_ID])
    }

    /// The C_SDU.
    pub fn data(&self) -> &[u8] {
        &self.buffer.as_ref()[field::DATA_START..field::DATA_START + self.data_length]
    }

    fn status(&self) -> &[u8] {
        &self.buffer.as_ref()[field::apdu_status(self.data_length)]
    }

    /// CycleCounter, in 31.25 µs units.
    pub fn cycle_counter(&self) -> u16 {
        be16(&self.status()[0..2])
    }

    /// DataStatus.
    pub fn data_status(&self) -> u8 {
        self.status()[2]
    }

    /// TransferStatus (0: OK).
    pub fn transfer_status(&self) -> u8 {
        self.status()[3]
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Packet<T> {
    /// Sets the FrameID.
    pub fn set_frame_id(&mut self, v: u16) {
        self.buffer.as_mut()[field::FRAME_ID].copy_from_slice(&v.to_be_bytes());
    }

    /// The C_SDU, writable.
    pub fn data_mut(&mut self) -> &mut [u8] {
        let n = self.data_length;
        &mut self.buffer.as_mut()[field::DATA_START..field::DATA_START + n]
    }

    /// Sets the APDU status.
    pub fn set_apdu_status(&mut self, cycle_counter: u16, data_status: u8, transfer_status: u8) {
        let at = field::apdu_status(self.data_length);
        let s = &mut self.buffer.as_mut()[at];
        s[0..2].copy_from_slice(&cycle_counter.to_be_bytes());
        s[2] = data_status;
        s[3] = transfer_status;
    }
}

/// The header and trailer of a cyclic frame; the C_SDU stays in the buffer (the cycle copies
/// IO data between frames and the image without an intermediate copy).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Repr {
    /// FrameID.
    pub frame_id: u16,
    /// C_SDU length.
    pub data_length: usize,
    /// CycleCounter.
    pub cycle_counter: u16,
    /// DataStatus.
    pub data_status: u8,
    /// TransferStatus.
    pub transfer_status: u8,
}

impl Repr {
    /// Parses a frame whose C_SDU the IOCR says is `data_length` bytes. Refuses frames that
    /// are too short, FrameIDs that are not cyclic, and lengths outside 40..=1440.
    pub fn parse<T: AsRef<[u8]>>(packet: &Packet<T>) -> Result<Repr> {
        packet.check_len()?;
        if !FrameIdClass::of(packet.frame_id()).is_cyclic() {
            return Err(Error);
        }
        Ok(Repr {
            frame_id: packet.frame_id(),
            data_length: packet.data_length,
            cycle_counter: packet.cycle_counter(),
            data_status: packet.data_status(),
            transfer_status: packet.transfer_status(),
        })
    }

    /// Bytes from the FrameID to the TransferStatus.
    pub const fn buffer_len(&self) -> usize {
        field::apdu_status(self.data_length).end
    }

    /// Writes the FrameID and the APDU status; the C_SDU between them is left as it is. A
    /// packet viewed with another C_SDU length than this frame's, or a buffer shorter than
    /// [`buffer_len`](Self::buffer_len), gives [`EmitError`].
    pub fn emit<T: AsRef<[u8]> + AsMut<[u8]>>(&self, packet: &mut Packet<T>) -> EmitResult<()> {
        if packet.data_length != self.data_length {
            return Err(EmitError::Inconsistent(
                "the packet is viewed with another C_SDU length than the frame has",
            ));
        }
        EmitError::check_len("RT frame", self.buffer_len(), packet.buffer.as_ref().len())?;
        packet.set_frame_id(self.frame_id);
        packet.set_apdu_status(self.cycle_counter, self.data_status, self.transfer_status);
        Ok(())
    }

    /// Whether a consumer may use the data: valid, and not to be ignored by the transfer.
    pub const fn data_usable(&self) -> bool {
        self.data_status & data_status::DATA_VALID != 0 && self.transfer_status == 0
    }
}

/// Whether `new` is a fresh CycleCounter after `last`: PROFINET consumers accept a frame
/// only if `(new − last) mod 2^16` lies in 1..=61440, which refuses repeats and old frames.
pub const fn cycle_counter_is_newer(new: u16, last: u16) -> bool {
    let d = new.wrapping_sub(last);
    d >= 1 && d <= 61440
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::ethernet;

    // The S7-1515 -> p-net cyclic frame, FrameID 0x8001, DataLength 40
    // (captures/rt/rtc_cpu_8001.hex; test data of the pnio crate 0.1.0, MIT OR Apache-2.0).
    static CPU_8001: [u8; 64] = [
        0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8, 0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f, 0x81, 0x00, 0xc0,
        0x00, 0x88, 0x92, 0x80, 0x01, 0x80, 0x80, 0x80, 0x80, 0x00, 0x80, 0x80, 0x00, 0x80, 0x80,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0xb8, 0x00, 0x35, 0x00,
    ];

    fn pdu(frame: &[u8]) -> &[u8] {
        ethernet::Frame::new_checked(frame).unwrap().payload()
    }

    #[test]
    fn deconstruct_capture() {
        let p = Packet::new_checked(pdu(&CPU_8001), 40).unwrap();
        let r = Repr::parse(&p).unwrap();
        assert_eq!(r.frame_id, 0x8001);
        assert_eq!(r.cycle_counter, 0xb800);
        assert_eq!(r.data_status, data_status::OPERATE);
        assert!(r.data_usable());
        assert_eq!(&p.data()[..6], &[0x80, 0x80, 0x80, 0x80, 0x00, 0x80]);
    }

    #[test]
    fn construct_capture() {
        let mut buf = [0xa5u8; 46];
        let src = Packet::new_checked(pdu(&CPU_8001), 40).unwrap();
        let r = Repr::parse(&src).unwrap();
        let mut p = Packet::new_unchecked(&mut buf[..], 40);
        p.data_mut().copy_from_slice(src.data());
        r.emit(&mut p).unwrap();
        assert_eq!(&buf[..], pdu(&CPU_8001));
        assert!(
            r.emit(&mut Packet::new_unchecked(&mut buf[..45], 40))
                .is_err()
        );
        assert!(
            r.emit(&mut Packet::new_unchecked(&mut buf[..], 39))
                .is_err()
        );
    }

    #[test]
    fn wrong_lengths_and_classes_are_refused() {
        let frame = pdu(&CPU_8001);
        assert!(Packet::new_checked(frame, 39).is_err());
        assert!(Packet::new_checked(frame, 41).is_err());
        assert!(Packet::new_checked(&frame[..45], 40).is_err());
        let mut dcp = frame.to_vec();
        dcp[0..2].copy_from_slice(&0xfefeu16.to_be_bytes());
        assert!(Repr::parse(&Packet::new_unchecked(&dcp[..], 40)).is_err());
    }

    #[test]
    fn cycle_counter_window() {
        assert!(cycle_counter_is_newer(32, 0));
        assert!(cycle_counter_is_newer(0, 65504));
        assert!(!cycle_counter_is_newer(0, 0));
        assert!(!cycle_counter_is_newer(0, 32));
        assert!(cycle_counter_is_newer(61440, 0));
        assert!(!cycle_counter_is_newer(61441, 0));
    }

    proptest::proptest! {
        #[test]
        fn parse_never_panics(buf in proptest::collection::vec(0u8..=255, 0..1600), len in 0usize..2000) {
            let _ = Repr::parse(&Packet::new_unchecked(&buf[..], len));
        }

        #[test]
        fn round_trip(frame_id in 0x8000u16..0xbc00, len in 40usize..=1440, cc: u16, ds: u8, ts: u8) {
            let r = Repr { frame_id, data_length: len, cycle_counter: cc, data_status: ds, transfer_status: ts };
            let mut buf = vec![0u8; r.buffer_len()];
            r.emit(&mut Packet::new_unchecked(&mut buf[..], len)).unwrap();
            proptest::prop_assert_eq!(Repr::parse(&Packet::new_unchecked(&buf[..], len)), Ok(r));
        }
    }
}
