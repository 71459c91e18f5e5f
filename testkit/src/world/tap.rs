// SPDX-License-Identifier: MIT OR Apache-2.0
//! What crossed the world's network: every frame and datagram as its sender put it there,
//! with the time, kept where a filter wants it ([`World::tap`](super::World::tap)), and
//! written as a pcap file for Wireshark or a replay.

use std::net::SocketAddrV4;

/// Who put a message on the network.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Origin {
    /// The controller's port (acyclic frames, cyclic output frames, datagrams).
    Controller,
    /// Device `d`.
    Device(usize),
    /// The test, through [`World::inject_frame`](super::World::inject_frame).
    Injected,
}

/// A frame or a datagram.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Message {
    /// An Ethernet frame.
    Frame(Vec<u8>),
    /// A UDP datagram.
    Datagram {
        /// Source address and port.
        from: SocketAddrV4,
        /// Destination address and port.
        to: SocketAddrV4,
        /// The UDP payload.
        payload: Vec<u8>,
    },
}

/// One message on the world's network.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Record {
    /// The world's time (ns) when it was sent.
    pub at_ns: u64,
    /// Who sent it.
    pub origin: Origin,
    /// What was sent.
    pub message: Message,
}

impl Record {
    /// The message as an Ethernet frame: a frame as it is, a datagram inside IPv4 and UDP.
    pub fn to_frame(&self) -> Vec<u8> {
        match &self.message {
            Message::Frame(f) => f.clone(),
            Message::Datagram { from, to, payload } => crate::udp::udp_frame(
                from.ip().octets(),
                to.ip().octets(),
                from.port(),
                to.port(),
                payload,
            ),
        }
    }
}

/// Decides which records a tap keeps; sees every message, so it may also check them.
pub type Filter = Box<dyn FnMut(&Record) -> bool>;

/// A pcap file (nanosecond timestamps) of `records` as frames ([`Record::to_frame`]), each at
/// its time after `epoch_ns`.
pub fn pcap(records: &[Record], epoch_ns: u64) -> Vec<u8> {
    let frames: Vec<(u64, Vec<u8>)> = records
        .iter()
        .map(|r| (epoch_ns.saturating_add(r.at_ns), r.to_frame()))
        .collect();
    crate::files::pcap(&frames)
}
