// SPDX-License-Identifier: MIT OR Apache-2.0
//! The image as the OPC UA server publishes it: one cycle's inputs, outputs as sent and
//! status bytes of every submodule, taken whole from procimgd's newest image, with the
//! devices' states, the server's status and the layout it is laid out by beside it. A thread
//! takes one per cycle (an asynchronous client: nothing on procimgd's cycle thread) and hands
//! it to the server. Everything the server resolves (an item's bytes, a tree variable, a
//! record's submodule) is resolved against one snapshot's layout, so that when procimgd
//! starts anew with another layout, the names that went away answer `BadNodeIdUnknown` and
//! the others carry on.

use procimg_client::{
    Client, DeviceState, Ioxs, Layout, Mode, StatusReport, SubmoduleIoxs, now_ns,
};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant, SystemTime};
use tokio::sync::watch;

/// How often the status report (devices' states, counters) is read.
const STATUS_EVERY: Duration = Duration::from_millis(200);

/// How old the image a Read finds may be when nothing is monitored faster: the feed's pace
/// without fast subscriptions (never slower than one cycle).
pub const IDLE_PERIOD: Duration = Duration::from_millis(10);

/// How often the feed takes an image: as often as the fastest monitored item samples,
/// between one cycle and [`IDLE_PERIOD`]. Copying every image of a 1 ms cycle that nobody
/// samples so fast would cost a server CPU for nothing.
#[derive(Debug)]
pub struct Pace {
    /// The fastest sampling interval asked for, in ns (`u64::MAX`: none).
    fastest_ns: AtomicU64,
}

impl Default for Pace {
    fn default() -> Pace {
        Pace {
            fastest_ns: AtomicU64::new(u64::MAX),
        }
    }
}

impl Pace {
    /// The fastest sampling interval the monitored items ask for now (`None`: none is
    /// monitored; zero: every image).
    pub fn set(&self, fastest: Option<Duration>) {
        let ns = fastest.map_or(u64::MAX, |d| {
            u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)
        });
        self.fastest_ns.store(ns, Ordering::Relaxed);
    }

    /// The feed's period for a server of cycle `cycle`.
    pub fn period(&self, cycle: Duration) -> Duration {
        let fastest = Duration::from_nanos(self.fastest_ns.load(Ordering::Relaxed));
        fastest.clamp(cycle, IDLE_PERIOD.max(cycle))
    }
}

/// One cycle of the image, whole.
#[derive(Clone, Debug)]
pub struct Snapshot {
    /// The cycle's number.
    pub cycle: u64,
    /// When the cycle started, as wall-clock time: the values' source timestamp.
    pub time: SystemTime,
    /// Per submodule (layout order): its inputs.
    pub inputs: Vec<Vec<u8>>,
    /// Per submodule: its outputs as sent.
    pub outputs: Vec<Vec<u8>>,
    /// Per submodule: its status bytes.
    pub status: Vec<SubmoduleIoxs>,
    /// The newest status report: mode, counters, devices' states.
    pub report: Arc<StatusReport>,
    /// The layout the image is laid out by.
    pub layout: Arc<Layout>,
}

impl Snapshot {
    /// The controller's mode.
    pub fn mode(&self) -> Mode {
        self.report.mode
    }

    /// The state of device `d` (a device-role station: the PLC's AR running or not).
    pub fn device_running(&self, d: usize) -> bool {
        match &self.report.station {
            Some(station) => station.ar.is_some(),
            None => self
                .report
                .devices
                .get(d)
                .is_some_and(|x| x.state == DeviceState::Running),
        }
    }
}

/// What the value of a submodule's data is worth: the OPC UA quality of its bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quality {
    /// In data exchange, the provider's status GOOD.
    Good,
    /// The device is not in data exchange (or, in the device role, no PLC has an AR).
    NotConnected,
    /// In data exchange, but the device marks its inputs invalid (IOPS BAD).
    InputsInvalid,
    /// In data exchange, but the outputs go out marked invalid (IOPS BAD): no client holds
    /// them, or the one that does says so, or the controller is in CLEAR.
    OutputsInvalid,
}

