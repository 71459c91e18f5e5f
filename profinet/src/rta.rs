// SPDX-License-Identifier: MIT OR Apache-2.0
//! One RTA alarm channel (one priority of an AR's alarm CR), sans-IO: the window-1 protocol
//! with transport acknowledgement, retransmission and abort.
//!
//! Feed it the RTA PDUs received for this channel ([`RtaChannel::receive`]), the alarm
//! blocks to send ([`RtaChannel::send`]) and the time ([`RtaChannel::poll`]); it answers
//! with [`RtaEvent`]s: PDUs to put on the wire, alarm blocks to deliver, confirmations and
//! aborts. No socket and no clock inside.

use super::wire::alarm::{AlarmBlock, Priority};
use super::wire::rta_pdu::{AbortCode, ErrRta, Received, RtaBody, RtaPdu, RtaSequence};
use std::collections::VecDeque;

/// What the channel asks its owner to do or tells it.
#[derive(Clone, Debug, PartialEq)]
pub enum RtaEvent {
    /// Put this PDU on the wire (from the FrameID on).
    Send(RtaPdu),
    /// The peer sent these alarm blocks (new, in order, each once).
    Deliver(Vec<AlarmBlock>),
    /// Our outstanding DATA-RTA was acknowledged.
    Confirmed,
    /// The channel is dead: the AR must be aborted.
    Abort {
        /// Why.
        code: AbortCode,
        /// We aborted (true) or the peer sent an ERR-RTA (false).
        local: bool,
    },
}

struct Outstanding {
    pdu: RtaPdu,
    sent_ns: u64,
    transmissions: u16,
}

/// One alarm channel.
pub struct RtaChannel {
    priority: Priority,
    local_endpoint: u16,
    remote_endpoint: u16,
    seq: RtaSequence,
    timeout_ns: u64,
    retries: u16,
    outstanding: Option<Outstanding>,
    queue: VecDeque<Vec<AlarmBlock>>,
    aborted: bool,
}

impl RtaChannel {
    /// A fresh channel between our alarm endpoint and the peer's, with the AlarmCR's
    /// RTATimeoutFactor (× 100 ms) and RTARetries.
    pub fn new(
        priority: Priority,
        local_endpoint: u16,
        remote_endpoint: u16,
        timeout_factor: u16,
        retries: u16,
    ) -> RtaChannel {
        RtaChannel::resume(
            priority,
            local_endpoint,
            remote_endpoint,
            timeout_factor,
            retries,
            RtaSequence::new(),
        )
    }

    /// A channel that continues at known sequence numbers.
    pub fn resume(
        priority: Priority,
        local_endpoint: u16,
        remote_endpoint: u16,
        timeout_factor: u16,
        retries: u16,
        seq: RtaSequence,
    ) -> RtaChannel {
        RtaChannel {
            priority,
            local_endpoint,
            remote_endpoint,
            seq,
            timeout_ns: timeout_factor.max(1) as u64 * 100_000_000,
            retries,
            outstanding: None,
            queue: VecDeque::new(),
            aborted: false,
        }
    }

    /// Whether the channel was aborted (it then ignores everything).
    pub fn is_aborted(&self) -> bool {
        self.aborted
    }

    /// Whether a DATA-RTA of ours waits for its acknowledgement.
    pub fn is_busy(&self) -> bool {
        self.outstanding.is_some()
    }

    /// Sends alarm blocks (a notification or an AlarmAck): at once, or after the outstanding
    /// DATA-RTA is acknowledged (window size 1).
    pub fn send(&mut self, blocks: Vec<AlarmBlock>, now_ns: u64, out: &mut Vec<RtaEvent>) {
        if self.aborted {
            return;
        }
        if self.outstanding.is_some() {
            self.queue.push_back(blocks);
        } else {
            self.transmit(blocks, now_ns, out);
        }
    }

    fn transmit(&mut self, blocks: Vec<AlarmBlock>, now_ns: u64, out: &mut Vec<RtaEvent>) {
        let pdu = RtaPdu::data(
            self.priority,
            self.remote_endpoint,
            self.local_endpoint,
            self.seq.send_seq(),
            self.seq.last_received(),
            blocks,
        );
        out.push(RtaEvent::Send(pdu.clone()));
        self.outstanding = Some(Outstanding {
            pdu,
            sent_ns: now_ns,
            transmissions: 1,
        });
    }

    fn ack(&self, acked: u16) -> RtaPdu {
        RtaPdu::ack(
            self.priority,
            self.remote_endpoint,
            self.local_endpoint,
            self.seq.last_sent(),
            acked,
        )
    }

