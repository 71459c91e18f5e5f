// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimg's network interfaces: whole Ethernet frames (without FCS) behind one small trait,
//! [`Nic`], for the cycle thread of procimgd and for the `procimg` tool.
//!
//! - [`af_packet`]: a real interface through an AF_PACKET socket, filtered in the kernel to
//!   PROFINET frames (EtherType 0x8892, tagged or not);
//! - [`sim_link`]: an in-process link between two ends, for the simulated network and tests;
//! - [`replay`]: a pcap or pcapng capture played as received frames;
//! - [`capture`]: a pcap writer, for what an interface saw;
//! - [`interfaces`]: the interfaces of this machine, for messages that name them.
//!
//! The crate knows nothing of procimgd: no configuration, image or cycle. The only `unsafe`
//! is in the packet socket's system calls.

pub mod af_packet;
pub mod capture;
pub mod interfaces;
// The AF_PACKET socket's system calls: the only module of the crate that may use unsafe.
#[allow(unsafe_code)]
mod packet_socket;
pub mod replay;
pub mod sim_link;

use procimg_profinet::wire::MacAddress;

/// Largest frame handled (a full-size frame with one VLAN tag, without FCS).
pub const MAX_FRAME: usize = 1518;

/// Refuses a frame longer than [`MAX_FRAME`], as the in-memory links must (their slots
/// hold that much).
pub(crate) fn check_frame_len(frame: &[u8]) -> std::io::Result<()> {
    if frame.len() > MAX_FRAME {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("frame of {} bytes exceeds {MAX_FRAME}", frame.len()),
        ));
    }
    Ok(())
}

/// A network interface for PROFINET frames. Implementations must not block longer than the
/// receive timeout they were made with, and must not allocate per frame.
pub trait Nic: Send {
    /// The interface's own MAC address.
    fn mac(&self) -> MacAddress;
    /// Sends one frame.
    fn send(&mut self, frame: &[u8]) -> std::io::Result<()>;
    /// Receives one PROFINET frame into `buf`, if one is there (or arrives within the
    /// implementation's timeout); returns its length. Frames this interface sent itself are
    /// not returned.
    fn recv(&mut self, buf: &mut [u8]) -> std::io::Result<Option<usize>>;
}
