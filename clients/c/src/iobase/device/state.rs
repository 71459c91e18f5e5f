// SPDX-License-Identifier: MIT OR Apache-2.0
//! One open IO device: its lifecycle, the program's configuration (APIs, modules,
//! submodules), its ARs, its client, services handle and library thread; and the
//! process-wide table of handles.

use super::Pos;
use super::held::{Isochronous, Waiting};
use super::jobs::{Job, Worker};
use crate::iobase::device_types::PNIO_CBF_FUNCTIONS;
use crate::iobase::errors::*;
use crate::iobase::sync::lock;
use crate::iobase::{handles, stopped};
use procimg_client::iobase::IoBaseDevice;
use procimg_client::{Client, Layout, Mode, StationTreeEntry};
use std::collections::{BTreeMap, BTreeSet};
use std::sync::{Arc, Mutex};

/// Where a device stands in the manual's program sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Life {
    /// After `PNIO_device_open`: APIs are added and modules plugged.
    Opened,
    /// After `PNIO_device_start`: PLCs may connect.
    Started,
    /// `PNIO_device_stop` called, `PNIO_CBF_DEVICE_STOPPED` not yet.
    Stopping,
    /// `PNIO_CBF_DEVICE_STOPPED` came: pull, remove the APIs, close (or start again).
    Stopped,
}

impl Life {
    /// The manual's name of the state, for error texts.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Life::Opened => "opened (not started)",
            Life::Started => "started",
            Life::Stopping => "stopping (PNIO_CBF_DEVICE_STOPPED not yet called)",
            Life::Stopped => "stopped",
        }
    }
}

/// A configured position of procimgd's station, with the ident numbers it is configured
/// with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Position {
    /// API, slot, subslot.
    pub at: Pos,
    /// ModuleIdentNumber in the configuration.
    pub module_ident: u32,
    /// SubmoduleIdentNumber in the configuration.
    pub submodule_ident: u32,
}

/// What the program configured, and where it stands.
pub(crate) struct Config {
    /// The lifecycle.
    pub life: Life,
    /// The added APIs with their highest slot and subslot numbers.
    pub apis: BTreeMap<u32, (u16, u16)>,
    /// The program's modules: (API, slot) → ModuleIdentNumber.
    pub modules: BTreeMap<(u32, u16), u32>,
    /// The program's submodules: position → SubmoduleIdentNumber.
    pub subs: BTreeMap<Pos, u32>,
    /// Plugs and pulls given to the library thread whose confirmation has not been called.
    pub pending: u32,
    /// The program's submodules plugged with I&M0 bits: their I&M records are the program's.
    pub im: BTreeSet<Pos>,
    /// The SequenceNum of the last record job.
    pub record_sequence: u32,
    /// The tree this device defined the station with, if it did (a station its program
    /// defines).
    pub defined: Option<Vec<StationTreeEntry>>,
}

/// One open device.
pub(crate) struct Device {
    /// The device handle.
    pub handle: u32,
    /// The CpIndex it was opened with.
    pub cp_index: u32,
    /// The procimgd instance CpIndex names.
    pub instance: String,
    /// The program's callbacks.
    pub cbf: PNIO_CBF_FUNCTIONS,
    /// `PNIO_device_open_ext`'s highest slot and subslot numbers.
    pub high: Option<(u16, u16)>,
    /// Opened with `PNIO_CEP_PE_MODE_ENABLE`: the program answers its submodules'
    /// PROFIenergy records (0x80A0) through its record callbacks.
    pub pe: bool,
    /// The station's positions, as its layout has them (a station its program defines
    /// gets new ones at start).
    positions: Mutex<Arc<Vec<Position>>>,
    /// For a station its program defines (`[station] gsdml`): the GSDML file, as procimgd
    /// reported it. The program's tree is then checked against the file and defined at
    /// start.
    pub gsdml: Option<String>,
    /// The program's configuration and the lifecycle.
    pub config: Mutex<Config>,
    /// The client of the instance (plug, pull, mode).
    pub client: Mutex<Client>,
    /// The IO-Base semantics: the station's notifications and services (it checks ARs and
    /// holds the ApplicationReady), the ARs, the diagnosis by DiagTag, the LED.
    pub iobase: IoBaseDevice,
    /// The program's alarms waiting for the PLC's acknowledgement.
    pub alarms: Mutex<Waiting>,
    /// The isochronous callbacks, the STARTOP window and the thread that delivers them.
    pub iso: Isochronous,
    worker: Mutex<Option<Worker>>,
}

static DEVICES: Mutex<BTreeMap<u32, Arc<Device>>> = Mutex::new(BTreeMap::new());

/// The open device with this handle (not one the watchdog's expiry stopped).
pub(crate) fn lookup(handle: u32) -> Option<Arc<Device>> {
    lookup_any(handle).filter(|d| !stopped::expired(d.handle))
}

/// The open device with this handle, also after the watchdog's expiry (for close).
pub(crate) fn lookup_any(handle: u32) -> Option<Arc<Device>> {
    lock(&DEVICES).get(&handle).cloned()
}

/// The open devices on procimgd instance `instance`.
pub(crate) fn on_instance(instance: &str) -> Vec<Arc<Device>> {
    lock(&DEVICES)
        .values()
        .filter(|d| d.instance == instance)
        .cloned()
        .collect()
}

