// SPDX-License-Identifier: MIT OR Apache-2.0
//! Adapter Event (0xF1): link, network and PLC events the module sends unsolicited in Run
//! (reference §1.5, the event table in §1.6).

use std::net::Ipv4Addr;

use super::network::AddressMode;
use super::status::Mode;
use super::{Message, ParseError, Reader, Writer};
use crate::frame::{EmitError, FrameId};

/// The information of the Network Up event (17 bytes): how the module got its address, and
/// the address.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct NetworkUp {
    /// Static or DHCP.
    pub mode: AddressMode,
    /// The IP address.
    pub ip: Ipv4Addr,
    /// The subnet mask.
    pub mask: Ipv4Addr,
    /// The gateway.
    pub gateway: Ipv4Addr,
    /// The DNS server.
    pub dns: Ipv4Addr,
}

/// An event and its information.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Event<'a> {
    /// 1: the Ethernet link came up (no information).
    LinkUp,
    /// 2: the Ethernet link went down.
    LinkDown,
    /// 3: the network is up, with the IP settings.
    NetworkUp(NetworkUp),
    /// 4: a PLC connected (an AR reached data exchange).
    PlcConnected,
    /// 5: the PLC stopped responding.
    PlcLost,
    /// 6: the PLC commanded an adapter reset, of type 0 or 1 (the reference does not say
    /// what the types mean; any byte is kept).
    PlcReset {
        /// The reset type.
        reset_type: u8,
    },
    /// 0 or above 6: reserved codes, their information kept as it came. Emitting one with a
    /// code 1–6 is an error: those are the named variants.
    Reserved {
        /// The event code.
        code: u16,
        /// The information.
        info: &'a [u8],
    },
}

impl Event<'_> {
    /// The event code.
    pub const fn code(&self) -> u16 {
        match self {
            Event::LinkUp => 1,
            Event::LinkDown => 2,
            Event::NetworkUp(_) => 3,
            Event::PlcConnected => 4,
            Event::PlcLost => 5,
            Event::PlcReset { .. } => 6,
            Event::Reserved { code, .. } => *code,
        }
    }

    /// Bytes of the information.
    pub const fn info_len(&self) -> usize {
        match self {
            Event::NetworkUp(_) => 17,
            Event::PlcReset { .. } => 1,
            Event::Reserved { info, .. } => info.len(),
            _ => 0,
        }
    }
}

/// The information length a named event code defines.
const fn info_len_of(code: u16) -> Option<usize> {
    match code {
        1 | 2 | 4 | 5 => Some(0),
        3 => Some(17),
        6 => Some(1),
        _ => None,
    }
}

/// Adapter Event (0xF1, LEN 3 + N): the mode, an event code and its information.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AdapterEvent<'a> {
    /// Byte 2: the module's mode (0–3; any other value is a parse error).
    pub mode: Mode,
    /// Bytes 3–4: the code; 5 on: the information.
    pub event: Event<'a>,
}

impl<'a> Message<'a> for AdapterEvent<'a> {
    const ID: FrameId = FrameId::AdapterEvent;

    fn parse_payload(payload: &'a [u8]) -> Result<AdapterEvent<'a>, ParseError> {
        let mut r = Reader::new(Self::ID, payload)?;
        let raw_mode = r.u8()?;
        let mode = Mode::from_u8(raw_mode).ok_or(ParseError::Invalid {
            id: Self::ID,
            field: "the mode",
            value: u32::from(raw_mode),
        })?;
        let code = r.u16()?;
        let info = r.rest();
        if let Some(expected) = info_len_of(code)
            && info.len() != expected
        {
            return Err(ParseError::InfoLength {
                id: Self::ID,
                code,
                expected,
                len: info.len(),
            });
        }
        let mut r = Reader::unchecked(Self::ID, info);
        let event = match code {
            1 => Event::LinkUp,
            2 => Event::LinkDown,
            3 => Event::NetworkUp(NetworkUp {
                mode: AddressMode::from_raw(r.u8()?),
                ip: r.ipv4()?,
                mask: r.ipv4()?,
                gateway: r.ipv4()?,
                dns: r.ipv4()?,
            }),
            4 => Event::PlcConnected,
            5 => Event::PlcLost,
            6 => Event::PlcReset {
                reset_type: r.u8()?,
            },
            code => Event::Reserved { code, info },
        };
        Ok(AdapterEvent { mode, event })
    }

    fn payload_len(&self) -> usize {
        3 + self.event.info_len()
    }

    fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
        let mut w = Writer::new(out);
        w.u8(self.mode.as_u8()).u16(self.event.code());
        match self.event {
            Event::NetworkUp(n) => {
                w.u8(n.mode.raw())
                    .ipv4(n.ip)
                    .ipv4(n.mask)
                    .ipv4(n.gateway)
                    .ipv4(n.dns);
            }
            Event::PlcReset { reset_type } => {
                w.u8(reset_type);
            }
            Event::Reserved { code, info } => {
                if info_len_of(code).is_some() {
                    return Err(EmitError::Invalid(
                        "a reserved adapter event has a code 1-6; use the named event",
                    ));
                }
                w.bytes(info);
            }
            Event::LinkUp | Event::LinkDown | Event::PlcConnected | Event::PlcLost => {}
        }
        w.finish()
    }
}
