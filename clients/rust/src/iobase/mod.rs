// SPDX-License-Identifier: MIT OR Apache-2.0
//! IO-Base's device semantics in safe Rust: what Siemens' IO-Base device interface
//! (`pniousrd.h`) gives a device program beyond the process image, for Rust programs and
//! as the core under the C library's `PNIO_device_*` functions, which only convert types.
//!
//! * [`IoBaseDevice`]: the AR indications in the manual's order, ArNumber and SessionKey,
//!   the program's ApplicationReady, an abort of one AR, the diagnosis by DiagTag and the
//!   LED flashing of a DCP Signal, over a [`Services`](crate::Services) handle;
//! * [`DeviceCallbacks`]: the callbacks, one method each;
//! * [`AppWatchdogs`]: the CP application watchdog's rule (the caller owns the timer);
//! * [`ArSessions`], [`DiagTags`], [`LedFlash`], [`ArEndReason`]: the rules on their own,
//!   for a program that drives them itself.
//!
//! And what PN Driver's start-up gives a controller or device program
//! (`SERV_CP_get_network_adapters`, `SERV_CP_startup`, `SERV_CP_shutdown`):
//! [`network_adapters`], the machine's Ethernet adapters to choose from, and [`Stack`], a
//! procimgd started with the program's configuration on the adapter it chose, ending with it.
//!
//! The IO data stay the client's: a device program attaches a [`Client`](crate::Client)
//! as any other, claims its I data and exchanges them in the cycle; [`ProgramAr::is_ready`]
//! tells when the PLC's AR takes them.
//!
//! ```no_run
//! use procimg_client::iobase::{ArId, DeviceCallbacks, IoBaseDevice};
//! use std::time::Duration;
//!
//! #[derive(Default)]
//! struct Program {
//!     prm_end: Option<ArId>,
//! }
//!
//! impl DeviceCallbacks for Program {
//!     fn prm_end(&mut self, ar: ArId, submodule: Option<(u32, u16, u16)>) {
//!         self.prm_end = Some(ar);
//!         let _ = submodule;
//!     }
//!     fn in_data(&mut self, ar: ArId) {
//!         println!("AR {} in data exchange", ar.number);
//!     }
//! }
//!
//! let device = IoBaseDevice::open("procimg", "my-device")?;
//! let mut program = Program::default();
//! loop {
//!     device.wait(Duration::from_millis(100), &mut program);
//!     if let Some(ar) = program.prm_end.take() {
//!         // Parameters taken: the PLC may have the inputs.
//!         device.application_ready(ar, &[])?;
//!     }
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod adapters;
mod callbacks;
mod device;
mod diag_tags;
mod end_reason;
mod led;
mod sessions;
mod stack;
mod watchdog;

pub use adapters::{NetworkAdapter, PciLocation, adapters_under, network_adapters, parse_mac};
pub use callbacks::DeviceCallbacks;
pub use device::{
    AbortError, ApplicationReadyError, DeviceOpenError, END_WAIT, IoBaseDevice, MODE_WAIT,
};
pub use diag_tags::{
    CHAN_PROP_MAINT_DEMANDED, CHAN_PROP_MAINT_REQUIRED, DiagTagError, DiagTagKind, DiagTags,
    Position, channel_entry, channel_properties, generic_entry,
};
pub use end_reason::{
    ArEndReason, REASON_ABORT, REASON_HIGHEST_ABORT_CODE, REASON_NONE, REASON_REL, REASON_RERUN,
};
pub use led::{FLASH_FOR, FLASH_HZ, LedFlash};
pub use sessions::{
    ApduStatus, ArId, ArPhase, ArSessions, ProgramAr, Ready, ReadyError, SessionError,
};
pub use stack::{
    LogSink, START_TIMEOUT, STOP_TIMEOUT, Stack, StackStart, StackStartError, StackStopError,
    instance_serves, procimgd_program,
};
pub use watchdog::{AppWatchdogs, WatchdogError};
