// SPDX-License-Identifier: MIT OR Apache-2.0
//! rtnetlink (`NETLINK_ROUTE`) requests for one interface's IPv4 addresses and its default
//! route: what `ip addr` and `ip route` do, without running them. Only the socket calls are
//! unsafe; messages are built and read as bytes (layouts from `linux/netlink.h`,
//! `linux/if_addr.h`, `linux/rtnetlink.h`), native-endian headers and network-order addresses.

use std::io;
use std::net::Ipv4Addr;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};

/// The mark procimgd puts on the addresses (`IFA_PROTO`) and routes (`rtm_protocol`) it
/// adds, so that a later run tells its own leftovers (after a crash) from the
/// administrator's. Unassigned in iproute2's `rt_protos`; `ip route` shows it as `proto 80`.
pub const PROCIMG_PROTOCOL: u8 = 80;

// linux/netlink.h
const NLMSG_HDRLEN: usize = 16;
const NLMSG_ERROR: u16 = 2;
const NLMSG_DONE: u16 = 3;
const NLM_F_REQUEST: u16 = 0x1;
const NLM_F_ACK: u16 = 0x4;
const NLM_F_DUMP: u16 = 0x300;
const NLM_F_EXCL: u16 = 0x200;
const NLM_F_CREATE: u16 = 0x400;
// linux/rtnetlink.h
const RTM_NEWADDR: u16 = 20;
const RTM_DELADDR: u16 = 21;
const RTM_GETADDR: u16 = 22;
const RTM_NEWROUTE: u16 = 24;
const RTM_DELROUTE: u16 = 25;
const RTM_NEWNEIGH: u16 = 28;
const NLM_F_REPLACE: u16 = 0x100;
// linux/neighbour.h
const NDA_DST: u16 = 1;
const NDA_LLADDR: u16 = 2;
/// NUD_STALE: an address known but not confirmed. The kernel sends to it at once and
/// confirms it itself (unicast probes) once it is used.
const NUD_STALE: u16 = 0x04;
/// `struct ndmsg`: family (u8), 3 pad bytes, interface index (i32), state (u16), flags (u8),
/// type (u8).
const NDMSG_LEN: usize = 12;
const RTA_OIF: u16 = 4;
const RTA_GATEWAY: u16 = 5;
const RTA_PRIORITY: u16 = 6;
const RT_TABLE_MAIN: u8 = 254;
const RT_SCOPE_UNIVERSE: u8 = 0;
const RT_SCOPE_NOWHERE: u8 = 255;
const RTN_UNICAST: u8 = 1;
// linux/if_addr.h
const IFA_ADDRESS: u16 = 1;
const IFA_LOCAL: u16 = 2;
const IFA_BROADCAST: u16 = 4;
const IFA_PROTO: u16 = 11;
/// `struct ifaddrmsg`: family, prefix length, flags, scope (u8 each), interface index (u32).
const IFADDRMSG_LEN: usize = 8;
/// `struct rtmsg`: family, dst_len, src_len, tos, table, protocol, scope, type (u8 each),
/// flags (u32).
const RTMSG_LEN: usize = 12;

/// An IPv4 address an interface carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IfAddress {
    /// The address.
    pub ip: Ipv4Addr,
    /// Its prefix length.
    pub prefix: u8,
    /// Marked with [`PROCIMG_PROTOCOL`]: procimgd added it.
    pub ours: bool,
}

/// A `NETLINK_ROUTE` socket of the calling thread's network namespace.
pub struct Netlink {
    fd: OwnedFd,
    seq: u32,
}

/// The index of interface `name` (`if_nametoindex(3)`).
pub fn interface_index(name: &str) -> io::Result<u32> {
    let c = std::ffi::CString::new(name).map_err(|_| io::ErrorKind::InvalidInput)?;
    // SAFETY: `c` is a NUL-terminated string that outlives the call.
    let index = unsafe { libc::if_nametoindex(c.as_ptr()) };
    if index == 0 {
        Err(io::Error::last_os_error())
    } else {
        Ok(index)
    }
}

