// SPDX-License-Identifier: MIT OR Apache-2.0
//! One error type per operation, each saying what to do.

use crate::access::AccessError;
use procimg_control::Refusal;
use std::time::Duration;

/// Why [`crate::Client::attach`] failed.
#[derive(Debug, thiserror::Error)]
pub enum AttachError {
    /// No server serves the instance.
    #[error(
        "no procimgd serves instance \"{instance}\": start it (`procimgd -c FILE` or \
         `procimgd --demo`) or check the instance name"
    )]
    NoServer {
        /// Instance name.
        instance: String,
    },
    /// The shared memory exists but this process may not open it.
    #[error(
        "access to instance \"{instance}\" denied ({detail}): run this client as the server's \
         user, or as a member of the group its [access] table names"
    )]
    AccessDenied {
        /// Instance name.
        instance: String,
        /// What was refused.
        detail: String,
    },
    /// The server uses a different version of the shared-memory layout.
    #[error(
        "instance \"{instance}\" uses {}, this client layout version {client}: rebuild the \
         client against the server's procimg version",
        if *server == 0 { "shared-memory types this client does not know".to_string() }
        else { format!("shared-memory layout version {server}") }
    )]
    LayoutVersion {
        /// Instance name.
        instance: String,
        /// The server's version (0 when its types did not even match, so it is unknown).
        server: u32,
        /// This client's version.
        client: u32,
    },
    /// The server's IO configuration is not the one the client expects.
    #[error(
        "instance \"{instance}\" has layout hash {found:016x}, this client expects \
         {expected:016x}: the IO configuration changed; rebuild the client for it or attach \
         without an expected hash"
    )]
    LayoutHash {
        /// Instance name.
        instance: String,
        /// Hash the client asked for.
        expected: u64,
        /// The server's hash.
        found: u64,
    },
    /// iceoryx2's directory belongs to another user (a run as root left it).
    #[error("cannot attach to instance \"{instance}\": {problem}")]
    ForeignDirectory {
        /// Instance name.
        instance: String,
        /// Whose directory, and what to do.
        problem: String,
    },
    /// The server refused the registration.
    #[error("instance \"{instance}\" refused this client: {refusal}")]
    Refused {
        /// Instance name.
        instance: String,
        /// Why.
        refusal: Refusal,
    },
    /// The server did not answer in time.
    #[error(
        "instance \"{instance}\" did not answer {what} within {timeout:?}: is procimgd stuck \
         or stopping? check `procimg status --instance {instance}`"
    )]
    Timeout {
        /// Instance name.
        instance: String,
        /// What was awaited.
        what: &'static str,
        /// How long.
        timeout: Duration,
    },
    /// iceoryx2 failed otherwise.
    #[error("shared memory of instance \"{instance}\": cannot open {what}: {detail}")]
    Shm {
        /// Instance name.
        instance: String,
        /// Which service or port.
        what: &'static str,
        /// iceoryx2's error.
        detail: String,
    },
}

/// Why waiting for STARTOP returned without a cycle.
#[derive(Debug, thiserror::Error)]
pub enum WaitError {
    /// No STARTOP within the timeout.
    #[error("no STARTOP within {0:?}: is the server in OFFLINE or stopped?")]
    Timeout(Duration),
    /// The server went away; the client re-attaches as soon as it is back.
    #[error(
        "the server of instance \"{instance}\" is gone; the client re-attaches when it returns"
    )]
    ServerGone {
        /// Instance name.
        instance: String,
    },
    /// The server came back with a different IO configuration.
    #[error(
        "the server of instance \"{instance}\" restarted with another IO configuration (layout \
         hash {found:016x}, was {was:016x}): attach again to use it"
    )]
    LayoutChanged {
        /// Instance name.
        instance: String,
        /// The hash before.
        was: u64,
        /// The new hash.
        found: u64,
    },
}

/// Why a read or write of IO data failed.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The address or length breaks IO-Base's rules.
    #[error(transparent)]
    Access(#[from] AccessError),
    /// The client does not hold the claim on these outputs.
    #[error(
        "the outputs at Q {address} (submodule #{submodule}) are not claimed by this client: \
         claim them first"
    )]
    NotClaimed {
        /// Submodule index.
        submodule: usize,
        /// Address written.
        address: u32,
    },
    /// No input image has been received yet.
    #[error("no process image received yet from instance \"{instance}\": wait for a cycle")]
    NoImage {
        /// Instance name.
        instance: String,
    },
    /// The server's buffer for this client is full: more writes than it takes per cycle.
    #[error(
        "the write was not delivered: the server's buffer for this client is full (more than \
         {0} writes in one cycle); use the write cache and flush once per cycle"
    )]
    NotDelivered(usize),
    /// The server is gone.
    #[error("the server of instance \"{instance}\" is gone; retry after it returns")]
    ServerGone {
        /// Instance name.
        instance: String,
    },
    /// A call of the device role (I and Q data named from the PLC's view) on a server that
    /// is an IO controller.
    #[error(
        "instance \"{instance}\" is an IO controller, and this is a call of the IO device role; \
         use the controller's inputs and outputs, or attach to a procimgd with role = \"device\""
    )]
    NotDevice {
        /// Instance name.
        instance: String,
    },
}

/// Why a control request (claim, mode, status) failed.
#[derive(Debug, thiserror::Error)]
pub enum ControlError {
    /// The server refused.
    #[error("{0}")]
    Refused(Refusal),
    /// A request of the device role on a server that is an IO controller.
    #[error(
        "instance \"{instance}\" is an IO controller, and this is a request of the IO device \
         role; attach to a procimgd with role = \"device\""
    )]
    NotDevice {
        /// Instance name.
        instance: String,
    },
    /// The server did not answer.
    #[error("instance \"{instance}\" did not answer within {timeout:?}")]
    NoAnswer {
        /// Instance name.
        instance: String,
        /// How long.
        timeout: Duration,
    },
    /// No server is connected.
    #[error("no procimgd serves instance \"{instance}\" at the moment")]
    NoServer {
        /// Instance name.
        instance: String,
    },
    /// The request could not be sent or the answer not read.
    #[error("control service of instance \"{instance}\": {detail}")]
    Transport {
        /// Instance name.
        instance: String,
        /// What failed.
        detail: String,
    },
    /// The server answered something unexpected.
    #[error("instance \"{instance}\" sent an unexpected answer: {detail}")]
    Protocol {
        /// Instance name.
        instance: String,
        /// What.
        detail: String,
    },
}
