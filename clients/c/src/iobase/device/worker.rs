// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device's library thread: carries the program's plugs and pulls, `PNIO_device_start`,
//! `PNIO_device_stop` and `PNIO_device_ar_abort` out on procimgd, one at a time in the order
//! they were called, and calls `PNIO_CBF_PULL_PLUG_CONF` and `PNIO_CBF_DEVICE_STOPPED`;
//! between jobs it has the station's notifications delivered (by the device's
//! [`IoBaseDevice`](procimg_client::iobase::IoBaseDevice) to [`super::ar`]'s callbacks). All callbacks of a device come from this thread, so in the order of their
//! causes (inside them only the IO data functions are allowed).

use super::Pos;
use super::alarms;
use super::ar;
use super::config::{defines_tree, program_tree};
use super::data;
use super::jobs::{Job, Worker};
use super::records;
use super::state::{Device, Life};
use super::station::{Occupants, code_of, plug, pull};
use crate::iobase::callbacks::invoke_device;
use crate::iobase::device_types::*;
use crate::iobase::errors::*;
use crate::iobase::sync::lock;
use crate::iobase::types::PNIO_ERR_STAT;
use crate::iobase::wake::Wake;
use procimg_client::iobase::AbortError;
use procimg_client::{ControlError, Mode, Refusal, StationTreeEntry};
use std::sync::Arc;
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::time::{Duration, Instant};

/// The longest the thread sleeps with neither a job nor a notification (a safety net: both
/// wake it).
const IDLE: Duration = Duration::from_millis(500);
/// How long a stop or an AR abort waits for the station to report the AR's end; then the
/// library ends it itself (`PNIO_AR_REASON_ABORT`).
const END_WAIT: Duration = Duration::from_secs(5);
/// How long `PNIO_device_start` waits for procimgd to run the station the program defined.
const DEFINE_WAIT: Duration = Duration::from_secs(10);

/// Starts the library thread of `dev`.
pub(crate) fn spawn(dev: Arc<Device>) -> std::io::Result<Worker> {
    let (jobs, rx) = channel();
    let wake = Arc::new(Wake::new()?);
    let woken = wake.clone();
    let thread = std::thread::Builder::new()
        .name(format!("pnio-dev-{}", dev.handle))
        .spawn(move || run(dev, rx, &woken))?;
    Ok(Worker::new(jobs, wake, thread))
}

/// Carries out the jobs in order and delivers the notifications, asleep on the services
/// handle's descriptor and the wake-up of a job until either comes (or the LED's flashing
/// is over).
fn run(dev: Arc<Device>, rx: Receiver<Job>, wake: &Wake) {
    let dev = &*dev;
    let mut occupants = occupants_of(dev);
    let mut taken = records::Taken::new();
    let notify_fd = dev.iobase.notify_fd();
    loop {
        wake.clear();
        loop {
            match rx.try_recv() {
                Ok(job) => run_job(dev, &mut occupants, job),
                Err(TryRecvError::Empty) => break,
                Err(TryRecvError::Disconnected) => return,
            }
        }
        records::follow(dev, &mut taken);
        dev.iobase.poll(&mut ar::Callbacks {
            dev,
            occupants: &mut occupants,
        });
        let sleep = dev.iobase.next_deadline().map_or(IDLE, |t| {
            t.saturating_duration_since(Instant::now()).min(IDLE)
        });
        procimg_shm_layout::os::wait_any_readable([wake.fd(), notify_fd], sleep.as_nanos() as u64);
    }
}

/// What procimgd has at each of the station's positions, as its layout says.
fn occupants_of(dev: &Device) -> Occupants {
    dev.positions()
        .iter()
        .map(|p| (p.at, Some((p.module_ident, p.submodule_ident))))
        .collect()
}

/// Whether a plug or pull at `at` only changes the tree the program defines at start (not
/// procimgd's station now).
fn tree_only(dev: &Device, at: Pos) -> bool {
    at.1 != 0 && defines_tree(dev, &lock(&dev.config))
}

