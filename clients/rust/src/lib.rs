// SPDX-License-Identifier: MIT OR Apache-2.0
//! The Rust client of the procimg process-image server.
//!
//! A client attaches to a running `procimgd` by instance name and reads inputs and writes
//! outputs in place in shared memory. A **synchronous** client takes part in the cycle
//! handshake of Siemens' IO-Base isochronous interface: it waits for STARTOP, reads this
//! cycle's inputs, writes its outputs and signals OPDONE; if it is late, it gets OPFAULT. An
//! **asynchronous** client reads the newest consistent image and writes outputs at any time,
//! each write applied whole in one cycle. Both can use IO-Base style access by logical
//! address (`data_read`, `data_write`, the buffered pair).
//!
//! ```no_run
//! use procimg_client::{AttachOptions, Client, Ioxs};
//! use std::time::Duration;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let mut client = Client::attach("procimg", AttachOptions::synchronous("my-plc"))?;
//! let echo = client.layout().find("echo", 1, 1).expect("the demo's echo module");
//! client.claim(&[echo])?;
//! loop {
//!     let mut cycle = client.wait_startop(Duration::from_millis(100))?;
//!     let n = cycle.number();
//!     let seen = cycle.input(echo).map(|i| i[0]).unwrap_or(0);   // in place, no copy
//!     cycle.output_mut(echo)?.fill(n as u8);                       // in place, no copy
//!     cycle.set_opdone()?;
//!     let _ = (seen, Ioxs::Good);
//! }
//! # }
//! ```
#![deny(unsafe_op_in_unsafe_fn)]

pub mod access;
mod arrivals;
mod cache;
mod client;
mod connection;
mod control;
mod cycle;
mod device;
mod error;
// The busy path reads images the handshake block names, in place.
#[allow(unsafe_code)]
mod input_view;
mod io;
pub mod iobase;
mod layout;
// The outputs are written where iceoryx2 loaned them, without its locks.
#[allow(unsafe_code)]
mod output_sample;
mod plug;
// SCHED_FIFO and mlockall are system calls.
#[allow(unsafe_code)]
pub mod realtime;
mod services;
mod station_alarms;
mod station_services;
mod status;
mod wake_ahead;

pub use access::{AccessError, Space};
pub use client::{AttachOptions, Client, Event, EventWait, WAKE_AHEAD};
#[doc(hidden)]
pub use connection::{OutputPublisher, OutputService, Registration, output_publisher};
pub use control::{ControlHandle, DEFAULT_CONTROL_TIMEOUT};
pub use cycle::{Cycle, DetachedCycle, now_ns};
pub use error::{AttachError, ControlError, IoError, WaitError};
pub use io::{ImageView, OutputReadResult, ReadResult};
pub use layout::Layout;
pub use procimg_control::pe;
pub use procimg_control::services::{
    APP_READY_HOLD_TIMEOUT_MS, AR_CHECK_TIMEOUT_MS, AddressProblem, AddressRefusal, AlarmReport,
    ArCr, CrDataObject, DCP_SET_CHECK_TIMEOUT_MS, DeviceDiagnosis, DiagnosisReport,
    ExpectedSubmodule, FailureCause, Notification, RecordConfirmation, RecordStatus, RecordTarget,
    STATION_RECORD_TIMEOUT_MS, StationArCheckJob, StationDcpSetJob, StationRecordJob,
    SubmoduleDiff, TailoringRefusal,
};
pub use procimg_control::{
    AccessArReport, AlarmRefusal, ArReport, ArState, ClientRole, ControllerReport, DefinedIdentity,
    DeviceState, DiagnosisDirection, DiagnosisEntry, DiagnosisKind, DiagnosisSeverity, ForceReport,
    InterfaceCounters, NeighbourReport, PlugRefusal, PortRef, Refusal, RestartClients,
    StationAlarmKind, StationDiagnosisChange, StationProgramReport, StationReport,
    StationTreeEntry, StatusReport, Tailoring, TreeRecords,
};
pub use procimg_rt_alloc as rt_alloc;
pub use procimg_shm_layout::{CycleInfo, Mode};
pub use services::{
    ActivationError, AddressChangeError, ControllerAddress, INTERFACE_SUBSLOT, PORT_SUBSLOT,
    RecordError, RestartError, ServiceOptions, Services,
};
pub use station_services::{AR_REFUSED_NO_RESOURCES, RecordRefusal};
pub use status::{Ioxs, SubmoduleIoxs};

pub use procimg_control::OUTPUT_BUFFER;

#[cfg(test)]
mod send_tests {
    /// Client and Services move between threads: a C program creates a handle on one thread
    /// and uses it on another, and IO-Base calls its callbacks on threads of their own.
    #[test]
    fn handles_are_send() {
        fn send<T: Send>() {}
        send::<crate::Client>();
        send::<crate::Services>();
        send::<crate::ControlHandle>();
    }
}
