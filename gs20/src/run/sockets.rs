// SPDX-License-Identifier: MIT OR Apache-2.0
//! The host's sockets (reference §1.5 and §1.6: 0x40–0x43, 0x50 from the host; 0xE0, 0xE1,
//! 0x51 to it), opened on the Linux machine's network on the host's behalf, non-blocking,
//! polled in the bridge's one loop.
//!
//! Choices where the reference is silent (the event codes are the crate's
//! [`SocketEventKind`]):
//! - **Handles** are 1 to 255, the lowest free one; 0 is "no socket" (the handle of a
//!   failed Open Socket). At most [`MAX_SOCKETS`] at once, the children of servers counted.
//! - **TCP client**: the connect runs in the background; the response says "connecting",
//!   then a Socket Event says "connected" (1) or "failed" (4, the socket dead).
//! - **TCP server**: listens on the port (on the address, 0.0.0.0 for any); each connection
//!   it accepts is a child socket with a handle of its own, announced on the server's handle
//!   by "accepted" (2, with the child's handle and the remote address); its data goes on the
//!   child's handle. The remote end closing is "disconnected" (3) on the child, which is
//!   then dead. Closing a server that has children fails (error bit 5).
//! - **UDP client**: sends to the address and port of Open Socket and receives what comes
//!   back. **UDP server**: receives on the port from anyone, and sends to the last sender
//!   (nobody yet: "send failed"). Datagrams come as one Adapter Socket Data each, cut to
//!   [`MAX_SOCKET_DATA`] bytes.
//! - **Options**: an option that does not apply to the socket's protocol (TCP no-delay on
//!   UDP, say) is "unknown option" (bit 2), data of the wrong size "bad option data" (bit
//!   3). TCP keep-alive's byte is the interval in seconds (0: off). Limited broadcast off
//!   (the default): a UDP client's 255.255.255.255 goes to the station's subnet broadcast
//!   address instead.
//! - **Send Socket Data** is answered too (error bit 4 when it failed). TCP data the
//!   kernel does not take at once waits in the socket's buffer, [`SEND_BUFFER`] bytes at
//!   most.
//! - The sockets use the Linux machine's network stack and routes; they are not bound to
//!   the station's address. They close at Request Reset.

use procimg_gs20::frame::MAX_SOCKET_DATA;
use procimg_gs20::link::SocketRequest;
use procimg_gs20::messages::{
    AdapterSocketData, Message, OpenSocket, SocketErrors, SocketEvent, SocketEventKind,
    SocketOption, SocketProtocol, SocketResponse, SocketRole, SocketStatus,
};
use socket2::{Domain, SockAddr, SockRef, Socket, TcpKeepalive, Type};
use std::collections::BTreeMap;
use std::io::{ErrorKind, Read, Write};
use std::net::{Ipv4Addr, SocketAddr, SocketAddrV4, TcpListener, TcpStream, UdpSocket};
use std::os::fd::{AsRawFd, RawFd};
use std::time::Duration;
use tracing::debug;

/// The most sockets open at once, servers' children included.
pub const MAX_SOCKETS: usize = 16;
/// The most TCP bytes waiting for the kernel per socket.
pub const SEND_BUFFER: usize = 64 * 1024;

/// What a socket is.
enum Kind {
    /// A TCP client, connecting until `connected`.
    TcpClient { stream: TcpStream, connected: bool },
    /// A TCP server and the handles of its connections.
    TcpServer {
        listener: TcpListener,
        children: Vec<u8>,
    },
    /// A connection a server accepted.
    TcpChild { stream: TcpStream, parent: u8 },
    /// A UDP socket: where it sends (a client's target; a server's last sender).
    Udp {
        socket: UdpSocket,
        role: SocketRole,
        target: Option<SocketAddrV4>,
    },
}

struct Sock {
    kind: Kind,
    /// Dead: the host should close it (the connection failed or ended).
    dead: bool,
    /// The remote end closed a child's connection.
    disconnected: bool,
    /// TCP bytes not yet taken by the kernel.
    out: Vec<u8>,
    /// Limited broadcast: 255.255.255.255 as is.
    limited_broadcast: bool,
}

impl Sock {
    fn new(kind: Kind) -> Sock {
        Sock {
            kind,
            dead: false,
            disconnected: false,
            out: Vec::new(),
            limited_broadcast: false,
        }
    }