impl Netlink {
    /// Opens the socket.
    pub fn open() -> io::Result<Netlink> {
        // SAFETY: plain socket(2) call with constant arguments.
        let fd = unsafe {
            libc::socket(
                libc::AF_NETLINK,
                libc::SOCK_RAW | libc::SOCK_CLOEXEC,
                libc::NETLINK_ROUTE,
            )
        };
        if fd < 0 {
            return Err(io::Error::last_os_error());
        }
        // SAFETY: `fd` was just returned by socket(2) and is owned by nobody else.
        let fd = unsafe { OwnedFd::from_raw_fd(fd) };
        Ok(Netlink { fd, seq: 0 })
    }

    /// The IPv4 addresses of interface `index`.
    pub fn addresses(&mut self, index: u32) -> io::Result<Vec<IfAddress>> {
        let mut m = Message::new(RTM_GETADDR, NLM_F_REQUEST | NLM_F_DUMP, self.next_seq());
        m.bytes(&ifaddrmsg(0, 0, 0));
        let mut found = Vec::new();
        self.exchange(&m.finish(), |kind, payload| {
            if kind == RTM_NEWADDR
                && let Some(a) = parse_address(payload, index)
            {
                found.push(a);
            }
        })?;
        Ok(found)
    }

    /// Gives interface `index` the address `ip/prefix` (with its broadcast address), marked
    /// as procimgd's. Already there is no error.
    pub fn add_address(&mut self, index: u32, ip: Ipv4Addr, prefix: u8) -> io::Result<()> {
        let flags = NLM_F_REQUEST | NLM_F_ACK | NLM_F_CREATE | NLM_F_EXCL;
        let mut m = Message::new(RTM_NEWADDR, flags, self.next_seq());
        m.bytes(&ifaddrmsg(prefix, RT_SCOPE_UNIVERSE, index));
        m.attr(IFA_LOCAL, &ip.octets());
        m.attr(IFA_ADDRESS, &ip.octets());
        if prefix < 31 {
            let host = u32::MAX.checked_shr(u32::from(prefix)).unwrap_or(0);
            m.attr(IFA_BROADCAST, &(u32::from(ip) | host).to_be_bytes());
        }
        m.attr(IFA_PROTO, &[PROCIMG_PROTOCOL]);
        match self.exchange(&m.finish(), |_, _| {}) {
            Err(e) if e.raw_os_error() == Some(libc::EEXIST) => Ok(()),
            other => other,
        }
    }

    /// Takes `ip/prefix` from interface `index`. Already gone is no error.
    pub fn remove_address(&mut self, index: u32, ip: Ipv4Addr, prefix: u8) -> io::Result<()> {
        let mut m = Message::new(RTM_DELADDR, NLM_F_REQUEST | NLM_F_ACK, self.next_seq());
        m.bytes(&ifaddrmsg(prefix, RT_SCOPE_UNIVERSE, index));
        m.attr(IFA_LOCAL, &ip.octets());
        m.attr(IFA_ADDRESS, &ip.octets());
        match self.exchange(&m.finish(), |_, _| {}) {
            Err(e) if e.raw_os_error() == Some(libc::EADDRNOTAVAIL) => Ok(()),
            other => other,
        }
    }

    /// Tells interface `index`'s neighbour table that `ip` is at `mac` (what `ip neigh
    /// replace IP lladdr MAC nud stale` does), replacing what it held for `ip`. Needs
    /// CAP_NET_ADMIN.
    pub fn set_neighbour(&mut self, index: u32, ip: Ipv4Addr, mac: [u8; 6]) -> io::Result<()> {
        let flags = NLM_F_REQUEST | NLM_F_ACK | NLM_F_CREATE | NLM_F_REPLACE;
        let mut m = Message::new(RTM_NEWNEIGH, flags, self.next_seq());
        m.bytes(&ndmsg(index, NUD_STALE));
        m.attr(NDA_DST, &ip.octets());
        m.attr(NDA_LLADDR, &mac);
        self.exchange(&m.finish(), |_, _| {})
    }

    /// Adds a default route through `gateway` on interface `index` with `metric`, marked as
    /// procimgd's, to the main table.
    pub fn add_default_route(
        &mut self,
        index: u32,
        gateway: Ipv4Addr,
        metric: u32,
    ) -> io::Result<()> {
        let flags = NLM_F_REQUEST | NLM_F_ACK | NLM_F_CREATE | NLM_F_EXCL;
        let mut m = Message::new(RTM_NEWROUTE, flags, self.next_seq());
        m.bytes(&rtmsg(RT_SCOPE_UNIVERSE, RTN_UNICAST));
        m.attr(RTA_GATEWAY, &gateway.octets());
        m.attr(RTA_OIF, &index.to_ne_bytes());
        m.attr(RTA_PRIORITY, &metric.to_ne_bytes());
        self.exchange(&m.finish(), |_, _| {})
    }