/// The quality of submodule `s`'s inputs (`output` false) or outputs in `snap`: one rule for
/// the browsable variables and the PNIO items.
pub fn quality(snap: &Snapshot, s: usize, output: bool) -> Quality {
    let Some(e) = snap.layout.submodules.get(s) else {
        return Quality::NotConnected;
    };
    if !snap.device_running(usize::from(e.device)) {
        return Quality::NotConnected;
    }
    let Some(st) = snap.status.get(s) else {
        return Quality::NotConnected;
    };
    let provider = if output {
        st.output_local
    } else {
        st.input_remote
    };
    match (provider, output) {
        (Ioxs::Good, _) => Quality::Good,
        (Ioxs::Bad, false) => Quality::InputsInvalid,
        (Ioxs::Bad, true) => Quality::OutputsInvalid,
    }
}

/// Why the feed ended.
#[derive(Debug, thiserror::Error)]
pub enum FeedError {
    /// The image could not be read.
    #[error("cannot read the image of instance \"{instance}\": {why}")]
    Image {
        /// The instance.
        instance: String,
        /// What the client said.
        why: String,
    },
}

/// The snapshot of `client`'s newest image, laid out by `layout` (the client's), with
/// `report`; `None` while there is no image, or when the newest is of cycle `unless`
/// (nothing is copied then).
pub fn take(
    client: &mut Client,
    layout: &Arc<Layout>,
    report: &Arc<StatusReport>,
    unless: Option<u64>,
) -> Option<Snapshot> {
    let n = layout.submodules.len();
    let image = match client.newest_image() {
        Ok(image) => image,
        Err(e) => {
            tracing::debug!("no image of instance {:?}: {e}", report.instance);
            return None;
        }
    };
    let cycle = image.cycle();
    if unless == Some(cycle.cycle_number) || image.layout().hash() != layout.hash() {
        return None;
    }
    let age = Duration::from_nanos(now_ns().saturating_sub(cycle.cycle_start_ns));
    Some(Snapshot {
        cycle: cycle.cycle_number,
        time: SystemTime::now()
            .checked_sub(age)
            .unwrap_or_else(SystemTime::now),
        inputs: (0..n)
            .map(|s| image.input(s).unwrap_or_default().to_vec())
            .collect(),
        outputs: (0..n)
            .map(|s| image.outputs_sent(s).unwrap_or_default().to_vec())
            .collect(),
        status: (0..n).map(|s| image.status(s).unwrap_or(BAD)).collect(),
        report: report.clone(),
        layout: layout.clone(),
    })
}

/// Every status byte BAD: what is known of submodules while procimgd is away.
const BAD: SubmoduleIoxs = SubmoduleIoxs {
    input_remote: Ioxs::Bad,
    input_local: Ioxs::Bad,
    output_local: Ioxs::Bad,
    output_remote: Ioxs::Bad,
};

impl Snapshot {
    /// This snapshot as it stands once procimgd is gone: the same values, no device (no AR)
    /// in data exchange, every status byte BAD, so that every value reads BadNotConnected
    /// until procimgd is back.
    pub fn orphaned(&self) -> Snapshot {
        let mut report = (*self.report).clone();
        for d in &mut report.devices {
            d.state = DeviceState::Offline;
        }
        if let Some(station) = report.station.as_mut() {
            station.ar = None;
        }
        report.mode = Mode::Offline;
        Snapshot {
            status: vec![BAD; self.status.len()],
            report: Arc::new(report),
            ..self.clone()
        }
    }
}

/// The status report of `client`'s server.
pub fn report(client: &Client) -> Result<Arc<StatusReport>, FeedError> {
    client
        .control()
        .status()
        .map(Arc::new)
        .map_err(|e| FeedError::Image {
            instance: client.instance().to_owned(),
            why: e.to_string(),
        })
}

