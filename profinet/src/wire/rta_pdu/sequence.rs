// SPDX-License-Identifier: MIT OR Apache-2.0
//! The sequence numbers of an alarm channel: SendSeqNum and AckSeqNum, window 1.

/// The first SendSeqNum of a fresh alarm channel (and the first expected receive number).
pub const SEQ_INITIAL: u16 = 0xffff;
/// The "last sent" and "last received" values before any DATA-RTA was exchanged.
pub const SEQ_INITIAL_LAST: u16 = 0xfffe;
/// The largest sequence number in the running cycle 0x0000..=0x7FFF.
pub const SEQ_MAX: u16 = 0x7fff;

/// The sequence number after `n`: `(n + 1) & 0x7FFF`, so 0xFFFF → 0x0000 and 0x7FFF → 0x0000.
/// 0xFFFE ([`SEQ_INITIAL_LAST`]) is followed by 0xFFFF ([`SEQ_INITIAL`]), so that "expected
/// = next_seq(last received)" holds from the start.
pub const fn next_seq(n: u16) -> u16 {
    match n {
        SEQ_INITIAL_LAST => SEQ_INITIAL,
        SEQ_INITIAL => 0,
        n => (n + 1) & SEQ_MAX,
    }
}

/// How a received DATA-RTA's SendSeqNum relates to what was expected.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Received {
    /// The expected number: deliver it and answer with an ACK-RTA.
    New,
    /// The last received number again (our ACK was lost): answer with the ACK-RTA again, do
    /// not deliver.
    Duplicate,
    /// Anything else: a sequence error (NACK-RTA, abort with [`AbortCode::SequenceError`](crate::wire::rta_pdu::AbortCode::SequenceError)).
    OutOfOrder,
}

/// The sequence numbers of one alarm channel (one priority) between two endpoints, window 1.
///
/// Sending: put [`send_seq`](Self::send_seq) and [`last_received`](Self::last_received) in the
/// DATA-RTA; when a received DATA or ACK carries it as AckSeqNum
/// ([`confirms`](Self::confirms)), call [`confirm`](Self::confirm). Receiving: call
/// [`receive`](Self::receive) with the SendSeqNum of a DATA-RTA and answer New and Duplicate
/// with an ACK-RTA carrying [`last_sent`](Self::last_sent) and the received number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RtaSequence {
    send_next: u16,
    last_sent: u16,
    expected: u16,
    last_received: u16,
}

impl Default for RtaSequence {
    fn default() -> RtaSequence {
        RtaSequence::new()
    }
}

impl RtaSequence {
    /// A fresh channel: send 0xFFFF next (last 0xFFFE), expect 0xFFFF (last 0xFFFE).
    pub const fn new() -> RtaSequence {
        RtaSequence {
            send_next: SEQ_INITIAL,
            last_sent: SEQ_INITIAL_LAST,
            expected: SEQ_INITIAL,
            last_received: SEQ_INITIAL_LAST,
        }
    }

    /// A channel resumed at known numbers (e.g. to replay a captured session from its middle):
    /// our next send number and last confirmed one, the peer's expected and last accepted one.
    pub const fn from_parts(
        send_next: u16,
        last_sent: u16,
        expected: u16,
        last_received: u16,
    ) -> RtaSequence {
        RtaSequence {
            send_next,
            last_sent,
            expected,
            last_received,
        }
    }

    /// SendSeqNum of our next (or outstanding) DATA-RTA.
    pub const fn send_seq(&self) -> u16 {
        self.send_next
    }

    /// SendSeqNum of our last confirmed DATA-RTA: the SendSeqNum of our ACK/NACK-RTAs.
    pub const fn last_sent(&self) -> u16 {
        self.last_sent
    }

    /// The SendSeqNum the peer's next DATA-RTA must carry.
    pub const fn expected(&self) -> u16 {
        self.expected
    }

    /// SendSeqNum of the peer's last accepted DATA-RTA: the AckSeqNum of everything we send.
    pub const fn last_received(&self) -> u16 {
        self.last_received
    }

    /// Whether a received AckSeqNum confirms our outstanding DATA-RTA.
    pub const fn confirms(&self, ack_seq: u16) -> bool {
        ack_seq == self.send_next
    }

    /// Our outstanding DATA-RTA was confirmed: advance the send number.
    pub fn confirm(&mut self) {
        self.last_sent = self.send_next;
        self.send_next = next_seq(self.send_next);
    }

    /// Classifies a received DATA-RTA's SendSeqNum without changing anything.
    pub const fn classify(&self, send_seq: u16) -> Received {
        if send_seq == self.expected {
            Received::New
        } else if send_seq == self.last_received {
            Received::Duplicate
        } else {
            Received::OutOfOrder
        }
    }

    /// Classifies a received DATA-RTA's SendSeqNum and, when it is new, accepts it.
    pub fn receive(&mut self, send_seq: u16) -> Received {
        let r = self.classify(send_seq);
        if r == Received::New {
            self.last_received = send_seq;
            self.expected = next_seq(send_seq);
        }
        r
    }
}
