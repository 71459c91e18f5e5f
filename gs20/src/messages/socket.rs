// SPDX-License-Identifier: MIT OR Apache-2.0
//! The socket frames (reference §1.5, codes in §1.6): the host opens TCP and UDP sockets on
//! the module's network and exchanges data through them, in Run only.
//!
//! | ID | Dir | Frame | Data |
//! |---|---|---|---|
//! | 0x40 | host | Open Socket | role, protocol, port, IP |
//! | 0x41 | host | Set Socket Option | handle, option, option data |
//! | 0x42 | host | Request Socket Status | handle |
//! | 0x43 | host | Close Socket | handle |
//! | 0x50 | host | Send Socket Data (2-byte LEN) | handle, data |
//! | 0x51 | module | Adapter Socket Data (2-byte LEN) | handle, data |
//! | 0xE0 | module | Socket Response | handle, status bits, error bits |
//! | 0xE1 | module | Socket Event (2-byte LEN) | handle, status bits, event code, information |
//!
//! Choices where the reference contradicts itself or is silent:
//! - Set Socket Option: its table gives the option 2 bytes, but its LEN (N + 2) and the
//!   offset of the option data (4) leave 1; the option is one byte.
//! - Adapter Socket Data: its table calls byte 3 "socket option"; it is the handle, as in
//!   Send Socket Data.
//! - Socket Event: its table gives a 2-byte LEN but offsets (handle at 2, status at 3, code
//!   at 5) that fit a 1-byte one. §1.4 lists 0xE1 among the 2-byte LEN frames, and so does
//!   this crate: the data (handle, status, code, information) starts at index 3.
//! - Socket event codes: the reference's table is missing. Chosen: [`SocketEventKind`].

use std::net::{Ipv4Addr, SocketAddrV4};

use bitflags::bitflags;

use super::{Message, ParseError, Reader, Writer, check_len};
use crate::frame::{EmitError, FrameId};

coded_enum! {
    /// Open Socket byte 2: which end the socket is.
    pub enum SocketRole(u8) display "unknown value {}" {
        /// 0: connects to (TCP) or sends to (UDP) the given IP and port.
        Client = 0 => "client",
        /// 1: listens (TCP) or receives (UDP) on the given port.
        Server = 1 => "server",
    }
}

coded_enum! {
    /// Open Socket byte 3: the transport.
    pub enum SocketProtocol(u8) display "unknown value {}" {
        /// 0.
        Tcp = 0 => "TCP",
        /// 1.
        Udp = 1 => "UDP",
    }
}

coded_enum! {
    /// The socket options (reference §1.6; the number of data bytes in brackets).
    pub enum SocketOption(u8) display "unknown value {}" {
        /// 0: allow broadcasts (1).
        Broadcast = 0 => "broadcast",
        /// 1: bind a port already in use (1).
        ReuseAddress = 1 => "reuse address",
        /// 2: the IP header's type of service (1).
        TypeOfService = 2 => "type of service",
        /// 3: use 255.255.255.255 as is; off, it is replaced by the interface's broadcast
        /// address (1).
        LimitedBroadcast = 3 => "limited broadcast",
        /// 4: join a multicast group (4: its address).
        JoinMulticast = 4 => "join multicast group",
        /// 5: leave a multicast group (4).
        LeaveMulticast = 5 => "leave multicast group",
        /// 6: TCP without Nagle's algorithm (1).
        TcpNoDelay = 6 => "TCP no delay",
        /// 7: TCP keep-alive on, with its interval (1).
        TcpKeepAlive = 7 => "TCP keep-alive",
    }
}

impl SocketOption {
    /// The data bytes the option takes; `None` for an unknown option (socket error bit 2).
    /// Other data lengths are socket error bit 3.
    pub const fn data_len(self) -> Option<usize> {
        match self {
            SocketOption::JoinMulticast | SocketOption::LeaveMulticast => Some(4),
            SocketOption::Unknown(_) => None,
            _ => Some(1),
        }
    }
}