    fn status(&self) -> SocketStatus {
        let mut s = match &self.kind {
            Kind::TcpClient {
                connected: false, ..
            } => SocketStatus::CONNECTING,
            Kind::TcpClient { .. } | Kind::TcpChild { .. } => SocketStatus::CONNECTED,
            Kind::TcpServer { .. } => SocketStatus::ACCEPTING,
            Kind::Udp { .. } => SocketStatus::LISTENING,
        };
        if self.dead {
            s.remove(SocketStatus::CONNECTING | SocketStatus::CONNECTED);
            s |= SocketStatus::DEAD;
        }
        if self.disconnected {
            s |= SocketStatus::DISCONNECTED;
        }
        s
    }

    fn fd(&self) -> RawFd {
        match &self.kind {
            Kind::TcpClient { stream, .. } | Kind::TcpChild { stream, .. } => stream.as_raw_fd(),
            Kind::TcpServer { listener, .. } => listener.as_raw_fd(),
            Kind::Udp { socket, .. } => socket.as_raw_fd(),
        }
    }

    /// The socket, for setting options.
    fn sockref(&self) -> SockRef<'_> {
        match &self.kind {
            Kind::TcpClient { stream, .. } | Kind::TcpChild { stream, .. } => SockRef::from(stream),
            Kind::TcpServer { listener, .. } => SockRef::from(listener),
            Kind::Udp { socket, .. } => SockRef::from(socket),
        }
    }

    fn protocol(&self) -> SocketProtocol {
        match self.kind {
            Kind::Udp { .. } => SocketProtocol::Udp,
            _ => SocketProtocol::Tcp,
        }
    }
}

/// What a socket wants of poll(2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Interest {
    /// The descriptor.
    pub fd: RawFd,
    /// Wake when readable (data, a connection).
    pub read: bool,
    /// Wake when writable (a connect done, room for waiting data).
    pub write: bool,
}

/// The host's sockets.
#[derive(Default)]
pub struct Sockets {
    table: BTreeMap<u8, Sock>,
    /// The station's subnet broadcast address, for limited broadcast off.
    subnet_broadcast: Option<Ipv4Addr>,
}

impl Sockets {
    /// Sets the station's subnet broadcast address (none while it has no address).
    pub fn set_subnet_broadcast(&mut self, broadcast: Option<Ipv4Addr>) {
        self.subnet_broadcast = broadcast;
    }

    /// Closes every socket (Request Reset).
    pub fn close_all(&mut self) {
        self.table.clear();
    }

    /// What to poll for; `read` only when `take_data` (the host link has room).
    pub fn interests(&self, take_data: bool) -> Vec<Interest> {
        self.table
            .values()
            .filter(|s| !s.dead)
            .map(|s| Interest {
                fd: s.fd(),
                read: take_data || matches!(s.kind, Kind::TcpServer { .. }),
                write: matches!(
                    s.kind,
                    Kind::TcpClient {
                        connected: false,
                        ..
                    }
                ) || !s.out.is_empty(),
            })
            .collect()
    }

    /// Carries out a request; the Socket Response.
    pub fn request(&mut self, req: SocketRequest) -> Vec<u8> {
        let (handle, status, errors) = match req {
            SocketRequest::Open(open) => match self.open(&open) {
                Ok(handle) => (handle, self.table[&handle].status(), SocketErrors::empty()),
                Err(e) => {
                    debug!("Open Socket {open:?} failed: {e}");
                    (0, SocketStatus::empty(), SocketErrors::OPEN_FAILED)
                }
            },
            SocketRequest::SetOption {
                handle,
                option,
                data,
            } => match self.table.get(&handle) {
                None => (handle, SocketStatus::empty(), SocketErrors::NOT_OPEN),
                Some(_) => {
                    let errors = self.set_option(handle, option, &data);
                    (handle, self.table[&handle].status(), errors)
                }
            },
            SocketRequest::Status { handle } => match self.table.get(&handle) {
                None => (handle, SocketStatus::empty(), SocketErrors::NOT_OPEN),
                Some(s) => (handle, s.status(), SocketErrors::empty()),
            },
            SocketRequest::Close { handle } => (handle, SocketStatus::empty(), self.close(handle)),
            SocketRequest::Send { handle, data } => match self.table.get(&handle) {
                None => (
                    handle,
                    SocketStatus::empty(),
                    SocketErrors::NOT_OPEN | SocketErrors::SEND_FAILED,
                ),
                Some(_) => {
                    let errors = self.send(handle, &data);
                    (handle, self.table[&handle].status(), errors)
                }
            },
        };
        frame(&SocketResponse {
            handle,
            status,
            errors,
        })
    }

