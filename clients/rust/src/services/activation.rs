// SPDX-License-Identifier: MIT OR Apache-2.0
//! Activating or deactivating a device and waiting for the server's confirmation (IO-Base's
//! `PNIO_device_activate` and its `PNIO_CBE_DEV_ACT_CONF`), for programs that would rather
//! wait: `procimg device activate`, procimg-opcua's `ActivateDevice` method.

use super::Services;
use crate::error::ControlError;
use procimg_control::services::Notification;
use std::time::{Duration, Instant};

/// Why an activation or deactivation was not confirmed.
#[derive(Debug, thiserror::Error)]
pub enum ActivationError {
    /// The server did not take the request (OFFLINE, an unknown device, the device role).
    #[error(transparent)]
    Control(#[from] ControlError),
    /// The server answered that the device did not take the change.
    #[error("device {device} did not take the change")]
    Refused {
        /// The device index.
        device: u32,
    },
    /// No confirmation came in time.
    #[error(
        "no confirmation from instance \"{instance}\" within {timeout:?}; is procimgd running \
         (procimg status)?"
    )]
    Timeout {
        /// The instance.
        instance: String,
        /// How long it was waited for.
        timeout: Duration,
    },
}

impl Services {
    /// Activates (`active`) or deactivates device `device` and waits up to `timeout` for
    /// the confirmation. Other notifications that come meanwhile are taken and dropped: use
    /// a handle of its own. The device's failure or return follows as notifications.
    pub fn activate_confirmed(
        &mut self,
        device: u32,
        active: bool,
        timeout: Duration,
    ) -> Result<(), ActivationError> {
        self.activate(device, active)?;
        let until = Instant::now() + timeout;
        while let Some(left) = until.checked_duration_since(Instant::now()) {
            if let Some(Notification::Activation { device: d, ok, .. }) =
                self.next(left.min(Duration::from_millis(100)))
                && d == device
            {
                return if ok {
                    Ok(())
                } else {
                    Err(ActivationError::Refused { device })
                };
            }
        }
        Err(ActivationError::Timeout {
            instance: self.control().instance().to_owned(),
            timeout,
        })
    }
}