    /// Aborts the channel: sends an ERR-RTA with `code` and reports the abort.
    pub fn abort(&mut self, code: AbortCode, out: &mut Vec<RtaEvent>) {
        if self.aborted {
            return;
        }
        self.aborted = true;
        out.push(RtaEvent::Send(RtaPdu::err(
            self.priority,
            self.remote_endpoint,
            self.local_endpoint,
            self.seq.last_sent(),
            self.seq.last_received(),
            ErrRta::abort(code),
        )));
        out.push(RtaEvent::Abort { code, local: true });
    }

    /// Takes a PDU received on this channel.
    pub fn receive(&mut self, pdu: &RtaPdu, now_ns: u64, out: &mut Vec<RtaEvent>) {
        if self.aborted {
            return;
        }
        let h = pdu.header;
        match &pdu.body {
            RtaBody::Data(blocks) => match self.seq.receive(h.send_seq) {
                Received::New => {
                    out.push(RtaEvent::Send(self.ack(h.send_seq)));
                    out.push(RtaEvent::Deliver(blocks.clone()));
                }
                Received::Duplicate => out.push(RtaEvent::Send(self.ack(h.send_seq))),
                Received::OutOfOrder => {
                    out.push(RtaEvent::Send(RtaPdu::nack(
                        self.priority,
                        self.remote_endpoint,
                        self.local_endpoint,
                        self.seq.last_sent(),
                        self.seq.last_received(),
                    )));
                    self.abort(AbortCode::SequenceError, out);
                    return;
                }
            },
            RtaBody::Err(e) => {
                self.aborted = true;
                out.push(RtaEvent::Abort {
                    code: e.abort_code().unwrap_or(AbortCode::Unspecified),
                    local: false,
                });
                return;
            }
            // A NACK asks for nothing the retransmission timer does not already do.
            RtaBody::Ack | RtaBody::Nack => {}
        }
        // DATA and ACK both carry the peer's acknowledgement of our DATA.
        if self.outstanding.is_some() && self.seq.confirms(h.ack_seq) {
            self.seq.confirm();
            self.outstanding = None;
            out.push(RtaEvent::Confirmed);
            if let Some(next) = self.queue.pop_front() {
                self.transmit(next, now_ns, out);
            }
        }
    }

