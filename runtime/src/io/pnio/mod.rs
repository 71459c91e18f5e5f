// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFINET IO on the cycle thread: the network interface, the cyclic frames of every AR
//! the controller has set up, and the consumer watchdogs. Everything else (DCP, RPC,
//! alarms) is the controller's, on the acyclic side; its frames pass through [`Channel`].
//!
//! Per cycle, [`IoSystem::receive`] drains the interface: cyclic frames of a running AR go
//! straight into the image (data, IOPS, IOCS); acyclic PROFINET frames are handed over;
//! anything malformed, unknown or stale is counted and dropped. Then every AR whose
//! watchdog ran out is stopped, its inputs marked BAD and the controller told.
//! [`IoSystem::send`] sends one output frame per AR due in this cycle, and the frames the
//! controller queued. A device's output frame is part of the image (its outputs where the
//! frame carries them, see `Tables::output_frames`): the cycle writes the header and status
//! bytes around them and sends it from there; an AR whose frame differs from the image's
//! (in the device role, a PLC that laid the station's frame out otherwise than the image
//! holds it) is written from the image first.

pub mod channel;

use super::{CycleTime, IoSystem};
use crate::image::Image;
use channel::{Channel, FromCycle, NetCounters, ToCycle};
use procimg_nic::{Nic, RecvError};
use procimg_profinet::cyclic::{Consumer, CyclicAr, ProducedData, Verdict};
use procimg_profinet::wire::ethernet::{self, ETHERTYPE_PROFINET};
use procimg_profinet::wire::lldp::ETHERTYPE_LLDP;
use procimg_profinet::wire::rt::{FrameIdClass, TIME_UNIT_NS, data_status};
use procimg_shm_layout::{IOXS_BAD, IOXS_GOOD, Mode, SubmoduleStatus};
use std::sync::Arc;
use std::sync::atomic::Ordering;

// The image's cycle_count (IO-Base's unit, in the shared-memory layout) counts the same unit
// as the wire's CycleCounter; the layout crate stands apart from the protocol crate.
const _: () = assert!(procimg_shm_layout::CYCLE_COUNT_UNIT_NS == TIME_UNIT_NS);

/// Frames taken from the interface per cycle at most, so that a flood cannot hold the
/// cycle; what is left is read in the next cycle (or dropped by the kernel).
const MAX_FRAMES_PER_CYCLE: usize = 512;

/// The run-time state of one AR's exchange: what the acyclic side handed over and the
/// consumer of its peer's frames.
struct Running {
    ar: Box<CyclicAr>,
    consumer: Consumer,
    /// Its output frame goes out from the image, where the outputs are already
    /// ([`frame_in_image`]); otherwise it is written from the image first.
    in_image: bool,
}

/// The PROFINET IO system of the cycle thread, over interface `N`. Generic over the
/// interface, so that the per-frame receive and send calls are direct and the closure that
/// parses a frame in place is inlined into the backend's receive.
pub struct PnioIo<N: Nic = Box<dyn Nic>> {
    nic: N,
    ex: Exchanges,
}

/// Everything of the IO system but the interface: the running exchanges and the reports
/// for the acyclic side.
struct Exchanges {
    channel: Arc<Channel>,
    /// Per device: its running exchange.
    running: Vec<Option<Running>>,
    /// Per FrameID: 1 + the device whose input frames carry it while it runs, 0 for none.
    /// Every frame received is looked up here: O(1), whatever the number of devices.
    device_by_frame_id: Box<[u16]>,
    /// Per device: the submodule table range, to mark a stopped device's inputs BAD.
    device_submodules: Vec<core::ops::Range<usize>>,
    /// Exchanges to hand back whose report did not fit the queue yet (capacity reserved).
    /// Boxed because they arrive and leave boxed: unboxing would free on this thread.
    #[allow(clippy::vec_box)]
    retired: Vec<Box<CyclicAr>>,
    /// Reports that did not fit the queue yet (capacity reserved).
    pending: Vec<FromCycle>,
    /// 31.25 µs units per cycle, for the CycleCounter.
    cycle_units: u64,
}

impl<N: Nic> PnioIo<N> {
    /// An IO system over `nic` for devices whose submodules occupy `device_submodules` of
    /// the submodule table.
    pub fn new(
        nic: N,
        channel: Arc<Channel>,
        device_submodules: Vec<core::ops::Range<usize>>,
        cycle_ns: u64,
    ) -> PnioIo<N> {
        PnioIo {
            nic,
            ex: Exchanges::new(channel, device_submodules, cycle_ns),
        }
    }
}

