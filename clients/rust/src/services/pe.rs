// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFIenergy commands to a device's submodule (IO-Base's `PNIO_pe_cmd_req`): the server
//! writes the request to record 0x80A0, reads the answer until it is ready (at most
//! [`PE_LIFETIME_MS`]) and confirms with [`Notification::PeConfirmation`].

use super::{RecordError, Services};
use crate::error::ControlError;
use procimg_control::ControllerRequest;
use procimg_control::pe::{PE_LIFETIME_MS, PeAnswer, PeCommand};
use procimg_control::services::{Notification, RecordTarget};
use std::time::Duration;

impl Services {
    /// Sends a PE command to the submodule `target` names (its `index` is not used); the
    /// outcome arrives as a [`Notification::PeConfirmation`] with `reference`.
    pub fn pe_command(
        &self,
        target: RecordTarget,
        command: PeCommand,
        reference: u64,
    ) -> Result<(), ControlError> {
        self.accepted(ControllerRequest::PeCommand {
            reply_to: self.id,
            reference,
            target,
            command,
        })
    }

    /// Sends a PE command and waits for the device's answer (a negative one included: it
    /// is [`PeAnswer::Error`]).
    pub fn pe(
        &mut self,
        target: RecordTarget,
        command: PeCommand,
    ) -> Result<PeAnswer, RecordError> {
        let reference = self.take_reference();
        self.pe_command(target, command, reference)?;
        // The server gives up after the lifetime; a little more for its confirmation.
        let timeout = Duration::from_millis(PE_LIFETIME_MS + 5_000);
        let found = self.await_notification(
            timeout,
            |n| matches!(n, Notification::PeConfirmation { reference: r, .. } if *r == reference),
        );
        match found {
            Some(Notification::PeConfirmation {
                answer: Some(a), ..
            }) => Ok(a),
            Some(Notification::PeConfirmation {
                status, message, ..
            }) => Err(RecordError::Failed { status, message }),
            _ => Err(RecordError::Timeout(timeout)),
        }
    }
}
