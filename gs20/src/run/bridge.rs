// SPDX-License-Identifier: MIT OR Apache-2.0
//! The bridge's loop: one thread, waiting in poll(2) on the serial port, procimgd's
//! notifications, procimgd's image (a wake-up per cycle while the station runs) and a timer.
//!
//! - Bytes from the port go through the stream decoder to the link; the link's frames go
//!   back, its actions are carried out here: Start defines the host's station in procimgd
//!   and waits (without blocking the port) until it runs; Set Bus Data is written as the
//!   station's I data in one piece; Reset releases the station.
//! - The PLC's Q data goes to the host as Adapter Data when it changes (see [`Pacer`]), the
//!   station's notifications as Adapter Events (see [`NetState`]).
//! - The host's sockets are polled in the same loop (see [`Sockets`]); their data is read
//!   only while the line to the host is idle, so that a busy socket cannot hold back the
//!   Adapter Data, nor pile up frames the UART cannot carry.
//! - procimgd's cycle never waits for the UART: the last complete host image stays in the I
//!   data until the next one has arrived whole, and Adapter Data is built from one image.
//!
//! Request Reset in Run: the link is in Standby at once and sends nothing unsolicited
//! there, but the host should still learn what its reset did on the network. So the events
//! of the station leaving the wire (PLC lost, if one was connected, and link down) go out
//! right after the reset, marked with mode Run, the mode they end; then the module is
//! silent until Request Status.
//!
//! When procimgd goes away in Run (stopped, restarted), the host gets PLC lost and link
//! down, keeps Run, and its station is defined again when procimgd is back (with its last
//! input image): a module whose network side restarts.

use crate::run::image::ImageMap;
use crate::run::network::{NetState, parse_suite};
use crate::run::pacer::Pacer;
use crate::run::procimgd::{Procimgd, Starting};
use crate::run::serial::{PortError, Serial};
use crate::run::sockets::Sockets;
use nix::poll::{PollFd, PollFlags};
use procimg_client::{ArState, Ioxs};
use procimg_gs20::link::{Action, Link, StartRefusal, Station, Step};
use procimg_gs20::messages::{AdapterEvent, AddressMode, Event, Message, Mode};
use procimg_gs20::stream::Decoder;
use std::net::Ipv4Addr;
use std::time::{Duration, Instant};
use tracing::{debug, error, info, warn};

/// How often the bridge looks after procimgd when nothing wakes it: to notice a server that
/// went away, and to follow a station that is starting.
const TICK: Duration = Duration::from_millis(20);
/// The longest sleep while nothing is going on.
const IDLE_TICK: Duration = Duration::from_millis(200);

/// Where the host's station is in procimgd.
enum Phase {
    /// No station of the host's: Standby, Config, or a start that failed.
    Idle,
    /// Request Start came while the station the host released is still leaving the wire
    /// (procimgd takes a definition only once the release's waiting station runs): the
    /// host's station is defined then.
    Deferred { station: Station, deadline: Instant },
    /// Defined, waiting for procimgd to run it; `resume` when the link is in Run already
    /// (procimgd came back).
    Starting { starting: Starting, resume: bool },
    /// The station runs, in procimgd's generation `generation`.
    Running { map: ImageMap, generation: u64 },
    /// In Run, procimgd went away; the station is defined again when it is back.
    Lost,
}

/// The bridge.
pub struct Bridge {
    serial: Serial,
    decoder: Decoder,
    link: Link,
    net: NetState,
    pacer: Pacer,
    procimgd: Procimgd,
    sockets: Sockets,
    phase: Phase,
    /// The host's station as it started.
    station: Option<Station>,
    /// The last complete input image of the host.
    inputs: Option<Vec<u8>>,
    /// Whether writing the I data failed (said once until it works again).
    write_failed: bool,
    /// The generation of procimgd in which the station was last defined again after
    /// procimgd came back (tried once per generation).
    resumed_in: Option<u64>,
    /// The generation in which the station was last released (Request Reset).
    released_in: Option<u64>,
}

impl Bridge {
    /// A bridge between `serial` and `procimgd`, the link knowing `baskets`, Adapter Data
    /// paced by `pacer`.
    pub fn new(serial: Serial, procimgd: Procimgd, link: Link, pacer: Pacer) -> Bridge {
        let mut net = NetState::default();
        net.set_server(true);
        let mut link = link;
        link.set_flags(net.flags());
        Bridge {
            serial,
            decoder: Decoder::new(),
            link,
            net,
            pacer,
            procimgd,
            sockets: Sockets::default(),
            phase: Phase::Idle,
            station: None,
            inputs: None,
            write_failed: false,
            resumed_in: None,
            released_in: None,
        }
    }

