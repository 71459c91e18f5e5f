// SPDX-License-Identifier: MIT OR Apache-2.0
//! The acyclic side of PROFINET: a thread that drives a sans-IO [`Role`] with the frames and
//! reports the cycle thread hands over (it rings the channel's doorbell with each), the datagrams of port 34964, the commands of
//! the client services, the mode the cycle runs in and the time, and carries out the
//! [`Effect`]s it asks for. It is the same thread for every role.

use crate::cycle::Shared;
use crate::io::pnio::channel::{Channel, FromCycle, ToCycle};
use crate::phy::datagram::Datagrams;
use crate::roles::{CycleReport, Effect, Role};
use crate::sys::clock::now_ns;
use procimg_shm_layout::Mode;
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::sync::mpsc::{Receiver, Sender};
use std::thread::JoinHandle;
use std::time::Duration;

/// The longest the loop sleeps: retransmissions and the mode are checked this often.
const MAX_WAIT: Duration = Duration::from_millis(5);
/// How long a stopping procimgd waits for the answers to its Releases.
pub const SETTLE_WAIT: Duration = Duration::from_millis(500);

pub use crate::roles::DatagramCounters;

/// What the acyclic thread works with.
pub struct AcyclicSetup<R: Role> {
    /// The role's state machines.
    pub role: R,
    /// The hand-over to the cycle thread.
    pub channel: Arc<Channel>,
    /// UDP port 34964.
    pub datagrams: Box<dyn Datagrams>,
    /// The mode and the stop flag.
    pub shared: Arc<Shared>,
    /// Where the dropped datagrams are counted.
    pub counters: Arc<DatagramCounters>,
    /// Commands from the role's client services.
    pub commands: Receiver<R::Command>,
    /// Where the role's events go (its client services), if anywhere.
    pub events: Option<Sender<R::Event>>,
    /// How long the role, stopping, may wait for its peers' answers ([`SETTLE_WAIT`]).
    pub settle_for: Duration,
    /// SCHED_FIFO priority of the thread (0: normal priority): it turns the cycle's reports
    /// into device states and client events.
    pub priority: u8,
}

/// Starts the acyclic thread; it ends when `shared.stop` is set, after taking the role
/// offline.
pub fn spawn<R: Role>(setup: AcyclicSetup<R>) -> std::io::Result<JoinHandle<()>> {
    std::thread::Builder::new()
        .name("procimg-pnio".into())
        .stack_size(crate::sys::rt::HELPER_THREAD_STACK)
        .spawn(move || run(setup))
}

fn run<R: Role>(setup: AcyclicSetup<R>) {
    let AcyclicSetup {
        mut role,
        channel,
        mut datagrams,
        shared,
        counters,
        commands,
        events,
        settle_for,
        priority,
    } = setup;
    if priority > 0
        && let Err(w) = crate::sys::rt::set_fifo_named("the PROFINET thread", priority)
    {
        tracing::warn!("{w}");
    }
    let mut out = Vec::new();
    let mut online = None;
    let mut buf = vec![0u8; 65536];
    let mut sink = Sink {
        channel: &channel,
        events: events.as_ref(),
        shared: &shared,
        neighbour_warned: false,
    };
    loop {
        let now = now_ns();
        if shared.stop.load(Ordering::Acquire) {
            role.set_online(false, now, &mut out);
            sink.carry_out(&mut out, datagrams.as_mut());
            let until = now_ns().saturating_add(settle_for.as_nanos() as u64);
            settle(
                &mut role,
                &mut sink,
                datagrams.as_mut(),
                &mut buf,
                &mut out,
                until,
            );
            break;
        }
        let want = !shared.release_all.load(Ordering::Acquire)
            && (shared.mode() != Mode::Offline
                || Mode::from_u32(shared.target_mode.load(Ordering::Acquire))
                    .is_some_and(|m| m != Mode::Offline));
        if online != Some(want) {
            online = Some(want);
            role.set_online(want, now, &mut out);
        }
        // Taken before the queue is looked at: a report left after this rings again.
        if let Some(bell) = &channel.doorbell {
            bell.take();
        }
        while let Ok(c) = commands.try_recv() {
            role.command(c, now, &mut out);
        }
        while let Some(r) = channel.from_cycle.pop() {
            match r {
                FromCycle::Received(frame) => {
                    role.on_frame(frame.bytes(), now, &mut out);
                    channel.recycle(frame);
                }
                FromCycle::DataStarted { device, epoch } => {
                    role.on_cycle(CycleReport::DataStarted { device, epoch }, now, &mut out)
                }
                FromCycle::WatchdogExpired { device, epoch } => role.on_cycle(
                    CycleReport::WatchdogExpired { device, epoch },
                    now,
                    &mut out,
                ),
                FromCycle::Retired(ar) => drop(ar),
            }
        }
        role.poll(now, &mut out);
        sink.carry_out(&mut out, datagrams.as_mut());
        let wait = role
            .deadline()
            .map_or(MAX_WAIT, |d| {
                Duration::from_nanos(d.saturating_sub(now_ns()))
            })
            .min(MAX_WAIT);
        let received = match &channel.doorbell {
            Some(bell) => datagrams.recv_from_or_wake(&mut buf, wait, bell.fd()),
            None => datagrams.recv_from(&mut buf, wait),
        };
        match received {
            Ok(Some((n, from))) => {
                role.on_datagram(from, &buf[..n], now_ns(), &mut out);
                let dropped = role.dropped_datagrams();
                counters
                    .malformed
                    .store(dropped.malformed, Ordering::Relaxed);
                counters
                    .unexpected
                    .store(dropped.unexpected, Ordering::Relaxed);
                sink.carry_out(&mut out, datagrams.as_mut());
            }
            Ok(None) => {}
            Err(e) => {
                tracing::warn!("PROFINET RPC socket: {e}");
                std::thread::sleep(wait);
            }
        }
    }
}

