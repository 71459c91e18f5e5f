// SPDX-License-Identifier: MIT OR Apache-2.0
//! What an open device keeps for the program besides its configuration: its alarms waiting
//! for `PNIO_CBF_REQ_DONE` (see `alarms`), its diagnosis entries by DiagTag (see `diag`),
//! and its isochronous callbacks and window (see `isochronous`).

use super::Pos;
use crate::iobase::callbacks::CallbackTable;
use crate::iobase::isochronous::Window;
use procimg_client::DiagnosisEntry;
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

/// The kinds of entries, one per add function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DiagFn {
    /// `PNIO_diag_channel_add`.
    Channel,
    /// `PNIO_diag_ext_channel_add`.
    ExtChannel,
    /// `PNIO_diag_generic_add`.
    Generic,
}

/// The program's entries: (submodule, DiagTag) → their kind and the entry.
pub(crate) type Entries = BTreeMap<(Pos, u16), (DiagFn, DiagnosisEntry)>;

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
