// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimg's network interfaces: whole Ethernet frames (without FCS) behind one small trait,
//! [`Nic`], for the cycle thread of procimgd and for the `procimg` tool.
//!
//! - [`af_packet`]: a real interface through an AF_PACKET socket, filtered in the kernel to
//!   PROFINET frames (EtherType 0x8892, tagged or not) and LLDP's (0x88CC);
//! - [`sim_link`]: an in-process link between two ends, for the simulated network and tests;
//! - [`replay`]: a pcap or pcapng capture played as received frames;
//! - [`capture`]: a pcap writer, for what an interface saw;
//! - [`interfaces`]: the interfaces of this machine, for messages that name them.
//!
//! A backend hands a received frame to a closure, in its own buffer, the way smoltcp's
//! `Device` tokens do: the caller parses it in place, nothing is copied into a caller's buffer,
//! and a frame that does not fit the backend's buffer is reported ([`RecvError::TooLong`]),
//! never passed on cut.
//!
//! ```no_run
//! use procimg_nic::Nic;
//! use procimg_nic::af_packet::AfPacket;
//! use std::time::Duration;
//!
//! let mut nic = AfPacket::open("eth0", Duration::from_millis(10))?;
//! let mut bytes = 0;
//! // Whatever arrived: `frame` is parsed in place, valid only during the call.
//! while nic.receive(&mut |frame| bytes += frame.len())? {}
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The crate knows nothing of procimgd: no configuration, image or cycle. Its only `unsafe`
//! is in the packet socket's system calls (`packet_socket.rs`).

pub mod af_packet;
pub mod capture;
pub mod interfaces;
// The AF_PACKET socket's system calls: the only module of the crate that may use unsafe.
#[allow(unsafe_code)]
mod packet_socket;
pub mod replay;
pub mod sim_link;

use procimg_profinet::wire::MacAddress;
use std::sync::Arc;

/// Largest frame handled (a full-size frame with one VLAN tag, without FCS).
pub const MAX_FRAME: usize = 1518;

/// A network interface for PROFINET frames.
///
/// Implementations must not block longer than the receive timeout they were made with, and
/// must not allocate per frame: the cycle thread sends and receives through them. Every
/// backend refuses to send a frame longer than [`MAX_FRAME`] and hands none longer to the
/// receive closure.
pub trait Nic: Send {
    /// The interface's own MAC address.
    fn mac(&self) -> MacAddress;

    /// Sends one frame.
    fn send(&mut self, frame: &[u8]) -> Result<(), SendError>;

    /// Hands the next received PROFINET frame to `f`, if one is there (or arrives within the
    /// implementation's timeout), and returns whether there was one. The slice is the
    /// backend's own buffer, valid during the call only. Frames this interface sent itself
    /// are not handed over.
    ///
    /// A frame longer than [`MAX_FRAME`] is dropped whole and reported as
    /// [`RecvError::TooLong`]; the next call takes the next frame.
    fn receive(&mut self, f: &mut dyn FnMut(&[u8])) -> Result<bool, RecvError>;
}

/// A boxed interface is one: callers that choose the backend at run time hold a
/// `Box<dyn Nic>`.
impl<N: Nic + ?Sized> Nic for Box<N> {
    fn mac(&self) -> MacAddress {
        (**self).mac()
    }

    fn send(&mut self, frame: &[u8]) -> Result<(), SendError> {
        (**self).send(frame)
    }

    fn receive(&mut self, f: &mut dyn FnMut(&[u8])) -> Result<bool, RecvError> {
        (**self).receive(f)
    }
}

/// Why a frame was not received.
///
/// Creating one allocates nothing (the interface name is shared), so the cycle thread may
/// get one, count it and go on.
#[derive(Debug, thiserror::Error)]
pub enum RecvError {
    /// A frame longer than the receive buffer arrived; it was dropped, and the next receive
    /// takes the next frame.
    #[error(
        "network interface \"{interface}\" received a frame of {len} bytes, more than the \
         {max} of a full-size Ethernet frame with one VLAN tag, and dropped it: a station on \
         this network sends jumbo frames; set its MTU to 1500"
    )]
    TooLong {
        /// The interface.
        interface: Arc<str>,
        /// The frame's length on the wire.
        len: usize,
        /// The longest frame taken ([`MAX_FRAME`]).
        max: usize,
    },
    /// The system refused the read.
    // Not a `source`: the message already holds it, and error chains would repeat it.
    #[error(
        "cannot receive on network interface \"{interface}\": {error}; check that it still \
         exists and is up (ip link show {interface})"
    )]
    Io {
        /// The interface.
        interface: Arc<str>,
        /// What the system said.
        error: std::io::Error,
    },
}

/// Why a frame was not sent.
///
/// Creating one allocates nothing (the interface name is shared), so the cycle thread may
/// get one, count it and go on.
#[derive(Debug, thiserror::Error)]
pub enum SendError {
    /// The frame is longer than any interface here carries.
    #[error(
        "cannot send a frame of {len} bytes on network interface \"{interface}\": at most \
         {max} fit (a full-size Ethernet frame with one VLAN tag, without FCS); send shorter \
         frames"
    )]
    TooLong {
        /// The interface.
        interface: Arc<str>,
        /// The frame's length.
        len: usize,
        /// The longest frame sent ([`MAX_FRAME`]).
        max: usize,
    },
    /// The system refused the frame.
    // Not a `source`: the message already holds it, and error chains would repeat it.
    #[error(
        "cannot send on network interface \"{interface}\": {error}; check that it is up (ip \
         link show {interface}) and not sending more than its link carries"
    )]
    Io {
        /// The interface.
        interface: Arc<str>,
        /// What the system said.
        error: std::io::Error,
    },
}

/// Refuses a frame longer than [`MAX_FRAME`], which no backend sends (the in-memory links'
/// slots hold that much, and no PROFINET frame is longer).
pub(crate) fn check_frame_len(interface: &Arc<str>, frame: &[u8]) -> Result<(), SendError> {
    if frame.len() > MAX_FRAME {
        return Err(SendError::TooLong {
            interface: interface.clone(),
            len: frame.len(),
            max: MAX_FRAME,
        });
    }
    Ok(())
}