    /// Runs until the serial port fails.
    pub fn run(mut self) -> Result<(), PortError> {
        let mut buf = vec![0u8; 4096];
        loop {
            let now = Instant::now();
            let timeout = self.timeout(now);
            let image_fd = match self.phase {
                Phase::Running { .. } => self.procimgd.image_fd(),
                _ => None,
            };
            let mut serial_events = PollFlags::POLLIN;
            if self.serial.has_queued() {
                serial_events |= PollFlags::POLLOUT;
            }
            let mut fds = vec![
                PollFd::new(self.serial.fd(), serial_events),
                PollFd::new(self.procimgd.notify_fd(), PollFlags::POLLIN),
            ];
            if let Some(fd) = image_fd {
                fds.push(PollFd::new(fd, PollFlags::POLLIN));
            }
            let take_data = self.take_socket_data();
            for i in self.sockets.interests(take_data) {
                let mut events = PollFlags::empty();
                events.set(PollFlags::POLLIN, i.read);
                events.set(PollFlags::POLLOUT, i.write);
                fds.push(PollFd::new(i.fd, events));
            }
            let ms = timeout.as_millis().clamp(0, i32::MAX as u128) as i32;
            match nix::poll::poll(&mut fds, ms) {
                Ok(_) | Err(nix::errno::Errno::EINTR) => {}
                Err(e) => warn!("poll failed: {e}"),
            }
            let port = fds[0].revents().unwrap_or(PollFlags::empty());
            if port.intersects(PollFlags::POLLIN | PollFlags::POLLHUP | PollFlags::POLLERR) {
                let read = self.read_port(&mut buf)?;
                // Hung up with nothing to read: the port will not come back by itself (and
                // poll would return at once for ever).
                if read == 0 && port.intersects(PollFlags::POLLHUP | PollFlags::POLLERR) {
                    return Err(self.serial.hung_up());
                }
            }
            // The decoder's silence timeout, whether or not bytes came.
            self.decode(&[], Instant::now());
            self.notifications();
            self.follow_procimgd(Instant::now());
            self.push_outputs(Instant::now());
            if self.link.mode() == Mode::Run {
                let take_data = self.take_socket_data();
                for frame in self.sockets.poll(take_data) {
                    self.serial.queue(&frame);
                }
            }
            self.serial.flush()?;
        }
    }

    /// How long to sleep at most.
    fn timeout(&self, now: Instant) -> Duration {
        let mut until = now
            + match self.phase {
                Phase::Idle => IDLE_TICK,
                _ => TICK,
            };
        if let Some(at) = self.decoder.poll_at() {
            until = until.min(at);
        }
        if let (Phase::Running { .. }, Some(at)) = (&self.phase, self.pacer.next_refresh()) {
            until = until.min(at);
        }
        until.saturating_duration_since(now)
    }

    /// Reads and decodes what the port has; how many bytes.
    fn read_port(&mut self, buf: &mut [u8]) -> Result<usize, PortError> {
        let mut total = 0;
        loop {
            let n = self.serial.read(buf)?;
            if n == 0 {
                return Ok(total);
            }
            total += n;
            self.decode(&buf[..n], Instant::now());
        }
    }

    /// Feeds bytes received at `now` (none: only the silence timeout) to the decoder and
    /// carries out what the link makes of them.
    fn decode(&mut self, bytes: &[u8], now: Instant) {
        let mut rest = bytes;
        loop {
            let taken = self.decoder.push(rest, now);
            rest = &rest[taken..];
            // Each frame's actions before the next frame: a Request Reset's release, say,
            // changes the status flags of the responses after it.
            while let Some((was, step)) = self.decoder.poll(now).map(|item| {
                let was = self.link.mode();
                (was, self.link.handle(item))
            }) {
                self.step(was, step);
            }
            // A drained decoder always has room: this ends.
            if rest.is_empty() || taken == 0 {
                return;
            }
        }
    }

    fn step(&mut self, was: Mode, step: Step) {
        for frame in &step.send {
            self.serial.queue(frame);
        }
        for action in step.actions {
            match action {
                Action::Start(station) => self.start(station),
                Action::Reset => self.reset(was),
                Action::SetInputs(bytes) => self.set_inputs(bytes),
                Action::Socket(request) => {
                    debug!("socket request {request:?}");
                    let frame = self.sockets.request(request);
                    self.serial.queue(&frame);
                }
                Action::Warn(w) => warn!("host link: {w}"),
            }
        }
    }

