// SPDX-License-Identifier: MIT OR Apache-2.0
//! The module's side of the host link as a state machine: the modes, which frame is
//! allowed in which mode, the Config rules, the Adapter Response to every command, and the
//! actions a bridge to procimgd carries out (define and start the station, reset, input
//! data, sockets). Sans-IO: frames (or the stream decoder's errors) in, frames to send and
//! actions out.
//!
//! [`Link`]'s methods, in the quinn-proto manner:
//! - getters: [`Link::mode`], [`Link::station`], [`Link::flags`];
//! - `handle`: [`Link::handle`] takes each item the [`crate::stream::Decoder`] yields and
//!   returns a [`Step`]: the frames to write to the UART, in order, and the [`Action`]s;
//! - the bridge's commands: [`Link::set_flags`] (link, IP, network, PLC state for the status
//!   word), [`Link::started`] and [`Link::start_failed`] (the end of Pending), and the Run
//!   frames [`Link::adapter_data`] and [`Link::event`], which are `None` outside Run.
//!
//! # Choices where the reference is silent (§1.3, §1.6)
//!
//! - **Standby** answers nothing but Request Status ("nothing happens until the host sends
//!   Request Status"): other frames and line errors are dropped without a response.
//! - **Error bits 0 and 2** describe the configuration (no device or item; no network
//!   configuration) and are set in every Config response while they hold — as in the
//!   reference's example, whose Add Item response reports "no network configuration". The
//!   other bits report what went wrong since the last response: they are latched and
//!   cleared once sent.
//! - **Line errors** (CRC, unknown ID, a LEN that does not fit) outside Standby are
//!   answered at once with an Adapter Response carrying bit 4 or 5: the damaged frame gets
//!   no answer of its own, and in Config the host is waiting for one.
//! - **Set Bus Data** of the right length is not acknowledged (one frame per host cycle
//!   would double the traffic); of a wrong length it gets an Adapter Response with bit 7
//!   and nothing reaches the PLC.
//! - **Request Reset** is not answered: the module resets to Standby, where it answers
//!   nothing until Request Status.
//! - **Retries**: Add Device with the same ID, or Add Item with the same item at the same
//!   slot, again is taken as the retry of a command whose response was lost.
//! - **Set MAC** with a group or all-zero address is refused with bit 3 (network
//!   configuration invalid), the reference having no bit of its own for it.
//! - **Sockets** are the bridge's: in Run the link hands them over as [`Action::Socket`],
//!   and the bridge answers with Socket Responses (0xE0); outside Run they get bit 5.

mod station;

pub use station::{
    AddError, Baskets, Definition, ItemSlot, MAX_ITEMS, NetworkSettings, StartRefusal, Station,
};

use crate::frame::{FrameId, FrameRepr};
use crate::messages::{
    AdapterData, AdapterEvent, AdapterResponse, ErrorBits, Event, HostMessage, MacAddress, Message,
    Mode, NetworkConfigError, OpenSocket, ParseError, SocketOption, StatusFlags,
};
use crate::stream::StreamError;

/// A socket request of the host, owned, for the bridge.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SocketRequest {
    /// Open Socket (0x40).
    Open(OpenSocket),
    /// Set Socket Option (0x41).
    SetOption {
        /// The socket.
        handle: u8,
        /// The option.
        option: SocketOption,
        /// Its data as sent.
        data: Vec<u8>,
    },
    /// Request Socket Status (0x42).
    Status {
        /// The socket.
        handle: u8,
    },
    /// Close Socket (0x43).
    Close {
        /// The socket.
        handle: u8,
    },
    /// Send Socket Data (0x50).
    Send {
        /// The socket.
        handle: u8,
        /// The data.
        data: Vec<u8>,
    },
}

