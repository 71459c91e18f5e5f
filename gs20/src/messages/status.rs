// SPDX-License-Identifier: MIT OR Apache-2.0
//! The module's modes, its status word and error bits (reference §1.3, §1.6), and the
//! Adapter Response (0xF0) that carries them.

use core::fmt;

use bitflags::bitflags;

use super::{Message, ParseError, Reader, Writer};
use crate::frame::{EmitError, FrameId};

/// The module's mode (reference §1.3): status bits 1–2 and the first byte of an Adapter
/// Event.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Mode {
    /// After power-up or reset, until Request Status.
    Standby = 0,
    /// Defining the station: strict command and response.
    Config = 1,
    /// After Request Start: applying the configuration, waiting for DHCP.
    Pending = 2,
    /// Exchanging data, events and sockets.
    Run = 3,
}

impl Mode {
    /// The mode of a two-bit value (0–3); `None` above.
    pub const fn from_u8(v: u8) -> Option<Mode> {
        Some(match v {
            0 => Mode::Standby,
            1 => Mode::Config,
            2 => Mode::Pending,
            3 => Mode::Run,
            _ => return None,
        })
    }

    /// The value, 0–3.
    pub const fn as_u8(self) -> u8 {
        self as u8
    }
}

impl fmt::Display for Mode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Mode::Standby => "Standby",
            Mode::Config => "Config",
            Mode::Pending => "Pending",
            Mode::Run => "Run",
        })
    }
}

bitflags! {
    /// The flags of the status word (reference §1.6), that is every bit but the mode
    /// (bits 1–2, see [`StatusWord`]).
    ///
    /// Bits 9–15 are reserved: parsing keeps them (so a frame emits back as it came), the
    /// module sends them as 0.
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
    pub struct StatusFlags: u16 {
        /// Bit 0. The table names it "checksum error", but the reference's own example
        /// (§1.4: `F0 06 00 03 00 04 …`, error "no network configuration" without any CRC
        /// fault) sets it with any error bit. Chosen: a summary "an error bit is set" flag,
        /// which [`AdapterResponse::new`] derives from the error bits.
        const ERROR = 1 << 0;
        /// Bit 3: the Ethernet link state is known.
        const LINK_KNOWN = 1 << 3;
        /// Bit 4: the Ethernet link is up.
        const LINK_UP = 1 << 4;
        /// Bit 5: the module has its IP address.
        const IP_OK = 1 << 5;
        /// Bit 6: the network is OK.
        const NETWORK_OK = 1 << 6;
        /// Bit 7: a PLC is connected (an AR is in data exchange).
        const PLC_CONNECTED = 1 << 7;
        /// Bit 8: the IO data is little-endian (0: big-endian).
        const LITTLE_ENDIAN = 1 << 8;
    }
}

/// The status word: the mode and the flags.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct StatusWord {
    /// Bits 1–2.
    pub mode: Mode,
    /// Every other bit. Bits 1–2 of `flags` are not written: the mode is `mode`.
    pub flags: StatusFlags,
}

impl StatusWord {
    /// Bits 1–2.
    pub const MODE_MASK: u16 = 0b110;

    /// The status word of a raw value.
    pub const fn from_u16(v: u16) -> StatusWord {
        let mode = match Mode::from_u8(((v & Self::MODE_MASK) >> 1) as u8) {
            Some(m) => m,
            // Two bits are always a mode.
            None => Mode::Standby,
        };
        StatusWord {
            mode,
            flags: StatusFlags::from_bits_retain(v & !Self::MODE_MASK),
        }
    }

    /// The raw value.
    pub const fn to_u16(self) -> u16 {
        (self.flags.bits() & !Self::MODE_MASK) | ((self.mode as u16) << 1)
    }
}

bitflags! {
    /// The error bits of the Adapter Response (reference §1.6). Bits 9–15 are not defined:
    /// parsing keeps them, the module sends them as 0.
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
    pub struct ErrorBits: u16 {
        /// Bit 0: no device or no item added.
        const INCOMPLETE_CONFIG = 1 << 0;
        /// Bit 1: a device, item or basket could not be added (invalid, too many, empty
        /// basket).
        const ADD_ERROR = 1 << 1;
        /// Bit 2: no network configuration received.
        const NO_NETWORK_CONFIG = 1 << 2;
        /// Bit 3: the network configuration is invalid (address mode, IP, gateway, DNS,
        /// host name).
        const NETWORK_CONFIG_INVALID = 1 << 3;
        /// Bit 4: a frame had a CRC error.
        const CRC = 1 << 4;
        /// Bit 5: a frame error: unknown ID, wrong mode, sockets unsupported, LEN does not
        /// fit the type, frame too large.
        const FRAME = 1 << 5;
        /// Bit 6: Request Start was refused.
        const START_REFUSED = 1 << 6;
        /// Bit 7: the host's IO data size does not match the configured one.
        const IO_SIZE_MISMATCH = 1 << 7;
        /// Bit 8: basket and device/item mixed.
        const LOCKOUT = 1 << 8;
    }
}

