// SPDX-License-Identifier: MIT OR Apache-2.0
//! The raw AF_PACKET socket the AF_PACKET backend reads and writes, with a kernel filter that
//! lets only PROFINET frames (and LLDP's, every few seconds) through, so the cycle thread
//! never wakes for other traffic. The crate's system calls, behind a safe interface.
//!
//! The socket is ours rather than a library's channel for the receive: `recv` with
//! `MSG_TRUNC` returns a frame's real length, so a frame longer than the buffer is seen
//! instead of arriving cut.

use std::io;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::time::Duration;

/// Classic BPF: accept EtherType 0x8892, directly or behind one 802.1Q tag, and LLDP
/// (0x88CC, never tagged: the port's neighbours); drop the rest.
const PROFINET_FILTER: [libc::sock_filter; 8] = [
    // ldh [12]: EtherType (or TPID)
    bpf(0x28, 0, 0, 12),
    // jeq #0x8892 -> accept, else next
    bpf(0x15, 4, 0, 0x8892),
    // jeq #0x88cc -> accept, else next
    bpf(0x15, 3, 0, 0x88cc),
    // jeq #0x8100 -> next (inner type), else reject
    bpf(0x15, 0, 3, 0x8100),
    // ldh [16]: EtherType behind the tag
    bpf(0x28, 0, 0, 16),
    // jeq #0x8892 -> accept, else reject
    bpf(0x15, 0, 1, 0x8892),
    // accept: the whole frame, so that MSG_TRUNC reports the length of a long one
    bpf(0x06, 0, 0, 0x0004_0000),
    // reject
    bpf(0x06, 0, 0, 0),
];

const fn bpf(code: u16, jt: u8, jf: u8, k: u32) -> libc::sock_filter {
    libc::sock_filter { code, jt, jf, k }
}

/// An AF_PACKET raw socket bound to one interface, with the PROFINET filter attached.
/// The multicast groups a PROFINET station receives on: DCP Identify, DCP Hello, and LLDP's
/// nearest bridge.
const STATION_MULTICAST: [[u8; 6]; 3] = [
    [0x01, 0x0e, 0xcf, 0x00, 0x00, 0x00],
    [0x01, 0x0e, 0xcf, 0x00, 0x00, 0x01],
    [0x01, 0x80, 0xc2, 0x00, 0x00, 0x0e],
];

/// Closed when dropped.
pub(crate) struct PacketSocket {
    fd: OwnedFd,
}

impl PacketSocket {
    /// Opens a socket on the interface with index `ifindex`. With `ignore_outgoing`, frames
    /// sent from this host are not delivered to it (what a protocol endpoint wants); without,
    /// it sees both directions (what a capture wants). With `promiscuous`, the interface
    /// also hands up the frames between other stations.
    pub(crate) fn open(
        ifindex: u32,
        ignore_outgoing: bool,
        promiscuous: bool,
    ) -> io::Result<PacketSocket> {
        let ifindex = libc::c_int::try_from(ifindex)
            .map_err(|_| io::Error::from(io::ErrorKind::InvalidInput))?;
        // Protocol 0: the socket takes no frame until `bind` names the protocol, so none
        // arrives unfiltered before the filter is attached.
        // SAFETY: socket(2) with constant arguments; the result is checked.
        let fd = unsafe { libc::socket(libc::AF_PACKET, libc::SOCK_RAW | libc::SOCK_CLOEXEC, 0) };
        if fd < 0 {
            return Err(io::Error::last_os_error());
        }
        // SAFETY: `fd` was just opened and nothing else owns it; from here on it is closed on
        // every return.
        let fd = unsafe { OwnedFd::from_raw_fd(fd) };
        let socket = PacketSocket { fd };
        let filter = libc::sock_fprog {
            len: PROFINET_FILTER.len() as u16,
            // The kernel copies the program and never writes through the pointer.
            filter: PROFINET_FILTER.as_ptr().cast_mut(),
        };
        socket.set_option(libc::SOL_SOCKET, libc::SO_ATTACH_FILTER, &filter)?;
        if ignore_outgoing {
            // Failure (kernels before 4.20) only means own frames come back, which the
            // backend also filters by source address.
            let _ = socket.set_option(
                libc::SOL_PACKET,
                libc::PACKET_IGNORE_OUTGOING,
                &(1 as libc::c_int),
            );
        }
        if promiscuous {
            let membership = libc::packet_mreq {
                mr_ifindex: ifindex,
                mr_type: libc::PACKET_MR_PROMISC as libc::c_ushort,
                mr_alen: 0,
                mr_address: [0; 8],
            };
            socket.set_option(libc::SOL_PACKET, libc::PACKET_ADD_MEMBERSHIP, &membership)?;
        } else {
            // A NIC hands up only the multicast groups it was told of: the station joins
            // those its protocols are addressed by, or it would never see an Identify, a
            // Hello or its neighbour's LLDP on real hardware (a veth pair passes them all).
            for group in STATION_MULTICAST {
                let mut mr_address = [0u8; 8];
                mr_address[..6].copy_from_slice(&group);
                let membership = libc::packet_mreq {
                    mr_ifindex: ifindex,
                    mr_type: libc::PACKET_MR_MULTICAST as libc::c_ushort,
                    mr_alen: 6,
                    mr_address,
                };
                socket.set_option(libc::SOL_PACKET, libc::PACKET_ADD_MEMBERSHIP, &membership)?;
            }
        }
        // Bound last, with the filter and the options in place: only from here on does the
        // socket take frames, and only those of this interface. ETH_P_ALL, narrowed by the
        // filter: a socket bound to 0x8892 would miss the tagged frames of a NIC that leaves
        // the 802.1Q tag in the frame (their protocol is 0x8100), and, capturing, the frames
        // this host sends (only ETH_P_ALL sockets see those).
        let address = libc::sockaddr_ll {
            sll_family: libc::AF_PACKET as libc::c_ushort,
            sll_protocol: (libc::ETH_P_ALL as u16).to_be(),
            sll_ifindex: ifindex,
            sll_hatype: 0,
            sll_pkttype: 0,
            sll_halen: 0,
            sll_addr: [0; 8],
        };
        // SAFETY: `address` is a valid sockaddr_ll, and the length passed is its size.
        let rc = unsafe {
            libc::bind(
                socket.fd.as_raw_fd(),
                (&address as *const libc::sockaddr_ll).cast(),
                size_of::<libc::sockaddr_ll>() as libc::socklen_t,
            )
        };
        if rc != 0 {
            return Err(io::Error::last_os_error());
        }
        Ok(socket)
    }

