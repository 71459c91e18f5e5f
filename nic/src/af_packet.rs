// SPDX-License-Identifier: MIT OR Apache-2.0
//! A real network interface through an AF_PACKET socket, filtered in the kernel to PROFINET
//! frames. The interface is looked up through pnet (getifaddrs); the socket is ours
//! (`packet_socket.rs`).

use crate::packet_socket::PacketSocket;
use crate::{MAX_FRAME, Nic, RecvError, SendError, check_frame_len};
use procimg_profinet::wire::MacAddress;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Why an interface could not be opened.
///
/// The messages do not name a program, a configuration key or an option: procimgd and the
/// `procimg` tool each say where the name came from (`network` in the configuration file,
/// `--iface`) and who needs the privilege.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// No interface has that name.
    #[error(
        "network interface \"{name}\" does not exist on this machine (its interfaces: {available})"
    )]
    NoSuchInterface {
        /// The name asked for.
        name: String,
        /// The interfaces there are, for the message (`eth0, lo`).
        available: String,
    },
    /// The interface is down.
    #[error("network interface \"{name}\" is down: bring it up (ip link set {name} up)")]
    Down {
        /// The interface.
        name: String,
    },
    /// The interface has no MAC address (not Ethernet).
    #[error(
        "network interface \"{name}\" has no MAC address: PROFINET needs an Ethernet interface"
    )]
    NoMac {
        /// The interface.
        name: String,
    },
    /// The process may not open raw sockets.
    #[error("no permission to open a raw socket on \"{name}\" (that needs root or CAP_NET_RAW)")]
    NotPermitted {
        /// The interface.
        name: String,
    },
    /// Anything else the system refused.
    // Not a `source`: the message already holds it, and error chains would repeat it.
    #[error("cannot open network interface \"{name}\": {error}")]
    Io {
        /// The interface.
        name: String,
        /// The error.
        error: std::io::Error,
    },
}

/// An open interface.
pub struct AfPacket {
    /// Shared with the errors, which then allocate nothing.
    name: Arc<str>,
    mac: MacAddress,
    /// Deliver frames this host sent too (capture mode).
    both_directions: bool,
    socket: PacketSocket,
    rx_timeout: Duration,
    /// The frame being received: handed to the receive closure in place.
    rx: Box<[u8; MAX_FRAME]>,
}

impl AfPacket {
    /// Opens `name` as a protocol endpoint: `receive` hands over the PROFINET frames others
    /// sent to this station, waiting at most `rx_timeout`.
    pub fn open(name: &str, rx_timeout: Duration) -> Result<AfPacket, OpenError> {
        AfPacket::open_with(name, rx_timeout, false)
    }

    /// Opens `name` for capturing: `receive` hands over the PROFINET frames of both
    /// directions, including those this host sends, and, the interface being promiscuous,
    /// those between other stations that reach it.
    pub fn open_capture(name: &str, rx_timeout: Duration) -> Result<AfPacket, OpenError> {
        AfPacket::open_with(name, rx_timeout, true)
    }

    fn open_with(
        name: &str,
        rx_timeout: Duration,
        both_directions: bool,
    ) -> Result<AfPacket, OpenError> {
        let interfaces = pnet_datalink::interfaces();
        let Some(iface) = interfaces.iter().find(|i| i.name == name) else {
            return Err(OpenError::NoSuchInterface {
                name: name.to_string(),
                available: crate::interfaces::list(&crate::interfaces::names()),
            });
        };
        if !iface.is_up() {
            return Err(OpenError::Down {
                name: name.to_string(),
            });
        }
        let mac = match iface.mac {
            Some(m) if m.octets() != [0; 6] => MacAddress(m.octets()),
            _ => {
                return Err(OpenError::NoMac {
                    name: name.to_string(),
                });
            }
        };
        // A protocol endpoint needs only the frames the NIC takes for this station;
        // promiscuous, the NIC hands up every frame on the wire and the cycle thread parses
        // (and counts as unknown) every PROFINET frame between other stations. A capture
        // wants exactly those.
        let socket = PacketSocket::open(iface.index, !both_directions, both_directions).map_err(
            |error| {
                if matches!(error.raw_os_error(), Some(libc::EPERM) | Some(libc::EACCES)) {
                    OpenError::NotPermitted {
                        name: name.to_string(),
                    }
                } else {
                    OpenError::Io {
                        name: name.to_string(),
                        error,
                    }
                }
            },
        )?;
        Ok(AfPacket {
            name: name.into(),
            mac,
            both_directions,
            socket,
            rx_timeout,
            rx: Box::new([0; MAX_FRAME]),
        })
    }

    /// The interface name.
    pub fn name(&self) -> &str {
        &self.name
    }
}

impl Nic for AfPacket {
    fn mac(&self) -> MacAddress {
        self.mac
    }

    fn send(&mut self, frame: &[u8]) -> Result<(), SendError> {
        check_frame_len(&self.name, frame)?;
        self.socket.send(frame).map_err(|error| SendError::Io {
            interface: self.name.clone(),
            error,
        })
    }

    fn receive(&mut self, f: &mut dyn FnMut(&[u8])) -> Result<bool, RecvError> {
        // Read lazily: a zero timeout (the cycle thread's) never reads the clock.
        let mut deadline = None;
        loop {
            let len = match self.socket.recv(&mut self.rx[..]) {
                Ok(Some(len)) => len,
                Ok(None) => {
                    if self.rx_timeout.is_zero() {
                        return Ok(false);
                    }
                    // `None`: a timeout past the clock's range; each wait then takes all of it.
                    let deadline = *deadline
                        .get_or_insert_with(|| Instant::now().checked_add(self.rx_timeout));
                    let left = deadline.map_or(self.rx_timeout, |d| {
                        d.saturating_duration_since(Instant::now())
                    });
                    if left.is_zero() || !self.socket.wait(left) {
                        return Ok(false);
                    }
                    continue;
                }
                Err(error) => {
                    return Err(RecvError::Io {
                        interface: self.name.clone(),
                        error,
                    });
                }
            };
            // The kernel wrote only what fits; the length is the frame's on the wire.
            let Some(frame) = self.rx.get(..len) else {
                return Err(RecvError::TooLong {
                    interface: self.name.clone(),
                    len,
                    max: MAX_FRAME,
                });
            };
            // Our own frames, where the kernel still loops them back.
            if !self.both_directions && frame.get(6..12) == Some(&self.mac.0[..]) {
                continue;
            }
            f(frame);
            return Ok(true);
        }
    }
}
