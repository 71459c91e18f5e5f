// SPDX-License-Identifier: MIT OR Apache-2.0
//! The frame of the host link: `ID | LEN | DATA | CRC` (reference §1.4).
//!
//! - `ID` is one byte and decides the rest: which of the two LEN widths the frame has and
//!   how much data it may carry ([`FrameId`]).
//! - `LEN` counts the data bytes. It is one byte, except in the frames that carry IO or
//!   socket data (0x30, 0x31, 0x50, 0x51, 0xE1), where it is two bytes and the data starts
//!   at index 3. The reference does not give the byte order of the two-byte LEN; every other
//!   multi-byte field of the protocol is big-endian, so this one is big-endian too.
//! - `CRC` is CRC-16/Modbus (reflected polynomial 0xA001, initial value 0xFFFF) over ID, LEN
//!   and DATA, sent low byte first — the one little-endian field of the protocol, as Modbus
//!   RTU sends its CRC.
//!
//! [`Frame`] is the checked view over the bytes, [`FrameRepr`] the frame as a value. The
//! contract is the smoltcp one: once [`Frame::check_len`] has returned `Ok`, no getter
//! panics; [`FrameRepr::parse`] never panics on any input; [`FrameRepr::emit`] never panics
//! and reports a short buffer or a LEN the frame's type cannot carry as [`EmitError`].

use core::fmt;

/// The most IO data one direction carries: 384 bytes (reference §1.1).
pub const MAX_IO_DATA: usize = 384;

/// The most data one socket frame (0x50, 0x51) carries.
///
/// The reference is silent (it names only "too much socket data", socket error bit 4).
/// Chosen: 1472 bytes, the largest UDP payload an Ethernet frame of 1500 bytes carries
/// unfragmented, so that one datagram is one frame and a TCP segment of the usual MSS (1460)
/// fits too.
pub const MAX_SOCKET_DATA: usize = 1472;

/// The most event information one Socket Event (0xE1) carries.
///
/// The reference is silent (its socket event table is missing). Chosen: 255 bytes, what a
/// one-byte LEN would allow; the events this crate defines carry at most 7
/// ([`crate::messages::socket`]).
pub const MAX_SOCKET_EVENT_INFO: usize = 255;

/// Bytes of the CRC at the end of every frame.
pub const CRC_LEN: usize = 2;

/// The longest frame of the protocol (a Send or Adapter Socket Data frame with
/// [`MAX_SOCKET_DATA`] bytes); the stream decoder never buffers more.
pub const MAX_FRAME_LEN: usize = LenWidth::Two.header_len() + 1 + MAX_SOCKET_DATA + CRC_LEN;

/// CRC-16/Modbus, from the `crc` crate's catalogue.
const MODBUS: crc::Crc<u16> = crc::Crc::<u16>::new(&crc::CRC_16_MODBUS);

/// The CRC-16/Modbus of `bytes` (for a frame: over ID, LEN and DATA).
pub fn crc16(bytes: &[u8]) -> u16 {
    MODBUS.checksum(bytes)
}

/// The width of a frame's LEN field.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LenWidth {
    /// One byte: DATA starts at index 2.
    One,
    /// Two bytes, big-endian: DATA starts at index 3.
    Two,
}

impl LenWidth {
    /// Bytes of the LEN field.
    pub const fn bytes(self) -> usize {
        match self {
            LenWidth::One => 1,
            LenWidth::Two => 2,
        }
    }

    /// Bytes before DATA: the ID and the LEN field.
    pub const fn header_len(self) -> usize {
        1 + self.bytes()
    }
}

/// Who sends a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Direction {
    /// The host microcontroller sends it to the module (a request or the host's data).
    HostToAdapter,
    /// The module (the adapter) sends it to the host (a response, an event or data).
    AdapterToHost,
}

/// The data lengths a frame type allows: `min..=max` bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LenRange {
    /// The fewest data bytes.
    pub min: usize,
    /// The most data bytes.
    pub max: usize,
}

impl LenRange {
    const fn exactly(n: usize) -> LenRange {
        LenRange { min: n, max: n }
    }

