// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller's side of the segment: a [`Port`] takes the frames the controller wants
//! sent and the cyclic exchanges it starts, puts frames on the segment, takes the frames
//! that arrive and reports to the controller what it received and what it supervises.
//! In procimgd that is the cycle thread; [`Direct`] is the plainest port that brings devices
//! up and keeps them in data exchange, for worlds without procimgd's cycle.

use procimg_profinet::controller::cyclic::CyclicAr;
use procimg_profinet::cyclic::{Consumer, ProducedData, Verdict, VerdictCounts};
use procimg_profinet::wire::ethernet::{self, ETHERTYPE_PROFINET};
use procimg_profinet::wire::rt::{FrameIdClass, cycle_counter_at, data_status};

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

/// IOPS and IOCS GOOD (IOxS: DataState good, no problem).
const IOXS_GOOD: u8 = 0x80;

/// One running exchange of [`Direct`].
#[derive(Debug)]
struct Exchange {
    /// As the controller handed it over.
    ar: Box<CyclicAr>,
    /// The copy this port produces its frames in; the AR's own stays as it came.
    producing: Box<CyclicAr>,
    /// The consumer of the device's frames, armed by the first (the port is not told when
    /// the exchange starts).
    consumer: Consumer,
}

/// What [`Direct`] produces: zero data, every status GOOD.
struct ZerosGood;

impl ProducedData for ZerosGood {
    fn data(&self, _: usize) -> &[u8] {
        &[]
    }
    fn iops(&self, _: usize) -> u8 {
        IOXS_GOOD
    }
    fn iocs(&self, _: usize) -> u8 {
        IOXS_GOOD
    }
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

    /// How the consumer of `device`'s exchange judged its frames, while it runs.
    pub fn verdicts(&self, device: usize) -> Option<VerdictCounts> {
        self.running
            .iter()
            .find(|e| e.ar.device == device)
            .map(|e| e.consumer.counts())
    }

    /// Hands an input frame to the consumer of its exchange: a report if it is the first
    /// accepted one.
    fn take_cyclic(&mut self, frame: &[u8], id: u16, now_ns: u64) -> Option<Report> {
        let eth = ethernet::Frame::new_checked(frame).ok()?;
        let e = self
            .running
            .iter_mut()
            .find(|e| e.ar.input.frame_id == id)?;
        match e.consumer.consume(eth.src(), eth.payload(), now_ns) {
            Verdict::Accepted { first: true, .. } => Some(Report::DataStarted {
                device: e.ar.device,
                epoch: e.ar.epoch,
            }),
            _ => None,
        }
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
                producing: ar.clone(),
                consumer: Consumer::new(
                    ar.input.frame_id,
                    ar.input.data_length,
                    ar.peer,
                    ar.timing.watchdog_ns(),
                ),
                ar,
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
            let expired = e.consumer.expired(tick.now_ns);
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
        let counter = cycle_counter_at(tick.now_ns);
        for e in &mut self.running {
            let ar = &mut e.producing;
            if !ar.due(tick.cycle) {
                continue;
            }
            ar.fill(&ZerosGood);
            let frame = ar.seal(counter, data_status::OPERATE).to_vec();
            self.outgoing.push(frame);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_profinet::controller::plan::{DevicePlan, DeviceSpec, SubmoduleSpec};
    use procimg_profinet::cyclic::trial::TrialSetup;
    use procimg_profinet::wire::MacAddress;

    const MS: u64 = 1_000_000;

    /// The test world's port judges the device's frames as the protocol crate's consumer
    /// does: data started once, and the watchdog when the rule says.
    #[test]
    fn the_direct_port_judges_the_consumer_trial_as_the_consumer_does() {
        let spec = DeviceSpec {
            name: "io".into(),
            ip: None,
            vendor_id: 1,
            device_id: 1,
            instance: 1,
            reduction_ratio: 1,
            watchdog_factor: 3,
            submodules: vec![SubmoduleSpec {
                api: 0,
                slot: 1,
                subslot: 1,
                module_ident: 1,
                submodule_ident: 1,
                input_length: 4,
                output_length: 0,
                records: vec![],
            }],
            ..Default::default()
        };
        let plan = &DevicePlan::all(&[spec], MS).unwrap()[0];
        let (own, device) = (
            MacAddress([2, 0, 0, 0, 0, 1]),
            MacAddress([2, 0, 0, 0, 0, 2]),
        );
        let ar = CyclicAr::new(plan, 1, own, device, plan.frame_ids);
        let trial = TrialSetup {
            peer: device,
            own,
            frame_id: ar.input.frame_id,
            data_length: ar.input.data_length,
            timing: ar.timing,
            first_at_ns: MS,
            first_counter: 7,
        }
        .trial();
        let mut port = Direct::new();
        port.start(Box::new(ar));
        let mut reports = Vec::new();
        for f in &trial.frames {
            port.arrive(&f.frame);
            let tick = Tick {
                cycle: f.at_ns / MS,
                now_ns: f.at_ns,
            };
            port.receive(tick, &mut reports);
        }
        assert_eq!(port.verdicts(0), Some(trial.counts));
        assert_eq!(
            reports,
            vec![Report::DataStarted {
                device: 0,
                epoch: 1
            }]
        );
        let at = |now_ns| Tick { cycle: 0, now_ns };
        port.receive(at(trial.expires_at_ns - 1), &mut reports);
        assert_eq!(reports.len(), 1, "nothing before the watchdog's time");
        port.receive(at(trial.expires_at_ns), &mut reports);
        assert_eq!(
            reports.last(),
            Some(&Report::Watchdog {
                device: 0,
                epoch: 1
            })
        );
    }
}
