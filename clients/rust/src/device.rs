// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO device role's view of the image: a server with `role = "device"` is a PROFINET
//! IO device, and its clients provide the device's input data (I), which the PLC reads, and
//! consume the output data (Q) the PLC wrote. Directions are named from the PLC's view, as
//! in IO-Base's device interface.
//!
//! The image keeps its two directions (see [`procimg_shm_layout::ROLE_DEVICE`]): the Q data
//! is in the server-written part, the I data in the client-written part, so the generic
//! calls work too; these name them as a device program thinks of them. A device call on a
//! controller's server is an error ([`IoError::NotDevice`]), never a silent mix-up.
//!
//! A device program follows its AR — GOAL's and IO-Base's AR indications — through a
//! [`Services`](crate::Services) handle: [`Services::next`](crate::Services::next) (or
//! [`try_next`](crate::Services::try_next) between cycles) gives a
//! [`Notification::StationAr`](crate::Notification::StationAr) as the PLC's AR reaches
//! [`ArState::Connected`](crate::ArState::Connected) (Connect accepted),
//! [`Parameterized`](crate::ArState::Parameterized) (the PLC's PrmEnd),
//! [`WaitingForApplicationReadyConfirm`](crate::ArState::WaitingForApplicationReadyConfirm)
//! and [`Data`](crate::ArState::Data) (IN_DATA: the PLC confirmed the ApplicationReady), then [`StationArEnded`](crate::Notification::StationArEnded) with
//! why it ended (released by the PLC, an IO data timeout, procimgd stopping). Also
//! [`StationPlcRunning`](crate::Notification::StationPlcRunning) for the PLC's RUN/STOP,
//! [`StationBlink`](crate::Notification::StationBlink) for DCP Signal and
//! [`StationIdentity`](crate::Notification::StationIdentity) when DCP gave the station a
//! name or address. A handle sees what happens after it was opened: where the AR stands
//! already is in the status ([`ControlHandle::status`](crate::ControlHandle::status),
//! `station.ar`).
//!
//! ```no_run
//! use procimg_client::{ArState, AttachOptions, Client, Notification, ServiceOptions, Services};
//! use std::time::Duration;
//!
//! let mut events = Services::open("procimg", ServiceOptions::new("echo-events"))?;
//! let mut client = Client::attach("procimg", AttachOptions::synchronous("echo"))?;
//! let mine = client.claim_i_data()?;
//! loop {
//!     let mut cycle = client.wait_startop(Duration::from_secs(1))?;
//!     for &s in &mine {
//!         // Q into I: what the PLC writes comes back to it.
//!         let q = cycle.q_data(s)?.to_vec();
//!         let i = cycle.i_data_mut(s)?;
//!         let n = i.len().min(q.len());
//!         i[..n].copy_from_slice(&q[..n]);
//!     }
//!     cycle.set_opdone()?;
//!     while let Some(n) = events.try_next() {
//!         match n {
//!             Notification::StationAr {
//!                 state: ArState::Data,
//!                 ..
//!             } => println!("IN_DATA"),
//!             Notification::StationArEnded { reason, .. } => println!("AR ended: {reason}"),
//!             _ => {}
//!         }
//!     }
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::client::Client;
use crate::cycle::Cycle;
use crate::error::{ControlError, IoError};
use crate::status::Ioxs;
use procimg_control::{DeviceRequest, DiagnosisEntry, StationDiagnosisChange};

impl Client {
    /// Whether the server is an IO device (`role = "device"`).
    pub fn is_device(&self) -> bool {
        self.layout().is_device()
    }

    /// In the device role: claims the I data of every submodule that has some (those no other
    /// client holds), for this client to provide; returns their indexes. Until a client owns
    /// a submodule's I data, the PLC gets it with IOPS BAD.
    pub fn claim_i_data(&mut self) -> Result<Vec<usize>, ControlError> {
        if !self.is_device() {
            return Err(ControlError::NotDevice {
                instance: self.instance().to_owned(),
            });
        }
        let mine: Vec<usize> = self.layout().output_submodules().collect();
        self.claim(&mine)?;
        Ok(mine)
    }

