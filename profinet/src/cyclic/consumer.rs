// SPDX-License-Identifier: MIT OR Apache-2.0
//! The consumer of a CR: which received frames carry usable data, and when the data hold
//! timer (the consumer watchdog) runs out. Every consumer in the workspace is this one: the
//! cycle thread's for each AR of either role, the device engine's own, the demo PLC's and
//! the test world's.
//!
//! The rule, from the consumer protocol machine of IEC 61158-6-10 as PROFINET devices
//! apply it (p-net, the S7's controllers):
//!
//! 1. A frame counts only if it comes from the AR's peer with the CR's FrameID, and holds
//!    the CR's C_SDU and APDU status (Ethernet padding may follow). Otherwise it is
//!    [`Verdict::Foreign`] or [`Verdict::TooShort`] and changes nothing.
//! 2. Its CycleCounter must be newer than the last accepted one: `(new − last) mod 2^16` in
//!    1..=61440. A repeat or an old frame is [`Verdict::Stale`] and changes nothing.
//! 3. Its data are usable only with DataStatus.DataValid set and TransferStatus 0; State
//!    (primary/backup) is not judged, since devices have been seen to send backup while
//!    meaning primary. A frame without valid data is [`Verdict::Invalid`]: it does not
//!    reload the watchdog and does not become the last counter, as if it had not come;
//!    the caller may say what the provider said (procimgd marks the inputs BAD).
//! 4. Only an [`Verdict::Accepted`] frame reloads the watchdog. The first one arms it: it
//!    ends [`started`](Consumer::start) supervision's grace, which waits up to
//!    [`FIRST_FRAME_GRACE_NS`] (or the watchdog time, if longer) for the peer to begin.
//!    After it, the watchdog runs out once DataHoldFactor frame periods pass without an
//!    accepted frame.

use super::CyclicAr;
use crate::wire::MacAddress;
use crate::wire::rt::{self, cycle_counter_is_newer};

/// How long a started consumer waits for the peer's first valid frame: a device begins to
/// send its inputs only at PrmEnd, after the record writes, and a controller's frames may
/// need the ARP and RPC exchanges of a Connect first. Whoever started the exchange gives up
/// on its own terms if that never comes (the controller's retries, the device's CMI
/// timeout); this bound only keeps a silent peer from being supervised forever.
pub const FIRST_FRAME_GRACE_NS: u64 = 5_000_000_000;

/// What a consumer made of one received frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict<'a> {
    /// Fresh, valid data: the watchdog is reloaded.
    Accepted {
        /// The C_SDU: the CR's `data_length` bytes of data and status.
        c_sdu: &'a [u8],
        /// The frame's DataStatus.
        data_status: u8,
        /// The first accepted frame since the consumer was made: data exchange began.
        first: bool,
    },
    /// Newer, but DataValid is off or TransferStatus is not 0: nothing to use.
    Invalid {
        /// The frame's DataStatus.
        data_status: u8,
    },
    /// Not newer than the last accepted frame: a repeat or an old frame.
    Stale,
    /// Another sender or another FrameID: not this consumer's frame.
    Foreign,
    /// Too short for the CR's C_SDU and APDU status.
    TooShort,
}

impl Verdict<'_> {
    /// The verdict without the frame's contents, for counting and comparing.
    pub const fn kind(&self) -> VerdictKind {
        match self {
            Verdict::Accepted { .. } => VerdictKind::Accepted,
            Verdict::Invalid { .. } => VerdictKind::Invalid,
            Verdict::Stale => VerdictKind::Stale,
            Verdict::Foreign => VerdictKind::Foreign,
            Verdict::TooShort => VerdictKind::TooShort,
        }
    }
}

/// A [`Verdict`] without the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VerdictKind {
    /// [`Verdict::Accepted`].
    Accepted,
    /// [`Verdict::Invalid`].
    Invalid,
    /// [`Verdict::Stale`].
    Stale,
    /// [`Verdict::Foreign`].
    Foreign,
    /// [`Verdict::TooShort`].
    TooShort,
}