    fn set_option<T>(&self, level: libc::c_int, name: libc::c_int, value: &T) -> io::Result<()> {
        // SAFETY: `value` points at a live `T` of the size passed, which the kernel only
        // reads (and copies) during the call.
        let rc = unsafe {
            libc::setsockopt(
                self.fd.as_raw_fd(),
                level,
                name,
                (value as *const T).cast(),
                size_of::<T>() as libc::socklen_t,
            )
        };
        if rc == 0 {
            Ok(())
        } else {
            Err(io::Error::last_os_error())
        }
    }

    /// Sends `frame` without waiting: a socket that cannot take a frame now (the kernel has
    /// not freed the frames sent before) fails at once rather than holding the cycle thread.
    pub(crate) fn send(&self, frame: &[u8]) -> io::Result<()> {
        // SAFETY: `frame` is valid for reads of its length during the call.
        let n = unsafe {
            libc::send(
                self.fd.as_raw_fd(),
                frame.as_ptr().cast(),
                frame.len(),
                libc::MSG_DONTWAIT,
            )
        };
        match usize::try_from(n) {
            Ok(n) if n == frame.len() => Ok(()),
            // A packet socket sends a frame whole or not at all.
            Ok(_) => Err(io::ErrorKind::WriteZero.into()),
            Err(_) => Err(io::Error::last_os_error()),
        }
    }

    /// Takes the next frame into `buf` without waiting and returns its length on the wire:
    /// larger than `buf` when the frame did not fit (only `buf.len()` bytes of it were
    /// written, and the rest is gone). `None` when no frame is queued.
    pub(crate) fn recv(&self, buf: &mut [u8]) -> io::Result<Option<usize>> {
        // SAFETY: `buf` is valid for writes of its length during the call; MSG_TRUNC changes
        // only the return value, the kernel writes at most `buf.len()` bytes.
        let n = unsafe {
            libc::recv(
                self.fd.as_raw_fd(),
                buf.as_mut_ptr().cast(),
                buf.len(),
                libc::MSG_TRUNC | libc::MSG_DONTWAIT,
            )
        };
        if let Ok(n) = usize::try_from(n) {
            return Ok(Some(n));
        }
        let error = io::Error::last_os_error();
        match error.kind() {
            io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted => Ok(None),
            _ => Err(error),
        }
    }

    /// Waits up to `timeout` for a frame (or an error) to be queued; whether one is.
    /// `ppoll` sleeps on a high-resolution timer: a timeout below a millisecond is kept.
    pub(crate) fn wait(&self, timeout: Duration) -> bool {
        let mut fd = libc::pollfd {
            fd: self.fd.as_raw_fd(),
            events: libc::POLLIN,
            revents: 0,
        };
        let ts = libc::timespec {
            tv_sec: libc::time_t::try_from(timeout.as_secs()).unwrap_or(libc::time_t::MAX),
            tv_nsec: timeout.subsec_nanos() as libc::c_long,
        };
        // SAFETY: `fd` is one valid pollfd, `ts` a valid timespec, and a null signal mask
        // keeps the thread's own.
        let rc = unsafe { libc::ppoll(&mut fd, 1, &ts, std::ptr::null()) };
        rc > 0
    }
}