/// What went wrong, for the bridge's log: each comes with the error bit the host got.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum Warning {
    /// The stream decoder dropped bytes (bit 4 or 5).
    #[error(transparent)]
    Stream(#[from] StreamError),
    /// A frame the host does not send (bit 5).
    #[error(transparent)]
    Parse(#[from] ParseError),
    /// A frame before Request Status, dropped.
    #[error("{id} in Standby is dropped: the host sends Request Status first")]
    Standby {
        /// The frame.
        id: FrameId,
    },
    /// A frame not allowed in the mode (bit 5).
    #[error("{id} is not allowed in {mode} mode (error bit 5)")]
    WrongMode {
        /// The frame.
        id: FrameId,
        /// The mode.
        mode: Mode,
    },
    /// Basket and device/item mixed (bit 8).
    #[error(
        "{id} after the station was defined by {definition:?}: basket and device/item exclude each other until a Request Reset (error bit 8)"
    )]
    Lockout {
        /// The frame.
        id: FrameId,
        /// How the station is defined.
        definition: Definition,
    },
    /// An Add command not taken (bit 1).
    #[error("{0} (error bit 1)")]
    Add(AddError),
    /// A network configuration not taken (bit 3).
    #[error("{0} (error bit 3)")]
    Network(NetworkConfigError),
    /// A MAC address a station cannot have (bit 3).
    #[error("MAC address {0} is a group or zero address; send the station's own (error bit 3)")]
    Mac(MacAddress),
    /// Request Start refused (bit 6).
    #[error("Request Start refused: {0} (error bit 6)")]
    StartRefused(StartRefusal),
    /// Set Bus Data of the wrong length (bit 7).
    #[error(
        "Set Bus Data with {received} bytes, the items' inputs are {expected} (error bit 7); nothing reached the PLC"
    )]
    IoSize {
        /// The configured input length.
        expected: usize,
        /// The length sent.
        received: usize,
    },
}

/// What the bridge does.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Action {
    /// Request Start was taken: define the station (its items, slot = position; its network
    /// settings, MAC, serial number) and start it; then call [`Link::started`] (or
    /// [`Link::start_failed`]).
    Start(Station),
    /// Request Reset: end the AR and take the station off the wire.
    Reset,
    /// Set Bus Data: the items' input bytes, whole, for the PLC.
    SetInputs(Vec<u8>),
    /// A socket request, to answer with a Socket Response (0xE0).
    Socket(SocketRequest),
    /// Something the host did wrong, for the log.
    Warn(Warning),
}

/// What one call of [`Link::handle`] produced.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Step {
    /// Frames to write to the UART, in order.
    pub send: Vec<Vec<u8>>,
    /// Actions for the bridge, in order.
    pub actions: Vec<Action>,
}

/// The module's side of the host link. See the [module docs](self).
#[derive(Clone, Debug)]
pub struct Link {
    mode: Mode,
    station: Station,
    baskets: Baskets,
    flags: StatusFlags,
    /// Error bits to report in the next response (then cleared).
    latched: ErrorBits,
}

impl Link {
    /// A module in Standby that knows `baskets`.
    pub fn new(baskets: Baskets) -> Link {
        Link {
            mode: Mode::Standby,
            station: Station::default(),
            baskets,
            flags: StatusFlags::empty(),
            latched: ErrorBits::empty(),
        }
    }

    /// The mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The station as defined so far.
    pub fn station(&self) -> &Station {
        &self.station
    }

    /// The status flags the bridge set.
    pub fn flags(&self) -> StatusFlags {
        self.flags
    }

    /// Sets the status word's flags from the network side (link known and up, IP, network,
    /// PLC connected, byte order); the error flag is the link's own.
    pub fn set_flags(&mut self, flags: StatusFlags) {
        self.flags = flags - StatusFlags::ERROR;
    }

    /// The station runs: Pending → Run.
    pub fn started(&mut self) {
        if self.mode == Mode::Pending {
            self.mode = Mode::Run;
        }
    }