/// How many frames a consumer gave each verdict.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VerdictCounts {
    /// [`Verdict::Accepted`].
    pub accepted: u64,
    /// [`Verdict::Invalid`].
    pub invalid: u64,
    /// [`Verdict::Stale`].
    pub stale: u64,
    /// [`Verdict::Foreign`].
    pub foreign: u64,
    /// [`Verdict::TooShort`].
    pub too_short: u64,
}

impl VerdictCounts {
    fn count(&mut self, v: VerdictKind) {
        let n = match v {
            VerdictKind::Accepted => &mut self.accepted,
            VerdictKind::Invalid => &mut self.invalid,
            VerdictKind::Stale => &mut self.stale,
            VerdictKind::Foreign => &mut self.foreign,
            VerdictKind::TooShort => &mut self.too_short,
        };
        *n += 1;
    }
}

/// The consumer of one CR (see the [module](self) for its rule). It allocates nothing, so
/// the cycle thread runs it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Consumer {
    frame_id: u16,
    data_length: usize,
    peer: MacAddress,
    watchdog_ns: u64,
    /// When supervision started; `None`: not yet (no deadline before the first frame).
    started_ns: Option<u64>,
    last_counter: Option<u16>,
    last_accepted_ns: Option<u64>,
    data_status: u8,
    counts: VerdictCounts,
}

impl Consumer {
    /// The consumer of the CR with `frame_id` and `data_length` C_SDU bytes sent by `peer`,
    /// whose watchdog runs out `watchdog_ns` after the last accepted frame. Supervision
    /// begins with the first accepted frame or [`start`](Self::start).
    pub const fn new(
        frame_id: u16,
        data_length: usize,
        peer: MacAddress,
        watchdog_ns: u64,
    ) -> Consumer {
        Consumer {
            frame_id,
            data_length,
            peer,
            watchdog_ns,
            started_ns: None,
            last_counter: None,
            last_accepted_ns: None,
            data_status: 0,
            counts: VerdictCounts {
                accepted: 0,
                invalid: 0,
                stale: 0,
                foreign: 0,
                too_short: 0,
            },
        }
    }

    /// The consumer of the CR that `ar` consumes, started at `now_ns` (the exchange runs
    /// from the moment it is handed to the cycle).
    pub const fn of(ar: &CyclicAr, now_ns: u64) -> Consumer {
        let mut c = Consumer::new(
            ar.input.frame_id,
            ar.input.data_length,
            ar.peer,
            ar.timing.watchdog_ns(),
        );
        c.started_ns = Some(now_ns);
        c
    }

    /// Starts supervision at `now_ns` if it has not started: from now on the peer's first
    /// frame is awaited for the grace time at most. A no-op once started.
    pub fn start(&mut self, now_ns: u64) {
        self.started_ns.get_or_insert(now_ns);
    }