    const fn between(min: usize, max: usize) -> LenRange {
        LenRange { min, max }
    }

    /// Whether `len` data bytes are allowed.
    pub const fn contains(self, len: usize) -> bool {
        self.min <= len && len <= self.max
    }
}

impl fmt::Display for LenRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.min == self.max {
            write!(f, "exactly {} bytes", self.min)
        } else {
            write!(f, "{} to {} bytes", self.min, self.max)
        }
    }
}

/// The frame types of the catalogue (reference §1.5), by their ID byte.
///
/// A closed enum: an ID outside the catalogue has no known LEN width, so there is no frame
/// to speak of; parsing reports it as [`FrameError::UnknownId`] with the raw byte.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum FrameId {
    /// 0x01, host: select a basket stored in the module.
    AddBasket = 0x01,
    /// 0x02, host: the device ID.
    AddDevice = 0x02,
    /// 0x03, host: one item at one slot.
    AddItem = 0x03,
    /// 0x10, host: address mode, IP settings and host name.
    SetNetworkConfig = 0x10,
    /// 0x11, host: the MAC address.
    SetMac = 0x11,
    /// 0x12, host: the serial number.
    SetSerialNumber = 0x12,
    /// 0x20, host: Standby → Config, or the status in any mode.
    RequestStatus = 0x20,
    /// 0x21, host: reset the module.
    RequestReset = 0x21,
    /// 0x22, host: Config → Pending → Run.
    RequestStart = 0x22,
    /// 0x30, host: the host's IO data (PROFINET input data of the items).
    SetBusData = 0x30,
    /// 0x31, adapter: the PLC's IO data (PROFINET output data of the items).
    AdapterData = 0x31,
    /// 0x40, host: open a TCP or UDP socket.
    OpenSocket = 0x40,
    /// 0x41, host: set an option of a socket.
    SetSocketOption = 0x41,
    /// 0x42, host: ask for a socket's status.
    RequestSocketStatus = 0x42,
    /// 0x43, host: close a socket.
    CloseSocket = 0x43,
    /// 0x50, host: data to send on a socket.
    SendSocketData = 0x50,
    /// 0x51, adapter: data a socket received.
    AdapterSocketData = 0x51,
    /// 0xE0, adapter: the answer to a socket request.
    SocketResponse = 0xE0,
    /// 0xE1, adapter: something happened on a socket.
    SocketEvent = 0xE1,
    /// 0xF0, adapter: the answer to every Config command and to Request Status.
    AdapterResponse = 0xF0,
    /// 0xF1, adapter: link, network and PLC events.
    AdapterEvent = 0xF1,
}

impl FrameId {
    /// Every frame type, in ID order.
    pub const ALL: [FrameId; 21] = [
        FrameId::AddBasket,
        FrameId::AddDevice,
        FrameId::AddItem,
        FrameId::SetNetworkConfig,
        FrameId::SetMac,
        FrameId::SetSerialNumber,
        FrameId::RequestStatus,
        FrameId::RequestReset,
        FrameId::RequestStart,
        FrameId::SetBusData,
        FrameId::AdapterData,
        FrameId::OpenSocket,
        FrameId::SetSocketOption,
        FrameId::RequestSocketStatus,
        FrameId::CloseSocket,
        FrameId::SendSocketData,
        FrameId::AdapterSocketData,
        FrameId::SocketResponse,
        FrameId::SocketEvent,
        FrameId::AdapterResponse,
        FrameId::AdapterEvent,
    ];