impl Exchanges {
    fn new(
        channel: Arc<Channel>,
        device_submodules: Vec<core::ops::Range<usize>>,
        cycle_ns: u64,
    ) -> Exchanges {
        let n = device_submodules.len();
        Exchanges {
            channel,
            running: (0..n).map(|_| None).collect(),
            // 128 KiB, once: a slot for every FrameID.
            device_by_frame_id: vec![0; 1 << 16].into_boxed_slice(),
            device_submodules,
            retired: Vec::with_capacity(4 * n + 8),
            pending: Vec::with_capacity(4 * n + 8),
            cycle_units: (cycle_ns / TIME_UNIT_NS).max(1),
        }
    }

    fn report(&mut self, r: FromCycle) {
        if let Some(bell) = &self.channel.doorbell {
            bell.ring();
        }
        if let Err(r) = self.channel.from_cycle.push(r) {
            match r {
                FromCycle::Retired(ar) if self.retired.len() < self.retired.capacity() => {
                    self.retired.push(ar)
                }
                FromCycle::Received(buf) => {
                    NetCounters::count(&self.channel.counters.dropped);
                    let _ = self.channel.free.push(buf);
                }
                r if self.pending.len() < self.pending.capacity() => self.pending.push(r),
                // Cannot happen with the reserved capacity; dropping here would free on the
                // real-time thread, so the exchange is leaked instead.
                FromCycle::Retired(ar) => core::mem::forget(ar),
                _ => {}
            }
        }
    }

    fn flush_reports(&mut self) {
        while let Some(r) = self.pending.pop() {
            if let Err(r) = self.channel.from_cycle.push(r) {
                self.pending.push(r);
                return;
            }
        }
        while let Some(ar) = self.retired.pop() {
            if let Err(FromCycle::Retired(ar)) =
                self.channel.from_cycle.push(FromCycle::Retired(ar))
            {
                self.retired.push(ar);
                return;
            }
        }
    }

    fn stop(&mut self, device: usize, image: Option<&mut Image>) {
        if let Some(r) = self.running.get_mut(device).and_then(Option::take) {
            let slot = &mut self.device_by_frame_id[usize::from(r.ar.input.frame_id)];
            if usize::from(*slot) == device + 1 {
                *slot = 0;
            }
            self.report(FromCycle::Retired(r.ar));
        }
        if let (Some(image), Some(range)) = (image, self.device_submodules.get(device)) {
            mark_disconnected(image, range.clone());
        }
    }

    fn apply_commands(&mut self, nic: &mut impl Nic, t: CycleTime, image: &mut Image) {
        while let Some(c) = self.channel.to_cycle.pop() {
            match c {
                ToCycle::Start(ar) => {
                    let d = ar.device;
                    if d >= self.running.len() {
                        self.report(FromCycle::Retired(ar));
                        continue;
                    }
                    self.stop(d, None);
                    // A replacement may leave submodules out (a device pulled them): their
                    // status turns BAD now rather than keep what the last exchange gave.
                    if let Some(range) = self.device_submodules.get(d) {
                        for s in range.clone().filter(|&s| !exchanges(&ar, s)) {
                            mark_disconnected(image, s..s + 1);
                        }
                    }
                    // Devices are at most MAX_DEVICES (256): the index fits.
                    self.device_by_frame_id[usize::from(ar.input.frame_id)] = d as u16 + 1;
                    self.running[d] = Some(Running {
                        consumer: Consumer::of(&ar, t.now_ns),
                        in_image: frame_in_image(&ar, image),
                        ar,
                    });
                }
                ToCycle::Stop { device } => self.stop(device, Some(image)),
                ToCycle::Send(buf) => {
                    if nic.send(buf.bytes()).is_err() {
                        NetCounters::count(&self.channel.counters.send_errors);
                    }
                    let _ = self.channel.free.push(buf);
                }
            }
        }
    }

    /// Hands an acyclic frame to the acyclic side, in a buffer of the pool (counted as
    /// dropped when the pool is empty: the cycle never waits for it).
    fn forward(&mut self, frame: &[u8]) {
        match self.channel.free.pop() {
            Some(mut buf) => {
                buf.data[..frame.len()].copy_from_slice(frame);
                buf.len = frame.len();
                self.report(FromCycle::Received(buf));
            }
            None => NetCounters::count(&self.channel.counters.dropped),
        }
    }