    /// The station could not start (say, the network went down while Pending): back to
    /// Config, with bit 6 in the next response.
    pub fn start_failed(&mut self, reason: StartRefusal) -> Action {
        if self.mode == Mode::Pending {
            self.mode = Mode::Config;
        }
        self.latched |= ErrorBits::START_REFUSED;
        Action::Warn(Warning::StartRefused(reason))
    }

    /// The Adapter Data frame of the PLC's output bytes, in Run; `None` in another mode or
    /// when `data` is not the items' output length (the bridge's error).
    pub fn adapter_data(&self, data: &[u8]) -> Option<Vec<u8>> {
        (self.mode == Mode::Run && data.len() == self.station.output_len())
            .then(|| AdapterData { data }.to_vec().ok())
            .flatten()
    }

    /// The Adapter Event frame of `event`, in Run; `None` otherwise (events are sent only
    /// in Run, §1.3).
    pub fn event(&self, event: Event<'_>) -> Option<Vec<u8>> {
        (self.mode == Mode::Run)
            .then(|| {
                AdapterEvent {
                    mode: self.mode,
                    event,
                }
                .to_vec()
                .ok()
            })
            .flatten()
    }

    /// Takes what the stream decoder yielded.
    pub fn handle(&mut self, item: Result<FrameRepr<'_>, StreamError>) -> Step {
        let mut step = Step::default();
        match item {
            Err(e) => {
                let bit = match e {
                    StreamError::Crc { .. } | StreamError::Truncated { .. } => ErrorBits::CRC,
                    StreamError::UnknownId(_) | StreamError::BadLen { .. } => ErrorBits::FRAME,
                };
                self.fault(&mut step, bit, e.into());
            }
            Ok(frame) => match HostMessage::parse(&frame) {
                Err(e) => self.fault(&mut step, ErrorBits::FRAME, e.into()),
                Ok(m) => self.message(&mut step, m),
            },
        }
        step
    }

    fn message(&mut self, step: &mut Step, m: HostMessage<'_>) {
        use HostMessage as H;
        match (self.mode, m) {
            (Mode::Standby, H::RequestStatus(_)) => {
                self.mode = Mode::Config;
                self.respond(step);
            }
            (Mode::Standby, m) => step
                .actions
                .push(Action::Warn(Warning::Standby { id: m.id() })),
            (_, H::RequestStatus(_)) => self.respond(step),
            (_, H::RequestReset(_)) => {
                self.mode = Mode::Standby;
                self.station = Station::default();
                self.latched = ErrorBits::empty();
                step.actions.push(Action::Reset);
            }
            (Mode::Config, m) => self.config(step, m),
            (Mode::Run, H::SetBusData(d)) => {
                let expected = self.station.input_len();
                if d.data.len() == expected {
                    step.actions.push(Action::SetInputs(d.data.to_vec()));
                } else {
                    let w = Warning::IoSize {
                        expected,
                        received: d.data.len(),
                    };
                    self.fault(step, ErrorBits::IO_SIZE_MISMATCH, w);
                }
            }
            (Mode::Run, m) => match socket_request(&m) {
                Some(r) => step.actions.push(Action::Socket(r)),
                None => self.wrong_mode(step, m.id()),
            },
            (Mode::Pending, m) => self.wrong_mode(step, m.id()),
        }
    }

