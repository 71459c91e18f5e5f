// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller's side of the segment: a [`Port`] takes the frames the controller wants
//! sent and the cyclic exchanges it starts, puts frames on the segment, takes the frames
//! that arrive and reports to the controller what it received and what it supervises.
//! In procimgd that is the cycle thread; [`Direct`] is the plainest port that brings devices
//! up and keeps them in data exchange, for worlds without procimgd's cycle.

use procimg_profinet::controller::cyclic::CyclicAr;
use procimg_profinet::wire::ethernet::{self, ETHERTYPE_PROFINET};
use procimg_profinet::wire::rt::{FrameIdClass, data_status};

/// The cycle a port runs: its number and the time (ns) of the world's clock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tick {
    /// Cycle number: the time in whole cycles.
    pub cycle: u64,
    /// Time in ns.
    pub now_ns: u64,
}

/// What a port tells the controller after the receive half of a cycle.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Report {
    /// An acyclic frame (DCP, alarm) arrived: [`Controller::on_frame`].
    ///
    /// [`Controller::on_frame`]: procimg_profinet::controller::Controller::on_frame
    Frame(Vec<u8>),
    /// A device's input frames stopped: [`Controller::on_watchdog`].
    ///
    /// [`Controller::on_watchdog`]: procimg_profinet::controller::Controller::on_watchdog
    Watchdog {
        /// Device index.
        device: usize,
        /// The AR's epoch.
        epoch: u32,
    },
    /// A device's first valid input frame arrived: [`Controller::on_data_started`].
    ///
    /// [`Controller::on_data_started`]: procimg_profinet::controller::Controller::on_data_started
    DataStarted {
        /// Device index.
        device: usize,
        /// The AR's epoch.
        epoch: u32,
    },
}

/// The controller's interface to the world's segment. The world calls `transmit`, `start`,
/// `stop` and `arrive` as things happen, and `depart`, `receive` and `send` once per cycle
/// (see the order in [`World::step`](super::World::step)).
pub trait Port {
    /// The controller wants an acyclic frame sent.
    fn transmit(&mut self, frame: Vec<u8>);
    /// The controller starts (or replaces) a device's cyclic exchange.
    fn start(&mut self, ar: Box<CyclicAr>);
    /// The controller stops a device's cyclic exchange.
    fn stop(&mut self, device: usize);
    /// A frame on the segment reaches the controller's interface.
    fn arrive(&mut self, frame: &[u8]);
    /// Appends the frames the port put on the segment since the last call, in order.
    fn depart(&mut self, out: &mut Vec<Vec<u8>>);
    /// The receive half of a cycle: takes what arrived, supervises the exchanges and appends
    /// what the controller must hear.
    fn receive(&mut self, tick: Tick, reports: &mut Vec<Report>);
    /// The send half of a cycle: the output frames due.
    fn send(&mut self, tick: Tick);
}

/// The CycleCounter counts 31.25 µs units.
const COUNTER_UNIT_NS: u64 = 31_250;
/// IOPS and IOCS GOOD (IOxS: DataState good, no problem).
const IOXS_GOOD: u8 = 0x80;

/// One running exchange of [`Direct`].
#[derive(Debug)]
struct Exchange {
    /// As the controller handed it over.
    ar: Box<CyclicAr>,
    /// The output frame this port sends; the AR's own stays as it came.
    frame: Vec<u8>,
    /// When its last input frame arrived; `None` before the first (the watchdog is armed by
    /// the first frame, as the consumer side of the standard has it).
    last_rx_ns: Option<u64>,
}

/// A port without an image: acyclic frames go out as the controller hands them over, every
/// exchange sends its output frame with all data zero and every status GOOD (DataStatus
/// OPERATE), the first input frame of an exchange is reported as data started, and an
/// exchange whose input frames stop for its watchdog time is stopped and reported. Its
/// running exchanges are what the controller handed over ([`exchanges`](Self::exchanges)).
#[derive(Debug, Default)]
pub struct Direct {
    outgoing: Vec<Vec<u8>>,
    arrived: Vec<Vec<u8>>,
    /// By device index, at most one each.
    running: Vec<Exchange>,
}

