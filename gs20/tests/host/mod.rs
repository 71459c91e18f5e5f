// SPDX-License-Identifier: MIT OR Apache-2.0
//! The host's end of a GS20-PN host link in a test: a pty pair whose slave the bridge opens
//! as its serial port, frames written to the master, and the module's frames read back
//! through the crate's stream decoder and kept, in order, for the test to look through.

#![allow(dead_code)]

pub mod bridge;
pub mod plant;

use nix::fcntl::{FcntlArg, FdFlag, fcntl};
use nix::poll::{PollFd, PollFlags, poll};
use nix::pty::openpty;
use nix::sys::termios::{SetArg, cfmakeraw, tcgetattr, tcsetattr};
use procimg_gs20::messages::{
    AdapterMessage, AdapterResponse, Event, Message, Mode, SocketResponse, SocketStatus,
};
use procimg_gs20::stream::Decoder;
use std::net::Ipv4Addr;
use std::os::fd::RawFd;
use std::time::{Duration, Instant};

/// How long a frame may take to come: generous, a loaded machine is slow, not wrong.
pub const GENEROUS: Duration = Duration::from_secs(30);

/// A frame of the module, owned.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Got {
    /// 0xF0.
    Response(AdapterResponse),
    /// 0xF1: the mode, the code, the address of Network Up.
    Event {
        /// The mode byte.
        mode: Mode,
        /// The event code.
        code: u16,
        /// Network Up's address.
        ip: Option<Ipv4Addr>,
    },
    /// 0x31.
    Data(Vec<u8>),
    /// 0xE0.
    SocketResponse(SocketResponse),
    /// 0xE1: the handle, the status, the event code.
    SocketEvent {
        /// The socket.
        handle: u8,
        /// Its status.
        status: SocketStatus,
        /// The event code.
        code: u8,
    },
    /// 0x51.
    SocketData {
        /// The socket.
        handle: u8,
        /// The data.
        data: Vec<u8>,
    },
    /// A decoding error (the bridge sent something broken).
    Broken(String),
}

impl Got {
    /// The event of this code, if it is one.
    pub fn is_event(&self, event: Event<'_>) -> bool {
        matches!(self, Got::Event { code, .. } if *code == event.code())
    }
}

/// The host: a pty pair and what came from the module.
pub struct Host {
    master: RawFd,
    slave: RawFd,
    path: String,
    decoder: Decoder,
    /// Every frame received, in order.
    pub got: Vec<Got>,
    /// When each frame of [`Host::got`] was read from the pty.
    pub arrived: Vec<Instant>,
}

impl Host {
    /// A pty pair, the slave in raw mode (before the bridge opens it, so that nothing the
    /// host writes early is echoed or cooked).
    pub fn new() -> Host {
        let pty = openpty(None, None).expect("openpty");
        // Not inherited by the bridge (or any child): the host's end must close when the
        // host drops it.
        for fd in [pty.master, pty.slave] {
            fcntl(fd, FcntlArg::F_SETFD(FdFlag::FD_CLOEXEC)).expect("close-on-exec");
        }
        let mut t = tcgetattr(pty.slave).expect("the slave's termios");
        cfmakeraw(&mut t);
        tcsetattr(pty.slave, SetArg::TCSANOW, &t).expect("the slave raw");
        let path = nix::unistd::ttyname(pty.slave)
            .expect("the slave's path")
            .display()
            .to_string();
        Host {
            master: pty.master,
            slave: pty.slave,
            path,
            decoder: Decoder::with_gap(None),
            got: Vec::new(),
            arrived: Vec::new(),
        }
    }

    /// The path the bridge opens.
    pub fn port(&self) -> &str {
        &self.path
    }

    /// Writes raw bytes to the module.
    pub fn send_bytes(&mut self, bytes: &[u8]) {
        let mut rest = bytes;
        while !rest.is_empty() {
            match nix::unistd::write(self.master, rest) {
                Ok(n) => rest = &rest[n..],
                Err(nix::errno::Errno::EINTR | nix::errno::Errno::EAGAIN) => {
                    std::thread::sleep(Duration::from_millis(1))
                }
                Err(e) => panic!("writing to the pty: {e}"),
            }
        }
    }

