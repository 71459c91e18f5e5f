// SPDX-License-Identifier: MIT OR Apache-2.0
//! UDP for the PROFINET connection services (port 34964): a real socket, or an in-process
//! network for the simulated devices. The acyclic side uses it; the cycle thread never does.

use crate::sys::netlink::Netlink;
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::rpc::RPC_PORT;
use std::net::{Ipv4Addr, SocketAddrV4, UdpSocket};
use std::os::fd::{AsRawFd as _, RawFd};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, channel};
use std::time::Duration;

/// Datagrams to and from port 34964.
pub trait Datagrams: Send {
    /// Sends `payload` to `to` from our port 34964.
    fn send_to(&mut self, to: SocketAddrV4, payload: &[u8]) -> std::io::Result<()>;
    /// Tells the network stack that `ip` has the MAC address `mac`, so that datagrams to it
    /// leave at once rather than wait for ARP. Where there is no stack to tell (the
    /// simulated network), nothing.
    fn set_neighbour(&mut self, ip: Ipv4Addr, mac: MacAddress) -> std::io::Result<()> {
        let _ = (ip, mac);
        Ok(())
    }
    /// Waits up to `timeout` for a datagram; its length and sender.
    fn recv_from(
        &mut self,
        buf: &mut [u8],
        timeout: Duration,
    ) -> std::io::Result<Option<(usize, SocketAddrV4)>>;
    /// As [`recv_from`](Self::recv_from), and also returns (with nothing) as soon as `wake`
    /// becomes readable. Where the datagrams do not come through a descriptor (the simulated
    /// network), `wake` is not watched and the wait is only the timeout.
    fn recv_from_or_wake(
        &mut self,
        buf: &mut [u8],
        timeout: Duration,
        wake: RawFd,
    ) -> std::io::Result<Option<(usize, SocketAddrV4)>> {
        let _ = wake;
        self.recv_from(buf, timeout)
    }
}

/// Why the RPC socket could not be opened.
#[derive(Debug, thiserror::Error)]
// Not a `source`: the message already holds it, and error chains would repeat it.
#[error(
    "cannot bind UDP port {RPC_PORT} on {addr} for the PROFINET connection services: {error}; \
     is another PROFINET stack (or procimgd instance) running on this host?"
)]
pub struct BindError {
    /// Address tried.
    pub addr: Ipv4Addr,
    /// The OS error.
    pub error: std::io::Error,
}

/// Why the RPC socket on an interface could not be opened.
#[derive(Debug, thiserror::Error)]
// Not a `source`: the message already holds it, and error chains would repeat it.
#[error(
    "cannot open UDP port {RPC_PORT} on network interface \"{interface}\" for the PROFINET \
     connection services: {error}; is another PROFINET stack (or procimgd instance) using the \
     port on this host without an interface of its own?"
)]
pub struct InterfaceBindError {
    /// The interface.
    pub interface: String,
    /// The OS error.
    pub error: std::io::Error,
}

/// A real UDP socket on port 34964.
pub struct UdpDatagrams {
    socket: UdpSocket,
    /// The interface whose neighbour table learns the peers' MAC addresses (its index), and
    /// the route socket that tells it, opened at the first peer.
    neighbours: Option<(u32, Option<Netlink>)>,
}

impl UdpDatagrams {
    /// Binds port 34964 on `addr` (the interface's address, or 0.0.0.0).
    pub fn bind(addr: Ipv4Addr) -> Result<UdpDatagrams, BindError> {
        let socket = UdpSocket::bind(SocketAddrV4::new(addr, RPC_PORT))
            .map_err(|error| BindError { addr, error })?;
        Ok(UdpDatagrams {
            socket,
            neighbours: None,
        })
    }

    /// Peers' MAC addresses ([`Datagrams::set_neighbour`]) go to the neighbour table of
    /// interface `index`, the one the peers are on.
    pub fn with_neighbours_on(mut self, index: u32) -> UdpDatagrams {
        self.neighbours = Some((index, None));
        self
    }

    /// Opens port 34964 on every address of `interface`, present and future: the device
    /// role's station changes its address by DCP while the socket stays. Answers leave
    /// from the interface's address in the PLC's subnet, which is the station's, as the
    /// station owns the interface's addresses.
    pub fn on_interface(interface: &str) -> Result<UdpDatagrams, InterfaceBindError> {
        let socket = crate::sys::udp::bound_to_device(interface, RPC_PORT).map_err(|error| {
            InterfaceBindError {
                interface: interface.to_owned(),
                error,
            }
        })?;
        Ok(UdpDatagrams {
            socket,
            neighbours: None,
        })
    }
}

