// SPDX-License-Identifier: MIT OR Apache-2.0
//! The server's answer to a request.

use crate::services::DiagnosisReport;
use crate::{HistogramsReport, Refusal, StatusReport};
use serde::{Deserialize, Serialize};

/// The server's answer.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "response", rename_all = "snake_case")]
pub enum Response {
    /// Registration accepted.
    Registered {
        /// The client's slot (0..MAX_CLIENTS).
        slot: u32,
        /// Identifies this registration in later requests and in output samples.
        token: u64,
        /// The server's generation: the data services are named after it.
        generation: u64,
        /// Hash of the server's layout.
        layout_hash: u64,
        /// The server's process id: a client tells its server from a successor started under
        /// the same name (0 from servers that do not say).
        #[serde(default)]
        server_pid: u32,
    },
    /// The request was carried out.
    Done,
    /// The request was refused.
    Refused(Refusal),
    /// The server's state.
    Status(Box<StatusReport>),
    /// The job was taken; its confirmation follows as a notification.
    Accepted,
    /// The devices' state.
    Diagnosis(Box<DiagnosisReport>),
    /// The cycle thread's latency histograms.
    Histograms(Box<HistogramsReport>),
}
