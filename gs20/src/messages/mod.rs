// SPDX-License-Identifier: MIT OR Apache-2.0
//! The frames of the catalogue (reference §1.5) as typed values.
//!
//! Every frame type has a `Repr` here, named after its [`FrameId`] variant, that implements
//! [`Message`]: `parse` from a [`FrameRepr`] (or its data alone), `buffer_len`, `emit` into
//! a buffer and `to_vec`. Payload bytes (IO data, socket data, the host name, event
//! information) are borrowed from the frame, not copied.
//!
//! Parsing checks the *wire*: lengths and values the encoding cannot carry. What the bytes
//! *mean* — whether an item ID is in the catalogue, an IP address is usable, a socket
//! option's data has its size — is checked by methods of the types (`AddItem::validate`,
//! `SetNetworkConfig::validate`, `SocketOption::data_len`), because the reference gives
//! those faults their own error bits (1, 3 and the socket error bits), not the frame error
//! (bit 5). So raw values with no name (an address mode 7, an option 12) parse, into an
//! `Unknown` variant, and emit back unchanged.
//!
//! [`HostMessage`] holds every frame the host sends, [`AdapterMessage`] every frame the
//! module sends, [`AnyMessage`] either.
//!
//! Where the reference contradicts itself or is silent, the choice is written at the type
//! it concerns, citing the section.

use core::fmt;
use std::net::Ipv4Addr;

use crate::frame::{self, Direction, EmitError, FrameId, FrameRepr};

pub mod config;
pub mod data;
pub mod event;
pub mod item;
pub mod network;
pub mod socket;
pub mod status;

pub use config::{
    AddBasket, AddDevice, AddItem, MacAddress, RequestReset, RequestStart, RequestStatus, SetMac,
    SetSerialNumber,
};
pub use data::{AdapterData, SetBusData};
pub use event::{AdapterEvent, Event, NetworkUp};
pub use item::{ItemId, ItemIdError, ItemKind};
pub use network::{AddressMode, NetworkConfigError, SetNetworkConfig};
pub use socket::{
    AdapterSocketData, CloseSocket, OpenSocket, RequestSocketStatus, SendSocketData,
    SetSocketOption, SocketErrors, SocketEvent, SocketEventKind, SocketOption, SocketProtocol,
    SocketResponse, SocketRole, SocketStatus,
};
pub use status::{AdapterResponse, ErrorBits, Mode, Protocol, StatusFlags, StatusWord};

/// Why a frame's data is not the message its ID names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, thiserror::Error)]
pub enum ParseError {
    /// The frame is of another type than the one asked for.
    #[error("expected {expected}, got {received}; parse it as its own type (or as `AnyMessage`)")]
    WrongId {
        /// The type asked for.
        expected: FrameId,
        /// The frame's type.
        received: FrameId,
    },
    /// The frame is sent the other way (a module frame where host frames are parsed, or the
    /// reverse).
    #[error(
        "{id} is a frame the {sender} sends, not the {other}: the two ends are swapped, or a \
         frame is echoed back",
        sender = sender(id.direction()),
        other = sender(other(id.direction()))
    )]
    WrongDirection {
        /// The frame's type.
        id: FrameId,
    },
    /// The data length is not one the type allows.
    #[error("{id} carries {allowed} of data, not {len}; the sender builds the frame wrong", allowed = id.payload_len())]
    Length {
        /// The frame's type.
        id: FrameId,
        /// The data bytes there are.
        len: usize,
    },
    /// A field holds a value its encoding cannot carry.
    #[error(
        "{id}: {field} is {value}, which the protocol does not define; the sender builds the frame wrong"
    )]
    Invalid {
        /// The frame's type.
        id: FrameId,
        /// The field.
        field: &'static str,
        /// Its raw value.
        value: u32,
    },
    /// An event's information does not have the length its code defines.
    #[error(
        "{id}: event code {code} carries {expected} bytes of information, this one {len}; the sender builds the event wrong"
    )]
    InfoLength {
        /// The frame's type.
        id: FrameId,
        /// The event code.
        code: u16,
        /// The bytes the code defines.
        expected: usize,
        /// The bytes there are.
        len: usize,
    },
}

const fn sender(d: Direction) -> &'static str {
    match d {
        Direction::HostToAdapter => "host",
        Direction::AdapterToHost => "module",
    }
}

const fn other(d: Direction) -> Direction {
    match d {
        Direction::HostToAdapter => Direction::AdapterToHost,
        Direction::AdapterToHost => Direction::HostToAdapter,
    }
}