impl Datagrams for UdpDatagrams {
    fn send_to(&mut self, to: SocketAddrV4, payload: &[u8]) -> std::io::Result<()> {
        self.socket.send_to(payload, to).map(|_| ())
    }

    fn set_neighbour(&mut self, ip: Ipv4Addr, mac: MacAddress) -> std::io::Result<()> {
        let Some((index, socket)) = &mut self.neighbours else {
            return Ok(());
        };
        let socket = match socket {
            Some(s) => s,
            None => socket.insert(Netlink::open()?),
        };
        socket.set_neighbour(*index, ip, mac.0)
    }

    fn recv_from_or_wake(
        &mut self,
        buf: &mut [u8],
        timeout: Duration,
        wake: RawFd,
    ) -> std::io::Result<Option<(usize, SocketAddrV4)>> {
        let ns = timeout.as_nanos().min(u128::from(u64::MAX)) as u64;
        let [datagram, _] =
            crate::sys::poll::wait_any_readable([self.socket.as_raw_fd(), wake], ns);
        if !datagram {
            return Ok(None);
        }
        self.recv_from(buf, Duration::from_micros(100))
    }

    fn recv_from(
        &mut self,
        buf: &mut [u8],
        timeout: Duration,
    ) -> std::io::Result<Option<(usize, SocketAddrV4)>> {
        self.socket
            .set_read_timeout(Some(timeout.max(Duration::from_micros(100))))?;
        match self.socket.recv_from(buf) {
            Ok((n, std::net::SocketAddr::V4(from))) => Ok(Some((n, from))),
            Ok(_) => Ok(None),
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                Ok(None)
            }
            Err(e) => Err(e),
        }
    }
}

/// A datagram in the simulated network.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SimDatagram {
    /// Sender.
    pub from: SocketAddrV4,
    /// Receiver.
    pub to: SocketAddrV4,
    /// Bytes.
    pub payload: Vec<u8>,
}

/// The controller's end of the simulated UDP network.
pub struct SimDatagrams {
    own: Ipv4Addr,
    tx: Sender<SimDatagram>,
    rx: Receiver<SimDatagram>,
}

/// The other end: what the simulated devices use.
pub struct SimDatagramPeer {
    /// Datagrams the controller sent.
    pub rx: Receiver<SimDatagram>,
    /// Datagrams for the controller.
    pub tx: Sender<SimDatagram>,
}

/// A simulated UDP network between the controller at `own` and the simulated devices.
pub fn sim_network(own: Ipv4Addr) -> (SimDatagrams, SimDatagramPeer) {
    let (to_peer, from_controller) = channel();
    let (to_controller, from_peer) = channel();
    (
        SimDatagrams {
            own,
            tx: to_peer,
            rx: from_peer,
        },
        SimDatagramPeer {
            rx: from_controller,
            tx: to_controller,
        },
    )
}

impl Datagrams for SimDatagrams {
    fn send_to(&mut self, to: SocketAddrV4, payload: &[u8]) -> std::io::Result<()> {
        // Once the simulated plant has stopped (shutdown), datagrams go nowhere, as on a
        // network whose devices were switched off.
        let _ = self.tx.send(SimDatagram {
            from: SocketAddrV4::new(self.own, RPC_PORT),
            to,
            payload: payload.to_vec(),
        });
        Ok(())
    }

    fn recv_from(
        &mut self,
        buf: &mut [u8],
        timeout: Duration,
    ) -> std::io::Result<Option<(usize, SocketAddrV4)>> {
        match self.rx.recv_timeout(timeout) {
            Ok(d) => {
                let n = d.payload.len().min(buf.len());
                buf[..n].copy_from_slice(&d.payload[..n]);
                Ok(Some((n, d.from)))
            }
            Err(RecvTimeoutError::Timeout) => Ok(None),
            Err(RecvTimeoutError::Disconnected) => {
                // The simulated devices are gone (shutdown): behave like a quiet network.
                std::thread::sleep(timeout);
                Ok(None)
            }
        }
    }
}
