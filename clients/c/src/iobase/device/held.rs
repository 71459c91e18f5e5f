// SPDX-License-Identifier: MIT OR Apache-2.0
//! What an open device keeps for the program besides its configuration: its alarms waiting
//! for `PNIO_CBF_REQ_DONE` (see `alarms`) and its isochronous callbacks and window (see `isochronous`).

use crate::iobase::callbacks::CallbackTable;
use crate::iobase::isochronous::Window;
use std::collections::BTreeMap;
use std::sync::Mutex;
use std::sync::atomic::AtomicBool;
use std::thread::JoinHandle;

/// The program's alarms waiting for their acknowledgement.
#[derive(Default)]
pub(crate) struct Waiting {
    /// The last tag given.
    pub next_tag: u64,
    /// Tag → UserHndl.
    pub waiting: BTreeMap<u64, u32>,
}

/// The isochronous part of an open device.
#[derive(Default)]
pub(crate) struct Isochronous {
    /// The `PNIO_CP_CBE_*` callbacks (only the isochronous half of the table is used).
    pub callbacks: CallbackTable,
    /// The open STARTOP..OPDONE window; locked after the device's client.
    pub window: Mutex<Window>,
    /// STARTOP is registered: the client is synchronous.
    pub on: AtomicBool,
    /// Tells the thread to end.
    pub stop: AtomicBool,
    /// The thread that delivers the callbacks.
    pub thread: Mutex<Option<JoinHandle<()>>>,
}