/// The handles of the devices open now.
pub(crate) fn open_handles() -> Vec<u32> {
    lock(&DEVICES).keys().copied().collect()
}

/// Whether a device of this process has instance `instance` open.
pub(crate) fn instance_open(instance: &str) -> bool {
    lock(&DEVICES).values().any(|d| d.instance == instance)
}

/// The text for a handle that is not an open device.
pub(crate) fn wrong_handle(function: &str, handle: u32) -> u32 {
    if stopped::expired(handle) && lookup_any(handle).is_some() {
        return stopped::refused(function, handle);
    }
    fail(
        function,
        PNIO_ERR_WRONG_HND,
        format_args!(
            "handle {handle} is not an open device (closed, or never returned by \
             PNIO_device_open)"
        ),
    )
}

impl Device {
    /// Makes an opened device and starts its library thread with `spawn`; returns its
    /// handle.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn register(
        cp_index: u32,
        instance: String,
        cbf: PNIO_CBF_FUNCTIONS,
        high: Option<(u16, u16)>,
        pe: bool,
        gsdml: Option<String>,
        client: Client,
        iobase: IoBaseDevice,
        spawn: impl FnOnce(Arc<Device>) -> std::io::Result<Worker>,
    ) -> Result<u32, u32> {
        let handle = handles::next();
        let dev = Arc::new(Device {
            handle,
            cp_index,
            instance,
            cbf,
            high,
            pe,
            positions: Mutex::new(Arc::new(positions_of(client.layout()))),
            gsdml,
            config: Mutex::new(Config {
                life: Life::Opened,
                apis: BTreeMap::new(),
                modules: BTreeMap::new(),
                subs: BTreeMap::new(),
                pending: 0,
                im: BTreeSet::new(),
                record_sequence: 0,
                defined: None,
            }),
            client: Mutex::new(client),
            iobase,
            alarms: Mutex::new(Waiting::default()),
            iso: Isochronous::default(),
            worker: Mutex::new(None),
        });
        let worker = spawn(dev.clone()).map_err(|e| {
            fail(
                "PNIO_device_open",
                PNIO_ERR_START_THREAD_FAILED,
                format_args!("cannot start the device's thread: {e}"),
            )
        })?;
        *lock(&dev.worker) = Some(worker);
        lock(&DEVICES).insert(handle, dev);
        Ok(handle)
    }

    /// Gives a job to the library thread.
    pub(crate) fn send(&self, job: Job) -> Result<(), u32> {
        match lock(&self.worker).as_ref() {
            Some(w) => w.send(job),
            None => Err(PNIO_ERR_WRONG_HND),
        }
    }

    /// `PNIO_device_close` after the checks: the library thread finishes its jobs and ends,
    /// the handle goes, a station this device defined waits for its next program, the
    /// station no longer waits for this device's AR checks and ApplicationReady, then the
    /// client goes.
    pub(crate) fn close(&self) {
        // No isochronous callback runs once close returned; one running now still finds
        // the handle for its PNIO_CP_set_opdone.
        self.iso.stop();
        lock(&DEVICES).remove(&self.handle);
        stopped::forget(self.handle);
        let worker = lock(&self.worker).take();
        if let Some(w) = worker {
            w.stop();
        }
        if lock(&self.config).defined.is_some() {
            // The program ends: its AR ends with an abort, and the station waits off the
            // wire for the next one. A server that is gone has nothing to release.
            let _ = self.iobase.services().release_station();
        }
        self.iobase.close();
    }

    /// `PNIO_device_close` after the watchdog's expiry, in any state: a started device goes
    /// OFFLINE first (the PLC's AR ends), as `PNIO_device_stop` would.
    pub(crate) fn close_stopped(&self) {
        let life = lock(&self.config).life;
        if matches!(life, Life::Started | Life::Stopping) {
            let _ = lock(&self.client).control().set_mode(Mode::Offline);
        }
        self.close();
    }

    /// The watchdog expired: the I data the device holds goes out BAD from now on (its
    /// isochronous thread answers every later cycle so).
    pub(crate) fn outputs_bad(&self) {
        let mut client = lock(&self.client);
        let mut window = lock(&self.iso.window);
        if window.is_open() {
            window.finish_bad(&mut client);
        } else {
            crate::iobase::isochronous::outputs_bad(&mut client);
        }
    }

    /// The station's positions now.
    pub(crate) fn positions(&self) -> Arc<Vec<Position>> {
        lock(&self.positions).clone()
    }

    /// The station's positions are `layout`'s from now on (the client follows a new one).
    pub(crate) fn follow_layout(&self, layout: &Layout) {
        *lock(&self.positions) = Arc::new(positions_of(layout));
    }

    /// Whether the station has a position at `at`.
    pub(crate) fn has_position(&self, at: Pos) -> bool {
        lock(&self.positions).iter().any(|p| p.at == at)
    }
}

/// The positions of `layout`, in its order.
pub(crate) fn positions_of(layout: &Layout) -> Vec<Position> {
    layout
        .submodules
        .iter()
        .map(|s| Position {
            at: (s.api, s.slot, s.subslot),
            module_ident: s.module_ident,
            submodule_ident: s.submodule_ident,
        })
        .collect()
}