    fn free_handle(&self) -> Option<u8> {
        if self.table.len() >= MAX_SOCKETS {
            return None;
        }
        (1..=u8::MAX).find(|h| !self.table.contains_key(h))
    }

    fn open(&mut self, open: &OpenSocket) -> std::io::Result<u8> {
        let handle = self
            .free_handle()
            .ok_or_else(|| std::io::Error::other("every socket handle is in use"))?;
        let addr = SocketAddrV4::new(open.ip, open.port);
        let kind = match (open.role, open.protocol) {
            (SocketRole::Client, SocketProtocol::Tcp) => {
                if open.ip.is_unspecified() || open.port == 0 {
                    return Err(ErrorKind::InvalidInput.into());
                }
                let socket = Socket::new(Domain::IPV4, Type::STREAM, None)?;
                socket.set_nonblocking(true)?;
                match socket.connect(&SockAddr::from(addr)) {
                    Ok(()) => {}
                    // A non-blocking connect goes on in the background.
                    Err(e) if e.raw_os_error() == Some(nix::errno::Errno::EINPROGRESS as i32) => {}
                    Err(e) => return Err(e),
                }
                Kind::TcpClient {
                    stream: socket.into(),
                    connected: false,
                }
            }
            (SocketRole::Server, SocketProtocol::Tcp) => {
                let listener = TcpListener::bind(addr)?;
                listener.set_nonblocking(true)?;
                Kind::TcpServer {
                    listener,
                    children: Vec::new(),
                }
            }
            (role @ (SocketRole::Client | SocketRole::Server), SocketProtocol::Udp) => {
                let (bind, target) = match role {
                    SocketRole::Client if open.port == 0 || open.ip.is_unspecified() => {
                        return Err(ErrorKind::InvalidInput.into());
                    }
                    SocketRole::Client => (SocketAddrV4::new(Ipv4Addr::UNSPECIFIED, 0), Some(addr)),
                    _ => (addr, None),
                };
                let socket = UdpSocket::bind(bind)?;
                socket.set_nonblocking(true)?;
                Kind::Udp {
                    socket,
                    role,
                    target,
                }
            }
            _ => return Err(ErrorKind::InvalidInput.into()),
        };
        self.table.insert(handle, Sock::new(kind));
        Ok(handle)
    }

    fn set_option(&mut self, handle: u8, option: SocketOption, data: &[u8]) -> SocketErrors {
        let Some(len) = option.data_len() else {
            return SocketErrors::UNKNOWN_OPTION;
        };
        if data.len() != len {
            return SocketErrors::BAD_OPTION_DATA;
        }
        let Some(s) = self.table.get_mut(&handle) else {
            return SocketErrors::NOT_OPEN;
        };
        let on = data.first().is_some_and(|&b| b != 0);
        let group = <[u8; 4]>::try_from(data).map(Ipv4Addr::from);
        let udp = s.protocol() == SocketProtocol::Udp;
        let fd = s.sockref();
        let result = match option {
            SocketOption::Broadcast if udp => fd.set_broadcast(on),
            SocketOption::ReuseAddress => fd.set_reuse_address(on),
            SocketOption::TypeOfService => fd.set_tos_v4(u32::from(data[0])),
            SocketOption::LimitedBroadcast if udp => {
                s.limited_broadcast = on;
                Ok(())
            }
            SocketOption::JoinMulticast if udp => match group {
                Ok(g) => fd.join_multicast_v4(&g, &Ipv4Addr::UNSPECIFIED),
                Err(_) => return SocketErrors::BAD_OPTION_DATA,
            },
            SocketOption::LeaveMulticast if udp => match group {
                Ok(g) => fd.leave_multicast_v4(&g, &Ipv4Addr::UNSPECIFIED),
                Err(_) => return SocketErrors::BAD_OPTION_DATA,
            },
            SocketOption::TcpNoDelay if !udp => fd.set_tcp_nodelay(on),
            SocketOption::TcpKeepAlive if !udp => match data[0] {
                0 => fd.set_keepalive(false),
                secs => {
                    let every = Duration::from_secs(u64::from(secs));
                    fd.set_tcp_keepalive(&TcpKeepalive::new().with_time(every).with_interval(every))
                }
            },
            _ => return SocketErrors::UNKNOWN_OPTION,
        };
        match result {
            Ok(()) => SocketErrors::empty(),
            Err(e) => {
                debug!("socket {handle}: option {option} failed: {e}");
                SocketErrors::BAD_OPTION_DATA
            }
        }
    }