    /// Writes a frame to the module.
    pub fn send<'a>(&mut self, m: impl Message<'a>) {
        self.send_bytes(&m.to_vec().expect("a frame"));
    }

    /// Where the frames received from now on start.
    pub fn mark(&self) -> usize {
        self.got.len()
    }

    /// Reads what comes within 100 ms into [`Host::got`].
    pub fn poll_once(&mut self) {
        self.read(Duration::from_millis(100));
    }

    /// Reads what is there (waiting up to `wait` for something) into [`Host::got`].
    pub fn read(&mut self, wait: Duration) {
        let mut fds = [PollFd::new(self.master, PollFlags::POLLIN)];
        let ms = wait.as_millis().min(i32::MAX as u128) as i32;
        if !matches!(poll(&mut fds, ms), Ok(n) if n > 0) {
            return;
        }
        let mut buf = [0u8; 4096];
        let n = match nix::unistd::read(self.master, &mut buf) {
            Ok(n) => n,
            Err(nix::errno::Errno::EINTR | nix::errno::Errno::EAGAIN) => return,
            Err(e) => panic!("reading the pty: {e}"),
        };
        let now = Instant::now();
        let got = &mut self.got;
        self.decoder.feed(&buf[..n], now, |item| {
            got.push(match item {
                Err(e) => Got::Broken(e.to_string()),
                Ok(frame) => match AdapterMessage::parse(&frame) {
                    Ok(AdapterMessage::AdapterResponse(r)) => Got::Response(r),
                    Ok(AdapterMessage::AdapterEvent(e)) => Got::Event {
                        mode: e.mode,
                        code: e.event.code(),
                        ip: match e.event {
                            Event::NetworkUp(n) => Some(n.ip),
                            _ => None,
                        },
                    },
                    Ok(AdapterMessage::AdapterData(d)) => Got::Data(d.data.to_vec()),
                    Ok(AdapterMessage::SocketResponse(r)) => Got::SocketResponse(r),
                    Ok(AdapterMessage::SocketEvent(e)) => Got::SocketEvent {
                        handle: e.handle,
                        status: e.status,
                        code: e.event.code(),
                    },
                    Ok(AdapterMessage::AdapterSocketData(d)) => Got::SocketData {
                        handle: d.handle,
                        data: d.data.to_vec(),
                    },
                    Err(e) => Got::Broken(e.to_string()),
                },
            })
        });
        self.arrived.resize(self.got.len(), now);
    }

    /// Reads until a frame at index `from` or later matches `pick`, within [`GENEROUS`]:
    /// its index and the frame.
    pub fn until(&mut self, from: usize, what: &str, pick: impl Fn(&Got) -> bool) -> (usize, Got) {
        let deadline = Instant::now() + GENEROUS;
        let mut looked = from;
        loop {
            if let Some(i) = (looked..self.got.len()).find(|&i| pick(&self.got[i])) {
                return (i, self.got[i].clone());
            }
            looked = looked.max(self.got.len());
            let now = Instant::now();
            assert!(
                now < deadline,
                "no {what} within {GENEROUS:?}; received since: {}",
                self.describe(from)
            );
            self.read((deadline - now).min(Duration::from_millis(200)));
        }
    }

    /// The frames received from `from` on, for a failure's message: the first and last 10,
    /// each run of equal frames once with its count.
    pub fn describe(&self, from: usize) -> String {
        let mut runs: Vec<(usize, &Got)> = Vec::new();
        for g in &self.got[from.min(self.got.len())..] {
            match runs.last_mut() {
                Some((n, last)) if *last == g => *n += 1,
                _ => runs.push((1, g)),
            }
        }
        let line = |(n, g): &(usize, &Got)| format!("{n} × {g:?}");
        if runs.len() <= 20 {
            runs.iter().map(line).collect::<Vec<_>>().join(", ")
        } else {
            format!(
                "{}, … {} more …, {}",
                runs[..10].iter().map(line).collect::<Vec<_>>().join(", "),
                runs.len() - 20,
                runs[runs.len() - 10..]
                    .iter()
                    .map(line)
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        }
    }

    /// The next Adapter Response at `from` or later.
    pub fn response(&mut self, from: usize) -> (usize, AdapterResponse) {
        match self.until(from, "Adapter Response", |g| matches!(g, Got::Response(_))) {
            (i, Got::Response(r)) => (i, r),
            _ => unreachable!(),
        }
    }

    /// Sends `m` and returns the Adapter Response that follows it.
    pub fn command<'a>(&mut self, m: impl Message<'a>) -> AdapterResponse {
        let from = self.mark();
        self.send(m);
        self.response(from).1
    }
}

impl Host {
    /// Sends a socket request and returns the Socket Response that follows it.
    pub fn socket<'a>(&mut self, m: impl Message<'a>) -> SocketResponse {
        let from = self.mark();
        self.send(m);
        match self.until(from, "Socket Response", |g| {
            matches!(g, Got::SocketResponse(_))
        }) {
            (_, Got::SocketResponse(r)) => r,
            _ => unreachable!(),
        }
    }

    /// Reads until the data of socket `handle` received from `from` on ends with `end`;
    /// that data.
    pub fn socket_data(&mut self, from: usize, handle: u8, end: &[u8]) -> Vec<u8> {
        let collected = |got: &[Got]| -> Vec<u8> {
            got.iter()
                .filter_map(|g| match g {
                    Got::SocketData { handle: h, data } if *h == handle => Some(data.clone()),
                    _ => None,
                })
                .flatten()
                .collect()
        };
        let deadline = Instant::now() + GENEROUS;
        loop {
            let data = collected(&self.got[from..]);
            if data.ends_with(end) {
                return data;
            }
            assert!(
                Instant::now() < deadline,
                "socket {handle} did not receive {end:?} within {GENEROUS:?}; received: {}",
                self.describe(from)
            );
            self.poll_once();
        }
    }
}

impl Drop for Host {
    fn drop(&mut self) {
        let _ = nix::unistd::close(self.master);
        let _ = nix::unistd::close(self.slave);
    }
}
