// SPDX-License-Identifier: MIT OR Apache-2.0
//! The subagent's side of one AgentX session, sans-IO: bytes in, bytes out.
//!
//! A [`Session`] belongs to one connection to the master: make a new one for every
//! connection (reconnecting is the caller's business, see [`runner`](crate::runner)). It
//! has no socket and no clock; time comes in as `now`.
//!
//! The methods, in the order a caller uses them:
//!
//! 1. [`Session::new`] queues the Open PDU;
//! 2. [`poll_transmit`](Session::poll_transmit): bytes to write to the master, after
//!    every other call;
//! 3. [`handle_input`](Session::handle_input) with the bytes read from the master, and a
//!    closure that makes a [`Snapshot`] when a request needs one (at most once per call);
//! 4. [`poll_event`](Session::poll_event) until `None`: opened, registered or refused,
//!    ready, closed, timed out;
//! 5. [`poll_timeout`](Session::poll_timeout) tells when to call
//!    [`handle_timeout`](Session::handle_timeout) if no input comes first;
//! 6. [`close`](Session::close) to leave, [`ping`](Session::ping) to check on the master,
//!    [`notify`](Session::notify) to send a notification.
//!
//! What happens on the way: the master's answer to Open gives the session its ID, and the
//! configured subtrees are registered (all at once); a refused registration is reported
//! and the others stand. Get, GetNext and GetBulk are answered from the snapshot's
//! [`MibView`](crate::mib::MibView); TestSet is answered notWritable (the MIB is
//! read-only) and CleanupSet not at all; a Close from the master ends the session.

mod answer;
mod config;
mod event;

#[cfg(test)]
mod tests;

use std::collections::VecDeque;
use std::time::Instant;

pub use config::{DEFAULT_PRIORITY, Registration, SYSTEM_PRIORITY, SessionConfig};
pub use event::{Event, InputError, SessionState};

use crate::mib::Snapshot;
use crate::pdu::{
    self, Close, CloseReason, Flags, Open, ParseError, Pdu, PduRepr, PduType, Register,
    ResponseError, VarBind,
};
use answer::{LazyView, answer, response};

/// A request of ours that waits for the master's Response.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Pending {
    packet_id: u32,
    kind: PendingKind,
    deadline: Instant,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PendingKind {
    Open,
    /// The index of the registration in the configuration.
    Register(usize),
    Ping,
    Notify,
    Close(CloseReason),
}

impl PendingKind {
    const fn pdu_type(self) -> PduType {
        match self {
            PendingKind::Open => PduType::Open,
            PendingKind::Register(_) => PduType::Register,
            PendingKind::Ping => PduType::Ping,
            PendingKind::Notify => PduType::Notify,
            PendingKind::Close(_) => PduType::Close,
        }
    }
}

/// One AgentX session of the subagent (see the [module](self) documentation).
#[derive(Debug)]
pub struct Session {
    config: SessionConfig,
    state: SessionState,
    session_id: u32,
    next_packet_id: u32,
    pending: Vec<Pending>,
    /// Bytes read but not yet a whole PDU.
    rx: Vec<u8>,
    /// Bytes to write.
    tx: Vec<u8>,
    events: VecDeque<Event>,
}

impl Session {
    /// A session on a new connection: queues the Open PDU.
    pub fn new(config: SessionConfig, now: Instant) -> Session {
        let mut session = Session {
            config,
            state: SessionState::Opening,
            session_id: 0,
            next_packet_id: 1,
            pending: Vec::new(),
            rx: Vec::new(),
            tx: Vec::new(),
            events: VecDeque::new(),
        };
        let open = Pdu::Open(Open {
            timeout: session.config.timeout,
            id: session.config.id.clone(),
            description: session.config.description.clone().into_bytes(),
        });
        session.request(now, PendingKind::Open, Flags::default(), open);
        session
    }

    /// Where the session is.
    pub const fn state(&self) -> SessionState {
        self.state
    }

    /// The master's number for the session (0 until it is open).
    pub const fn session_id(&self) -> u32 {
        self.session_id
    }

    /// The configuration.
    pub const fn config(&self) -> &SessionConfig {
        &self.config
    }

    /// Takes the bytes to write to the master, if there are any.
    pub fn poll_transmit(&mut self) -> Option<Vec<u8>> {
        (!self.tx.is_empty()).then(|| std::mem::take(&mut self.tx))
    }

    /// Takes the next event.
    pub fn poll_event(&mut self) -> Option<Event> {
        self.events.pop_front()
    }

