// SPDX-License-Identifier: MIT OR Apache-2.0
//! The jobs an open device gives its library thread, and the handle of that thread
//! (`worker.rs` runs it).

use super::Pos;
use crate::iobase::device_types::*;
use crate::iobase::errors::*;
use crate::iobase::wake::Wake;
use procimg_client::iobase::ArId;
use std::sync::Arc;
use std::sync::mpsc::{Sender, SyncSender};
use std::thread::JoinHandle;

/// What the library thread does.
pub(crate) enum Job {
    /// Plug the program's submodule at `at`; confirm with `PNIO_SUB_PLUG`.
    Plug {
        /// The API of the call.
        api: u32,
        /// Where.
        at: Pos,
        /// ModuleIdentNumber, SubmoduleIdentNumber.
        idents: (u32, u32),
        /// The program's address, for the confirmation.
        addr: PNIO_DEV_ADDR,
    },
    /// Pull the program's submodules at `at` (a submodule, or a module's); confirm with
    /// `action`. On failure the program keeps what `restore` says.
    Pull {
        /// The API of the call.
        api: u32,
        /// The submodules.
        at: Vec<(Pos, u32)>,
        /// `PNIO_SUB_PULL` or `PNIO_MOD_PULL`.
        action: PNIO_DEV_ACTION,
        /// The module to restore on failure (`PNIO_mod_pull`).
        module: Option<((u32, u16), u32)>,
        /// The program's address, for the confirmation.
        addr: PNIO_DEV_ADDR,
    },
    /// Confirm a call that needs nothing of procimgd (`PNIO_mod_plug`).
    Confirm {
        /// The API of the call.
        api: u32,
        /// What is confirmed.
        action: PNIO_DEV_ACTION,
        /// The program's address.
        addr: PNIO_DEV_ADDR,
    },
    /// `PNIO_device_start`: pull what the program did not plug, then OPERATE; the result
    /// goes back to the caller.
    Start(SyncSender<Result<(), (u32, String)>>),
    /// `PNIO_device_stop`: OFFLINE, the current AR's `AR_OFFLINE_IND` or `AR_ABORT_IND`, then
    /// `PNIO_CBF_DEVICE_STOPPED`.
    Stop,
    /// `PNIO_device_ar_abort` of this AR: the station ends it, and the library delivers the
    /// notifications until its end callback was given.
    Abort(ArId),
    /// `PNIO_CBF_REQ_DONE` of an alarm that did not go out, with `status`.
    AlarmDone {
        /// The program's UserHndl.
        user: u32,
        /// The Status.
        status: u32,
    },
}

/// The library thread of a device.
pub(crate) struct Worker {
    jobs: Sender<Job>,
    /// Wakes the thread for a job or the stop.
    wake: Arc<Wake>,
    thread: JoinHandle<()>,
}

impl Worker {
    /// The library thread `thread`, taking jobs from `jobs` when `wake` is raised.
    pub(crate) fn new(jobs: Sender<Job>, wake: Arc<Wake>, thread: JoinHandle<()>) -> Worker {
        Worker { jobs, wake, thread }
    }

    /// Queues a job.
    pub(crate) fn send(&self, job: Job) -> Result<(), u32> {
        self.jobs.send(job).map_err(|_| PNIO_ERR_INTERNAL)?;
        self.wake.raise();
        Ok(())
    }

    /// Lets the thread finish its jobs and waits for it.
    pub(crate) fn stop(self) {
        drop(self.jobs);
        self.wake.raise();
        // A panic on that thread already ended it.
        let _ = self.thread.join();
    }
}