    /// The frame type of an ID byte; `None` outside the catalogue.
    pub const fn from_u8(id: u8) -> Option<FrameId> {
        Some(match id {
            0x01 => FrameId::AddBasket,
            0x02 => FrameId::AddDevice,
            0x03 => FrameId::AddItem,
            0x10 => FrameId::SetNetworkConfig,
            0x11 => FrameId::SetMac,
            0x12 => FrameId::SetSerialNumber,
            0x20 => FrameId::RequestStatus,
            0x21 => FrameId::RequestReset,
            0x22 => FrameId::RequestStart,
            0x30 => FrameId::SetBusData,
            0x31 => FrameId::AdapterData,
            0x40 => FrameId::OpenSocket,
            0x41 => FrameId::SetSocketOption,
            0x42 => FrameId::RequestSocketStatus,
            0x43 => FrameId::CloseSocket,
            0x50 => FrameId::SendSocketData,
            0x51 => FrameId::AdapterSocketData,
            0xE0 => FrameId::SocketResponse,
            0xE1 => FrameId::SocketEvent,
            0xF0 => FrameId::AdapterResponse,
            0xF1 => FrameId::AdapterEvent,
            _ => return None,
        })
    }

    /// The ID byte.
    pub const fn as_u8(self) -> u8 {
        self as u8
    }

    /// The LEN width: two bytes for 0x30, 0x31, 0x50, 0x51 and 0xE1 (reference §1.4), one
    /// byte for the rest.
    pub const fn len_width(self) -> LenWidth {
        match self {
            FrameId::SetBusData
            | FrameId::AdapterData
            | FrameId::SendSocketData
            | FrameId::AdapterSocketData
            | FrameId::SocketEvent => LenWidth::Two,
            _ => LenWidth::One,
        }
    }

    /// Who sends frames of this type.
    pub const fn direction(self) -> Direction {
        match self {
            FrameId::AdapterData
            | FrameId::AdapterSocketData
            | FrameId::SocketResponse
            | FrameId::SocketEvent
            | FrameId::AdapterResponse
            | FrameId::AdapterEvent => Direction::AdapterToHost,
            _ => Direction::HostToAdapter,
        }
    }

    /// The data lengths the type allows (reference §1.5); a LEN outside them is a frame
    /// error (error bit 5, "LEN does not fit the type" or "frame too large").
    ///
    /// The fixed-size frames allow their one length. For the variable ones:
    /// - Set Network Configuration: 21 bytes of addresses and a host name of N bytes. The
    ///   frame allows N up to what a one-byte LEN holds: a host name of 0 or more than 63
    ///   bytes is a *network configuration* error (error bit 3, reference §1.6), which
    ///   [`crate::messages::network`] reports, not a framing one.
    /// - Set Socket Option and Adapter Event: their fixed part, then up to a one-byte LEN.
    /// - Set Bus Data and Adapter Data: 0 to [`MAX_IO_DATA`] bytes (0 for a station without
    ///   inputs or without outputs); more is "frame too large".
    /// - Send and Adapter Socket Data: the handle and up to [`MAX_SOCKET_DATA`] bytes.
    /// - Socket Event: 4 bytes and up to [`MAX_SOCKET_EVENT_INFO`] bytes of information.
    pub const fn payload_len(self) -> LenRange {
        match self {
            FrameId::AddBasket | FrameId::AddDevice => LenRange::exactly(2),
            FrameId::AddItem | FrameId::SetMac | FrameId::AdapterResponse => LenRange::exactly(6),
            FrameId::SetNetworkConfig => LenRange::between(21, u8::MAX as usize),
            FrameId::SetSerialNumber => LenRange::exactly(4),
            FrameId::RequestStatus | FrameId::RequestReset | FrameId::RequestStart => {
                LenRange::exactly(0)
            }
            FrameId::SetBusData | FrameId::AdapterData => LenRange::between(0, MAX_IO_DATA),
            FrameId::OpenSocket => LenRange::exactly(8),
            FrameId::SetSocketOption => LenRange::between(2, u8::MAX as usize),
            FrameId::RequestSocketStatus | FrameId::CloseSocket => LenRange::exactly(1),
            FrameId::SendSocketData | FrameId::AdapterSocketData => {
                LenRange::between(1, 1 + MAX_SOCKET_DATA)
            }
            FrameId::SocketResponse => LenRange::exactly(5),
            FrameId::SocketEvent => LenRange::between(4, 4 + MAX_SOCKET_EVENT_INFO),
            FrameId::AdapterEvent => LenRange::between(3, u8::MAX as usize),
        }
    }