    /// Removes procimgd's default route on interface `index` with `metric`, whatever its
    /// gateway; `false` if there was none.
    pub fn remove_default_route(&mut self, index: u32, metric: u32) -> io::Result<bool> {
        let mut m = Message::new(RTM_DELROUTE, NLM_F_REQUEST | NLM_F_ACK, self.next_seq());
        // Scope "nowhere" and no type: the kernel matches any; the protocol, interface and
        // metric pick ours.
        m.bytes(&rtmsg(RT_SCOPE_NOWHERE, 0));
        m.attr(RTA_OIF, &index.to_ne_bytes());
        m.attr(RTA_PRIORITY, &metric.to_ne_bytes());
        match self.exchange(&m.finish(), |_, _| {}) {
            Ok(()) => Ok(true),
            Err(e) if e.raw_os_error() == Some(libc::ESRCH) => Ok(false),
            Err(e) => Err(e),
        }
    }

    fn next_seq(&mut self) -> u32 {
        self.seq = self.seq.wrapping_add(1);
        self.seq
    }

    /// Sends `request` and reads the answers to it until its acknowledgement (or the end of
    /// a dump), handing every other message to `each` as (type, payload).
    fn exchange(&mut self, request: &[u8], mut each: impl FnMut(u16, &[u8])) -> io::Result<()> {
        let seq = u32::from_ne_bytes([request[8], request[9], request[10], request[11]]);
        // SAFETY: a zeroed sockaddr_nl is valid; the family and (zero: the kernel) port are
        // set below.
        let mut kernel: libc::sockaddr_nl = unsafe { std::mem::zeroed() };
        kernel.nl_family = libc::AF_NETLINK as libc::sa_family_t;
        // SAFETY: `request` and `kernel` are valid for the lengths given during the call.
        let sent = unsafe {
            libc::sendto(
                self.fd.as_raw_fd(),
                request.as_ptr().cast(),
                request.len(),
                0,
                (&raw const kernel).cast(),
                std::mem::size_of::<libc::sockaddr_nl>() as libc::socklen_t,
            )
        };
        if sent < 0 {
            return Err(io::Error::last_os_error());
        }
        // Dumps come in parts of at most 32 KiB.
        let mut buf = vec![0u8; 64 * 1024];
        loop {
            // SAFETY: `buf` is valid and writable for its length during the call.
            let n =
                unsafe { libc::recv(self.fd.as_raw_fd(), buf.as_mut_ptr().cast(), buf.len(), 0) };
            let Ok(n) = usize::try_from(n) else {
                let e = io::Error::last_os_error();
                if e.kind() == io::ErrorKind::Interrupted {
                    continue;
                }
                return Err(e);
            };
            for (kind, msg_seq, payload) in Messages(&buf[..n]) {
                if msg_seq != seq {
                    continue;
                }
                match kind {
                    NLMSG_ERROR => {
                        let code = payload
                            .get(..4)
                            .map_or(0, |b| i32::from_ne_bytes([b[0], b[1], b[2], b[3]]));
                        return if code == 0 {
                            Ok(())
                        } else {
                            Err(io::Error::from_raw_os_error(-code))
                        };
                    }
                    NLMSG_DONE => return Ok(()),
                    _ => each(kind, payload),
                }
            }
        }
    }
}

/// A request under construction: header, fixed part, attributes.
struct Message(Vec<u8>);

impl Message {
    fn new(kind: u16, flags: u16, seq: u32) -> Message {
        let mut b = Vec::with_capacity(64);
        b.extend_from_slice(&0u32.to_ne_bytes()); // length, set by `finish`
        b.extend_from_slice(&kind.to_ne_bytes());
        b.extend_from_slice(&flags.to_ne_bytes());
        b.extend_from_slice(&seq.to_ne_bytes());
        b.extend_from_slice(&0u32.to_ne_bytes()); // port: the kernel fills ours in
        Message(b)
    }

    fn bytes(&mut self, b: &[u8]) {
        self.0.extend_from_slice(b);
    }

