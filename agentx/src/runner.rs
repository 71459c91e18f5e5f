// SPDX-License-Identifier: MIT OR Apache-2.0
//! A blocking runner around [`Session`]: the only part of the crate that does IO.
//!
//! [`run`] connects to the master agent's socket, runs one session per connection with
//! snapshots from the caller's closure, and when the master is missing or goes away tries
//! again every [`RunnerConfig::retry_interval`] until the caller's stop flag is set; then
//! it closes the session (reasonShutdown) and returns. Run it on a thread of its own.

use std::fmt;
use std::io::{self, Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::os::unix::net::UnixStream;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread;
use std::time::{Duration, Instant};

use crate::mib::Snapshot;
use crate::pdu::CloseReason;
use crate::session::{Event, Session, SessionConfig, SessionState};

/// Where net-snmp's snmpd listens for subagents unless `agentXSocket` says otherwise.
pub const DEFAULT_MASTER_SOCKET: &str = "/var/agentx/master";

/// How often the runner looks at the stop flag and the session's deadlines while it
/// waits for the master.
const POLL: Duration = Duration::from_millis(100);
/// How long a shutdown waits for the master to answer the Close.
const CLOSE_WAIT: Duration = Duration::from_secs(1);

/// The master agent's socket, as net-snmp's `agentXSocket` names it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MasterAddress {
    /// A unix stream socket: a path, or `unix:PATH`.
    Unix(PathBuf),
    /// A TCP socket: `tcp:HOST:PORT`.
    Tcp(String),
}

impl Default for MasterAddress {
    fn default() -> MasterAddress {
        MasterAddress::Unix(PathBuf::from(DEFAULT_MASTER_SOCKET))
    }
}

/// A text that names no master socket.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{0:?} is not an AgentX master address: write a socket path (/var/agentx/master), unix:PATH or tcp:HOST:PORT"
)]
pub struct AddressError(pub String);

impl MasterAddress {
    /// Parses `/path`, `unix:/path` or `tcp:host:port`.
    pub fn parse(text: &str) -> Result<MasterAddress, AddressError> {
        let error = || AddressError(text.to_owned());
        if let Some(host_port) = text.strip_prefix("tcp:") {
            let (host, port) = host_port.rsplit_once(':').ok_or_else(error)?;
            if host.is_empty() || port.parse::<u16>().is_err() {
                return Err(error());
            }
            return Ok(MasterAddress::Tcp(host_port.to_owned()));
        }
        let path = text.strip_prefix("unix:").unwrap_or(text);
        if path.is_empty() {
            return Err(error());
        }
        Ok(MasterAddress::Unix(PathBuf::from(path)))
    }
}

impl fmt::Display for MasterAddress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MasterAddress::Unix(path) => write!(f, "{}", path.display()),
            MasterAddress::Tcp(host_port) => write!(f, "tcp:{host_port}"),
        }
    }
}

/// How the runner connects and retries.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunnerConfig {
    /// The master's socket.
    pub master: MasterAddress,
    /// The session opened on every connection.
    pub session: SessionConfig,
    /// The wait between a failed or lost connection and the next try.
    pub retry_interval: Duration,
    /// A Ping after this long without a word from the master, so that a master gone
    /// silent (over TCP) is noticed; `None` never pings.
    pub ping_interval: Option<Duration>,
}

impl Default for RunnerConfig {
    fn default() -> RunnerConfig {
        RunnerConfig {
            master: MasterAddress::default(),
            session: SessionConfig::procimgd(),
            retry_interval: Duration::from_secs(5),
            ping_interval: Some(Duration::from_secs(30)),
        }
    }
}

/// What the runner tells its caller, to log.
#[derive(Debug)]
pub enum RunnerEvent {
    /// Connected to the master; a session is opening.
    Connected(MasterAddress),
    /// No master to connect to (snmpd not running, or not a master agent); the runner
    /// tries again after the retry interval.
    ConnectFailed(MasterAddress, io::Error),
    /// The connection ended; the runner reconnects after the retry interval.
    Disconnected(String),
    /// What the session reported.
    Session(Event),
}

/// Serves snapshots to the master until `stop` is set, reconnecting as needed; `snapshot`
/// is called once per batch of requests that needs one.
pub fn run<S, E>(config: &RunnerConfig, stop: &AtomicBool, mut snapshot: S, mut on_event: E)
where
    S: FnMut() -> Snapshot,
    E: FnMut(RunnerEvent),
{
    while !stop.load(Ordering::Relaxed) {
        match Connection::open(&config.master) {
            Ok(conn) => {
                on_event(RunnerEvent::Connected(config.master.clone()));
                let why = serve(config, conn, stop, &mut snapshot, &mut on_event);
                on_event(RunnerEvent::Disconnected(why));
            }
            Err(e) => on_event(RunnerEvent::ConnectFailed(config.master.clone(), e)),
        }
        sleep_unless_stopped(config.retry_interval, stop);
    }
}