    /// The name the reference gives the frame.
    pub const fn name(self) -> &'static str {
        match self {
            FrameId::AddBasket => "Add Basket",
            FrameId::AddDevice => "Add Device",
            FrameId::AddItem => "Add Item",
            FrameId::SetNetworkConfig => "Set Network Configuration",
            FrameId::SetMac => "Set MAC",
            FrameId::SetSerialNumber => "Set Serial Number",
            FrameId::RequestStatus => "Request Status",
            FrameId::RequestReset => "Request Reset",
            FrameId::RequestStart => "Request Start",
            FrameId::SetBusData => "Set Bus Data",
            FrameId::AdapterData => "Adapter Data",
            FrameId::OpenSocket => "Open Socket",
            FrameId::SetSocketOption => "Set Socket Option",
            FrameId::RequestSocketStatus => "Request Socket Status",
            FrameId::CloseSocket => "Close Socket",
            FrameId::SendSocketData => "Send Socket Data",
            FrameId::AdapterSocketData => "Adapter Socket Data",
            FrameId::SocketResponse => "Socket Response",
            FrameId::SocketEvent => "Socket Event",
            FrameId::AdapterResponse => "Adapter Response",
            FrameId::AdapterEvent => "Adapter Event",
        }
    }
}

impl fmt::Display for FrameId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} (0x{:02X})", self.name(), self.as_u8())
    }
}

impl TryFrom<u8> for FrameId {
    type Error = FrameError;

    fn try_from(id: u8) -> Result<FrameId, FrameError> {
        FrameId::from_u8(id).ok_or(FrameError::UnknownId(id))
    }
}

impl From<FrameId> for u8 {
    fn from(id: FrameId) -> u8 {
        id.as_u8()
    }
}

/// Why bytes are not a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, thiserror::Error)]
pub enum FrameError {
    /// Fewer bytes than the header or the LEN asks for.
    #[error(
        "the frame is cut short: it needs {needed} bytes and {len} are there; pass the whole \
         frame (the stream decoder waits for the rest)"
    )]
    Truncated {
        /// Bytes the frame needs (so far as its header tells).
        needed: usize,
        /// Bytes there are.
        len: usize,
    },
    /// The first byte is no ID of the catalogue.
    #[error(
        "0x{0:02X} is not a frame ID of the GS20-PN host protocol: the sender uses a frame the \
         module does not know, or the byte is not the start of a frame"
    )]
    UnknownId(u8),
    /// The LEN is not one the frame type allows.
    #[error(
        "{id} carries {allowed} of data, its LEN says {len}: the sender builds the frame \
         wrong, or the byte is not the start of a frame",
        allowed = id.payload_len()
    )]
    BadLen {
        /// The frame type.
        id: FrameId,
        /// The LEN field.
        len: usize,
    },
    /// The CRC does not match the bytes.
    #[error(
        "{id} has a CRC error (computed 0x{computed:04X}, received 0x{received:04X}): bytes were \
         damaged on the line; check baud rate, parity (115200 8E1), wiring and ground"
    )]
    Crc {
        /// The frame type.
        id: FrameId,
        /// The CRC of the bytes received.
        computed: u16,
        /// The CRC field.
        received: u16,
    },
}

/// Why a frame could not be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, thiserror::Error)]
pub enum EmitError {
    /// The buffer is shorter than the frame.
    #[error("the buffer holds {len} bytes, the frame needs {needed}; pass `buffer_len()` bytes")]
    BufferTooShort {
        /// Bytes the frame needs.
        needed: usize,
        /// Bytes the buffer has.
        len: usize,
    },
    /// The data does not fit the frame type.
    #[error(
        "{id} carries {allowed} of data, not {len}; shorten the data (or split it over \
         several frames)",
        allowed = id.payload_len()
    )]
    BadLen {
        /// The frame type.
        id: FrameId,
        /// The data bytes there were to be.
        len: usize,
    },
    /// A message's fields contradict each other, so there is no encoding to write.
    #[error("{0}")]
    Invalid(&'static str),
}

mod field {
    /// The ID byte.
    pub const ID: usize = 0;
    /// The LEN field starts here, whatever its width.
    pub const LEN: usize = 1;
}