/// The uuid of the current AR, if there is one.
fn current_uuid(dev: &Device) -> Option<String> {
    dev.iobase.current_ar().map(|a| a.uuid)
}

fn run_job(dev: &Device, occupants: &mut Occupants, job: Job) {
    match job {
        Job::Plug {
            api,
            at,
            idents,
            mut addr,
        } => {
            let code = if tree_only(dev, at) {
                PNIO_OK
            } else {
                plug(&lock(&dev.client), occupants, at, idents)
            };
            let started = lock(&dev.config).life == Life::Started;
            if code == PNIO_OK && started {
                // Plugged all the same: without the claim the PLC gets the I data with IOPS
                // BAD, and PNIO_initiate_data_write says why.
                let _ = data::claim(&mut lock(&dev.client), &[at]);
            }
            if code != PNIO_OK {
                let mut c = lock(&dev.config);
                if c.subs.get(&at) == Some(&idents.1) {
                    c.subs.remove(&at);
                }
            }
            confirm(dev, api, PNIO_SUB_PLUG, &mut addr, code);
        }
        Job::Pull {
            api,
            at,
            action,
            module,
            mut addr,
        } => {
            let mut code = PNIO_OK;
            let mut kept = Vec::new();
            {
                let mut client = lock(&dev.client);
                for &(p, _) in &at {
                    data::release(&mut client, Some(p));
                }
                for (p, ident) in at {
                    if tree_only(dev, p) {
                        continue;
                    }
                    let c = pull(&client, occupants, p);
                    if c != PNIO_OK {
                        code = c;
                        kept.push((p, ident));
                    }
                }
            }
            if code != PNIO_OK {
                let started = lock(&dev.config).life == Life::Started;
                if started {
                    // The program keeps these: its I data too.
                    let at: Vec<Pos> = kept.iter().map(|&(p, _)| p).collect();
                    let _ = data::claim(&mut lock(&dev.client), &at);
                }
                let mut c = lock(&dev.config);
                c.subs.extend(kept);
                if let Some((m, ident)) = module {
                    c.modules.insert(m, ident);
                }
            }
            confirm(dev, api, action, &mut addr, code);
        }
        Job::Confirm {
            api,
            action,
            mut addr,
        } => confirm(dev, api, action, &mut addr, PNIO_OK),
        Job::Start(reply) => {
            let _ = reply.send(start(dev, occupants));
        }
        Job::Stop => {
            let running = current_uuid(dev);
            let code = match lock(&dev.client).control().set_mode(Mode::Offline) {
                Ok(()) => PNIO_OK,
                Err(e) => code_of(&e),
            };
            if let Some(uuid) = running {
                ar::until_ended(dev, occupants, &uuid, END_WAIT);
            }
            if code == PNIO_OK {
                data::release(&mut lock(&dev.client), None);
            }
            lock(&dev.config).life = if code == PNIO_OK {
                Life::Stopped
            } else {
                Life::Started
            };
            if let Some(f) = dev.cbf.cbf_device_stopped {
                // SAFETY: a PNIO_CBF_DEVICE_STOPPED the program gave PNIO_device_open,
                // callable until PNIO_device_close (which waits for this thread).
                invoke_device(|| unsafe { f(dev.handle, code) });
            }
        }
        Job::AlarmDone { user, status } => {
            alarms::done(dev, user, status, PNIO_ERR_STAT::default())
        }
        Job::Abort(ar) => {
            let mut callbacks = ar::Callbacks { dev, occupants };
            match dev.iobase.abort(ar, &mut callbacks) {
                // Ended meanwhile: its end callback was given.
                Ok(()) | Err(AbortError::Session(_)) => {}
                Err(e) => {
                    fail("PNIO_device_ar_abort", PNIO_ERR_NO_FW_COMMUNICATION, e);
                }
            }
        }
    }
}