    fn take_frame(&mut self, frame: &[u8], now_ns: u64, image: &mut Image) {
        let counters = &self.channel.counters;
        let Ok(eth) = ethernet::Frame::new_checked(frame) else {
            NetCounters::count(&counters.malformed);
            return;
        };
        if eth.ethertype() == ETHERTYPE_LLDP {
            // The port's neighbours: the acyclic side's business.
            return self.forward(frame);
        }
        if eth.ethertype() != ETHERTYPE_PROFINET {
            NetCounters::count(&counters.unknown);
            return;
        }
        let payload = eth.payload();
        let Some(id) = payload.get(..2).map(|b| u16::from_be_bytes([b[0], b[1]])) else {
            NetCounters::count(&counters.malformed);
            return;
        };
        if !FrameIdClass::of(id).is_cyclic() {
            // DCP, alarms: the acyclic side's business.
            return self.forward(frame);
        }
        let src = eth.src();
        let Some(d) = usize::from(self.device_by_frame_id[usize::from(id)]).checked_sub(1) else {
            NetCounters::count(&counters.unknown);
            return;
        };
        let Some(run) = self.running.get_mut(d).and_then(Option::as_mut) else {
            return;
        };
        let (c_sdu, data_status, first) = match run.consumer.consume(src, payload, now_ns) {
            Verdict::Accepted {
                c_sdu,
                data_status,
                first,
            } => (Some(c_sdu), data_status, first),
            // The provider says its data are not valid: the image says so too.
            Verdict::Invalid { data_status } => (None, data_status, false),
            Verdict::Stale => return NetCounters::count(&counters.stale),
            Verdict::Foreign => return NetCounters::count(&counters.unknown),
            Verdict::TooShort => return NetCounters::count(&counters.malformed),
        };
        NetCounters::count(&counters.cyclic_frames);
        self.channel
            .peer_data_status
            .store(data_status, Ordering::Relaxed);
        let data = c_sdu.unwrap_or_default();
        for o in &run.ar.input.objects {
            let iops = match (data.get(o.data..o.data + o.len), data.get(o.iops)) {
                (Some(src), Some(&iops)) => {
                    if o.len > 0 {
                        image.set_inputs(o.submodule, src);
                    }
                    iops
                }
                _ => IOXS_BAD,
            };
            let mut st = image.status(o.submodule);
            st.input_iops = iops;
            image.set_status(o.submodule, st);
        }
        for c in &run.ar.input.iocs {
            let mut st = image.status(c.submodule);
            st.output_iocs = data.get(c.offset).copied().unwrap_or(IOXS_BAD);
            image.set_status(c.submodule, st);
        }
        if first {
            let (device, epoch) = (run.ar.device, run.ar.epoch);
            self.report(FromCycle::DataStarted { device, epoch });
        }
    }

    fn check_watchdogs(&mut self, now_ns: u64, image: &mut Image) {
        for d in 0..self.running.len() {
            let expired = self.running[d]
                .as_ref()
                .is_some_and(|r| r.consumer.expired(now_ns));
            if expired {
                let epoch = self.running[d].as_ref().map_or(0, |r| r.ar.epoch);
                NetCounters::count(&self.channel.counters.watchdog_expiries);
                self.stop(d, Some(image));
                self.report(FromCycle::WatchdogExpired { device: d, epoch });
            }
        }
    }
}

/// Whether exchange `ar` carries anything of submodule `s`: data or a status byte in
/// either CR.
fn exchanges(ar: &CyclicAr, s: usize) -> bool {
    [&ar.input, &ar.output].iter().any(|cr| {
        cr.objects.iter().any(|o| o.submodule == s) || cr.iocs.iter().any(|i| i.submodule == s)
    })
}

/// Marks a device's submodules as not exchanged: inputs and the device's consumer status
/// BAD, except directions without data, which stay GOOD as IO-Base specifies.
fn mark_disconnected(image: &mut Image, range: core::ops::Range<usize>) {
    for s in range {
        let e = image.submodules()[s];
        let st = image.status(s);
        image.set_status(
            s,
            SubmoduleStatus {
                input_iops: if e.input_length > 0 {
                    IOXS_BAD
                } else {
                    IOXS_GOOD
                },
                output_iocs: if e.output_length > 0 {
                    IOXS_BAD
                } else {
                    IOXS_GOOD
                },
                ..st
            },
        );
    }
}