impl ErrorBits {
    /// What each defined bit means, for logs and error messages.
    pub const DESCRIPTIONS: [(ErrorBits, &'static str); 9] = [
        (ErrorBits::INCOMPLETE_CONFIG, "incomplete configuration"),
        (ErrorBits::ADD_ERROR, "device/item/basket add error"),
        (ErrorBits::NO_NETWORK_CONFIG, "no network configuration"),
        (
            ErrorBits::NETWORK_CONFIG_INVALID,
            "network configuration invalid",
        ),
        (ErrorBits::CRC, "frame CRC error"),
        (ErrorBits::FRAME, "frame error"),
        (ErrorBits::START_REFUSED, "start refused"),
        (ErrorBits::IO_SIZE_MISMATCH, "IO data size mismatch"),
        (ErrorBits::LOCKOUT, "lockout (basket vs device/item)"),
    ];
}

impl fmt::Display for ErrorBits {
    /// The meanings of the bits set, separated by commas; "none" for none.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_empty() {
            return f.write_str("none");
        }
        let mut sep = "";
        for (bit, text) in ErrorBits::DESCRIPTIONS {
            if self.contains(bit) {
                write!(f, "{sep}{text}")?;
                sep = ", ";
            }
        }
        let undefined = self.bits() & !ErrorBits::all().bits();
        if undefined != 0 {
            write!(f, "{sep}undefined bits 0x{undefined:04X}")?;
        }
        Ok(())
    }
}

coded_enum! {
    /// The protocol of the module (reference §1.5, Adapter Response byte 6).
    pub enum Protocol(u8) display "unknown value {}" {
        /// 1.
        Profibus = 1 => "PROFIBUS",
        /// 2: the GS20-PN.
        Profinet = 2 => "PROFINET",
        /// 3.
        EtherNetIp = 3 => "EtherNet/IP",
        /// 4.
        ModbusTcp = 4 => "Modbus/TCP",
    }
}

/// Adapter Response (0xF0, module → host, LEN 6): the answer to every Config command and to
/// Request Status.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AdapterResponse {
    /// Bytes 2–3.
    pub status: StatusWord,
    /// Bytes 4–5.
    pub errors: ErrorBits,
    /// Byte 6.
    pub protocol: Protocol,
    /// Byte 7. The reference's example sends 1; it does not say of what. Chosen: the
    /// protocol version, 1 ([`AdapterResponse::VERSION`]).
    pub version: u8,
}

impl AdapterResponse {
    /// The version byte of the reference's example.
    pub const VERSION: u8 = 1;

    /// A PROFINET module's response in `mode` with `flags` and `errors`; the status word's
    /// error flag (bit 0) is set exactly when an error bit is.
    pub fn new(mode: Mode, flags: StatusFlags, errors: ErrorBits) -> AdapterResponse {
        let mut flags = flags;
        flags.set(StatusFlags::ERROR, !errors.is_empty());
        AdapterResponse {
            status: StatusWord { mode, flags },
            errors,
            protocol: Protocol::Profinet,
            version: AdapterResponse::VERSION,
        }
    }
}

impl<'a> Message<'a> for AdapterResponse {
    const ID: FrameId = FrameId::AdapterResponse;

    fn parse_payload(payload: &'a [u8]) -> Result<AdapterResponse, ParseError> {
        let mut r = Reader::new(Self::ID, payload)?;
        let status = StatusWord::from_u16(r.u16()?);
        let errors = ErrorBits::from_bits_retain(r.u16()?);
        let protocol = Protocol::from_raw(r.u8()?);
        let version = r.u8()?;
        r.end()?;
        Ok(AdapterResponse {
            status,
            errors,
            protocol,
            version,
        })
    }

    fn payload_len(&self) -> usize {
        6
    }

    fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
        Writer::new(out)
            .u16(self.status.to_u16())
            .u16(self.errors.bits())
            .u8(self.protocol.raw())
            .u8(self.version)
            .finish()
    }
}