/// A frame type of the catalogue as a typed value.
///
/// Implementors write `parse_payload`, `payload_len` and `emit_payload`; the framing (the
/// header, the LEN width, the CRC) is the provided methods' job, in one place
/// ([`frame::emit_with`]).
pub trait Message<'a>: Sized {
    /// The frame type.
    const ID: FrameId;

    /// Parses the frame's data (never panics: malformed data gives [`ParseError`]).
    fn parse_payload(payload: &'a [u8]) -> Result<Self, ParseError>;

    /// Bytes of the frame's data.
    fn payload_len(&self) -> usize;

    /// Writes the frame's data into `out`, which must be exactly `payload_len()` bytes
    /// (anything else is an [`EmitError`], not a panic).
    fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError>;

    /// Parses a frame of this type.
    fn parse(frame: &FrameRepr<'a>) -> Result<Self, ParseError> {
        if frame.id != Self::ID {
            return Err(ParseError::WrongId {
                expected: Self::ID,
                received: frame.id,
            });
        }
        Self::parse_payload(frame.payload)
    }

    /// Bytes of the whole frame: header, data and CRC.
    fn buffer_len(&self) -> usize {
        Self::ID.len_width().header_len() + self.payload_len() + frame::CRC_LEN
    }

    /// Writes the whole frame at the start of `buf`; returns its length.
    fn emit(&self, buf: &mut [u8]) -> Result<usize, EmitError> {
        frame::emit_with(Self::ID, self.payload_len(), buf, |out| {
            self.emit_payload(out)
        })
    }

    /// The whole frame as a new vector.
    fn to_vec(&self) -> Result<Vec<u8>, EmitError> {
        let mut v = vec![0; self.buffer_len()];
        self.emit(&mut v)?;
        Ok(v)
    }
}

/// Checks that `payload` has a length the frame type allows.
fn check_len(id: FrameId, payload: &[u8]) -> Result<(), ParseError> {
    if id.payload_len().contains(payload.len()) {
        Ok(())
    } else {
        Err(ParseError::Length {
            id,
            len: payload.len(),
        })
    }
}

/// Reads big-endian fields one after the other; running out is [`ParseError::Length`].
struct Reader<'a> {
    id: FrameId,
    len: usize,
    rest: &'a [u8],
}

impl<'a> Reader<'a> {
    /// A reader of a frame's data, after checking its length against the type.
    fn new(id: FrameId, payload: &'a [u8]) -> Result<Reader<'a>, ParseError> {
        check_len(id, payload)?;
        Ok(Reader {
            id,
            len: payload.len(),
            rest: payload,
        })
    }

    /// A reader of bytes whose length was checked otherwise (a part of a frame's data).
    fn unchecked(id: FrameId, bytes: &'a [u8]) -> Reader<'a> {
        Reader {
            id,
            len: bytes.len(),
            rest: bytes,
        }
    }

    fn take<const N: usize>(&mut self) -> Result<[u8; N], ParseError> {
        let Some((head, rest)) = self.rest.split_first_chunk::<N>() else {
            return Err(ParseError::Length {
                id: self.id,
                len: self.len,
            });
        };
        self.rest = rest;
        Ok(*head)
    }

    fn u8(&mut self) -> Result<u8, ParseError> {
        Ok(self.take::<1>()?[0])
    }

    fn u16(&mut self) -> Result<u16, ParseError> {
        self.take().map(u16::from_be_bytes)
    }

    fn u32(&mut self) -> Result<u32, ParseError> {
        self.take().map(u32::from_be_bytes)
    }

    fn ipv4(&mut self) -> Result<Ipv4Addr, ParseError> {
        self.take().map(Ipv4Addr::from)
    }

    /// The bytes left.
    fn rest(self) -> &'a [u8] {
        self.rest
    }

    /// Checks nothing is left (the fixed-size frames).
    fn end(self) -> Result<(), ParseError> {
        if self.rest.is_empty() {
            Ok(())
        } else {
            Err(ParseError::Length {
                id: self.id,
                len: self.len,
            })
        }
    }
}

/// Writes big-endian fields one after the other into exactly the frame's data.
struct Writer<'o> {
    out: &'o mut [u8],
    at: usize,
    overflow: bool,
}