    fn close(&mut self, handle: u8) -> SocketErrors {
        match self.table.get(&handle) {
            None => return SocketErrors::NOT_OPEN,
            Some(Sock {
                kind: Kind::TcpServer { children, .. },
                ..
            }) if !children.is_empty() => return SocketErrors::CLOSE_FAILED,
            Some(_) => {}
        }
        if let Some(Sock {
            kind: Kind::TcpChild { parent, .. },
            ..
        }) = self.table.remove(&handle)
            && let Some(Sock {
                kind: Kind::TcpServer { children, .. },
                ..
            }) = self.table.get_mut(&parent)
        {
            children.retain(|&c| c != handle);
        }
        SocketErrors::empty()
    }

    fn send(&mut self, handle: u8, data: &[u8]) -> SocketErrors {
        let broadcast = self.subnet_broadcast;
        let Some(s) = self.table.get_mut(&handle) else {
            return SocketErrors::NOT_OPEN | SocketErrors::SEND_FAILED;
        };
        if data.is_empty() || s.dead {
            return SocketErrors::SEND_FAILED;
        }
        let limited = s.limited_broadcast;
        match &mut s.kind {
            Kind::TcpClient {
                connected: false, ..
            }
            | Kind::TcpServer { .. } => SocketErrors::SEND_FAILED,
            Kind::TcpClient { stream, .. } | Kind::TcpChild { stream, .. } => {
                if s.out.len() + data.len() > SEND_BUFFER {
                    return SocketErrors::SEND_FAILED;
                }
                s.out.extend_from_slice(data);
                match flush_stream(stream, &mut s.out) {
                    Ok(()) => SocketErrors::empty(),
                    Err(_) => {
                        s.dead = true;
                        SocketErrors::SEND_FAILED
                    }
                }
            }
            Kind::Udp { socket, target, .. } => {
                let Some(mut to) = *target else {
                    return SocketErrors::SEND_FAILED;
                };
                if *to.ip() == Ipv4Addr::BROADCAST
                    && !limited
                    && let Some(b) = broadcast
                {
                    to.set_ip(b);
                }
                match socket.send_to(data, to) {
                    Ok(n) if n == data.len() => SocketErrors::empty(),
                    _ => SocketErrors::SEND_FAILED,
                }
            }
        }
    }

