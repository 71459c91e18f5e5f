// SPDX-License-Identifier: MIT OR Apache-2.0
//! Restarting the server: a reset with the configuration it runs, or a download of a new
//! one (IO-Base's `SERV_CP_reset` and `SERV_CP_download`, `procimg config load`). Programs
//! attached to the server are asked to stop ([`Notification::StopRequest`]) and waited for;
//! the new server's start comes as [`Notification::ServerStarted`].

use super::Services;
use crate::error::ControlError;
use procimg_control::services::Notification;
use procimg_control::{CoreRequest, RestartClients};
use std::time::{Duration, Instant};

/// Why a restart did not happen.
#[derive(Debug, thiserror::Error)]
pub enum RestartError {
    /// The server did not take it (a configuration that does not check, programs attached
    /// to a SAFE restart, a restart under way).
    #[error(transparent)]
    Control(#[from] ControlError),
    /// It was given up: a program asked to stop stayed attached.
    #[error("{0}")]
    GivenUp(String),
    /// The new server did not start in time.
    #[error(
        "the server did not start anew within {0:?}; look at procimgd's log (journalctl -u \
         procimgd, or its standard error)"
    )]
    Timeout(Duration),
}

impl Services {
    /// Asks the server to restart, with `configuration` (TOML text) or the one it runs; the
    /// outcome comes as a [`Notification::Restart`] to this subscriber.
    pub fn restart_server(
        &self,
        configuration: Option<String>,
        clients: RestartClients,
    ) -> Result<(), ControlError> {
        self.accepted(CoreRequest::Restart {
            reply_to: self.id,
            configuration,
            clients,
        })
    }

    /// Restarts the server and waits until the new one runs (up to `timeout`, which must
    /// leave room for the programs asked to stop); what happened, in words.
    pub fn restart_and_wait(
        &mut self,
        configuration: Option<String>,
        clients: RestartClients,
        timeout: Duration,
    ) -> Result<String, RestartError> {
        // The server asked now is the one to be replaced. The generation this handle knew may
        // be older (another program's restart since), and that restart's ServerStarted may
        // still wait in the queue: it must not pass for this one's.
        self.learn_server();
        let before = self.generation;
        self.restart_server(configuration, clients)?;
        let until = Instant::now() + timeout;
        let id = self.id;
        let left = || until.saturating_duration_since(Instant::now());
        let outcome = self.await_notification(
            left(),
            |n| matches!(n, Notification::Restart { reply_to, .. } if *reply_to == id),
        );
        let message = match outcome {
            Some(Notification::Restart {
                done: true,
                message,
                ..
            }) => message,
            Some(Notification::Restart { message, .. }) => {
                return Err(RestartError::GivenUp(message));
            }
            _ => return Err(RestartError::Timeout(timeout)),
        };
        let started = self.await_notification(left(), |n| {
            matches!(n, Notification::ServerStarted { generation } if Some(*generation) != before)
        });
        match started {
            Some(_) => Ok(message),
            None => Err(RestartError::Timeout(timeout)),
        }
    }

    /// Sets the type of station of the server's own station, from its next start on.
    pub fn set_type_of_station(&self, text: &str) -> Result<(), ControlError> {
        self.control.request_done(CoreRequest::SetTypeOfStation {
            text: text.to_owned(),
        })
    }
}