    /// A route attribute: length, type, value, padded to 4 bytes.
    fn attr(&mut self, kind: u16, value: &[u8]) {
        let len = 4 + value.len();
        self.0.extend_from_slice(&(len as u16).to_ne_bytes());
        self.0.extend_from_slice(&kind.to_ne_bytes());
        self.0.extend_from_slice(value);
        self.0.resize(self.0.len() + (align4(len) - len), 0);
    }

    fn finish(mut self) -> Vec<u8> {
        let len = (self.0.len() as u32).to_ne_bytes();
        self.0[..4].copy_from_slice(&len);
        self.0
    }
}

fn align4(n: usize) -> usize {
    (n + 3) & !3
}

fn ifaddrmsg(prefix: u8, scope: u8, index: u32) -> [u8; IFADDRMSG_LEN] {
    let i = index.to_ne_bytes();
    [
        libc::AF_INET as u8,
        prefix,
        0,
        scope,
        i[0],
        i[1],
        i[2],
        i[3],
    ]
}

fn ndmsg(index: u32, state: u16) -> [u8; NDMSG_LEN] {
    let mut b = [0u8; NDMSG_LEN];
    b[0] = libc::AF_INET as u8;
    b[4..8].copy_from_slice(&index.to_ne_bytes());
    b[8..10].copy_from_slice(&state.to_ne_bytes());
    b
}

/// A default route (dst_len 0) of the main table, marked as ours.
fn rtmsg(scope: u8, kind: u8) -> [u8; RTMSG_LEN] {
    [
        libc::AF_INET as u8,
        0,
        0,
        0,
        RT_TABLE_MAIN,
        PROCIMG_PROTOCOL,
        scope,
        kind,
        0,
        0,
        0,
        0,
    ]
}

/// The messages of a received buffer: (type, sequence number, payload).
struct Messages<'a>(&'a [u8]);

impl<'a> Iterator for Messages<'a> {
    type Item = (u16, u32, &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        let h = self.0.get(..NLMSG_HDRLEN)?;
        let len = u32::from_ne_bytes([h[0], h[1], h[2], h[3]]) as usize;
        let kind = u16::from_ne_bytes([h[4], h[5]]);
        let seq = u32::from_ne_bytes([h[8], h[9], h[10], h[11]]);
        let payload = self.0.get(NLMSG_HDRLEN..len)?;
        self.0 = self.0.get(align4(len).min(self.0.len())..)?;
        Some((kind, seq, payload))
    }
}

/// The attributes of a payload after its fixed part: (type, value).
struct Attributes<'a>(&'a [u8]);

impl<'a> Iterator for Attributes<'a> {
    type Item = (u16, &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        let h = self.0.get(..4)?;
        let len = usize::from(u16::from_ne_bytes([h[0], h[1]]));
        let kind = u16::from_ne_bytes([h[2], h[3]]);
        let value = self.0.get(4..len)?;
        self.0 = self.0.get(align4(len).min(self.0.len())..)?;
        Some((kind, value))
    }
}

