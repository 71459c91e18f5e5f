// SPDX-License-Identifier: MIT OR Apache-2.0
//! A trial of a consumer: one sequence of frames that earns every [`Verdict`](super::Verdict)
//! and then a silence past the watchdog, with what the rule says of each. Every side that
//! consumes cyclic frames (procimgd's cycle thread, the device engine, the demo's PLC, the
//! test world) is fed it in its tests, which check that the side judges as the one
//! [`Consumer`](super::Consumer) does.

use super::{CrTiming, VerdictCounts, VerdictKind};
use crate::wire::MacAddress;
use crate::wire::ethernet::{self, ETHERTYPE_PROFINET, VlanTag};
use crate::wire::rt::{self, data_status};

/// One frame of a [`Trial`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TrialFrame {
    /// When it arrives, ns.
    pub at_ns: u64,
    /// The whole Ethernet frame.
    pub frame: Vec<u8>,
    /// The verdict the rule gives it.
    pub verdict: VerdictKind,
}

/// The frames of a trial and the rule's conclusions.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Trial {
    /// In the order they arrive, an eighth of a frame period apart.
    pub frames: Vec<TrialFrame>,
    /// The verdicts, counted.
    pub counts: VerdictCounts,
    /// When the watchdog runs out: its time after the last accepted frame.
    pub expires_at_ns: u64,
    /// The C_SDU of the last accepted frame: what the consumer's side holds at the end.
    pub last_c_sdu: Vec<u8>,
}

/// What goes into a trial: the CR consumed, who sends it to whom, and its timing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TrialSetup {
    /// The peer, the consumer's sender.
    pub peer: MacAddress,
    /// The consumer's own address.
    pub own: MacAddress,
    /// FrameID of the CR.
    pub frame_id: u16,
    /// C_SDU bytes.
    pub data_length: usize,
    /// The CR's timing: a frame every period, the watchdog.
    pub timing: CrTiming,
    /// The time of the first frame, ns.
    pub first_at_ns: u64,
    /// The first CycleCounter.
    pub first_counter: u16,
}

impl TrialSetup {
    /// The trial: a valid frame (accepted, data starts), its repeat (stale), a newer frame
    /// with DataValid off (invalid), a newer valid one (accepted), a frame of the CR from
    /// another MAC (foreign), a cut frame (too short), an old counter (stale), then nothing.
    /// Every C_SDU byte is 0x80 | the frame's number (1 to 7).
    pub fn trial(&self) -> Trial {
        // All within one frame period, as a burst after a stall would come: whatever the
        // DataHoldFactor, only the silence after them lets the watchdog run out.
        let spacing = self.timing.period_ns() / 8;
        let step = self.timing.counter_step();
        let c0 = self.first_counter;
        let stranger = MacAddress([0x02, 0xde, 0xad, 0xbe, 0xef, 0x01]);
        let plan: [(MacAddress, u16, u8, Option<usize>, VerdictKind); 7] = [
            (
                self.peer,
                c0,
                data_status::OPERATE,
                None,
                VerdictKind::Accepted,
            ),
            (
                self.peer,
                c0,
                data_status::OPERATE,
                None,
                VerdictKind::Stale,
            ),
            (
                self.peer,
                c0.wrapping_add(step),
                data_status::OPERATE & !data_status::DATA_VALID,
                None,
                VerdictKind::Invalid,
            ),
            (
                self.peer,
                c0.wrapping_add(step.wrapping_mul(2)),
                data_status::OPERATE,
                None,
                VerdictKind::Accepted,
            ),
            (
                stranger,
                c0.wrapping_add(step.wrapping_mul(3)),
                data_status::OPERATE,
                None,
                VerdictKind::Foreign,
            ),
            (
                self.peer,
                c0.wrapping_add(step.wrapping_mul(3)),
                data_status::OPERATE,
                Some(3),
                VerdictKind::TooShort,
            ),
            (
                self.peer,
                c0,
                data_status::OPERATE,
                None,
                VerdictKind::Stale,
            ),
        ];
        let mut counts = VerdictCounts::default();
        let (mut last_accepted, mut last_c_sdu) = (self.first_at_ns, Vec::new());
        let frames = plan
            .iter()
            .enumerate()
            .map(|(i, &(src, counter, status, cut, verdict))| {
                let at_ns = self.first_at_ns + spacing * i as u64;
                // Every byte 0x80 | the frame's number: data that differ per frame, and
                // status bytes (wherever the CR has them) whose DataState reads GOOD.
                let c_sdu = vec![0x80 | (i as u8 + 1); self.data_length];
                if verdict == VerdictKind::Accepted {
                    last_accepted = at_ns;
                    last_c_sdu.clone_from(&c_sdu);
                }
                match verdict {
                    VerdictKind::Accepted => counts.accepted += 1,
                    VerdictKind::Invalid => counts.invalid += 1,
                    VerdictKind::Stale => counts.stale += 1,
                    VerdictKind::Foreign => counts.foreign += 1,
                    VerdictKind::TooShort => counts.too_short += 1,
                }
                let mut frame = self.frame(src, counter, status, &c_sdu);
                if let Some(n) = cut {
                    // FrameID and a few bytes: the frame ends inside the C_SDU.
                    frame.truncate(frame.len() - 4 - self.data_length + n);
                }
                TrialFrame {
                    at_ns,
                    frame,
                    verdict,
                }
            })
            .collect();
        Trial {
            frames,
            counts,
            expires_at_ns: last_accepted + self.timing.watchdog_ns(),
            last_c_sdu,
        }
    }

    fn frame(&self, src: MacAddress, cycle_counter: u16, data_status: u8, c_sdu: &[u8]) -> Vec<u8> {
        let repr = rt::Repr {
            frame_id: self.frame_id,
            data_length: c_sdu.len(),
            cycle_counter,
            data_status,
            transfer_status: 0,
        };
        let mut pdu = vec![0u8; repr.buffer_len()];
        let mut packet = rt::Packet::new_unchecked(&mut pdu[..], c_sdu.len());
        packet.data_mut().copy_from_slice(c_sdu);
        // The buffer is sized for the repr: emitting cannot fail.
        let _ = repr.emit(&mut packet);
        ethernet::Repr {
            dst: self.own,
            src,
            vlan: Some(VlanTag::RT),
            ethertype: ETHERTYPE_PROFINET,
        }
        .frame(&pdu, 0)
    }
}
