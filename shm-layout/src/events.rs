// SPDX-License-Identifier: MIT OR Apache-2.0
//! Event ids on the server's cycle-event service and the clients' OPDONE service.
//!
//! Every client listens to the one cycle-event service; an OPFAULT carries the slot of the
//! client it is meant for, so a client ignores the OPFAULTs of others.

/// The inputs of a new cycle are published: process them (IO-Base STARTOP).
pub const EVENT_STARTOP: usize = 1;
/// The outputs of the cycle went out and a new bus cycle begins (IO-Base NEWCYCLE).
pub const EVENT_NEWCYCLE: usize = 2;
/// The server's mode changed (IO-Base MODE_IND); the new mode is in the next image header.
pub const EVENT_MODE: usize = 3;
/// The server is shutting down; clients should expect a restart.
pub const EVENT_SHUTDOWN: usize = 4;
/// OPFAULT for the client in slot `s` is `EVENT_OPFAULT_BASE + s`.
pub const EVENT_OPFAULT_BASE: usize = 16;
/// Largest event id in use.
pub const EVENT_ID_MAX: usize = EVENT_OPFAULT_BASE + crate::MAX_CLIENTS - 1;

/// The OPFAULT event id for client slot `slot`.
pub const fn opfault_event(slot: u32) -> usize {
    EVENT_OPFAULT_BASE + slot as usize
}