bitflags! {
    /// A socket's status bits (reference §1.6).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
    pub struct SocketStatus: u16 {
        /// Bit 0: listening (UDP client or server).
        const LISTENING = 1 << 0;
        /// Bit 1: connecting (TCP client).
        const CONNECTING = 1 << 1;
        /// Bit 2: accepting (TCP server).
        const ACCEPTING = 1 << 2;
        /// Bit 3: connected (TCP client or server).
        const CONNECTED = 1 << 3;
        /// Bit 4: dead; the host should close it.
        const DEAD = 1 << 4;
        /// Bit 5: disconnected (TCP server).
        const DISCONNECTED = 1 << 5;
    }
}

bitflags! {
    /// A socket request's error bits (reference §1.6).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
    pub struct SocketErrors: u16 {
        /// Bit 0: the socket is not open.
        const NOT_OPEN = 1 << 0;
        /// Bit 1: open failed (role, protocol, IP unsupported or invalid; listen failed).
        const OPEN_FAILED = 1 << 1;
        /// Bit 2: unknown option.
        const UNKNOWN_OPTION = 1 << 2;
        /// Bit 3: option data of the wrong size or value.
        const BAD_OPTION_DATA = 1 << 3;
        /// Bit 4: send failed (too much or too little data, socket not open).
        const SEND_FAILED = 1 << 4;
        /// Bit 5: close failed (the host tried to close a parent socket).
        const CLOSE_FAILED = 1 << 5;
    }
}

/// Open Socket (0x40, LEN 8). Answered by a Socket Response with the new handle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct OpenSocket {
    /// Byte 2.
    pub role: SocketRole,
    /// Byte 3.
    pub protocol: SocketProtocol,
    /// Bytes 4–5: the remote port of a client, the local port of a server.
    pub port: u16,
    /// Bytes 6–9: the remote address of a client (most significant octet first); a server
    /// binds to it, 0.0.0.0 for any.
    pub ip: Ipv4Addr,
}

/// Set Socket Option (0x41, LEN 2 + N).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SetSocketOption<'a> {
    /// Byte 2.
    pub handle: u8,
    /// Byte 3 (one byte, see the module docs).
    pub option: SocketOption,
    /// Bytes 4 on, as sent ([`SocketOption::data_len`] tells what it should be).
    pub data: &'a [u8],
}

/// Request Socket Status (0x42, LEN 1). Answered by a Socket Response.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RequestSocketStatus {
    /// Byte 2.
    pub handle: u8,
}

/// Close Socket (0x43, LEN 1). Answered by a Socket Response.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CloseSocket {
    /// Byte 2.
    pub handle: u8,
}

/// Send Socket Data (0x50, host → module, 2-byte LEN 1 + N).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SendSocketData<'a> {
    /// Byte 3.
    pub handle: u8,
    /// Bytes 4 on: up to [`crate::frame::MAX_SOCKET_DATA`].
    pub data: &'a [u8],
}

/// Adapter Socket Data (0x51, module → host, unsolicited, 2-byte LEN 1 + N).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AdapterSocketData<'a> {
    /// Byte 3.
    pub handle: u8,
    /// Bytes 4 on: up to [`crate::frame::MAX_SOCKET_DATA`].
    pub data: &'a [u8],
}

/// Socket Response (0xE0, LEN 5): the answer to every socket request.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SocketResponse {
    /// Byte 2: the socket's handle (the new one, after Open Socket).
    pub handle: u8,
    /// Bytes 3–4.
    pub status: SocketStatus,
    /// Bytes 5–6.
    pub errors: SocketErrors,
}