/// Runs one session on one connection; returns why it ended.
fn serve<S, E>(
    config: &RunnerConfig,
    mut conn: Connection,
    stop: &AtomicBool,
    snapshot: &mut S,
    on_event: &mut E,
) -> String
where
    S: FnMut() -> Snapshot,
    E: FnMut(RunnerEvent),
{
    if let Err(e) = conn.set_timeouts(POLL) {
        return format!("the socket's timeouts could not be set: {e}");
    }
    let mut session = Session::new(config.session.clone(), Instant::now());
    let mut heard = Instant::now();
    let mut stopping_since: Option<Instant> = None;
    let mut buf = vec![0; 64 * 1024];
    loop {
        if let Some(bytes) = session.poll_transmit()
            && let Err(e) = conn.write_all(&bytes)
        {
            return format!("writing to the master failed: {e}");
        }
        while let Some(event) = session.poll_event() {
            on_event(RunnerEvent::Session(event));
        }
        let now = Instant::now();
        if session.state() == SessionState::Closed {
            return "the session is closed".into();
        }
        match stopping_since {
            Some(since) if now.duration_since(since) > CLOSE_WAIT => {
                return "stopped (the master did not answer the Close)".into();
            }
            None if stop.load(Ordering::Relaxed) => {
                stopping_since = Some(now);
                session.close(now, CloseReason::Shutdown);
                continue;
            }
            _ => {}
        }
        if session.poll_timeout().is_some_and(|t| t <= now) {
            session.handle_timeout(now);
            continue;
        }
        if config
            .ping_interval
            .is_some_and(|every| now.duration_since(heard) >= every)
        {
            session.ping(now);
            heard = now;
            continue;
        }
        match conn.read(&mut buf) {
            Ok(0) => return "the master closed the connection".into(),
            Ok(n) => {
                heard = Instant::now();
                let input = buf.get(..n).unwrap_or_default();
                if let Err(e) = session.handle_input(heard, input, &mut *snapshot) {
                    if let Some(bytes) = session.poll_transmit() {
                        let _ = conn.write_all(&bytes);
                    }
                    return e.to_string();
                }
            }
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut
                ) => {}
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return format!("reading from the master failed: {e}"),
        }
    }
}

/// Sleeps `total` in short steps, returning early once `stop` is set.
fn sleep_unless_stopped(total: Duration, stop: &AtomicBool) {
    let until = Instant::now() + total;
    while !stop.load(Ordering::Relaxed) {
        let left = until.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return;
        }
        thread::sleep(left.min(POLL));
    }
}

/// A connection to the master over either kind of socket.
enum Connection {
    Unix(UnixStream),
    Tcp(TcpStream),
}

impl Connection {
    fn open(address: &MasterAddress) -> io::Result<Connection> {
        match address {
            MasterAddress::Unix(path) => UnixStream::connect(path).map(Connection::Unix),
            MasterAddress::Tcp(host_port) => {
                let mut last = io::Error::new(io::ErrorKind::NotFound, "no address");
                for addr in host_port.to_socket_addrs()? {
                    match TcpStream::connect_timeout(&addr, Duration::from_secs(2)) {
                        Ok(stream) => return Ok(Connection::Tcp(stream)),
                        Err(e) => last = e,
                    }
                }
                Err(last)
            }
        }
    }

    /// Reads wait at most `poll`; a write that waits longer than a second fails.
    fn set_timeouts(&self, poll: Duration) -> io::Result<()> {
        let write = Some(Duration::from_secs(1));
        match self {
            Connection::Unix(s) => {
                s.set_read_timeout(Some(poll))?;
                s.set_write_timeout(write)
            }
            Connection::Tcp(s) => {
                s.set_nodelay(true)?;
                s.set_read_timeout(Some(poll))?;
                s.set_write_timeout(write)
            }
        }
    }

    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        match self {
            Connection::Unix(s) => s.read(buf),
            Connection::Tcp(s) => s.read(buf),
        }
    }

    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        match self {
            Connection::Unix(s) => s.write_all(bytes),
            Connection::Tcp(s) => s.write_all(bytes),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn master_addresses() {
        assert_eq!(
            MasterAddress::parse("/var/agentx/master"),
            Ok(MasterAddress::default())
        );
        assert_eq!(
            MasterAddress::parse("unix:/tmp/x"),
            Ok(MasterAddress::Unix("/tmp/x".into()))
        );
        assert_eq!(
            MasterAddress::parse("tcp:localhost:705"),
            Ok(MasterAddress::Tcp("localhost:705".into()))
        );
        assert_eq!(
            MasterAddress::parse("tcp:[::1]:705"),
            Ok(MasterAddress::Tcp("[::1]:705".into()))
        );
        for bad in ["", "unix:", "tcp:705", "tcp:host:port", "tcp::705"] {
            assert!(MasterAddress::parse(bad).is_err(), "{bad}");
        }
        assert_eq!(
            MasterAddress::Tcp("localhost:705".into()).to_string(),
            "tcp:localhost:705"
        );
    }

    #[test]
    fn a_missing_master_is_retried_until_stopped() {
        let dir = tempfile::tempdir().unwrap();
        let config = RunnerConfig {
            master: MasterAddress::Unix(dir.path().join("absent")),
            retry_interval: Duration::from_millis(20),
            ..RunnerConfig::default()
        };
        let stop = AtomicBool::new(false);
        let mut failures = 0;
        run(&config, &stop, Snapshot::example, |event| {
            assert!(matches!(event, RunnerEvent::ConnectFailed(..)), "{event:?}");
            failures += 1;
            if failures == 3 {
                stop.store(true, Ordering::Relaxed);
            }
        });
        assert_eq!(failures, 3);
    }
}