    /// Judges a cyclic frame from `src`, `pdu` being its Ethernet payload from the FrameID
    /// on, received at `now_ns`.
    #[inline]
    pub fn consume<'a>(&mut self, src: MacAddress, pdu: &'a [u8], now_ns: u64) -> Verdict<'a> {
        let v = self.judge(src, pdu, now_ns);
        self.counts.count(v.kind());
        v
    }

    #[inline]
    fn judge<'a>(&mut self, src: MacAddress, pdu: &'a [u8], now_ns: u64) -> Verdict<'a> {
        if src != self.peer || pdu.get(..2) != Some(&self.frame_id.to_be_bytes()[..]) {
            return Verdict::Foreign;
        }
        let Ok(packet) = rt::Packet::new_checked(pdu, self.data_length) else {
            return Verdict::TooShort;
        };
        let Ok(repr) = rt::Repr::parse(&packet) else {
            return Verdict::TooShort;
        };
        if self
            .last_counter
            .is_some_and(|last| !cycle_counter_is_newer(repr.cycle_counter, last))
        {
            return Verdict::Stale;
        }
        if !repr.data_usable() {
            return Verdict::Invalid {
                data_status: repr.data_status,
            };
        }
        let first = self.last_accepted_ns.is_none();
        self.last_counter = Some(repr.cycle_counter);
        self.last_accepted_ns = Some(now_ns);
        self.started_ns.get_or_insert(now_ns);
        self.data_status = repr.data_status;
        let Some(c_sdu) = pdu.get(2..2 + self.data_length) else {
            // new_checked saw the C_SDU, so this cannot be; judged as what it would mean.
            return Verdict::TooShort;
        };
        Verdict::Accepted {
            c_sdu,
            data_status: repr.data_status,
            first,
        }
    }

    /// When the watchdog runs out if no frame is accepted before it: the watchdog time after
    /// the last accepted frame; before the first, the grace after the start; `None` before
    /// either.
    #[inline]
    pub fn deadline_ns(&self) -> Option<u64> {
        match (self.last_accepted_ns, self.started_ns) {
            (Some(t), _) => Some(t.saturating_add(self.watchdog_ns)),
            (None, Some(t)) => Some(t.saturating_add(self.watchdog_ns.max(FIRST_FRAME_GRACE_NS))),
            (None, None) => None,
        }
    }

    /// Whether the watchdog ran out by `now_ns`: its whole time passed without an accepted
    /// frame.
    #[inline]
    pub fn expired(&self, now_ns: u64) -> bool {
        self.deadline_ns().is_some_and(|d| now_ns >= d)
    }

    /// Whether a frame was accepted: data exchange began.
    pub const fn receiving(&self) -> bool {
        self.last_accepted_ns.is_some()
    }

    /// The DataStatus of the last accepted frame (0 before the first).
    pub const fn data_status(&self) -> u8 {
        self.data_status
    }

    /// The FrameID consumed.
    pub const fn frame_id(&self) -> u16 {
        self.frame_id
    }

    /// The C_SDU length consumed.
    pub const fn data_length(&self) -> usize {
        self.data_length
    }

    /// How many frames got each verdict.
    pub const fn counts(&self) -> VerdictCounts {
        self.counts
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cyclic::CrTiming;
    use crate::cyclic::trial::TrialSetup;
    use crate::test_fixtures::capture;
    use crate::wire::ethernet;
    use proptest::prelude::*;

    const MS: u64 = 1_000_000;
    /// The S7-1515 and the p-net device of the captures.
    const S7: MacAddress = MacAddress([0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f]);
    const PNET: MacAddress = MacAddress([0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8]);

    /// The capture's output CR: 40 bytes every 32 ms (SendClockFactor 32, ReductionRatio
    /// 32), DataHoldFactor 3, as the S7 bench configured it.
    fn s7_output_cr() -> Consumer {
        let timing = CrTiming {
            send_clock_factor: 32,
            reduction_ratio: 32,
            every_cycles: 1,
            data_hold_factor: 3,
        };
        Consumer::new(0x8001, 40, S7, timing.watchdog_ns())
    }

    fn pdu(frame: &[u8]) -> (MacAddress, &[u8]) {
        let eth = ethernet::Frame::new_checked(frame).unwrap();
        (eth.src(), &frame[frame.len() - eth.payload().len()..])
    }

    #[test]
    fn the_s7s_captured_frame_is_accepted_once_and_arms_the_watchdog() {
        // rt/rtc_cpu_8001.hex: CycleCounter 0xb800, DataStatus 0x35.
        let frame = capture("rt/rtc_cpu_8001");
        let (src, pdu) = pdu(&frame);
        let mut c = s7_output_cr();
        assert_eq!(
            c.deadline_ns(),
            None,
            "nothing supervised before a start or a frame"
        );
        match c.consume(src, pdu, 10 * MS) {
            Verdict::Accepted {
                c_sdu,
                data_status,
                first,
            } => {
                assert_eq!(c_sdu, &pdu[2..42]);
                assert_eq!((data_status, first), (0x35, true));
            }
            v => panic!("the S7's frame was judged {v:?}"),
        }
        assert_eq!(
            c.deadline_ns(),
            Some(10 * MS + 96 * MS),
            "3 × 32 ms after it"
        );
        assert_eq!(
            c.consume(src, pdu, 11 * MS),
            Verdict::Stale,
            "the same frame again"
        );
        assert_eq!(
            c.consume(PNET, pdu, 12 * MS),
            Verdict::Foreign,
            "from the device"
        );
        assert!(!c.expired(10 * MS + 96 * MS - 1));
        assert!(c.expired(10 * MS + 96 * MS));
        assert_eq!(c.data_status(), 0x35);
    }

    #[test]
    fn the_captured_frame_with_data_valid_off_is_invalid_and_reloads_nothing() {
        let mut frame = capture("rt/rtc_cpu_8001");
        let n = frame.len();
        frame[n - 2] &= !rt::data_status::DATA_VALID;
        let (src, pdu) = pdu(&frame);
        let mut c = s7_output_cr();
        c.start(0);
        assert_eq!(
            c.consume(src, pdu, MS),
            Verdict::Invalid { data_status: 0x31 }
        );
        assert!(!c.receiving());
        assert_eq!(
            c.deadline_ns(),
            Some(FIRST_FRAME_GRACE_NS),
            "still the grace after the start"
        );
    }

    #[test]
    fn a_started_consumer_waits_the_grace_or_the_watchdog_whichever_is_longer() {
        let mut c = Consumer::new(0x8001, 40, S7, 10 * MS);
        c.start(7);
        c.start(99);
        assert_eq!(c.deadline_ns(), Some(7 + FIRST_FRAME_GRACE_NS));
        let mut slow = Consumer::new(0x8001, 40, S7, 2 * FIRST_FRAME_GRACE_NS);
        slow.start(0);
        assert_eq!(slow.deadline_ns(), Some(2 * FIRST_FRAME_GRACE_NS));
    }

    /// The trial's expectations are the consumer's verdicts, at every CR timing.
    fn run_trial(timing: CrTiming, first_counter: u16) {
        let setup = TrialSetup {
            peer: S7,
            own: PNET,
            frame_id: 0x8001,
            data_length: 40,
            timing,
            first_at_ns: 5 * MS,
            first_counter,
        };
        let trial = setup.trial();
        let mut c = Consumer::new(0x8001, 40, S7, timing.watchdog_ns());
        for f in &trial.frames {
            let (src, pdu) = pdu(&f.frame);
            let v = c.consume(src, pdu, f.at_ns);
            assert_eq!(v.kind(), f.verdict, "frame at {} ns", f.at_ns);
            assert!(!c.expired(f.at_ns), "expired early at {} ns", f.at_ns);
        }
        assert_eq!(c.counts(), trial.counts);
        assert_eq!(c.deadline_ns(), Some(trial.expires_at_ns));
        assert!(!c.expired(trial.expires_at_ns - 1));
        assert!(c.expired(trial.expires_at_ns));
    }

    #[test]
    fn the_trial_earns_every_verdict_and_its_silence_the_watchdog() {
        for (scf, rr, dhf) in [(32, 1, 3), (32, 32, 3), (8, 4, 10), (1, 1, 1)] {
            for first in [0, 0x7fff, 0xffe0] {
                let timing = CrTiming {
                    send_clock_factor: scf,
                    reduction_ratio: rr,
                    every_cycles: 1,
                    data_hold_factor: dhf,
                };
                run_trial(timing, first);
            }
        }
    }

    proptest! {
        #[test]
        fn any_bytes_are_judged_without_panic(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
            let mut c = Consumer::new(0x8001, 40, S7, 3 * MS);
            let mut with_id = vec![0x80, 0x01];
            with_id.extend_from_slice(&bytes);
            for pdu in [&bytes[..], &with_id[..]] {
                if let Verdict::Accepted { c_sdu, .. } = c.consume(S7, pdu, 0) {
                    prop_assert_eq!(c_sdu.len(), 40);
                }
            }
        }
    }
}