/// A checked view of a frame at the start of a buffer (bytes after the frame are ignored).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Frame<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Frame<T> {
    /// Wraps a buffer without checking it.
    pub const fn new_unchecked(buffer: T) -> Frame<T> {
        Frame { buffer }
    }

    /// Wraps a buffer after [`check_len`](Self::check_len).
    pub fn new_checked(buffer: T) -> Result<Frame<T>, FrameError> {
        let frame = Frame::new_unchecked(buffer);
        frame.check_len()?;
        Ok(frame)
    }

    /// The buffer.
    pub fn into_inner(self) -> T {
        self.buffer
    }

    /// Checks that the buffer starts with a frame of a known type and holds all of it, as
    /// its LEN says (whether that LEN is one the type allows is [`FrameRepr::parse`]'s check).
    pub fn check_len(&self) -> Result<(), FrameError> {
        let b = self.buffer.as_ref();
        let Some(&raw) = b.get(field::ID) else {
            return Err(FrameError::Truncated {
                needed: LenWidth::One.header_len(),
                len: 0,
            });
        };
        let id = FrameId::try_from(raw)?;
        let header = id.len_width().header_len();
        if b.len() < header {
            return Err(FrameError::Truncated {
                needed: header,
                len: b.len(),
            });
        }
        let needed = self.frame_len();
        if b.len() < needed {
            return Err(FrameError::Truncated {
                needed,
                len: b.len(),
            });
        }
        Ok(())
    }

    /// The ID byte, known or not; 0 on an empty buffer.
    pub fn raw_id(&self) -> u8 {
        self.buffer.as_ref().first().copied().unwrap_or(0)
    }

    /// The frame type; `None` for an ID outside the catalogue.
    pub fn id(&self) -> Option<FrameId> {
        FrameId::from_u8(self.raw_id())
    }

    /// The LEN width (one byte for an unknown ID, where there is none to speak of).
    pub fn len_width(&self) -> LenWidth {
        self.id().map_or(LenWidth::One, FrameId::len_width)
    }

    /// Bytes before DATA.
    pub fn header_len(&self) -> usize {
        self.len_width().header_len()
    }

    /// The LEN field: the number of data bytes. 0 where the buffer ends inside the field.
    pub fn payload_len(&self) -> usize {
        let b = self.buffer.as_ref();
        match self.len_width() {
            LenWidth::One => b.get(field::LEN).map_or(0, |&n| usize::from(n)),
            LenWidth::Two => b
                .get(field::LEN..field::LEN + 2)
                .map_or(0, |n| usize::from(u16::from_be_bytes([n[0], n[1]]))),
        }
    }

    /// Bytes of the whole frame as its header tells: header, data and CRC.
    pub fn frame_len(&self) -> usize {
        self.header_len() + self.payload_len() + CRC_LEN
    }

    /// The CRC field (sent low byte first).
    pub fn crc(&self) -> u16 {
        let at = self.header_len() + self.payload_len();
        let b = self.buffer.as_ref();
        u16::from_le_bytes([b[at], b[at + 1]])
    }

    /// The CRC of the bytes the CRC covers: ID, LEN and DATA.
    pub fn computed_crc(&self) -> u16 {
        let end = self.header_len() + self.payload_len();
        crc16(&self.buffer.as_ref()[..end])
    }
}