impl<'o> Writer<'o> {
    fn new(out: &'o mut [u8]) -> Writer<'o> {
        Writer {
            out,
            at: 0,
            overflow: false,
        }
    }

    fn bytes(&mut self, b: &[u8]) -> &mut Self {
        match self.out.get_mut(self.at..self.at + b.len()) {
            Some(dst) => {
                dst.copy_from_slice(b);
                self.at += b.len();
            }
            None => self.overflow = true,
        }
        self
    }

    fn u8(&mut self, v: u8) -> &mut Self {
        self.bytes(&[v])
    }

    fn u16(&mut self, v: u16) -> &mut Self {
        self.bytes(&v.to_be_bytes())
    }

    fn u32(&mut self, v: u32) -> &mut Self {
        self.bytes(&v.to_be_bytes())
    }

    fn ipv4(&mut self, v: Ipv4Addr) -> &mut Self {
        self.bytes(&v.octets())
    }

    /// Checks the data was written exactly: no more, no less than the buffer.
    fn finish(&mut self) -> Result<(), EmitError> {
        if self.overflow || self.at != self.out.len() {
            Err(EmitError::BufferTooShort {
                needed: self.at.max(self.out.len() + usize::from(self.overflow)),
                len: self.out.len(),
            })
        } else {
            Ok(())
        }
    }
}

/// Declares an enum over the messages of one direction, with parse/emit dispatched to them.
macro_rules! message_enum {
    (
        $(#[$m:meta])*
        pub enum $name:ident, $dir:ident { $( $(#[$vm:meta])* $var:ident($ty:ty), )+ }
    ) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum $name<'a> {
            $( $(#[$vm])* $var($ty), )+
        }

        impl<'a> $name<'a> {
            /// Parses a frame sent in this direction.
            pub fn parse(frame: &FrameRepr<'a>) -> Result<$name<'a>, ParseError> {
                match frame.id {
                    $( FrameId::$var => {
                        <$ty as Message<'a>>::parse_payload(frame.payload).map($name::$var)
                    } )+
                    id => Err(ParseError::WrongDirection { id }),
                }
            }

            /// The frame type.
            pub const fn id(&self) -> FrameId {
                match self {
                    $( $name::$var(_) => FrameId::$var, )+
                }
            }

            /// Bytes of the whole frame.
            pub fn buffer_len(&self) -> usize {
                match self {
                    $( $name::$var(m) => m.buffer_len(), )+
                }
            }

            /// Writes the whole frame at the start of `buf`; returns its length.
            pub fn emit(&self, buf: &mut [u8]) -> Result<usize, EmitError> {
                match self {
                    $( $name::$var(m) => m.emit(buf), )+
                }
            }

            /// The whole frame as a new vector.
            pub fn to_vec(&self) -> Result<Vec<u8>, EmitError> {
                match self {
                    $( $name::$var(m) => m.to_vec(), )+
                }
            }
        }

        $(
            impl<'a> From<$ty> for $name<'a> {
                fn from(m: $ty) -> $name<'a> {
                    $name::$var(m)
                }
            }
        )+

        impl fmt::Display for $name<'_> {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                self.id().fmt(f)
            }
        }

        // Every variant is of this direction, and every frame type of it has a variant.
        const _: () = {
            $( assert!(matches!(FrameId::$var.direction(), Direction::$dir)); )+
        };
    };
}

message_enum! {
    /// A frame the host sends to the module.
    pub enum HostMessage, HostToAdapter {
        /// 0x01.
        AddBasket(AddBasket),
        /// 0x02.
        AddDevice(AddDevice),
        /// 0x03.
        AddItem(AddItem),
        /// 0x10.
        SetNetworkConfig(SetNetworkConfig<'a>),
        /// 0x11.
        SetMac(SetMac),
        /// 0x12.
        SetSerialNumber(SetSerialNumber),
        /// 0x20.
        RequestStatus(RequestStatus),
        /// 0x21.
        RequestReset(RequestReset),
        /// 0x22.
        RequestStart(RequestStart),
        /// 0x30.
        SetBusData(SetBusData<'a>),
        /// 0x40.
        OpenSocket(OpenSocket),
        /// 0x41.
        SetSocketOption(SetSocketOption<'a>),
        /// 0x42.
        RequestSocketStatus(RequestSocketStatus),
        /// 0x43.
        CloseSocket(CloseSocket),
        /// 0x50.
        SendSocketData(SendSocketData<'a>),
    }
}

message_enum! {
    /// A frame the module sends to the host.
    pub enum AdapterMessage, AdapterToHost {
        /// 0x31.
        AdapterData(AdapterData<'a>),
        /// 0x51.
        AdapterSocketData(AdapterSocketData<'a>),
        /// 0xE0.
        SocketResponse(SocketResponse),
        /// 0xE1.
        SocketEvent(SocketEvent<'a>),
        /// 0xF0.
        AdapterResponse(AdapterResponse),
        /// 0xF1.
        AdapterEvent(AdapterEvent<'a>),
    }
}

/// A frame of either direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnyMessage<'a> {
    /// Sent by the host.
    Host(HostMessage<'a>),
    /// Sent by the module.
    Adapter(AdapterMessage<'a>),
}

impl<'a> AnyMessage<'a> {
    /// Parses any frame of the catalogue.
    pub fn parse(frame: &FrameRepr<'a>) -> Result<AnyMessage<'a>, ParseError> {
        match frame.id.direction() {
            Direction::HostToAdapter => HostMessage::parse(frame).map(AnyMessage::Host),
            Direction::AdapterToHost => AdapterMessage::parse(frame).map(AnyMessage::Adapter),
        }
    }

    /// The frame type.
    pub const fn id(&self) -> FrameId {
        match self {
            AnyMessage::Host(m) => m.id(),
            AnyMessage::Adapter(m) => m.id(),
        }
    }

    /// The whole frame as a new vector.
    pub fn to_vec(&self) -> Result<Vec<u8>, EmitError> {
        match self {
            AnyMessage::Host(m) => m.to_vec(),
            AnyMessage::Adapter(m) => m.to_vec(),
        }
    }
}

// The two directions together cover the catalogue.
const _: () = assert!(FrameId::ALL.len() == 15 + 6);

#[cfg(test)]
mod tests;