/// A socket event and its information.
///
/// The reference's socket event table is missing; it names only "remote connect and
/// disconnect" events. Chosen, with the information big-endian like every field:
///
/// | Code | Event | Information |
/// |---|---|---|
/// | 1 | a TCP client connected | 6 bytes: remote IP, remote port |
/// | 2 | a TCP server accepted a connection: a child socket with its own handle | 7 bytes: child handle, remote IP, remote port |
/// | 3 | the remote end closed the connection | none |
/// | 4 | the connection failed (refused, timed out, reset): the socket is dead | none |
///
/// The server socket stays the parent of its children: data of a connection goes on the
/// child's handle, and closing the parent while it has children fails (socket error bit 5,
/// the only reading of "attempt to close a parent socket").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SocketEventKind<'a> {
    /// 1.
    Connected {
        /// The server's address.
        remote: SocketAddrV4,
    },
    /// 2.
    Accepted {
        /// The handle of the connection's socket.
        child: u8,
        /// The client's address.
        remote: SocketAddrV4,
    },
    /// 3.
    Disconnected,
    /// 4.
    Failed,
    /// Any other code, its information kept as it came. Emitting one with a code 1–4 is an
    /// error: those are the named variants.
    Other {
        /// The event code.
        code: u8,
        /// The information.
        info: &'a [u8],
    },
}

impl SocketEventKind<'_> {
    /// The event code.
    pub const fn code(&self) -> u8 {
        match self {
            SocketEventKind::Connected { .. } => 1,
            SocketEventKind::Accepted { .. } => 2,
            SocketEventKind::Disconnected => 3,
            SocketEventKind::Failed => 4,
            SocketEventKind::Other { code, .. } => *code,
        }
    }

    /// Bytes of the information.
    pub const fn info_len(&self) -> usize {
        match self {
            SocketEventKind::Connected { .. } => 6,
            SocketEventKind::Accepted { .. } => 7,
            SocketEventKind::Disconnected | SocketEventKind::Failed => 0,
            SocketEventKind::Other { info, .. } => info.len(),
        }
    }
}

/// The information length a named socket event code defines.
const fn socket_info_len_of(code: u8) -> Option<usize> {
    match code {
        1 => Some(6),
        2 => Some(7),
        3 | 4 => Some(0),
        _ => None,
    }
}

/// Socket Event (0xE1, module → host, unsolicited, 2-byte LEN 4 + N).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SocketEvent<'a> {
    /// Byte 3.
    pub handle: u8,
    /// Bytes 4–5.
    pub status: SocketStatus,
    /// Byte 6: the code; 7 on: the information.
    pub event: SocketEventKind<'a>,
}

impl<'a> Message<'a> for OpenSocket {
    const ID: FrameId = FrameId::OpenSocket;

    fn parse_payload(payload: &'a [u8]) -> Result<OpenSocket, ParseError> {
        let mut r = Reader::new(Self::ID, payload)?;
        let open = OpenSocket {
            role: SocketRole::from_raw(r.u8()?),
            protocol: SocketProtocol::from_raw(r.u8()?),
            port: r.u16()?,
            ip: r.ipv4()?,
        };
        r.end()?;
        Ok(open)
    }

    fn payload_len(&self) -> usize {
        8
    }

    fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
        Writer::new(out)
            .u8(self.role.raw())
            .u8(self.protocol.raw())
            .u16(self.port)
            .ipv4(self.ip)
            .finish()
    }
}

impl<'a> Message<'a> for SetSocketOption<'a> {
    const ID: FrameId = FrameId::SetSocketOption;

    fn parse_payload(payload: &'a [u8]) -> Result<SetSocketOption<'a>, ParseError> {
        let mut r = Reader::new(Self::ID, payload)?;
        Ok(SetSocketOption {
            handle: r.u8()?,
            option: SocketOption::from_raw(r.u8()?),
            data: r.rest(),
        })
    }

    fn payload_len(&self) -> usize {
        2 + self.data.len()
    }

    fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
        Writer::new(out)
            .u8(self.handle)
            .u8(self.option.raw())
            .bytes(self.data)
            .finish()
    }
}

/// The two one-byte requests and the two data frames with a handle.
macro_rules! handle_message {
    ($($ty:ident),+) => {$(
        impl<'a> Message<'a> for $ty {
            const ID: FrameId = FrameId::$ty;

            fn parse_payload(payload: &'a [u8]) -> Result<$ty, ParseError> {
                let mut r = Reader::new(Self::ID, payload)?;
                let handle = r.u8()?;
                r.end()?;
                Ok($ty { handle })
            }

            fn payload_len(&self) -> usize {
                1
            }

            fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
                Writer::new(out).u8(self.handle).finish()
            }
        }
    )+};
}

