// SPDX-License-Identifier: MIT OR Apache-2.0
//! The serial port: opened raw at the host link's settings (115200 8E1 by default), read
//! and written without blocking, so that one thread serves the port, procimgd and the
//! sockets. Frames to the host wait in a queue of their own while the port's buffer is full.

use nix::errno::Errno;
use nix::fcntl::{FcntlArg, OFlag, fcntl};
use serialport::{DataBits, FlowControl, Parity, SerialPort, StopBits, TTYPort};
use std::os::fd::{AsRawFd, RawFd};
use std::time::Duration;

/// Why the port could not be opened.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// open(2) or the line settings failed.
    #[error(
        "cannot open serial port {port} at {baud} bit/s, 8 data bits, parity {parity}, 1 stop \
         bit: {cause}; check the path (ls /dev/ttyUSB* /dev/ttyACM* /dev/ttyS*), that no other \
         program holds the port, and that you may use it (the dialout group)"
    )]
    Open {
        /// The port's path.
        port: String,
        /// The baud rate.
        baud: u32,
        /// The parity.
        parity: Parity,
        /// What failed.
        cause: serialport::Error,
    },
    /// fcntl(2) failed.
    #[error("cannot make serial port {port} non-blocking: {cause}")]
    NonBlocking {
        /// The port's path.
        port: String,
        /// What failed.
        cause: Errno,
    },
}

/// Why reading or writing the port failed (it is gone: unplugged, or the other end of a
/// pty closed).
#[derive(Debug, thiserror::Error)]
#[error(
    "serial port {port} failed while {what}: {cause}; was the USB-UART unplugged? start \
     procimg-gs20 again once the port is back"
)]
pub struct PortError {
    /// The port's path.
    pub port: String,
    /// Reading or writing.
    pub what: &'static str,
    /// The error.
    pub cause: Errno,
}

/// An open serial port with its queue of bytes to write.
pub struct Serial {
    port: TTYPort,
    name: String,
    /// Bytes not yet taken by the port.
    out: Vec<u8>,
}

impl Serial {
    /// Opens `path` raw, 8 data bits, `parity`, 1 stop bit, no flow control, non-blocking.
    pub fn open(path: &str, baud: u32, parity: Parity) -> Result<Serial, OpenError> {
        let port = serialport::new(path, baud)
            .data_bits(DataBits::Eight)
            .parity(parity)
            .stop_bits(StopBits::One)
            .flow_control(FlowControl::None)
            .timeout(Duration::ZERO)
            .open_native()
            .map_err(|cause| OpenError::Open {
                port: path.to_owned(),
                baud,
                parity,
                cause,
            })?;
        fcntl(port.as_raw_fd(), FcntlArg::F_SETFL(OFlag::O_NONBLOCK)).map_err(|cause| {
            OpenError::NonBlocking {
                port: path.to_owned(),
                cause,
            }
        })?;
        Ok(Serial {
            port,
            name: path.to_owned(),
            out: Vec::new(),
        })
    }

    /// The port's descriptor, for poll(2).
    pub fn fd(&self) -> RawFd {
        self.port.as_raw_fd()
    }

    /// The port's path.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Reads what has arrived into `buf`: the bytes read, 0 when nothing is there.
    pub fn read(&mut self, buf: &mut [u8]) -> Result<usize, PortError> {
        loop {
            match nix::unistd::read(self.fd(), buf) {
                Ok(n) => return Ok(n),
                Err(Errno::EAGAIN) => return Ok(0),
                Err(Errno::EINTR) => continue,
                Err(cause) => return Err(self.error("reading", cause)),
            }
        }
    }

    /// Queues a frame for the host, behind those queued before.
    pub fn queue(&mut self, frame: &[u8]) {
        self.out.extend_from_slice(frame);
    }

    /// Whether bytes wait for room in the port.
    pub fn has_queued(&self) -> bool {
        !self.out.is_empty()
    }

    /// Hands the port as much of the queue as it takes now.
    pub fn flush(&mut self) -> Result<(), PortError> {
        while !self.out.is_empty() {
            match nix::unistd::write(self.fd(), &self.out) {
                Ok(n) => {
                    self.out.drain(..n);
                }
                Err(Errno::EAGAIN) => break,
                Err(Errno::EINTR) => continue,
                Err(cause) => return Err(self.error("writing", cause)),
            }
        }
        Ok(())
    }

    /// Whether the line is idle: nothing queued here, nothing left in the driver's buffer.
    /// Adapter Data goes out only then, so the host gets the newest Q data rather than a
    /// backlog of old ones (a port that cannot tell counts as idle).
    pub fn idle(&self) -> bool {
        self.out.is_empty() && self.port.bytes_to_write().unwrap_or(0) == 0
    }

    /// The error of a port that hung up (the adapter unplugged, the pty's other end
    /// closed).
    pub fn hung_up(&self) -> PortError {
        self.error("reading (it hung up)", Errno::EIO)
    }

    fn error(&self, what: &'static str, cause: Errno) -> PortError {
        PortError {
            port: self.name.clone(),
            what,
            cause,
        }
    }
}
