// SPDX-License-Identifier: MIT OR Apache-2.0
//! The requests the control side answers for either role: registration, output claims,
//! modes, status, subscriptions, histograms and forces.

use crate::Space;
use procimg_shm_layout::Mode;
use serde::{Deserialize, Serialize};

/// How a client takes part in the cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ClientRole {
    /// Takes part in the STARTOP/OPDONE handshake: the server waits for its OPDONE each cycle.
    Synchronous,
    /// Reads and writes at any time; not waited for.
    Asynchronous,
}

/// A request either role's server answers.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "request", rename_all = "snake_case")]
pub enum CoreRequest {
    /// Join the instance; answered with [`Response::Registered`](crate::Response::Registered).
    Register {
        /// A name for status displays.
        name: String,
        /// The client's process id.
        pid: u32,
        /// Synchronous or asynchronous.
        role: ClientRole,
        /// Wants NEWCYCLE events (IO-Base registers PNIO_CP_CBE_NEWCYCLE_IND only on request).
        #[serde(default)]
        newcycle: bool,
        /// The iceoryx2 node id of the client, so the server notices when the process dies.
        node_id: String,
    },
    /// Leave the instance; claims are released.
    Unregister {
        /// Slot from the registration.
        slot: u32,
        /// Token from the registration.
        token: u64,
    },
    /// Take the outputs this client publishes on its output service
    /// ([`client_output_service`](crate::client_output_service)), which it created after
    /// registering: answered when the server's subscriber is connected to it, so that the
    /// client's first sample reaches the server.
    ConnectOutputs {
        /// Slot from the registration.
        slot: u32,
        /// Token from the registration.
        token: u64,
    },
    /// Claim the outputs of these submodules (indices in the submodule table).
    Claim {
        /// Slot from the registration.
        slot: u32,
        /// Token from the registration.
        token: u64,
        /// Submodule table indices.
        submodules: Vec<u32>,
    },
    /// Release claimed outputs.
    Release {
        /// Slot from the registration.
        slot: u32,
        /// Token from the registration.
        token: u64,
        /// Submodule table indices.
        submodules: Vec<u32>,
    },
    /// Change the mode; confirmed by a MODE event once the cycle has reached it.
    SetMode {
        /// The mode wanted.
        mode: Mode,
    },
    /// Report the server's state.
    Status,
    /// Announce a notification subscriber. Broadcasts and confirmations reach any subscriber;
    /// announcing is what makes the server wait for this one's alarm acknowledgements, and
    /// what shows it in the status.
    Subscribe {
        /// The subscriber's id (random, chosen by the subscriber).
        subscriber: u64,
        /// A name for status displays and messages.
        name: String,
        /// The subscriber's process id.
        pid: u32,
        /// The iceoryx2 node id of the subscriber, so the server notices when it dies.
        node_id: String,
        /// The server waits for this subscriber's [`ControllerRequest::AcknowledgeAlarm`](crate::ControllerRequest::AcknowledgeAlarm) before it
        /// acknowledges an alarm to the device (IO-Base: when the alarm callback returns).
        /// A server in the device role takes it and ignores it: the PLC acknowledges the
        /// station's alarms.
        acknowledge_alarms: bool,
    },
    /// Withdraw a subscriber; alarms waiting for it are acknowledged if nobody else waits.
    Unsubscribe {
        /// The subscriber's id.
        subscriber: u64,
    },
    /// The cycle thread's latency histograms since start, bucket by bucket; answered with
    /// [`Response::Histograms`](crate::Response::Histograms). Two answers subtracted give the histograms of the time
    /// between them.
    Histograms,
    /// Force bytes of the image, as a PLC's force table does: from the next cycle on, the
    /// server puts `data` at `address` in every cycle, over what the devices deliver (I) or
    /// what clients write (Q, sent with IOPS GOOD in OPERATE whoever owns the outputs), until
    /// an [`CoreRequest::Unforce`] or the server's end. The bytes lie in one submodule.
    Force {
        /// I or Q.
        space: Space,
        /// First logical address.
        address: u32,
        /// The forced values.
        data: Vec<u8>,
    },
    /// End forcing: `length` bytes from `address`, the rest of its submodule when `None`;
    /// every force when `address` is `None`.
    Unforce {
        /// I or Q.
        space: Space,
        /// First logical address; `None`: every force (in both spaces).
        address: Option<u32>,
        /// Bytes; `None`: to the end of the submodule.
        length: Option<u32>,
    },
    /// Start the server anew, with the configuration it runs (a reset, IO-Base's
    /// `SERV_CP_reset`) or with a new one (a download, `SERV_CP_download`, `procimg config
    /// load`). The configuration is checked first (refused as
    /// [`Refusal::BadConfiguration`](crate::Refusal::BadConfiguration)); then what
    /// `clients` says happens to the attached programs. Answered with
    /// [`Response::Accepted`](crate::Response::Accepted); the outcome follows as a
    /// [`Notification::Restart`](crate::services::Notification::Restart) to `reply_to`, and
    /// the new server as [`Notification::ServerStarted`](crate::services::Notification::ServerStarted).
    Restart {
        /// The subscriber that gets the outcome.
        reply_to: u64,
        /// The new configuration (TOML text); `None`: the one the server runs.
        configuration: Option<String>,
        /// What happens while programs are attached.
        clients: RestartClients,
    },
    /// The type of station the server's own station reports (DCP's DeviceVendorValue,
    /// IO-Base's `SERV_CP_set_type_of_station`), from the server's next start on (a
    /// [`CoreRequest::Restart`]); answered with [`Response::Done`](crate::Response::Done).
    SetTypeOfStation {
        /// The text, at most 255 bytes (engineering tools show 19 characters).
        text: String,
    },
}

/// What a [`CoreRequest::Restart`] does while programs are attached to the server.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RestartClients {
    /// Refuse at once ([`Refusal::ClientsAttached`](crate::Refusal::ClientsAttached)):
    /// `SERV_CP_reset` SAFE.
    Refuse,
    /// Ask them to stop ([`Notification::StopRequest`](crate::services::Notification::StopRequest),
    /// IO-Base's CP_STOP_REQ) and restart once all have detached; give up if one is still
    /// attached after [`RESTART_WAIT_MS`](crate::services::RESTART_WAIT_MS).
    Ask,
    /// Ask them, and restart after [`RESTART_WAIT_MS`](crate::services::RESTART_WAIT_MS)
    /// whoever is still attached: `SERV_CP_reset` FORCE.
    Force,
}