handle_message!(RequestSocketStatus, CloseSocket);

macro_rules! socket_data_message {
    ($($ty:ident),+) => {$(
        impl<'a> Message<'a> for $ty<'a> {
            const ID: FrameId = FrameId::$ty;

            fn parse_payload(payload: &'a [u8]) -> Result<$ty<'a>, ParseError> {
                check_len(Self::ID, payload)?;
                let mut r = Reader::unchecked(Self::ID, payload);
                Ok($ty {
                    handle: r.u8()?,
                    data: r.rest(),
                })
            }

            fn payload_len(&self) -> usize {
                1 + self.data.len()
            }

            fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
                Writer::new(out).u8(self.handle).bytes(self.data).finish()
            }
        }
    )+};
}

socket_data_message!(SendSocketData, AdapterSocketData);

impl<'a> Message<'a> for SocketResponse {
    const ID: FrameId = FrameId::SocketResponse;

    fn parse_payload(payload: &'a [u8]) -> Result<SocketResponse, ParseError> {
        let mut r = Reader::new(Self::ID, payload)?;
        let response = SocketResponse {
            handle: r.u8()?,
            status: SocketStatus::from_bits_retain(r.u16()?),
            errors: SocketErrors::from_bits_retain(r.u16()?),
        };
        r.end()?;
        Ok(response)
    }

    fn payload_len(&self) -> usize {
        5
    }

    fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
        Writer::new(out)
            .u8(self.handle)
            .u16(self.status.bits())
            .u16(self.errors.bits())
            .finish()
    }
}

fn socket_addr(r: &mut Reader<'_>) -> Result<SocketAddrV4, ParseError> {
    let ip = r.ipv4()?;
    Ok(SocketAddrV4::new(ip, r.u16()?))
}

impl<'a> Message<'a> for SocketEvent<'a> {
    const ID: FrameId = FrameId::SocketEvent;

    fn parse_payload(payload: &'a [u8]) -> Result<SocketEvent<'a>, ParseError> {
        let mut r = Reader::new(Self::ID, payload)?;
        let handle = r.u8()?;
        let status = SocketStatus::from_bits_retain(r.u16()?);
        let code = r.u8()?;
        let info = r.rest();
        if let Some(expected) = socket_info_len_of(code)
            && info.len() != expected
        {
            return Err(ParseError::InfoLength {
                id: Self::ID,
                code: u16::from(code),
                expected,
                len: info.len(),
            });
        }
        let mut i = Reader::unchecked(Self::ID, info);
        let event = match code {
            1 => SocketEventKind::Connected {
                remote: socket_addr(&mut i)?,
            },
            2 => SocketEventKind::Accepted {
                child: i.u8()?,
                remote: socket_addr(&mut i)?,
            },
            3 => SocketEventKind::Disconnected,
            4 => SocketEventKind::Failed,
            code => SocketEventKind::Other { code, info },
        };
        Ok(SocketEvent {
            handle,
            status,
            event,
        })
    }

    fn payload_len(&self) -> usize {
        4 + self.event.info_len()
    }

    fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
        let mut w = Writer::new(out);
        w.u8(self.handle)
            .u16(self.status.bits())
            .u8(self.event.code());
        match self.event {
            SocketEventKind::Connected { remote } => {
                w.ipv4(*remote.ip()).u16(remote.port());
            }
            SocketEventKind::Accepted { child, remote } => {
                w.u8(child).ipv4(*remote.ip()).u16(remote.port());
            }
            SocketEventKind::Other { code, info } => {
                if socket_info_len_of(code).is_some() {
                    return Err(EmitError::Invalid(
                        "a socket event of another kind has a code 1-4; use the named event",
                    ));
                }
                w.bytes(info);
            }
            SocketEventKind::Disconnected | SocketEventKind::Failed => {}
        }
        w.finish()
    }
}
