// SPDX-License-Identifier: MIT OR Apache-2.0
//! The acyclic thread with a role that is not the controller: what the thread hands a role
//! and how it carries out the role's effects, whatever the role is.

use super::*;
use crate::phy::datagram::{SimDatagram, sim_network};
use crate::roles::DroppedDatagrams;
use std::net::{Ipv4Addr, SocketAddrV4};
use std::time::Instant;

/// What the test role was told, as events.
#[derive(Debug, PartialEq, Eq)]
enum Seen {
    Online(bool),
    Command(u32),
    Frame(Vec<u8>),
    Datagram(Vec<u8>),
    Cycle(CycleReport),
}

/// A role that answers every datagram with its bytes reversed, sends one frame when it goes
/// online, stops the AR a command names, and reports everything it is given.
struct Mirror;

impl Role for Mirror {
    type Command = u32;
    type Event = Seen;

    fn set_online(&mut self, online: bool, _now: u64, out: &mut Vec<Effect<Seen>>) {
        if online {
            out.push(Effect::Frame(vec![0xaa; 60]));
        }
        out.push(Effect::Event(Seen::Online(online)));
    }
    fn command(&mut self, c: u32, _now: u64, out: &mut Vec<Effect<Seen>>) {
        out.push(Effect::Stop { device: c as usize });
        out.push(Effect::Event(Seen::Command(c)));
    }
    fn on_frame(&mut self, frame: &[u8], _now: u64, out: &mut Vec<Effect<Seen>>) {
        out.push(Effect::Event(Seen::Frame(frame.to_vec())));
    }
    fn on_datagram(
        &mut self,
        from: SocketAddrV4,
        payload: &[u8],
        _now: u64,
        out: &mut Vec<Effect<Seen>>,
    ) {
        let mut back = payload.to_vec();
        back.reverse();
        out.push(Effect::Datagram {
            to: from,
            payload: back,
        });
        out.push(Effect::Event(Seen::Datagram(payload.to_vec())));
    }
    fn on_cycle(&mut self, report: CycleReport, _now: u64, out: &mut Vec<Effect<Seen>>) {
        out.push(Effect::Event(Seen::Cycle(report)));
    }
    fn poll(&mut self, _now: u64, _out: &mut Vec<Effect<Seen>>) {}
    fn deadline(&self) -> Option<u64> {
        None
    }
    fn dropped_datagrams(&self) -> DroppedDatagrams {
        DroppedDatagrams {
            malformed: 3,
            unexpected: 4,
        }
    }
}

/// The next event, waiting up to 20 s (the thread runs at normal priority on a busy machine).
fn next(events: &Receiver<Seen>) -> Seen {
    events
        .recv_timeout(Duration::from_secs(20))
        .expect("the acyclic thread reports within 20 s")
}

#[test]
fn the_thread_hands_a_role_its_inputs_and_carries_out_its_effects() {
    let own = Ipv4Addr::new(192, 168, 0, 1);
    let (udp, peer) = sim_network(own);
    let channel = Arc::new(Channel::new());
    let shared = Arc::new(Shared::new(0));
    shared
        .target_mode
        .store(Mode::Clear.as_u32(), Ordering::Release);
    let counters = Arc::new(DatagramCounters::default());
    let (commands, command_rx) = std::sync::mpsc::channel();
    let (events_tx, events) = std::sync::mpsc::channel();
    let thread = spawn(AcyclicSetup {
        role: Mirror,
        channel: channel.clone(),
        datagrams: Box::new(udp),
        shared: shared.clone(),
        counters: counters.clone(),
        commands: command_rx,
        events: Some(events_tx),
        settle_for: SETTLE_WAIT,
        priority: 0,
    })
    .unwrap();

    // Going online: the role's frame is queued for the cycle thread to send.
    assert_eq!(next(&events), Seen::Online(true));
    match channel.to_cycle.pop() {
        Some(ToCycle::Send(buf)) => assert_eq!(buf.bytes(), &[0xaa; 60][..]),
        _ => panic!("the role's frame is not queued for the cycle thread"),
    }

    // A command, and the Stop it asks for.
    commands.send(7).unwrap();
    assert_eq!(next(&events), Seen::Command(7));
    assert!(matches!(
        channel.to_cycle.pop(),
        Some(ToCycle::Stop { device: 7 })
    ));

    // A frame the cycle thread received, in one of the channel's buffers.
    assert!(channel.send(&[1, 2, 3]));
    let Some(ToCycle::Send(buf)) = channel.to_cycle.pop() else {
        panic!("no frame buffer");
    };
    assert!(channel.from_cycle.push(FromCycle::Received(buf)).is_ok());
    assert_eq!(next(&events), Seen::Frame(vec![1, 2, 3]));

    // What the cycle thread reports about an exchange.
    let started = FromCycle::DataStarted {
        device: 2,
        epoch: 9,
    };
    assert!(channel.from_cycle.push(started).is_ok());
    assert_eq!(
        next(&events),
        Seen::Cycle(CycleReport::DataStarted {
            device: 2,
            epoch: 9
        })
    );

    // A datagram in, its answer out, the dropped counts published.
    let from = SocketAddrV4::new(Ipv4Addr::new(192, 168, 0, 2), 49152);
    peer.tx
        .send(SimDatagram {
            from,
            to: SocketAddrV4::new(own, 34964),
            payload: vec![1, 2, 3],
        })
        .unwrap();
    assert_eq!(next(&events), Seen::Datagram(vec![1, 2, 3]));
    let answer = peer
        .rx
        .recv_timeout(Duration::from_secs(20))
        .expect("the answer within 20 s");
    assert_eq!((answer.to, answer.payload), (from, vec![3, 2, 1]));
    assert_eq!(counters.malformed.load(Ordering::Relaxed), 3);
    assert_eq!(counters.unexpected.load(Ordering::Relaxed), 4);

    // Stopping takes the role offline first.
    shared.stop.store(true, Ordering::Release);
    let until = Instant::now() + Duration::from_secs(20);
    while !thread.is_finished() && Instant::now() < until {
        std::thread::sleep(Duration::from_millis(5));
    }
    thread.join().unwrap();
    assert_eq!(next(&events), Seen::Online(false));
}