impl<'a, T: AsRef<[u8]> + ?Sized> Frame<&'a T> {
    /// The DATA bytes.
    pub fn payload(&self) -> &'a [u8] {
        let at = self.header_len();
        &self.buffer.as_ref()[at..at + self.payload_len()]
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Frame<T> {
    /// Writes the ID byte. Write it first: the LEN width depends on it.
    pub fn set_id(&mut self, id: FrameId) {
        self.buffer.as_mut()[field::ID] = id.as_u8();
    }

    /// Writes the LEN field in the width the ID has (a value over the width is cut: emit
    /// through [`FrameRepr::emit`], which checks it first).
    pub fn set_payload_len(&mut self, len: usize) {
        let width = self.len_width();
        let b = self.buffer.as_mut();
        match width {
            LenWidth::One => b[field::LEN] = len as u8,
            LenWidth::Two => {
                b[field::LEN..field::LEN + 2].copy_from_slice(&(len as u16).to_be_bytes())
            }
        }
    }

    /// The DATA bytes, to write.
    pub fn payload_mut(&mut self) -> &mut [u8] {
        let at = self.header_len();
        let len = self.payload_len();
        &mut self.buffer.as_mut()[at..at + len]
    }

    /// Computes the CRC of ID, LEN and DATA and writes it, low byte first.
    pub fn fill_crc(&mut self) {
        let at = self.header_len() + self.payload_len();
        let crc = self.computed_crc();
        self.buffer.as_mut()[at..at + CRC_LEN].copy_from_slice(&crc.to_le_bytes());
    }
}

/// A frame as a value: its type and its data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FrameRepr<'a> {
    /// The frame type.
    pub id: FrameId,
    /// The DATA bytes.
    pub payload: &'a [u8],
}

impl<'a> FrameRepr<'a> {
    /// Parses a frame: a known ID, a LEN the type allows, all bytes there and a good CRC.
    pub fn parse<T: AsRef<[u8]> + ?Sized>(
        frame: &Frame<&'a T>,
    ) -> Result<FrameRepr<'a>, FrameError> {
        frame.check_len()?;
        let raw = frame.raw_id();
        let id = FrameId::try_from(raw)?;
        let len = frame.payload_len();
        if !id.payload_len().contains(len) {
            return Err(FrameError::BadLen { id, len });
        }
        let (computed, received) = (frame.computed_crc(), frame.crc());
        if computed != received {
            return Err(FrameError::Crc {
                id,
                computed,
                received,
            });
        }
        Ok(FrameRepr {
            id,
            payload: frame.payload(),
        })
    }

    /// Parses the frame at the start of `bytes` (bytes after it are ignored; see
    /// [`Self::buffer_len`]).
    pub fn parse_bytes(bytes: &'a [u8]) -> Result<FrameRepr<'a>, FrameError> {
        FrameRepr::parse(&Frame::new_unchecked(bytes))
    }

    /// Bytes of the frame: header, data and CRC.
    pub const fn buffer_len(&self) -> usize {
        self.id.len_width().header_len() + self.payload.len() + CRC_LEN
    }

    /// Writes the frame at the start of `buf`; returns its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, EmitError> {
        emit_with(self.id, self.payload.len(), buf, |out| {
            out.copy_from_slice(self.payload);
            Ok(())
        })
    }

    /// The frame as a new vector.
    pub fn to_vec(&self) -> Result<Vec<u8>, EmitError> {
        let mut v = vec![0; self.buffer_len()];
        self.emit(&mut v)?;
        Ok(v)
    }
}

impl fmt::Display for FrameRepr<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}, {} data bytes", self.id, self.payload.len())
    }
}

/// Writes a frame of type `id` with `payload_len` data bytes at the start of `buf`: the
/// header, then `fill` writes the data (it gets exactly `payload_len` bytes), then the CRC.
/// Returns the frame's length. The one place frames are put together, so that a message
/// writes its data in place without a copy.
pub fn emit_with(
    id: FrameId,
    payload_len: usize,
    buf: &mut [u8],
    fill: impl FnOnce(&mut [u8]) -> Result<(), EmitError>,
) -> Result<usize, EmitError> {
    if !id.payload_len().contains(payload_len) {
        return Err(EmitError::BadLen {
            id,
            len: payload_len,
        });
    }
    let needed = id.len_width().header_len() + payload_len + CRC_LEN;
    let Some(buf) = buf.get_mut(..needed) else {
        return Err(EmitError::BufferTooShort {
            needed,
            len: buf.len(),
        });
    };
    let mut frame = Frame::new_unchecked(buf);
    frame.set_id(id);
    frame.set_payload_len(payload_len);
    fill(frame.payload_mut())?;
    frame.fill_crc();
    Ok(needed)
}

#[cfg(test)]
pub(crate) mod tests;
