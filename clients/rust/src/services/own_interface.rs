// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller's own interface, as IO-Base's `PNIO_interface_*` functions use it: its
//! records (the interface submodule 0x8000 and its port 0x8001), its station's name and IP
//! suite where the configuration lets programs change them (`[interface] name_by_program`,
//! `address_by_program`), and its alarms, which arrive as
//! [`Notification::InterfaceAlarm`] to every subscriber.

use super::{RecordError, Services};
use crate::error::ControlError;
use procimg_control::ControllerRequest;
use procimg_control::services::Notification;
use std::net::Ipv4Addr;
use std::time::Duration;

/// The subslot of the controller's interface submodule.
pub const INTERFACE_SUBSLOT: u16 = 0x8000;
/// The subslot of its port.
pub const PORT_SUBSLOT: u16 = 0x8001;

/// A new NameOfStation and/or IP suite for the controller's station.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ControllerAddress {
    /// The new name, if it is to change.
    pub name: Option<String>,
    /// The new address, netmask and gateway, if they are to change.
    pub ip_suite: Option<[Ipv4Addr; 3]>,
    /// To be kept across a restart of procimgd.
    pub permanent: bool,
}

/// Why a change of the controller's name or address did not happen.
#[derive(Debug, thiserror::Error)]
pub enum AddressChangeError {
    /// The server did not take the request.
    #[error(transparent)]
    Control(#[from] ControlError),
    /// No confirmation came in time.
    #[error("no confirmation of the change within {0:?}; check `procimg status`")]
    Timeout(Duration),
    /// The server refused it (not allowed by the configuration, not a valid name or suite,
    /// or the interface would not take the address).
    #[error("{0}")]
    Refused(String),
}

impl Services {
    /// Starts a read of record `index` of the controller's own interface (`subslot`
    /// [`INTERFACE_SUBSLOT`] or [`PORT_SUBSLOT`]), at most `max_len` bytes; the record
    /// arrives as a [`Notification::InterfaceRecord`] with `reference`.
    pub fn interface_record_read(
        &self,
        subslot: u16,
        index: u16,
        max_len: u32,
        reference: u64,
    ) -> Result<(), ControlError> {
        self.accepted(ControllerRequest::InterfaceRecordRead {
            reply_to: self.id,
            reference,
            subslot,
            index,
            max_len,
        })
    }

    /// Reads a record of the controller's own interface and waits for it; other
    /// notifications stay queued.
    pub fn read_interface_record(
        &mut self,
        subslot: u16,
        index: u16,
        max_len: u32,
        timeout: Duration,
    ) -> Result<Vec<u8>, RecordError> {
        let reference = self.take_reference();
        self.interface_record_read(subslot, index, max_len, reference)?;
        let found = self.await_notification(
            timeout,
            |n| matches!(n, Notification::InterfaceRecord { reference: r, .. } if *r == reference),
        );
        match found {
            Some(Notification::InterfaceRecord { status, data, .. }) if status.is_ok() => Ok(data),
            Some(Notification::InterfaceRecord {
                status, message, ..
            }) => Err(RecordError::Failed { status, message }),
            _ => Err(RecordError::Timeout(timeout)),
        }
    }

    /// Asks for a new name or IP suite of the controller's station; confirmed by a
    /// [`Notification::ControllerAddress`] to this subscriber.
    pub fn set_controller_address(&self, change: &ControllerAddress) -> Result<(), ControlError> {
        self.accepted(ControllerRequest::SetControllerAddress {
            reply_to: self.id,
            name: change.name.clone(),
            ip_suite: change.ip_suite,
            permanent: change.permanent,
        })
    }

    /// Changes the controller station's name or IP suite and waits for the outcome.
    pub fn change_controller_address(
        &mut self,
        change: &ControllerAddress,
        timeout: Duration,
    ) -> Result<(), AddressChangeError> {
        self.set_controller_address(change)?;
        let id = self.id;
        let found = self.await_notification(
            timeout,
            |n| matches!(n, Notification::ControllerAddress { reply_to: Some(r), .. } if *r == id),
        );
        match found {
            Some(Notification::ControllerAddress {
                refused: Some(why), ..
            }) => Err(AddressChangeError::Refused(why.message)),
            Some(_) => Ok(()),
            None => Err(AddressChangeError::Timeout(timeout)),
        }
    }
}