/// How long procimgd may leave the status unanswered before the feed takes it for gone.
const GONE_AFTER: Duration = Duration::from_secs(2);

/// Takes `client`'s newest image at `pace` (a cycle being `cycle`) and sends it on `tx` (with the status
/// report, read every `STATUS_EVERY`) until `stop` says so or the receivers are gone.
/// When procimgd goes away (or starts anew), the image turns [`Snapshot::orphaned`] until
/// the client is attached to the new one (it attaches again by itself) and its images
/// come, with whatever layout procimgd has then. Runs on a thread of its own: the client
/// blocks.
pub fn feed(
    mut client: Client,
    mut report: Arc<StatusReport>,
    (pace, cycle): (&Pace, Duration),
    tx: watch::Sender<Arc<Snapshot>>,
    stop: impl Fn() -> bool,
) -> Result<(), FeedError> {
    let instance = client.instance().to_owned();
    let mut layout = Arc::new(client.layout().clone());
    let mut report_at = Instant::now();
    let mut answered_at = Instant::now();
    let mut last_cycle = None;
    // procimgd went away: nothing is sent until the client is attached to a new one.
    let mut away = false;
    let mut report_now = false;
    while !stop() {
        let mut fresh_report = false;
        if report_now || report_at.elapsed() >= STATUS_EVERY {
            report_now = false;
            report_at = Instant::now();
            match client.control().status() {
                Ok(r) if r.generation == client.generation() => {
                    answered_at = Instant::now();
                    if r.layout_hash == layout.hash() {
                        report = Arc::new(r);
                        fresh_report = true;
                        if away {
                            tracing::info!(
                                "procimgd instance {instance:?} is back (layout {:016x})",
                                layout.hash()
                            );
                            away = false;
                        }
                    }
                }
                // Another generation: the client has not attached to it yet.
                Ok(_) => {}
                Err(e) => tracing::debug!("no status of instance {instance:?}: {e}"),
            }
            if !away && answered_at.elapsed() >= GONE_AFTER {
                tracing::warn!(
                    "procimgd instance {instance:?} is gone or started anew: its values read \
                     BadNotConnected until it is back"
                );
                away = true;
                let orphaned = tx.borrow().orphaned();
                if tx.send(Arc::new(orphaned)).is_err() {
                    return Ok(());
                }
            }
        }
        // Images are taken (the client attaches again in doing so) but not sent while away.
        let unless = if fresh_report { None } else { last_cycle };
        let snap = take(&mut client, &layout, &report, unless);
        if client.layout().hash() != layout.hash() {
            // Attached to a procimgd with another layout: its status comes next.
            layout = Arc::new(client.layout().clone());
            last_cycle = None;
            report_now = true;
            continue;
        }
        if let Some(snap) = snap.filter(|_| !away) {
            last_cycle = Some(snap.cycle);
            if tx.send(Arc::new(snap)).is_err() {
                return Ok(());
            }
        }
        std::thread::sleep(pace.period(cycle));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_feed_keeps_the_pace_of_the_fastest_item_within_a_cycle_and_the_idle_period() {
        let pace = Pace::default();
        let ms = Duration::from_millis;
        assert_eq!(pace.period(ms(1)), IDLE_PERIOD);
        pace.set(Some(ms(4)));
        assert_eq!(pace.period(ms(1)), ms(4));
        pace.set(Some(Duration::ZERO));
        assert_eq!(pace.period(ms(1)), ms(1));
        pace.set(Some(ms(100)));
        assert_eq!(pace.period(ms(1)), IDLE_PERIOD);
        // A cycle slower than the idle period is the pace.
        assert_eq!(pace.period(ms(32)), ms(32));
        pace.set(None);
        assert_eq!(pace.period(ms(2)), IDLE_PERIOD);
    }
}