/// Counts a confirmation and calls `PNIO_CBF_PULL_PLUG_CONF`, if registered.
fn confirm(dev: &Device, api: u32, action: PNIO_DEV_ACTION, addr: &mut PNIO_DEV_ADDR, code: u32) {
    {
        let mut c = lock(&dev.config);
        c.pending = c.pending.saturating_sub(1);
    }
    if let Some(f) = dev.cbf.cbf_pull_plug_conf {
        let addr: *mut PNIO_DEV_ADDR = addr;
        // SAFETY: a PNIO_CBF_PULL_PLUG_CONF the program gave PNIO_device_open, callable until
        // PNIO_device_close (which waits for this thread); `addr` is valid for the call.
        invoke_device(|| unsafe { f(dev.handle, api, action, addr, code) });
    }
}

/// `PNIO_device_start`: a station its program defines is defined with the program's tree
/// (unless it has that one already); else the positions outside slot 0 that the program did
/// not plug are pulled. Then procimgd goes to OPERATE, the program's I data claimed. `Err`
/// with the code and the text for the caller.
fn start(dev: &Device, occupants: &mut Occupants) -> Result<(), (u32, String)> {
    let (mine, tree, defined) = {
        let c = lock(&dev.config);
        let mine: Vec<Pos> = c.subs.keys().copied().collect();
        (mine, program_tree(&c), c.defined.clone())
    };
    if dev.gsdml.is_some() && defined.as_ref() != Some(&tree) {
        define(dev, &tree)?;
        *occupants = occupants_of(dev);
        lock(&dev.config).defined = Some(tree);
    } else if dev.gsdml.is_none() {
        pull_unplugged(dev, occupants, &mine)?;
    }
    let mut client = lock(&dev.client);
    data::claim(&mut client, &mine).map_err(|e| {
        (
            PNIO_ERR_NO_CONNECTION,
            format!("instance \"{}\": {e}", dev.instance),
        )
    })?;
    client.control().set_mode(Mode::Operate).map_err(|e| {
        (
            code_of(&e),
            format!("instance \"{}\" did not take OPERATE: {e}", dev.instance),
        )
    })
}

/// Pulls the station's positions outside slot 0 that the program did not plug (`mine`).
fn pull_unplugged(
    dev: &Device,
    occupants: &mut Occupants,
    mine: &[Pos],
) -> Result<(), (u32, String)> {
    let client = lock(&dev.client);
    for p in dev.positions().iter() {
        if p.at.1 == 0 || mine.contains(&p.at) || occupants.get(&p.at) == Some(&None) {
            continue;
        }
        let code = pull(&client, occupants, p.at);
        if code != PNIO_OK {
            let (api, slot, subslot) = p.at;
            return Err((
                code,
                format!(
                    "instance \"{}\" did not pull API {api} slot {slot} subslot {subslot:#06x}, \
                     which the program did not plug",
                    dev.instance
                ),
            ));
        }
    }
    Ok(())
}

/// Defines procimgd's station with `tree` and follows it: procimgd runs the station anew
/// with it, and the device's client re-attaches to the new layout (within [`DEFINE_WAIT`]).
fn define(dev: &Device, tree: &[StationTreeEntry]) -> Result<(), (u32, String)> {
    let mut client = lock(&dev.client);
    let before = client.generation();
    let defined = dev.iobase.services().define_station(tree);
    defined.map_err(|e| {
        let code = match &e {
            ControlError::Refused(Refusal::BadRequest { .. }) => PNIO_ERR_PRM_ADD,
            e => code_of(e),
        };
        (
            code,
            format!(
                "instance \"{}\" did not take the program's tree: {e}",
                dev.instance
            ),
        )
    })?;
    let until = Instant::now() + DEFINE_WAIT;
    while client.generation() == before || !client.connected() {
        if Instant::now() >= until {
            return Err((
                PNIO_ERR_NO_FW_COMMUNICATION,
                format!(
                    "instance \"{}\" took the program's tree but did not run the station \
                     with it within {} s",
                    dev.instance,
                    DEFINE_WAIT.as_secs()
                ),
            ));
        }
        // Waiting for a cycle drives the client: it re-attaches when the server's new
        // generation is there.
        let _ = client.wait_startop(Duration::from_millis(20));
    }
    // The events of the change are the library's own doing.
    let _ = client.events();
    dev.follow_layout(client.layout());
    Ok(())
}