/// An `RTM_NEWADDR` payload, if it is an IPv4 address of interface `index`.
fn parse_address(payload: &[u8], index: u32) -> Option<IfAddress> {
    let fixed = payload.get(..IFADDRMSG_LEN)?;
    let of = u32::from_ne_bytes([fixed[4], fixed[5], fixed[6], fixed[7]]);
    if fixed[0] != libc::AF_INET as u8 || of != index {
        return None;
    }
    let (mut local, mut address, mut ours) = (None, None, false);
    for (kind, value) in Attributes(&payload[IFADDRMSG_LEN..]) {
        let ip = <[u8; 4]>::try_from(value).ok().map(Ipv4Addr::from);
        match kind {
            IFA_LOCAL => local = ip,
            IFA_ADDRESS => address = ip,
            IFA_PROTO => ours = value.first() == Some(&PROCIMG_PROTOCOL),
            _ => {}
        }
    }
    // IFA_LOCAL is the interface's own address; IFA_ADDRESS the peer's on point-to-point
    // links, and the same otherwise.
    Some(IfAddress {
        ip: local.or(address)?,
        prefix: fixed[1],
        ours,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_address_request_is_laid_out_as_the_kernel_reads_it() {
        let mut m = Message::new(RTM_NEWADDR, NLM_F_REQUEST | NLM_F_ACK, 7);
        m.bytes(&ifaddrmsg(24, RT_SCOPE_UNIVERSE, 3));
        m.attr(IFA_LOCAL, &[10, 47, 0, 50]);
        m.attr(IFA_PROTO, &[PROCIMG_PROTOCOL]);
        let b = m.finish();
        // Header 16, ifaddrmsg 8, IFA_LOCAL 8, IFA_PROTO 5 padded to 8.
        assert_eq!(b.len(), 40);
        assert_eq!(u32::from_ne_bytes(b[..4].try_into().unwrap()), 40);
        assert_eq!(&b[16..24], &ifaddrmsg(24, 0, 3));
        let local = [
            &8u16.to_ne_bytes()[..],
            &IFA_LOCAL.to_ne_bytes(),
            &[10, 47, 0, 50],
        ]
        .concat();
        assert_eq!(&b[24..32], &local[..]);
        assert_eq!(&b[36..], &[PROCIMG_PROTOCOL, 0, 0, 0]);
    }

    #[test]
    fn a_neighbour_request_is_laid_out_as_the_kernel_reads_it() {
        let mut m = Message::new(RTM_NEWNEIGH, NLM_F_REQUEST, 1);
        m.bytes(&ndmsg(3, NUD_STALE));
        m.attr(NDA_DST, &[10, 0, 0, 2]);
        m.attr(NDA_LLADDR, &[2, 0, 0, 0, 0, 11]);
        let b = m.finish();
        // Header 16, ndmsg 12, NDA_DST 8, NDA_LLADDR 10 padded to 12.
        assert_eq!(b.len(), 48);
        assert_eq!(b[16], libc::AF_INET as u8);
        assert_eq!(&b[20..24], &3u32.to_ne_bytes());
        assert_eq!(&b[24..26], &NUD_STALE.to_ne_bytes());
        assert_eq!(&b[32..36], &[10, 0, 0, 2]);
        assert_eq!(&b[36..38], &10u16.to_ne_bytes());
        assert_eq!(&b[40..46], &[2, 0, 0, 0, 0, 11]);
    }

    #[test]
    fn an_address_message_reads_back_with_its_mark() {
        let mut m = Message::new(RTM_NEWADDR, 0, 1);
        m.bytes(&ifaddrmsg(16, 0, 5));
        m.attr(IFA_ADDRESS, &[192, 168, 3, 4]);
        m.attr(IFA_LOCAL, &[192, 168, 3, 4]);
        m.attr(IFA_PROTO, &[PROCIMG_PROTOCOL]);
        let b = m.finish();
        let (kind, seq, payload) = Messages(&b).next().unwrap();
        assert_eq!((kind, seq), (RTM_NEWADDR, 1));
        assert_eq!(
            parse_address(payload, 5),
            Some(IfAddress {
                ip: Ipv4Addr::new(192, 168, 3, 4),
                prefix: 16,
                ours: true
            })
        );
        assert_eq!(parse_address(payload, 6), None, "another interface's");
        // Truncated messages end the walk instead of panicking.
        assert_eq!(Messages(&b[..b.len() - 3]).count(), 0);
        assert_eq!(Attributes(&[8, 0, 1, 0, 1]).count(), 0);
    }

    #[test]
    #[ignore = "needs root: a network namespace of its own"]
    fn an_address_comes_and_goes_in_a_namespace_of_its_own() {
        std::thread::spawn(|| {
            // SAFETY: unshare(2) with CLONE_NEWNET moves only this thread into a new network
            // namespace, which ends with it.
            assert_eq!(unsafe { libc::unshare(libc::CLONE_NEWNET) }, 0);
            let lo = interface_index("lo").unwrap();
            let mut nl = Netlink::open().unwrap();
            let ip = Ipv4Addr::new(10, 9, 8, 7);
            nl.add_address(lo, ip, 24).unwrap();
            nl.add_address(lo, ip, 24)
                .expect("already there is no error");
            let ours = IfAddress {
                ip,
                prefix: 24,
                ours: true,
            };
            assert!(nl.addresses(lo).unwrap().contains(&ours));
            assert!(!nl.remove_default_route(lo, 34964).unwrap(), "none there");
            nl.remove_address(lo, ip, 24).unwrap();
            nl.remove_address(lo, ip, 24)
                .expect("already gone is no error");
            assert!(!nl.addresses(lo).unwrap().contains(&ours));
        })
        .join()
        .unwrap();
    }
}