impl<N: Nic + 'static> IoSystem for PnioIo<N> {
    fn receive(&mut self, t: CycleTime, mode: Mode, image: &mut Image) {
        let ex = &mut self.ex;
        ex.flush_reports();
        ex.apply_commands(&mut self.nic, t, image);
        if mode == Mode::Offline {
            // OFFLINE exchanges nothing, from its first cycle on: the controller releases
            // the ARs on its own time, but the image says so at once.
            for d in 0..ex.device_submodules.len() {
                ex.stop(d, Some(image));
            }
        }
        let mut frames = 0;
        while frames < MAX_FRAMES_PER_CYCLE {
            match self
                .nic
                .receive(&mut |frame| ex.take_frame(frame, t.now_ns, image))
            {
                Ok(true) => frames += 1,
                // Dropped by the interface: a frame longer than any PROFINET frame.
                Err(RecvError::TooLong { .. }) => {
                    frames += 1;
                    NetCounters::count(&ex.channel.counters.malformed);
                }
                Ok(false) | Err(RecvError::Io { .. }) => break,
            }
        }
        ex.check_watchdogs(t.now_ns, image);
    }

    fn send(&mut self, t: CycleTime, mode: Mode, image: &mut Image) {
        let ex = &mut self.ex;
        // The cycle's scheduled start in RT time units, modulo 2^16 (cycle_counter_at's
        // rule, without the multiplication that would overflow after years of cycles).
        let counter = t.cycle.wrapping_mul(ex.cycle_units) as u16;
        // In CLEAR the provider is stopped: the device applies its substitute values.
        let mut status = match mode {
            Mode::Operate => data_status::OPERATE,
            _ => data_status::CLEAR,
        };
        if ex.channel.station_problem.load(Ordering::Relaxed) {
            status &= !data_status::STATION_OK;
        }
        for r in ex.running.iter_mut().flatten() {
            if !r.ar.due(t.cycle) {
                continue;
            }
            let counters = &ex.channel.counters;
            let sent = match send_from_image(&mut self.nic, r, image, counter, status) {
                Some(sent) => {
                    NetCounters::count(&counters.sent_in_place);
                    sent
                }
                None => {
                    NetCounters::count(&counters.sent_copied);
                    r.ar.fill(&FromImage(image));
                    self.nic.send(r.ar.seal(counter, status))
                }
            };
            if sent.is_err() {
                NetCounters::count(&ex.channel.counters.send_errors);
            }
        }
    }
}

/// Whether `ar`'s output frame can go out from the image as it stands: the image holds the
/// device's frame, of this frame's length, each output the frame carries is there where the
/// frame carries it, and no other output is in it. Then writing the frame's header and
/// status bytes around the outputs changes no output.
fn frame_in_image(ar: &CyclicAr, image: &Image) -> bool {
    let Some(frame) = image.output_frame(ar.device) else {
        return false;
    };
    if frame.range.len() != ar.frame.len() || !ar.data_in_frame_order() {
        return false;
    }
    let c_sdu = frame.range.start + ar.payload_offset() + 2;
    let mut outputs = 0;
    for o in ar.output.objects.iter().filter(|o| o.len > 0) {
        let Some(e) = image.submodules().get(o.submodule) else {
            return false;
        };
        if e.output_mirror_offset as usize != c_sdu + o.data
            || usize::from(e.output_length) != o.len
        {
            return false;
        }
        outputs += 1;
    }
    outputs == frame.outputs
}

/// Sends `r`'s output frame from the image, where the cycle put the outputs: its header,
/// IOPS, IOCS and APDU status written around them. The one copy of an output byte in the
/// server is the cycle's, from the client's sample into the image. `None` if the frame is
/// not in the image.
fn send_from_image(
    nic: &mut impl Nic,
    r: &mut Running,
    image: &mut Image,
    counter: u16,
    status: u8,
) -> Option<Result<(), procimg_nic::SendError>> {
    if !r.in_image {
        return None;
    }
    r.ar.fill_status(&FromImage(image));
    r.ar.seal(counter, status);
    let frame = image.output_frame_mut(r.ar.device)?;
    r.ar.write_around_data(frame).then(|| nic.send(frame))
}

/// The image as what the cycle thread produces: the outputs and their IOPS, and the IOCS
/// for the inputs.
struct FromImage<'a>(&'a Image);

impl ProducedData for FromImage<'_> {
    fn data(&self, submodule: usize) -> &[u8] {
        self.0.outputs(submodule)
    }
    fn iops(&self, submodule: usize) -> u8 {
        self.0.status(submodule).output_iops
    }
    fn iocs(&self, submodule: usize) -> u8 {
        self.0.status(submodule).input_iocs
    }
}

#[cfg(test)]
mod capture_tests;
#[cfg(test)]
mod hostile_tests;
#[cfg(test)]
mod send_tests;
#[cfg(test)]
mod test_rig;
#[cfg(test)]
mod trial_tests;
