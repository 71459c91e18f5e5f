// SPDX-License-Identifier: MIT OR Apache-2.0
//! The requests only a server in the IO controller role answers: record jobs, device
//! activation, alarm acknowledgement and the IO system's diagnosis.

use crate::services::{PortRef, RecordTarget};
use serde::{Deserialize, Serialize};

/// A request of the IO controller's services.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "request", rename_all = "snake_case")]
pub enum ControllerRequest {
    /// Read a record; answered with [`Response::Accepted`](crate::Response::Accepted), the data follows as a
    /// [`Notification::Record`](crate::services::Notification::Record) to `reply_to`.
    RecordRead {
        /// The subscriber that gets the confirmation.
        reply_to: u64,
        /// Echoed in the confirmation.
        reference: u64,
        /// The record.
        target: RecordTarget,
        /// The most bytes wanted.
        max_len: u32,
    },
    /// Write a record; answered with [`Response::Accepted`](crate::Response::Accepted), the result follows as a
    /// [`Notification::Record`](crate::services::Notification::Record) to `reply_to`.
    RecordWrite {
        /// The subscriber that gets the confirmation.
        reply_to: u64,
        /// Echoed in the confirmation.
        reference: u64,
        /// The record.
        target: RecordTarget,
        /// The record.
        data: Vec<u8>,
    },
    /// Activate or deactivate a device (IO-Base `PNIO_device_activate`); not in OFFLINE.
    /// Confirmed by a [`Notification::Activation`](crate::services::Notification::Activation)
    /// to `reply_to`.
    ActivateDevice {
        /// The subscriber that gets the confirmation.
        reply_to: u64,
        /// Device index.
        device: u32,
        /// Activate (`true`) or deactivate.
        active: bool,
    },
    /// Reconfigure the IO system (IO-Base `PNIO_iosystem_reconfig`): deactivate every
    /// device (`tailoring` `None`), or tailor it: every device down, the optional devices
    /// present and the ports joined taken, then the mandatory devices and those present
    /// up. Confirmed by a
    /// [`Notification::Reconfigured`](crate::services::Notification::Reconfigured) to
    /// `reply_to`.
    ReconfigureIoSystem {
        /// The subscriber that gets the confirmation.
        reply_to: u64,
        /// What the machine has; `None`: deactivate all.
        tailoring: Option<Tailoring>,
    },
    /// Acknowledge an alarm this subscriber was given with `ack_expected`.
    AcknowledgeAlarm {
        /// The subscriber's id.
        subscriber: u64,
        /// The alarm's id.
        alarm: u64,
    },
    /// The state of every device; answered with [`Response::Diagnosis`](crate::Response::Diagnosis).
    Diagnosis,
    /// Start the controller interface's communication counters again from 0 (IO-Base's
    /// RESET_COMM_COUNTERS); answered with [`Response::Done`](crate::Response::Done).
    ResetCommCounters,
    /// Read a record of the controller's own interface (IO-Base
    /// `PNIO_interface_rec_read_req`): subslot 0x8000 is the interface, 0x8001 its port.
    /// Answered with [`Response::Accepted`](crate::Response::Accepted); the record follows
    /// as a [`Notification::InterfaceRecord`](crate::services::Notification::InterfaceRecord)
    /// to `reply_to`.
    InterfaceRecordRead {
        /// The subscriber that gets the confirmation.
        reply_to: u64,
        /// Echoed in the confirmation.
        reference: u64,
        /// The submodule: 0x8000 the interface, 0x8001 the port.
        subslot: u16,
        /// The record index.
        index: u16,
        /// The most bytes wanted.
        max_len: u32,
    },
    /// A PROFIenergy command to a submodule of a device (IO-Base `PNIO_pe_cmd_req`): its
    /// record 0x80A0 written, the answer read until it is ready or
    /// [`PE_LIFETIME_MS`](crate::pe::PE_LIFETIME_MS) passed. Answered with
    /// [`Response::Accepted`](crate::Response::Accepted); the outcome follows as a
    /// [`Notification::PeConfirmation`](crate::services::Notification::PeConfirmation) to
    /// `reply_to`.
    PeCommand {
        /// The subscriber that gets the confirmation.
        reply_to: u64,
        /// Echoed in the confirmation.
        reference: u64,
        /// The submodule (its `index` is not used: PE's record is 0x80A0).
        target: RecordTarget,
        /// The command.
        command: crate::pe::PeCommand,
    },
    /// Give the controller's own station a new NameOfStation and/or IP suite (IO-Base
    /// `PNIO_interface_set_ip_and_nos`), where `[interface]` lets programs change them.
    /// Answered with [`Response::Accepted`](crate::Response::Accepted); confirmed by a
    /// [`Notification::ControllerAddress`](crate::services::Notification::ControllerAddress)
    /// to `reply_to`.
    SetControllerAddress {
        /// The subscriber that gets the confirmation.
        reply_to: u64,
        /// The new name, if it is to change.
        name: Option<String>,
        /// The new address, netmask and gateway, if they are to change.
        ip_suite: Option<[std::net::Ipv4Addr; 3]>,
        /// To be kept across a restart of procimgd.
        permanent: bool,
    },
}

impl ControllerRequest {
    /// What it asks for, in words, for a refusal by a server in another role.
    pub const fn service(&self) -> &'static str {
        match self {
            ControllerRequest::RecordRead { .. } => "reading a record of an IO device",
            ControllerRequest::RecordWrite { .. } => "writing a record of an IO device",
            ControllerRequest::ActivateDevice { .. } => "activating an IO device",
            ControllerRequest::ReconfigureIoSystem { .. } => "reconfiguring the IO system",
            ControllerRequest::AcknowledgeAlarm { .. } => "acknowledging an IO device's alarm",
            ControllerRequest::Diagnosis => "the IO system diagnosis",
            ControllerRequest::ResetCommCounters => "resetting the communication counters",
            ControllerRequest::InterfaceRecordRead { .. } => {
                "reading a record of the controller's own interface"
            }
            ControllerRequest::PeCommand { .. } => "a PROFIenergy command to an IO device",
            ControllerRequest::SetControllerAddress { .. } => {
                "setting the controller's name or IP suite"
            }
        }
    }
}

/// How a machine is built, for tailoring its IO system.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Tailoring {
    /// The optional devices it has (device indexes).
    pub devices: Vec<u32>,
    /// The ports joined, in pairs.
    pub links: Vec<[PortRef; 2]>,
}
