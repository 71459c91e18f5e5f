// SPDX-License-Identifier: MIT OR Apache-2.0
//! The raw AF_PACKET socket a NIC backend reads and writes, with a kernel filter that lets
//! only PROFINET frames through, so the cycle thread never wakes for other traffic.

use std::os::fd::RawFd;

/// Classic BPF: accept EtherType 0x8892, directly or behind one 802.1Q tag; drop the rest.
const PROFINET_FILTER: [libc::sock_filter; 7] = [
    // ldh [12]: EtherType (or TPID)
    bpf(0x28, 0, 0, 12),
    // jeq #0x8892 -> accept, else next
    bpf(0x15, 3, 0, 0x8892),
    // jeq #0x8100 -> next (inner type), else reject
    bpf(0x15, 0, 3, 0x8100),
    // ldh [16]: EtherType behind the tag
    bpf(0x28, 0, 0, 16),
    // jeq #0x8892 -> accept, else reject
    bpf(0x15, 0, 1, 0x8892),
    // accept: the whole frame
    bpf(0x06, 0, 0, 0x0004_0000),
    // reject
    bpf(0x06, 0, 0, 0),
];

const fn bpf(code: u16, jt: u8, jf: u8, k: u32) -> libc::sock_filter {
    libc::sock_filter { code, jt, jf, k }
}

/// `PACKET_IGNORE_OUTGOING` (Linux 4.20): do not deliver our own outgoing frames back to us.
const PACKET_IGNORE_OUTGOING: libc::c_int = 23;

/// Opens an AF_PACKET raw socket for all protocols with the PROFINET filter attached. With
/// `ignore_outgoing`, frames sent from this host are not delivered to it (what a protocol
/// endpoint wants); without, it sees both directions (what a capture wants). The caller binds
/// it to an interface and owns the descriptor.
pub fn open_profinet_socket(ignore_outgoing: bool) -> std::io::Result<RawFd> {
    let proto = (libc::ETH_P_ALL as u16).to_be() as libc::c_int;
    // SAFETY: socket(2) with constant arguments; the result is checked.
    let fd = unsafe { libc::socket(libc::AF_PACKET, libc::SOCK_RAW, proto) };
    if fd < 0 {
        return Err(std::io::Error::last_os_error());
    }
    let prog = libc::sock_fprog {
        len: PROFINET_FILTER.len() as u16,
        filter: PROFINET_FILTER.as_ptr() as *mut libc::sock_filter,
    };
    // SAFETY: `prog` points at a valid filter array that outlives the call (the kernel copies
    // it); the option length is the size of the struct passed.
    let rc = unsafe {
        libc::setsockopt(
            fd,
            libc::SOL_SOCKET,
            libc::SO_ATTACH_FILTER,
            (&prog as *const libc::sock_fprog).cast(),
            std::mem::size_of::<libc::sock_fprog>() as libc::socklen_t,
        )
    };
    if rc != 0 {
        let e = std::io::Error::last_os_error();
        // SAFETY: closing the descriptor this function opened.
        unsafe { libc::close(fd) };
        return Err(e);
    }
    if !ignore_outgoing {
        return Ok(fd);
    }
    let one: libc::c_int = 1;
    // SAFETY: an int option; failure (older kernels) only means own frames come back, which
    // the backend also filters by source address.
    unsafe {
        libc::setsockopt(
            fd,
            libc::SOL_PACKET,
            PACKET_IGNORE_OUTGOING,
            (&one as *const libc::c_int).cast(),
            std::mem::size_of::<libc::c_int>() as libc::socklen_t,
        )
    };
    Ok(fd)
}