    /// A command in Config: every one gets a response.
    fn config(&mut self, step: &mut Step, m: HostMessage<'_>) {
        use HostMessage as H;
        // Whichever of basket and device/item came first locks the other out.
        let lockout = match (&m, self.station.definition) {
            (H::AddBasket(_), Some(d @ Definition::Device { .. }))
            | (H::AddDevice(_) | H::AddItem(_), Some(d @ Definition::Basket { .. })) => Some(d),
            _ => None,
        };
        if let Some(definition) = lockout {
            let w = Warning::Lockout {
                id: m.id(),
                definition,
            };
            return self.fault(step, ErrorBits::LOCKOUT, w);
        }
        let result: Result<(), (ErrorBits, Warning)> = match m {
            H::AddBasket(b) => self
                .station
                .add_basket(b.basket_id, &self.baskets)
                .map_err(add),
            H::AddDevice(d) => self.station.add_device(d.device_id).map_err(add),
            H::AddItem(a) => self.station.add_item(&a).map_err(add),
            H::SetNetworkConfig(c) => match NetworkSettings::from_frame(&c) {
                Ok(n) => {
                    self.station.network = Some(n);
                    Ok(())
                }
                Err(e) => Err((ErrorBits::NETWORK_CONFIG_INVALID, Warning::Network(e))),
            },
            H::SetMac(s) if s.mac.is_unicast() => {
                self.station.mac = Some(s.mac);
                Ok(())
            }
            H::SetMac(s) => Err((ErrorBits::NETWORK_CONFIG_INVALID, Warning::Mac(s.mac))),
            H::SetSerialNumber(s) => {
                self.station.serial = Some(s.serial);
                Ok(())
            }
            H::RequestStart(_) => {
                let refusal = self.station.start_refusal().or_else(|| {
                    (!self.flags.contains(StatusFlags::LINK_UP)).then_some(StartRefusal::NoLink)
                });
                match refusal {
                    Some(r) => Err((ErrorBits::START_REFUSED, Warning::StartRefused(r))),
                    None => {
                        self.mode = Mode::Pending;
                        step.actions.push(Action::Start(self.station.clone()));
                        Ok(())
                    }
                }
            }
            m => Err((
                ErrorBits::FRAME,
                Warning::WrongMode {
                    id: m.id(),
                    mode: Mode::Config,
                },
            )),
        };
        match result {
            Ok(()) => self.respond(step),
            Err((bit, w)) => self.fault(step, bit, w),
        }
    }

    fn wrong_mode(&mut self, step: &mut Step, id: FrameId) {
        let w = Warning::WrongMode {
            id,
            mode: self.mode,
        };
        self.fault(step, ErrorBits::FRAME, w);
    }

    /// Warns, and outside Standby latches `bit` and responds at once.
    fn fault(&mut self, step: &mut Step, bit: ErrorBits, w: Warning) {
        step.actions.push(Action::Warn(w));
        if self.mode != Mode::Standby {
            self.latched |= bit;
            self.respond(step);
        }
    }

    /// An Adapter Response with the configuration's bits and the latched ones (cleared).
    fn respond(&mut self, step: &mut Step) {
        let mut errors = std::mem::replace(&mut self.latched, ErrorBits::empty());
        if self.mode == Mode::Config {
            errors.set(ErrorBits::INCOMPLETE_CONFIG, self.station.is_incomplete());
            errors.set(ErrorBits::NO_NETWORK_CONFIG, self.station.network.is_none());
        }
        let response = AdapterResponse::new(self.mode, self.flags, errors);
        // Six bytes of data always fit the frame.
        if let Ok(frame) = response.to_vec() {
            step.send.push(frame);
        }
    }
}

fn add(e: AddError) -> (ErrorBits, Warning) {
    (ErrorBits::ADD_ERROR, Warning::Add(e))
}

/// The socket frames, owned; `None` for every other frame.
fn socket_request(m: &HostMessage<'_>) -> Option<SocketRequest> {
    Some(match *m {
        HostMessage::OpenSocket(o) => SocketRequest::Open(o),
        HostMessage::SetSocketOption(o) => SocketRequest::SetOption {
            handle: o.handle,
            option: o.option,
            data: o.data.to_vec(),
        },
        HostMessage::RequestSocketStatus(r) => SocketRequest::Status { handle: r.handle },
        HostMessage::CloseSocket(c) => SocketRequest::Close { handle: c.handle },
        HostMessage::SendSocketData(s) => SocketRequest::Send {
            handle: s.handle,
            data: s.data.to_vec(),
        },
        _ => return None,
    })
}

#[cfg(test)]
mod tests;