    /// Retransmits an unacknowledged DATA-RTA whose timeout passed; after the last retry,
    /// aborts.
    pub fn poll(&mut self, now_ns: u64, out: &mut Vec<RtaEvent>) {
        if self.aborted {
            return;
        }
        let Some(o) = self.outstanding.as_mut() else {
            return;
        };
        if now_ns.saturating_sub(o.sent_ns) < self.timeout_ns {
            return;
        }
        if o.transmissions > self.retries {
            self.outstanding = None;
            self.abort(AbortCode::AlarmSendNegative, out);
            return;
        }
        o.transmissions += 1;
        o.sent_ns = now_ns;
        out.push(RtaEvent::Send(o.pdu.clone()));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::alarm::AlarmAck;
    use crate::wire::rta_pdu::Packet;
    use crate::wire::{PnioStatus, ethernet};

    /// A captured frame's RTA PDU bytes (from the FrameID) and its parse. The frames are the
    /// test data of the pnio crate 0.1.0 (MIT OR Apache-2.0), copied in tests/fixtures.
    fn rta(name: &str) -> (Vec<u8>, RtaPdu) {
        let frame = crate::test_fixtures::capture(&format!("alarm/{name}"));
        let at = ethernet::Frame::new_checked(&frame[..])
            .unwrap()
            .header_len();
        let pdu = RtaPdu::parse(&Packet::new_checked(&frame[at..]).unwrap()).unwrap();
        let len = pdu.to_vec().unwrap().len();
        (frame[at..at + len].to_vec(), pdu)
    }

    fn sent(out: &[RtaEvent]) -> Vec<Vec<u8>> {
        out.iter()
            .filter_map(|e| match e {
                RtaEvent::Send(p) => Some(p.to_vec().unwrap()),
                _ => None,
            })
            .collect()
    }

    /// The captured low-priority exchange, played from the controller's side: p-net's
    /// diagnosis alarm, the PLC's ACK-RTA, the PLC's AlarmAck, p-net's ACK-RTA. What the
    /// channel sends equals what the S7-1515 sent, byte for byte.
    #[test]
    fn replays_the_s7_side_of_a_captured_diagnosis_alarm() {
        let (_, notif) = rta("alarm_diag_notif");
        let (ack_bytes, ack) = rta("alarm_ack_rta_low_cpu");
        let (data_bytes, data) = rta("alarm_diag_ack_cpu");
        let (_, dev_ack) = rta("alarm_ack_rta_low_dev");
        // Resume where the capture is: the PLC's next DATA and last confirmed numbers from its
        // frames, the device's numbers from the notification.
        let seq = RtaSequence::from_parts(
            data.header.send_seq,
            ack.header.send_seq,
            notif.header.send_seq,
            // The device's DATA before this one.
            match notif.header.send_seq {
                0 => 0x7fff,
                n => n - 1,
            },
        );
        let mut ch = RtaChannel::resume(
            Priority::Low,
            notif.header.dst_endpoint,
            notif.header.src_endpoint,
            1,
            3,
            seq,
        );
        let mut out = Vec::new();
        ch.receive(&notif, 0, &mut out);
        assert_eq!(
            sent(&out),
            vec![ack_bytes],
            "the transport ACK differs from the PLC's"
        );
        let delivered = out.iter().find_map(|e| match e {
            RtaEvent::Deliver(b) => Some(b.clone()),
            _ => None,
        });
        let Some(AlarmBlock::Notification(n)) = delivered.and_then(|b| b.into_iter().next()) else {
            panic!("no notification delivered: {out:?}");
        };
        out.clear();
        ch.send(
            vec![AlarmBlock::Ack(AlarmAck::for_notification(
                &n,
                PnioStatus::OK,
            ))],
            1,
            &mut out,
        );
        assert_eq!(
            sent(&out),
            vec![data_bytes],
            "the AlarmAck DATA differs from the PLC's"
        );
        out.clear();
        ch.receive(&dev_ack, 2, &mut out);
        assert_eq!(out, vec![RtaEvent::Confirmed]);
        assert!(!ch.is_busy());
    }

    fn blocks() -> Vec<AlarmBlock> {
        let (_, notif) = rta("alarm_process_notif");
        match notif.body {
            RtaBody::Data(b) => b,
            _ => unreachable!(),
        }
    }

    #[test]
    fn retransmits_then_aborts() {
        let mut ch = RtaChannel::new(Priority::High, 1, 0, 1, 2);
        let mut out = Vec::new();
        ch.send(blocks(), 0, &mut out);
        let first = sent(&out);
        out.clear();
        ch.poll(99_000_000, &mut out);
        assert!(out.is_empty(), "retransmitted before the timeout");
        for t in [100_000_000, 200_000_000] {
            ch.poll(t, &mut out);
            assert_eq!(sent(&out), first, "a retransmission is the same PDU");
            out.clear();
        }
        ch.poll(300_000_000, &mut out);
        assert!(
            matches!(out.last(), Some(RtaEvent::Abort { local: true, .. })),
            "{out:?}"
        );
        assert!(ch.is_aborted());
    }

    #[test]
    fn duplicates_are_acked_again_but_delivered_once_and_gaps_abort() {
        let mut dev = RtaChannel::new(Priority::High, 0, 1, 1, 3);
        let mut ctl = RtaChannel::new(Priority::High, 1, 0, 1, 3);
        let mut out = Vec::new();
        dev.send(blocks(), 0, &mut out);
        let RtaEvent::Send(data) = out[0].clone() else {
            panic!()
        };
        let mut got = Vec::new();
        ctl.receive(&data, 0, &mut got);
        ctl.receive(&data, 1, &mut got);
        let delivers = got
            .iter()
            .filter(|e| matches!(e, RtaEvent::Deliver(_)))
            .count();
        assert_eq!((delivers, sent(&got).len()), (1, 2));
        // The ACK confirms the device's DATA; a second send goes out at once.
        let RtaEvent::Send(ack) = got[0].clone() else {
            panic!()
        };
        out.clear();
        dev.receive(&ack, 2, &mut out);
        assert_eq!(out, vec![RtaEvent::Confirmed]);
        // A DATA that skips a number: NACK and abort with a sequence error.
        let mut skipped = data.clone();
        skipped.header.send_seq = 5;
        got.clear();
        ctl.receive(&skipped, 3, &mut got);
        assert!(
            got.contains(&RtaEvent::Abort {
                code: AbortCode::SequenceError,
                local: true
            }),
            "{got:?}"
        );
    }

    #[test]
    fn window_one_queues_and_err_rta_aborts() {
        let mut ch = RtaChannel::new(Priority::Low, 1, 0, 1, 3);
        let mut out = Vec::new();
        ch.send(blocks(), 0, &mut out);
        ch.send(blocks(), 0, &mut out);
        assert_eq!(sent(&out).len(), 1, "the second waits for the first's ACK");
        let (_, err) = rta("alarm_err_rta_dev");
        let mut peer = err.clone();
        peer.header.dst_endpoint = 1;
        out.clear();
        ch.receive(&peer, 1, &mut out);
        assert!(
            matches!(out[0], RtaEvent::Abort { local: false, .. }),
            "{out:?}"
        );
    }
}
