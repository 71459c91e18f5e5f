// SPDX-License-Identifier: MIT OR Apache-2.0
//! What a session reports to its caller, and what can go wrong with its input.

use crate::pdu::{CloseReason, Oid, ParseError, PduType, ResponseError};

/// Where a session is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SessionState {
    /// Open sent, waiting for the master's answer.
    Opening,
    /// Open accepted; Register PDUs sent, not all answered.
    Registering,
    /// Every registration answered (accepted or refused): serving requests.
    Ready,
    /// Close sent, waiting for the master's answer.
    Closing,
    /// Over: closed by either side, refused, timed out or out of step. Make a new
    /// session on a new connection.
    Closed,
}

/// Something the caller should know (and probably log).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Event {
    /// The master opened the session.
    Opened {
        /// The master's number for it.
        session_id: u32,
    },
    /// The master refused to open the session; the session is closed.
    OpenRefused {
        /// Why.
        error: ResponseError,
    },
    /// The master accepted a registration.
    Registered {
        /// The registered subtree.
        subtree: Oid,
        /// At this priority.
        priority: u8,
    },
    /// The master refused a registration: the subtree stays someone else's.
    RegistrationRefused {
        /// The subtree.
        subtree: Oid,
        /// The priority asked for.
        priority: u8,
        /// Why (duplicateRegistration: the same subtree at the same priority is taken).
        error: ResponseError,
    },
    /// Every registration has been answered.
    Ready,
    /// The session ended.
    Closed {
        /// The reason given.
        reason: CloseReason,
        /// Whether the master closed it (else this side did).
        by_master: bool,
    },
    /// The master did not answer in time; the session is closed.
    MasterTimeout {
        /// The request that went unanswered.
        request: PduType,
    },
}

/// Input that cannot be taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum InputError {
    /// The byte stream is out of step: a header that cannot start a PDU. The session has
    /// queued a Close (reasonParseError) and is closed.
    #[error(
        "the master's byte stream is out of step ({0}): send the queued Close, drop the connection and open a new session"
    )]
    Framing(ParseError),
    /// The session is closed; input is not read any more.
    #[error("the AgentX session is closed: open a new session on a new connection")]
    Closed,
}