    /// In the device role: `entry` appears on the submodule at `api`/`slot`/`subslot` (or an
    /// entry of the same channel and error changes its severity). The PLC gets the diagnosis
    /// alarm while its AR runs, and the entry in the diagnosis records (0x800A and the
    /// others); a fault turns the station problem indicator on.
    pub fn add_diagnosis(
        &self,
        (api, slot, subslot): (u32, u16, u16),
        entry: DiagnosisEntry,
    ) -> Result<(), ControlError> {
        self.station_diagnosis(StationDiagnosisChange::Add {
            api,
            slot,
            subslot,
            entry,
        })
    }

    /// In the device role: the entry of the same channel and error (or USI) disappears from
    /// the submodule, with its alarm.
    pub fn remove_diagnosis(
        &self,
        (api, slot, subslot): (u32, u16, u16),
        entry: DiagnosisEntry,
    ) -> Result<(), ControlError> {
        self.station_diagnosis(StationDiagnosisChange::Remove {
            api,
            slot,
            subslot,
            entry,
        })
    }

    /// In the device role: every entry of the submodule disappears, with one alarm.
    pub fn clear_diagnosis(
        &self,
        (api, slot, subslot): (u32, u16, u16),
    ) -> Result<(), ControlError> {
        self.station_diagnosis(StationDiagnosisChange::Clear { api, slot, subslot })
    }

    /// In the device role: a process alarm of the submodule at `api`/`slot`/`subslot`
    /// (high priority) to the PLC, with manufacturer-specific `usi` (0x0000–0x7FFF) and
    /// `data`. Refused without an AR in data exchange that holds the submodule. The PLC's
    /// acknowledgement shows in the station's status (`alarms_acknowledged`).
    pub fn raise_process_alarm(
        &self,
        (api, slot, subslot): (u32, u16, u16),
        usi: u16,
        data: &[u8],
    ) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationProcessAlarm {
            api,
            slot,
            subslot,
            usi,
            data: data.to_vec(),
        })
    }

    /// In the device role: reports a problem of the station (`true`) or none. The PLC sees
    /// it in the StationProblemIndicator of the input data's DataStatus, as it sees a pending
    /// fault diagnosis (which it shows whatever this says).
    pub fn set_station_problem(&self, problem: bool) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationProblem { problem })
    }

    fn station_diagnosis(&self, change: StationDiagnosisChange) -> Result<(), ControlError> {
        self.station_request(DeviceRequest::StationDiagnosis {
            change,
            silent: false,
        })
    }

    /// Sends a request of the device role's services; a controller's server is an error.
    pub(crate) fn station_request(&self, request: DeviceRequest) -> Result<(), ControlError> {
        if !self.is_device() {
            return Err(ControlError::NotDevice {
                instance: self.instance().to_owned(),
            });
        }
        self.control().request_done(request)
    }
}

impl Cycle<'_> {
    fn device_only(&self) -> Result<(), IoError> {
        if self.layout().is_device() {
            Ok(())
        } else {
            Err(IoError::NotDevice {
                instance: self.instance().to_owned(),
            })
        }
    }

    /// The Q data of submodule `s` in this cycle (what the PLC wrote), in place; empty for a
    /// submodule without Q data.
    pub fn q_data(&self, s: usize) -> Result<&[u8], IoError> {
        self.device_only()?;
        Ok(self.input(s).unwrap_or(&[]))
    }

    /// The PLC's provider status of submodule `s`'s Q data (BAD when the PLC is in STOP,
    /// the AR is down, or the submodule is not in the AR).
    pub fn q_status(&self, s: usize) -> Result<Ioxs, IoError> {
        self.device_only()?;
        Ok(self.status(s).map_or(Ioxs::Bad, |st| st.input_remote))
    }

    /// The I data of submodule `s` for this cycle (what the PLC will read), writable in
    /// place, starting as last sent; marked written with provider status GOOD. The client
    /// must hold the claim.
    pub fn i_data_mut(&mut self, s: usize) -> Result<&mut [u8], IoError> {
        self.device_only()?;
        self.output_mut(s)
    }

    /// Sets the provider status (IOPS) the PLC gets with submodule `s`'s I data.
    pub fn set_i_status(&mut self, s: usize, local: Ioxs) -> Result<(), IoError> {
        self.device_only()?;
        self.set_output_status(s, local)
    }

    /// The PLC's consumer status (IOCS) of submodule `s`'s I data, from its last frame.
    pub fn plc_iocs(&self, s: usize) -> Result<Ioxs, IoError> {
        self.device_only()?;
        Ok(self.status(s).map_or(Ioxs::Bad, |st| st.output_remote))
    }
}