    /// Request Start: defines the host's station.
    fn start(&mut self, station: Station) {
        if let Some(mac) = station.mac {
            let actual = self
                .procimgd
                .status()
                .ok()
                .and_then(|s| s.station)
                .map_or_else(|| "its network interface's".to_owned(), |s| s.mac);
            warn!(
                "Set MAC {mac} is not applied: the station's MAC address is that of procimgd's \
                 network interface ({actual})"
            );
        }
        if self.released_in == Some(self.procimgd.generation()) {
            debug!("Request Start: waiting for the released station to leave the wire first");
            self.phase = Phase::Deferred {
                station,
                deadline: Instant::now() + crate::run::procimgd::START_WAIT,
            };
            return;
        }
        self.define(station);
    }

    /// Defines the host's station (Request Start).
    fn define(&mut self, station: Station) {
        match self.procimgd.define(&station) {
            Ok(starting) => {
                info!(
                    "Request Start: defined the host's station in procimgd instance \"{}\" ({} \
                     items); waiting for it to run",
                    self.procimgd.instance(),
                    station.items.len()
                );
                self.phase = Phase::Starting {
                    starting,
                    resume: false,
                };
                self.station = Some(station);
                self.inputs = None;
            }
            Err(e) => {
                error!("{e}");
                self.fail_start(StartRefusal::NotTaken, false);
            }
        }
    }

    /// The start did not happen: the host gets error bit 6 (or, in Run, waits for procimgd
    /// to come back).
    fn fail_start(&mut self, refusal: StartRefusal, resume: bool) {
        if resume {
            self.phase = Phase::Lost;
            return;
        }
        if let Action::Warn(w) = self.link.start_failed(refusal) {
            warn!("host link: {w}");
        }
        self.phase = Phase::Idle;
    }

    /// Request Reset: releases the station.
    fn reset(&mut self, was: Mode) {
        if matches!(self.phase, Phase::Starting { .. } | Phase::Running { .. }) {
            match self.procimgd.release() {
                Ok(()) => self.released_in = Some(self.procimgd.generation()),
                Err(e) => warn!("Request Reset: releasing the station failed: {e}"),
            }
        }
        let events = self.net.went_off_wire();
        self.link.set_flags(self.net.flags());
        if was == Mode::Run {
            for event in events {
                // The link is in Standby already; these are the last words of Run (see the
                // module docs).
                if let Ok(frame) = (AdapterEvent {
                    mode: Mode::Run,
                    event,
                })
                .to_vec()
                {
                    self.serial.queue(&frame);
                }
            }
        }
        if !matches!(self.phase, Phase::Idle) {
            info!("Request Reset: the station left the wire and waits for the host's next start");
        }
        self.phase = Phase::Idle;
        self.station = None;
        self.inputs = None;
        self.pacer.reset();
        self.sockets.close_all();
    }

    /// Whether the sockets' data may be read now: in Run, on an idle line.
    fn take_socket_data(&self) -> bool {
        self.link.mode() == Mode::Run && self.serial.idle()
    }

    /// Set Bus Data: the host's whole input image.
    fn set_inputs(&mut self, bytes: Vec<u8>) {
        if let Phase::Running { map, .. } = &self.phase {
            match self.procimgd.write_inputs(map, &bytes, Ioxs::Good) {
                Ok(()) => self.write_failed = false,
                Err(e) if !self.write_failed => {
                    warn!("the host's inputs did not reach procimgd: {e}");
                    self.write_failed = true;
                }
                Err(_) => {}
            }
        }
        self.inputs = Some(bytes);
    }

    /// Takes procimgd's notifications: the events for the host.
    fn notifications(&mut self) {
        while let Some(n) = self.procimgd.services().try_next() {
            debug!("procimgd: {n:?}");
            for event in self.net.notification(&n) {
                self.send_event(event);
            }
        }
        self.link.set_flags(self.net.flags());
        self.sockets
            .set_subnet_broadcast(self.net.subnet_broadcast());
    }

    fn send_event(&mut self, event: Event<'_>) {
        if let Some(frame) = self.link.event(event) {
            self.serial.queue(&frame);
        }
    }

