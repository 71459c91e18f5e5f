// SPDX-License-Identifier: MIT OR Apache-2.0
//! The image as the OPC UA server publishes it: one cycle's inputs, outputs as sent and
//! status bytes of every submodule, taken whole from procimgd's newest image, with the
//! devices' states and the server's status beside it. A thread takes one per cycle (an
//! asynchronous client: nothing on procimgd's cycle thread) and hands it to the server.

use procimg_client::{
    Client, DeviceState, Ioxs, Layout, Mode, StatusReport, SubmoduleIoxs, now_ns,
};
use std::sync::Arc;
use std::time::{Duration, Instant, SystemTime};
use tokio::sync::watch;

/// How often the status report (devices' states, counters) is read.
const STATUS_EVERY: Duration = Duration::from_millis(200);

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
pub fn quality(snap: &Snapshot, layout: &Layout, s: usize, output: bool) -> Quality {
    let Some(e) = layout.submodules.get(s) else {
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
    /// procimgd went away or started with another layout: the address space is no longer
    /// the image's.
    #[error(
        "procimgd's instance \"{0}\" started anew with another layout: restart procimg-opcua to serve it"
    )]
    LayoutChanged(String),
    /// The image could not be read.
    #[error("cannot read the image of instance \"{instance}\": {why}")]
    Image {
        /// The instance.
        instance: String,
        /// What the client said.
        why: String,
    },
}

/// The snapshot of `client`'s newest image with `report`; `None` while there is no image,
/// or when the newest is of cycle `unless` (nothing is copied then).
pub fn take(
    client: &mut Client,
    report: &Arc<StatusReport>,
    unless: Option<u64>,
) -> Option<Snapshot> {
    let n = client.layout().submodules.len();
    let image = match client.newest_image() {
        Ok(image) => image,
        Err(e) => {
            tracing::debug!("no image of instance {:?}: {e}", report.instance);
            return None;
        }
    };
    let cycle = image.cycle();
    if unless == Some(cycle.cycle_number) {
        return None;
    }
    let age = Duration::from_nanos(now_ns().saturating_sub(cycle.cycle_start_ns));
    let bad = SubmoduleIoxs {
        input_remote: Ioxs::Bad,
        input_local: Ioxs::Bad,
        output_local: Ioxs::Bad,
        output_remote: Ioxs::Bad,
    };
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
        status: (0..n).map(|s| image.status(s).unwrap_or(bad)).collect(),
        report: report.clone(),
    })
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

/// Takes `client`'s newest image every `period` and sends it on `tx` (with the status
/// report, read every [`STATUS_EVERY`]) until `stop` says so, the receivers are gone or the
/// layout changes. Runs on a thread of its own: the client blocks.
pub fn feed(
    mut client: Client,
    mut report: Arc<StatusReport>,
    period: Duration,
    tx: watch::Sender<Arc<Snapshot>>,
    stop: impl Fn() -> bool,
) -> Result<(), FeedError> {
    let instance = client.instance().to_owned();
    let hash = client.layout().hash();
    let mut report_at = Instant::now();
    let mut last_cycle = None;
    while !stop() {
        let mut fresh_report = false;
        if report_at.elapsed() >= STATUS_EVERY {
            if let Ok(r) = client.control().status() {
                if r.layout_hash != hash {
                    return Err(FeedError::LayoutChanged(instance));
                }
                report = Arc::new(r);
                fresh_report = true;
            }
            report_at = Instant::now();
        }
        // A cycle already sent is sent again only with a fresh report.
        let unless = if fresh_report { None } else { last_cycle };
        if let Some(snap) = take(&mut client, &report, unless) {
            last_cycle = Some(snap.cycle);
            if tx.send(Arc::new(snap)).is_err() {
                return Ok(());
            }
        }
        std::thread::sleep(period);
    }
    Ok(())
}
