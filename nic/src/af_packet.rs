// SPDX-License-Identifier: MIT OR Apache-2.0
//! A real network interface through AF_PACKET (pnet's datalink channel), filtered in the
//! kernel to PROFINET frames.

use crate::Nic;
use crate::packet_socket::open_profinet_socket;
use pnet_datalink::{Channel, ChannelType, Config, DataLinkReceiver, DataLinkSender};
use procimg_profinet::wire::MacAddress;
use std::time::Duration;

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
    name: String,
    mac: MacAddress,
    /// Deliver frames this host sent too (capture mode).
    both_directions: bool,
    tx: Box<dyn DataLinkSender>,
    rx: Box<dyn DataLinkReceiver>,
}

impl AfPacket {
    /// Opens `name` as a protocol endpoint: `recv` returns the PROFINET frames others sent to
    /// this station, waiting at most `rx_timeout`.
    pub fn open(name: &str, rx_timeout: Duration) -> Result<AfPacket, OpenError> {
        AfPacket::open_with(name, rx_timeout, false)
    }

    /// Opens `name` for capturing: `recv` returns the PROFINET frames of both directions,
    /// including those this host sends, and, the interface being promiscuous, those between
    /// other stations that reach it.
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
        let io = |error: std::io::Error| {
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
        };
        let fd = open_profinet_socket(!both_directions).map_err(io)?;
        let config = Config {
            read_timeout: Some(rx_timeout),
            // The cycle thread sends: a socket that cannot take a frame now (the kernel has not
            // freed the frames sent before) must not hold the cycle for milliseconds. The send
            // fails at once and is counted; the next cycle sends fresh data anyway.
            write_timeout: Some(Duration::ZERO),
            channel_type: ChannelType::Layer2,
            socket_fd: Some(fd),
            // pnet's default is promiscuous. A protocol endpoint needs only the frames the NIC
            // takes for this station; promiscuous, the NIC hands up every frame on the wire and
            // the cycle thread parses (and counts as unknown) every PROFINET frame between
            // other stations. A capture wants exactly those.
            promiscuous: both_directions,
            ..Config::default()
        };
        match pnet_datalink::channel(iface, config).map_err(io)? {
            Channel::Ethernet(tx, rx) => Ok(AfPacket {
                name: name.to_string(),
                mac,
                both_directions,
                tx,
                rx,
            }),
            _ => Err(OpenError::Io {
                name: name.to_string(),
                error: std::io::Error::other("not an Ethernet channel"),
            }),
        }
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

    fn send(&mut self, frame: &[u8]) -> std::io::Result<()> {
        match self.tx.send_to(frame, None) {
            Some(r) => r,
            None => Err(std::io::Error::other("the interface took no frame")),
        }
    }

    fn recv(&mut self, buf: &mut [u8]) -> std::io::Result<Option<usize>> {
        loop {
            match self.rx.next() {
                Ok(frame) => {
                    // Our own frames, where the kernel still loops them back.
                    if !self.both_directions && frame.len() >= 12 && frame[6..12] == self.mac.0 {
                        continue;
                    }
                    let n = frame.len().min(buf.len());
                    buf[..n].copy_from_slice(&frame[..n]);
                    return Ok(Some(n));
                }
                Err(e) if e.kind() == std::io::ErrorKind::TimedOut => return Ok(None),
                Err(e) => return Err(e),
            }
        }
    }
}