    /// Does what the sockets can do now without waiting: connects completed, connections
    /// accepted, data received (only when `take_data`), waiting data sent. Returns the
    /// frames for the host: Socket Events and Adapter Socket Data.
    pub fn poll(&mut self, take_data: bool) -> Vec<Vec<u8>> {
        let mut frames = Vec::new();
        let handles: Vec<u8> = self.table.keys().copied().collect();
        for handle in handles {
            let mut accepted = Vec::new();
            let Some(s) = self.table.get_mut(&handle) else {
                continue;
            };
            if s.dead {
                continue;
            }
            let mut event = None;
            match &mut s.kind {
                Kind::TcpClient { stream, connected } => {
                    if !*connected {
                        match (stream.take_error(), stream.peer_addr()) {
                            (Ok(None), Ok(SocketAddr::V4(remote))) => {
                                *connected = true;
                                event = Some(SocketEventKind::Connected { remote });
                            }
                            (Ok(Some(_)) | Err(_), _) => {
                                s.dead = true;
                                event = Some(SocketEventKind::Failed);
                            }
                            _ => {}
                        }
                    } else {
                        event = stream_io(stream, &mut s.out, handle, take_data, &mut frames)
                            .then_some(SocketEventKind::Disconnected);
                    }
                }
                Kind::TcpChild { stream, .. } => {
                    if stream_io(stream, &mut s.out, handle, take_data, &mut frames) {
                        s.disconnected = true;
                        event = Some(SocketEventKind::Disconnected);
                    }
                }
                Kind::TcpServer { listener, .. } => {
                    while let Ok((stream, remote)) = listener.accept() {
                        accepted.push((stream, remote));
                    }
                }
                Kind::Udp {
                    socket,
                    role,
                    target,
                } => {
                    // One datagram per call: the next when the line is idle again.
                    let mut buf = vec![0u8; MAX_SOCKET_DATA];
                    if take_data && let Ok((n, SocketAddr::V4(from))) = socket.recv_from(&mut buf) {
                        if *role == SocketRole::Server {
                            *target = Some(from);
                        }
                        frames.push(frame(&AdapterSocketData {
                            handle,
                            data: &buf[..n],
                        }));
                    }
                }
            }
            if matches!(event, Some(SocketEventKind::Disconnected)) {
                s.dead = true;
            }
            if let Some(event) = event {
                let status = s.status();
                frames.push(frame(&SocketEvent {
                    handle,
                    status,
                    event,
                }));
            }
            for (stream, remote) in accepted {
                frames.extend(self.adopt(handle, stream, remote));
            }
        }
        frames
    }

    /// A connection server `parent` accepted: a child socket, announced on the parent.
    fn adopt(&mut self, parent: u8, stream: TcpStream, remote: SocketAddr) -> Option<Vec<u8>> {
        let (SocketAddr::V4(remote), Some(child)) = (remote, self.free_handle()) else {
            debug!("socket {parent}: a connection from {remote} refused: no free handle");
            return None;
        };
        stream.set_nonblocking(true).ok()?;
        self.table
            .insert(child, Sock::new(Kind::TcpChild { stream, parent }));
        let s = self.table.get_mut(&parent)?;
        if let Kind::TcpServer { children, .. } = &mut s.kind {
            children.push(child);
        }
        Some(frame(&SocketEvent {
            handle: parent,
            status: s.status(),
            event: SocketEventKind::Accepted { child, remote },
        }))
    }
}

/// Writes what waits on a TCP stream and reads (when `take_data`) one Adapter Socket Data
/// frame's worth; whether the connection ended.
fn stream_io(
    stream: &mut TcpStream,
    out: &mut Vec<u8>,
    handle: u8,
    take_data: bool,
    frames: &mut Vec<Vec<u8>>,
) -> bool {
    if flush_stream(stream, out).is_err() {
        return true;
    }
    if !take_data {
        return false;
    }
    // One frame's worth per call: the next when the line is idle again.
    let mut buf = vec![0u8; MAX_SOCKET_DATA];
    match stream.read(&mut buf) {
        Ok(0) => true,
        Ok(n) => {
            frames.push(frame(&AdapterSocketData {
                handle,
                data: &buf[..n],
            }));
            false
        }
        Err(e) => !matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::Interrupted),
    }
}