/// Gone offline at the end, the role waits (until `until` at most) for the answers to what
/// it sent (the devices' answers to its Releases), so that they do not arrive at a closed
/// port.
fn settle<R: Role>(
    role: &mut R,
    sink: &mut Sink<'_, R::Event>,
    datagrams: &mut dyn Datagrams,
    buf: &mut [u8],
    out: &mut Vec<Effect<R::Event>>,
    until: u64,
) {
    while role.settling() {
        let now = now_ns();
        if now >= until {
            tracing::debug!("stopping without every device's answer to its Release");
            return;
        }
        role.poll(now, out);
        sink.carry_out(out, datagrams);
        let wait = Duration::from_nanos(until - now).min(MAX_WAIT);
        if let Ok(Some((n, from))) = datagrams.recv_from(buf, wait) {
            role.on_datagram(from, &buf[..n], now_ns(), out);
            sink.carry_out(out, datagrams);
        }
    }
}

/// Where effects go.
struct Sink<'a, E> {
    channel: &'a Channel,
    events: Option<&'a Sender<E>>,
    /// Whose control thread learns of the events.
    shared: &'a Shared,
    /// A peer's MAC address could not be given to the network stack before (warned once).
    neighbour_warned: bool,
}

impl<E> Sink<'_, E> {
    /// The stack would not take a peer's MAC address: its calls then wait for ARP, and one
    /// repeated meanwhile reaches the peer twice. Said once, with what to do; then quietly.
    fn neighbour_failed(&mut self, ip: std::net::Ipv4Addr, e: &std::io::Error) {
        if self.neighbour_warned {
            tracing::debug!("cannot set the neighbour entry of {ip}: {e}");
            return;
        }
        self.neighbour_warned = true;
        tracing::warn!(
            "cannot tell the network stack the MAC address DCP found for {ip} ({e}); RPC \
             calls to devices wait for ARP instead, and a call repeated while a device's \
             address does not resolve reaches it twice: run procimgd as root or grant it \
             cap_net_admin"
        );
    }

    fn carry_out(&mut self, out: &mut Vec<Effect<E>>, datagrams: &mut dyn Datagrams) {
        let mut events = 0;
        for effect in out.drain(..) {
            match effect {
                Effect::Frame(f) => {
                    self.channel.send(&f);
                }
                Effect::Datagram { to, payload } => {
                    if let Err(e) = datagrams.send_to(to, &payload) {
                        tracing::warn!("cannot send to {to}: {e}");
                    }
                }
                Effect::Neighbour { ip, mac } => {
                    if let Err(e) = datagrams.set_neighbour(ip, mac) {
                        self.neighbour_failed(ip, &e);
                    }
                }
                Effect::Start(ar) => {
                    if let Err(ToCycle::Start(ar)) = self.channel.to_cycle.push(ToCycle::Start(ar))
                    {
                        tracing::warn!(
                            "the cycle thread is not taking commands; AR of peer {} stays down",
                            ar.device
                        );
                    }
                }
                Effect::Stop { device } => {
                    let _ = self.channel.to_cycle.push(ToCycle::Stop { device });
                }
                Effect::Event(e) => {
                    if let Some(tx) = self.events
                        && tx.send(e).is_ok()
                    {
                        events += 1;
                    }
                }
            }
        }
        if events > 0 {
            // The control thread turns them into notifications now, not at its next round.
            self.shared.ring_control();
        }
    }
}

#[cfg(test)]
mod tests;