    /// Follows procimgd: whether it answers, the station starting, procimgd gone and back.
    fn follow_procimgd(&mut self, now: Instant) {
        let (up, _) = self.procimgd.drive();
        self.net.set_server(up);
        match std::mem::replace(&mut self.phase, Phase::Idle) {
            Phase::Starting { starting, resume } => {
                match self.procimgd.poll_start(&starting, now) {
                    Ok(None) => self.phase = Phase::Starting { starting, resume },
                    Ok(Some(map)) => self.running(map, resume),
                    Err(e) => {
                        error!("{e}");
                        let _ = self.procimgd.release();
                        let refusal = match e {
                            crate::run::procimgd::StartError::Refused { .. } => {
                                StartRefusal::NotTaken
                            }
                            _ => StartRefusal::NotRunning,
                        };
                        self.fail_start(refusal, resume);
                    }
                }
            }
            Phase::Running { map, generation } => {
                if up && self.procimgd.generation() == generation {
                    self.phase = Phase::Running { map, generation };
                } else {
                    warn!(
                        "procimgd instance \"{}\" went away: the host's station is off the \
                         wire until it is back",
                        self.procimgd.instance()
                    );
                    for event in self.net.went_off_wire() {
                        self.send_event(event);
                    }
                    self.phase = Phase::Lost;
                }
            }
            Phase::Lost => {
                self.phase = Phase::Lost;
                if up {
                    self.resume();
                }
            }
            Phase::Deferred { station, deadline } => {
                if up && self.released_in != Some(self.procimgd.generation()) {
                    self.define(station);
                } else if now >= deadline {
                    error!(
                        "procimgd instance \"{}\" did not take the released station off the \
                         wire within {} s",
                        self.procimgd.instance(),
                        crate::run::procimgd::START_WAIT.as_secs()
                    );
                    self.fail_start(StartRefusal::NotRunning, false);
                } else {
                    self.phase = Phase::Deferred { station, deadline };
                }
            }
            Phase::Idle => {}
        }
        self.link.set_flags(self.net.flags());
    }

    /// procimgd is back in Run: defines the host's station again if the station waits.
    fn resume(&mut self) {
        let Some(station) = self.station.clone() else {
            return;
        };
        let generation = self.procimgd.generation();
        if self.resumed_in == Some(generation) {
            return;
        }
        let waits = self
            .procimgd
            .status()
            .ok()
            .and_then(|s| s.station)
            .and_then(|s| s.program)
            .is_some_and(|p| p.defined_by.is_none());
        if !waits {
            return;
        }
        self.resumed_in = Some(generation);
        match self.procimgd.define(&station) {
            Ok(starting) => {
                info!("procimgd is back: defined the host's station again");
                self.phase = Phase::Starting {
                    starting,
                    resume: true,
                };
            }
            Err(e) => error!("{e}"),
        }
    }

    /// The station runs: the host's Run begins (or goes on).
    fn running(&mut self, map: ImageMap, resume: bool) {
        let (inputs, status) = match &self.inputs {
            Some(i) if i.len() == map.input_len() => (i.clone(), Ioxs::Good),
            // Until the host's first image the PLC gets the I data as invalid.
            _ => (vec![0; map.input_len()], Ioxs::Bad),
        };
        if let Err(e) = self.procimgd.write_inputs(&map, &inputs, status) {
            warn!("the station's first I data did not reach procimgd: {e}");
        }
        if !resume {
            self.link.started();
        }
        let status = self.procimgd.status().ok();
        let station = status.as_ref().and_then(|s| s.station.as_ref());
        let plc = station
            .and_then(|s| s.ar.as_ref())
            .is_some_and(|ar| ar.state == ArState::Data);
        let network = self.station.as_ref().and_then(|s| s.network.as_ref());
        let (mode, mask, gateway, dns) = network.map_or(
            (
                AddressMode::Static,
                Ipv4Addr::UNSPECIFIED,
                Ipv4Addr::UNSPECIFIED,
                Ipv4Addr::UNSPECIFIED,
            ),
            |n| match n.mode {
                AddressMode::Static => (n.mode, n.mask, n.gateway, n.dns1),
                _ => (n.mode, Ipv4Addr::UNSPECIFIED, Ipv4Addr::UNSPECIFIED, n.dns1),
            },
        );
        let suite =
            station.and_then(|s| parse_suite(&s.ip, &mask.to_string(), &gateway.to_string()));
        for event in self.net.went_on_wire(suite, plc, mode, dns) {
            self.send_event(event);
        }
        self.link.set_flags(self.net.flags());
        self.sockets
            .set_subnet_broadcast(self.net.subnet_broadcast());
        self.pacer.reset();
        info!(
            "the host's station runs: {} bytes of I data, {} of Q data{}",
            map.input_len(),
            map.output_len(),
            station.map_or(String::new(), |s| format!(", \"{}\" at {}", s.name, s.ip))
        );
        let generation = self.procimgd.generation();
        self.phase = Phase::Running { map, generation };
    }

    /// Adapter Data: the PLC's Q data when due and the line is idle.
    fn push_outputs(&mut self, now: Instant) {
        let Phase::Running { map, .. } = &self.phase else {
            return;
        };
        if map.output_len() == 0 || self.link.mode() != Mode::Run || !self.serial.idle() {
            return;
        }
        let Some(q) = self.procimgd.read_outputs(map) else {
            return;
        };
        if !self.pacer.due(&q, now) {
            return;
        }
        if let Some(frame) = self.link.adapter_data(&q) {
            self.serial.queue(&frame);
            self.pacer.sent(q, now);
        }
    }
}