/// Writes what the kernel takes now.
fn flush_stream(stream: &mut TcpStream, out: &mut Vec<u8>) -> std::io::Result<()> {
    while !out.is_empty() {
        match stream.write(out) {
            Ok(n) => {
                out.drain(..n);
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock => break,
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

/// A frame of the module; the messages here always fit one.
fn frame<'a>(m: &impl Message<'a>) -> Vec<u8> {
    m.to_vec().unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_gs20::frame::FrameRepr;
    use procimg_gs20::messages::AdapterMessage;
    use std::time::Instant;

    fn response(bytes: &[u8]) -> SocketResponse {
        let frame = FrameRepr::parse_bytes(bytes).unwrap();
        <SocketResponse as Message>::parse(&frame).unwrap()
    }

    fn open(
        s: &mut Sockets,
        role: SocketRole,
        protocol: SocketProtocol,
        port: u16,
    ) -> SocketResponse {
        response(&s.request(SocketRequest::Open(OpenSocket {
            role,
            protocol,
            port,
            ip: Ipv4Addr::LOCALHOST,
        })))
    }

    fn option(s: &mut Sockets, handle: u8, option: SocketOption, data: &[u8]) -> SocketErrors {
        response(&s.request(SocketRequest::SetOption {
            handle,
            option,
            data: data.to_vec(),
        }))
        .errors
    }

    /// Polls until a frame `pick` takes comes, within 30 s.
    fn until<T>(s: &mut Sockets, pick: impl Fn(AdapterMessage<'_>) -> Option<T>) -> T {
        let deadline = Instant::now() + Duration::from_secs(30);
        loop {
            for f in s.poll(true) {
                let frame = FrameRepr::parse_bytes(&f).unwrap();
                if let Some(t) = pick(AdapterMessage::parse(&frame).unwrap()) {
                    return t;
                }
            }
            assert!(Instant::now() < deadline, "nothing came within 30 s");
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    #[test]
    fn options_and_sends_that_do_not_apply_are_refused_with_their_bits() {
        let mut s = Sockets::default();
        let udp = open(&mut s, SocketRole::Server, SocketProtocol::Udp, 0);
        assert_eq!((udp.handle, udp.errors), (1, SocketErrors::empty()));
        let h = udp.handle;
        assert_eq!(
            option(&mut s, h, SocketOption::Broadcast, &[1]),
            SocketErrors::empty()
        );
        assert_eq!(
            option(&mut s, h, SocketOption::Broadcast, &[1, 0]),
            SocketErrors::BAD_OPTION_DATA
        );
        assert_eq!(
            option(&mut s, h, SocketOption::TcpNoDelay, &[1]),
            SocketErrors::UNKNOWN_OPTION
        );
        assert_eq!(
            option(&mut s, h, SocketOption::Unknown(9), &[1]),
            SocketErrors::UNKNOWN_OPTION
        );
        assert_eq!(
            option(&mut s, 7, SocketOption::Broadcast, &[1]),
            SocketErrors::NOT_OPEN
        );
        // A UDP server has nobody to send to before somebody sent to it.
        let r = response(&s.request(SocketRequest::Send {
            handle: h,
            data: b"x".to_vec(),
        }));
        assert_eq!(r.errors, SocketErrors::SEND_FAILED);
        // A client needs an address and a port.
        let bad = response(&s.request(SocketRequest::Open(OpenSocket {
            role: SocketRole::Client,
            protocol: SocketProtocol::Tcp,
            port: 0,
            ip: Ipv4Addr::UNSPECIFIED,
        })));
        assert_eq!((bad.handle, bad.errors), (0, SocketErrors::OPEN_FAILED));
        let r = response(&s.request(SocketRequest::Close { handle: h }));
        assert_eq!(r.errors, SocketErrors::empty());
        let r = response(&s.request(SocketRequest::Status { handle: h }));
        assert_eq!(r.errors, SocketErrors::NOT_OPEN);
    }

    #[test]
    fn a_connect_nobody_takes_fails_and_the_socket_is_dead() {
        // A port just freed: nobody listens there.
        let port = TcpListener::bind((Ipv4Addr::LOCALHOST, 0))
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let mut s = Sockets::default();
        let r = open(&mut s, SocketRole::Client, SocketProtocol::Tcp, port);
        let h = r.handle;
        let status = until(&mut s, |m| match m {
            AdapterMessage::SocketEvent(e) if e.handle == h => {
                assert_eq!(e.event, SocketEventKind::Failed);
                Some(e.status)
            }
            _ => None,
        });
        assert_eq!(status, SocketStatus::DEAD);
        let r = response(&s.request(SocketRequest::Send {
            handle: h,
            data: b"x".to_vec(),
        }));
        assert_eq!(r.errors, SocketErrors::SEND_FAILED);
        assert!(s.interests(true).is_empty(), "a dead socket is not polled");
    }

    #[test]
    fn handles_run_out_at_the_limit() {
        let mut s = Sockets::default();
        for i in 0..MAX_SOCKETS {
            let r = open(&mut s, SocketRole::Server, SocketProtocol::Udp, 0);
            assert_eq!(usize::from(r.handle), i + 1);
        }
        let r = open(&mut s, SocketRole::Server, SocketProtocol::Udp, 0);
        assert_eq!((r.handle, r.errors), (0, SocketErrors::OPEN_FAILED));
        s.close_all();
        assert_eq!(
            open(&mut s, SocketRole::Server, SocketProtocol::Udp, 0).handle,
            1
        );
    }
}
