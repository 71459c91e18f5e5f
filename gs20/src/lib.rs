// SPDX-License-Identifier: MIT OR Apache-2.0
//! The host protocol of the SiboTech GS20-PN, sans-IO.
//!
//! The GS20-PN is an embedded PROFINET IO device module: a host microcontroller defines its
//! IO items over a UART (115200 bit/s, 8E1) and then exchanges its IO bytes, the module's
//! events and even TCP/UDP sockets through it. This crate is that protocol as bytes in and
//! bytes out, so that procimg can stand in for the module (the `procimg-gs20` program, a
//! later step, puts a serial port on one side and procimgd's device role on the other).
//! It has no serial port, no clock and no daemon code (the catalogue's GSDML comes from
//! procimg's configuration crate): time comes in as an argument.
//! The reference is `shared/reference/gs20-goal-sfc.md` §1, cited by section.
//!
//! # The frame (§1.4)
//!
//! ```text
//! ID (1) | LEN (1, or 2 big-endian for 0x30 0x31 0x50 0x51 0xE1) | DATA (LEN) | CRC (2)
//! ```
//!
//! The CRC is CRC-16/Modbus over ID, LEN and DATA, low byte first. Request Status is
//! `20 00 18 70`. [`frame`] has the codec (a checked view and a `FrameRepr`), [`stream`]
//! finds frames in the UART's byte stream and resynchronises after garbage or a damaged
//! frame, [`messages`] types every frame of the catalogue, and [`link`] is the module's side
//! of the protocol as a state machine: frames in, responses and actions for a bridge out.
//!
//! # The modes (§1.3)
//!
//! - **Standby** after power-up or reset, until the host sends Request Status (0x20);
//! - **Config**: the host defines the station — Add Device (0x02) and Add Item (0x03), or
//!   Add Basket (0x01) — and sends Set Network Configuration (0x10), optionally Set MAC
//!   (0x11) and Set Serial Number (0x12); the module answers every command with an Adapter
//!   Response (0xF0): status word (mode, link, IP, PLC) and error bits;
//! - **Pending** after Request Start (0x22), while the module applies the configuration
//!   (and waits for DHCP);
//! - **Run**: the host sends its input data (Set Bus Data, 0x30), the module sends the PLC's
//!   output data (Adapter Data, 0x31) and events (0xF1) unsolicited; sockets (0x40–0x43,
//!   0x50, 0x51, 0xE0, 0xE1) work. Request Reset (0x21) goes back to Standby.
//!
//! # The item catalogue (§1.5, §1.7)
//!
//! A host adds items by ID (`D·1000 + n`: n bytes in, out, or both) at positions that are
//! the PLC's slots, and the PLC's project must hold the same modules there. [`catalogue`]
//! writes the GSDML file that makes this so: every item of the catalogue as a module whose
//! ModuleIdentNumber is the item ID, with one submodule of the item's lengths, allowed in
//! every slot 1 to 64 and plugged in none. The same file is procimgd's station's
//! (`[station] gsdml = "FILE"`), against which the host's items become the station's
//! modules. `procimg-gs20 gsdml -o FILE` writes it.
//!
//! # Example
//!
//! The module's side of the first exchange: decode the host's bytes, answer Request Status.
//!
//! ```
//! use procimg_gs20::messages::{
//!     AdapterResponse, ErrorBits, HostMessage, Message, Mode, StatusFlags,
//! };
//! use procimg_gs20::stream::Decoder;
//! use std::time::Instant;
//!
//! let mut decoder = Decoder::new();
//! let mut replies = Vec::new();
//! // Noise on the line, then Request Status.
//! decoder.feed(&[0x00, 0x7F, 0x20, 0x00, 0x18, 0x70], Instant::now(), |item| match item {
//!     Ok(frame) => {
//!         if let Ok(HostMessage::RequestStatus(_)) = HostMessage::parse(&frame) {
//!             let response = AdapterResponse::new(
//!                 Mode::Config,
//!                 StatusFlags::empty(),
//!                 ErrorBits::empty(),
//!             );
//!             replies.push(response.to_vec().unwrap());
//!         }
//!     }
//!     // The noise: the module would set error bit 5 in its next response.
//!     Err(e) => eprintln!("{e}"),
//! });
//! assert_eq!(replies, [[0xF0, 0x06, 0x00, 0x02, 0x00, 0x00, 0x02, 0x01, 0x90, 0x2F]]);
//! ```
#![forbid(unsafe_code)]

#[macro_use]
extern crate coded_enum;

pub mod catalogue;
pub mod frame;
pub mod link;
pub mod messages;
pub mod stream;