impl Direct {
    /// A port with nothing running.
    pub fn new() -> Direct {
        Direct::default()
    }

    /// The running exchanges, by device index, as the controller handed them over.
    pub fn exchanges(&self) -> impl Iterator<Item = &CyclicAr> + '_ {
        self.running.iter().map(|e| &*e.ar)
    }

    /// Whether `frame` is an input frame of a running exchange; marks it received.
    fn take_cyclic(&mut self, frame: &[u8], id: u16, now_ns: u64) -> Option<Report> {
        let src = ethernet::Frame::new_checked(frame).ok()?.src();
        let e = self
            .running
            .iter_mut()
            .find(|e| e.ar.input.frame_id == id && e.ar.peer == src)?;
        let first = e.last_rx_ns.is_none();
        e.last_rx_ns = Some(now_ns);
        first.then_some(Report::DataStarted {
            device: e.ar.device,
            epoch: e.ar.epoch,
        })
    }
}

/// The FrameID of a PROFINET frame; `None` for other frames.
fn frame_id(frame: &[u8]) -> Option<u16> {
    let eth = ethernet::Frame::new_checked(frame).ok()?;
    if eth.ethertype() != ETHERTYPE_PROFINET {
        return None;
    }
    let id = eth.payload().get(..2)?;
    Some(u16::from_be_bytes([id[0], id[1]]))
}

impl Port for Direct {
    fn transmit(&mut self, frame: Vec<u8>) {
        self.outgoing.push(frame);
    }

    fn start(&mut self, ar: Box<CyclicAr>) {
        self.stop(ar.device);
        let at = self.running.partition_point(|e| e.ar.device < ar.device);
        self.running.insert(
            at,
            Exchange {
                frame: ar.frame.clone(),
                ar,
                last_rx_ns: None,
            },
        );
    }

    fn stop(&mut self, device: usize) {
        self.running.retain(|e| e.ar.device != device);
    }

    fn arrive(&mut self, frame: &[u8]) {
        self.arrived.push(frame.to_vec());
    }

    fn depart(&mut self, out: &mut Vec<Vec<u8>>) {
        out.append(&mut self.outgoing);
    }

    fn receive(&mut self, tick: Tick, reports: &mut Vec<Report>) {
        for frame in std::mem::take(&mut self.arrived) {
            match frame_id(&frame) {
                Some(id) if FrameIdClass::of(id).is_cyclic() => {
                    // Cyclic frames of no running exchange are dropped, as the cycle does.
                    reports.extend(self.take_cyclic(&frame, id, tick.now_ns));
                }
                Some(_) => reports.push(Report::Frame(frame)),
                None => {}
            }
        }
        self.running.retain(|e| {
            let expired = e
                .last_rx_ns
                .is_some_and(|t| tick.now_ns.saturating_sub(t) > e.ar.timing.watchdog_ns());
            if expired {
                reports.push(Report::Watchdog {
                    device: e.ar.device,
                    epoch: e.ar.epoch,
                });
            }
            !expired
        });
    }

    fn send(&mut self, tick: Tick) {
        let counter = (tick.now_ns / COUNTER_UNIT_NS) as u16;
        for e in &mut self.running {
            let (ar, frame) = (&e.ar, &mut e.frame);
            if !tick
                .cycle
                .is_multiple_of(u64::from(ar.timing.every_cycles.max(1)))
            {
                continue;
            }
            let c_sdu = ar.payload_offset() + 2;
            for o in &ar.output.objects {
                frame[c_sdu + o.iops] = IOXS_GOOD;
            }
            for c in &ar.output.iocs {
                frame[c_sdu + c.offset] = IOXS_GOOD;
            }
            let trailer = c_sdu + ar.output.data_length;
            let [hi, lo] = counter.to_be_bytes();
            frame[trailer..trailer + 4].copy_from_slice(&[hi, lo, data_status::OPERATE, 0]);
            self.outgoing.push(frame.clone());
        }
    }
}