    /// When [`handle_timeout`](Self::handle_timeout) is due: the earliest deadline of a
    /// request the master has not answered.
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.pending.iter().map(|p| p.deadline).min()
    }

    /// Gives the session up if a request of ours went unanswered past its deadline:
    /// [`Event::MasterTimeout`], a Close (reasonTimeouts) queued, the session closed.
    pub fn handle_timeout(&mut self, now: Instant) {
        let Some(late) = self.pending.iter().find(|p| p.deadline <= now).copied() else {
            return;
        };
        self.events.push_back(Event::MasterTimeout {
            request: late.kind.pdu_type(),
        });
        if !matches!(late.kind, PendingKind::Close(_)) && self.session_id != 0 {
            self.send_close(CloseReason::Timeouts);
        }
        self.finish();
    }

    /// Reads bytes from the master: answers its requests (making at most one snapshot
    /// for this call, and only if a Get, GetNext or GetBulk needs it) and takes its
    /// answers to ours. Bytes of an incomplete PDU are kept for the next call.
    pub fn handle_input<F: FnMut() -> Snapshot>(
        &mut self,
        now: Instant,
        bytes: &[u8],
        mut snapshot: F,
    ) -> Result<(), InputError> {
        if self.state == SessionState::Closed {
            return Err(InputError::Closed);
        }
        self.rx.extend_from_slice(bytes);
        let mut view = LazyView::new(&mut snapshot);
        loop {
            let len = match pdu::frame_len(&self.rx) {
                Ok(Some(len)) if len <= self.rx.len() => len,
                Ok(_) => return Ok(()),
                Err(e) => return Err(self.out_of_step(e)),
            };
            let frame: Vec<u8> = self.rx.drain(..len).collect();
            match PduRepr::parse(&frame) {
                Ok(repr) => self.handle_pdu(now, &repr, &mut view),
                Err(e) => self.unparsable(&frame, e),
            }
            if self.state == SessionState::Closed {
                return Ok(());
            }
        }
    }

    /// Ends the session: queues a Close with `reason` and waits for the master's answer.
    /// A session not yet open is closed at once.
    pub fn close(&mut self, now: Instant, reason: CloseReason) {
        match self.state {
            SessionState::Registering | SessionState::Ready => {
                self.pending.clear();
                self.request(
                    now,
                    PendingKind::Close(reason),
                    Flags::default(),
                    close(reason),
                );
                self.state = SessionState::Closing;
            }
            SessionState::Opening => {
                self.events.push_back(Event::Closed {
                    reason,
                    by_master: false,
                });
                self.finish();
            }
            SessionState::Closing | SessionState::Closed => {}
        }
    }

    /// Asks the master whether it is still there (agentx-Ping-PDU); an unanswered ping
    /// times the session out.
    pub fn ping(&mut self, now: Instant) {
        if matches!(self.state, SessionState::Registering | SessionState::Ready) {
            self.request(now, PendingKind::Ping, Flags::default(), Pdu::Ping);
        }
    }

    /// Sends a notification (agentx-Notify-PDU): snmpd forwards it as a trap to its
    /// trap sinks. RFC 2741 §6.2.10 wants `snmpTrapOID.0` (1.3.6.1.6.3.1.1.4.1.0) first,
    /// after an optional sysUpTime.0. Ignored until the session is open.
    pub fn notify(&mut self, now: Instant, varbinds: Vec<VarBind>) {
        if matches!(self.state, SessionState::Registering | SessionState::Ready) {
            self.request(
                now,
                PendingKind::Notify,
                Flags::default(),
                Pdu::Notify(varbinds),
            );
        }
    }

    fn handle_pdu<F: FnMut() -> Snapshot>(
        &mut self,
        now: Instant,
        repr: &PduRepr,
        view: &mut LazyView<'_, F>,
    ) {
        match &repr.pdu {
            Pdu::Response(r) => self.handle_response(now, repr, r.error),
            Pdu::Close(c) => {
                self.events.push_back(Event::Closed {
                    reason: c.reason,
                    by_master: true,
                });
                self.finish();
            }
            _ if repr.session_id != self.session_id || self.session_id == 0 => {
                self.send(&response(repr, ResponseError::NotOpen, 0, Vec::new()));
            }
            _ => {
                if let Some(answer) = answer(repr, view) {
                    self.send(&answer);
                }
            }
        }
    }

    fn handle_response(&mut self, now: Instant, repr: &PduRepr, error: ResponseError) {
        let Some(at) = self
            .pending
            .iter()
            .position(|p| p.packet_id == repr.packet_id)
        else {
            // An answer to nothing we asked (or asked before a close): nothing to do.
            return;
        };
        let pending = self.pending.remove(at);
        match pending.kind {
            PendingKind::Open if error == ResponseError::NoError => {
                self.session_id = repr.session_id;
                self.events.push_back(Event::Opened {
                    session_id: repr.session_id,
                });
                self.state = SessionState::Registering;
                self.register_all(now);
            }
            PendingKind::Open => {
                self.events.push_back(Event::OpenRefused { error });
                self.finish();
            }
            PendingKind::Register(i) => {
                if let Some(r) = self.config.registrations.get(i) {
                    let (subtree, priority) = (r.subtree.clone(), r.priority);
                    self.events.push_back(if error == ResponseError::NoError {
                        Event::Registered { subtree, priority }
                    } else {
                        Event::RegistrationRefused {
                            subtree,
                            priority,
                            error,
                        }
                    });
                }
                self.ready_when_registered();
            }
            PendingKind::Ping | PendingKind::Notify => {}
            PendingKind::Close(reason) => {
                self.events.push_back(Event::Closed {
                    reason,
                    by_master: false,
                });
                self.finish();
            }
        }
    }

    fn register_all(&mut self, now: Instant) {
        let registrations = self.config.registrations.clone();
        for (i, r) in registrations.into_iter().enumerate() {
            let (range_subid, upper_bound) = match r.range {
                Some((subid, bound)) => (subid, Some(bound)),
                None => (0, None),
            };
            let flags = if r.instance {
                Flags::INSTANCE_REGISTRATION
            } else {
                Flags::default()
            };
            let register = Pdu::Register(Register {
                timeout: r.timeout,
                priority: r.priority,
                range_subid,
                subtree: r.subtree,
                upper_bound,
            });
            self.request(now, PendingKind::Register(i), flags, register);
        }
        self.ready_when_registered();
    }

    fn ready_when_registered(&mut self) {
        let registering = self
            .pending
            .iter()
            .any(|p| matches!(p.kind, PendingKind::Register(_)));
        if self.state == SessionState::Registering && !registering {
            self.state = SessionState::Ready;
            self.events.push_back(Event::Ready);
        }
    }

    /// A PDU whose header framed it but whose payload is malformed: answered with
    /// parseError (RFC 2741 §7.1.2), the session goes on.
    fn unparsable(&mut self, frame: &[u8], _error: ParseError) {
        let Ok(header) = pdu::Header::new_checked(frame).and_then(|h| pdu::HeaderRepr::parse(&h))
        else {
            return;
        };
        if matches!(header.pdu_type, PduType::Response | PduType::CleanupSet) {
            return;
        }
        let request = PduRepr::new(
            header.session_id,
            header.transaction_id,
            header.packet_id,
            Pdu::Ping,
        );
        self.send(&response(
            &request,
            ResponseError::ParseError,
            0,
            Vec::new(),
        ));
    }

    /// The stream cannot be read on: close with reasonParseError.
    fn out_of_step(&mut self, error: ParseError) -> InputError {
        if self.session_id != 0 {
            self.send_close(CloseReason::ParseError);
        }
        self.events.push_back(Event::Closed {
            reason: CloseReason::ParseError,
            by_master: false,
        });
        self.finish();
        InputError::Framing(error)
    }

    /// Queues a request of ours and waits for its answer.
    fn request(&mut self, now: Instant, kind: PendingKind, flags: Flags, pdu: Pdu) {
        let packet_id = self.next_packet_id;
        self.next_packet_id = self.next_packet_id.wrapping_add(1).max(1);
        let repr = PduRepr {
            flags,
            ..PduRepr::new(self.session_id, 0, packet_id, pdu)
        };
        self.send(&repr);
        self.pending.push(Pending {
            packet_id,
            kind,
            deadline: now + self.config.response_timeout,
        });
    }

    /// A Close that nobody waits for an answer to.
    fn send_close(&mut self, reason: CloseReason) {
        let packet_id = self.next_packet_id;
        self.next_packet_id = self.next_packet_id.wrapping_add(1).max(1);
        self.send(&PduRepr::new(self.session_id, 0, packet_id, close(reason)));
    }

    fn send(&mut self, repr: &PduRepr) {
        // Our PDUs are small and well-formed; an answer that could not be written (an OID
        // of over 255 subidentifiers in a snapshot) is sent as a processing error.
        match repr.to_bytes() {
            Ok(bytes) => self.tx.extend_from_slice(&bytes),
            Err(_) if matches!(repr.pdu, Pdu::Response(_)) => {
                if let Ok(bytes) =
                    response(repr, ResponseError::ProcessingError, 0, Vec::new()).to_bytes()
                {
                    self.tx.extend_from_slice(&bytes);
                }
            }
            Err(_) => {}
        }
    }

    fn finish(&mut self) {
        self.pending.clear();
        self.rx.clear();
        self.state = SessionState::Closed;
    }
}

fn close(reason: CloseReason) -> Pdu {
    Pdu::Close(Close { reason })
}