/// A role that sends a "Release" to [`PEER`] when it goes offline and settles until the
/// peer answers.
struct Releaser {
    releasing: bool,
}

const PEER: SocketAddrV4 = SocketAddrV4::new(Ipv4Addr::new(192, 168, 0, 2), 34964);

impl Role for Releaser {
    type Command = u32;
    type Event = Seen;

    fn set_online(&mut self, online: bool, _now: u64, out: &mut Vec<Effect<Seen>>) {
        if !online && !self.releasing {
            self.releasing = true;
            out.push(Effect::Datagram {
                to: PEER,
                payload: vec![0x52],
            });
        }
        out.push(Effect::Event(Seen::Online(online)));
    }
    fn command(&mut self, _: u32, _now: u64, _out: &mut Vec<Effect<Seen>>) {}
    fn on_frame(&mut self, _: &[u8], _now: u64, _out: &mut Vec<Effect<Seen>>) {}
    fn on_datagram(
        &mut self,
        _: SocketAddrV4,
        payload: &[u8],
        _: u64,
        out: &mut Vec<Effect<Seen>>,
    ) {
        self.releasing = false;
        out.push(Effect::Event(Seen::Datagram(payload.to_vec())));
    }
    fn on_cycle(&mut self, _: CycleReport, _now: u64, _out: &mut Vec<Effect<Seen>>) {}
    fn poll(&mut self, _now: u64, _out: &mut Vec<Effect<Seen>>) {}
    fn deadline(&self) -> Option<u64> {
        None
    }
    fn dropped_datagrams(&self) -> DroppedDatagrams {
        DroppedDatagrams::default()
    }
    fn settling(&self) -> bool {
        self.releasing
    }
}

#[test]
fn a_stopping_role_gets_the_answer_to_its_release_before_the_socket_closes() {
    let own = Ipv4Addr::new(192, 168, 0, 1);
    let (udp, peer) = sim_network(own);
    let shared = Arc::new(Shared::new(0));
    shared
        .target_mode
        .store(Mode::Clear.as_u32(), Ordering::Release);
    let (_commands, command_rx) = std::sync::mpsc::channel();
    let (events_tx, events) = std::sync::mpsc::channel();
    let thread = spawn(AcyclicSetup {
        role: Releaser { releasing: false },
        channel: Arc::new(Channel::new()),
        datagrams: Box::new(udp),
        shared: shared.clone(),
        counters: Arc::new(DatagramCounters::default()),
        commands: command_rx,
        events: Some(events_tx),
        // Longer than any test waits: the answer comes, however late the test sends it.
        settle_for: Duration::from_secs(600),
        priority: 0,
    })
    .unwrap();
    assert_eq!(next(&events), Seen::Online(true));
    shared.stop.store(true, Ordering::Release);
    let release = peer
        .rx
        .recv_timeout(Duration::from_secs(20))
        .expect("the Release within 20 s");
    assert_eq!((release.to, release.payload), (PEER, vec![0x52]));
    assert_eq!(next(&events), Seen::Online(false));
    // The answer reaches the role: the thread waited for it.
    peer.tx
        .send(SimDatagram {
            from: PEER,
            to: SocketAddrV4::new(own, 34964),
            payload: vec![0x41],
        })
        .unwrap();
    assert_eq!(next(&events), Seen::Datagram(vec![0x41]));
    thread.join().unwrap();
}
