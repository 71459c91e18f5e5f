// SPDX-License-Identifier: MIT OR Apache-2.0
//! The server's iceoryx2 nodes, and what goes wrong setting up shared memory.

use super::Ipc;
use iceoryx2::node::{Node, NodeBuilder};
use iceoryx2::prelude::NodeName;
use procimg_control as control;

/// Why a shared-memory service or port could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum ShmError {
    /// iceoryx2 refused to create a node, service or port.
    #[error("cannot create the shared-memory {what} for instance \"{instance}\": {detail}")]
    Create {
        /// Instance name.
        instance: String,
        /// Which service or port.
        what: String,
        /// iceoryx2's error.
        detail: String,
    },
    /// iceoryx2's directory belongs to another user (a run as root left it).
    #[error("cannot create the shared-memory node for instance \"{instance}\": {problem}")]
    ForeignDirectory {
        /// Instance name.
        instance: String,
        /// Whose directory, and what to do: [`super::dir::foreign_directory`].
        problem: String,
    },
    /// Another server of the same instance is running.
    #[error(
        "another procimgd already serves instance \"{instance}\" (its node is alive); stop it \
         first or give this one another instance name"
    )]
    AlreadyRunning {
        /// Instance name.
        instance: String,
    },
}

pub(super) fn err(instance: &str, what: impl Into<String>, e: impl core::fmt::Debug) -> ShmError {
    ShmError::Create {
        instance: instance.to_string(),
        what: what.into(),
        detail: format!("{e:?}"),
    }
}

/// Creates a node for the server of `instance` (one per thread that owns ports).
pub fn server_node(instance: &str, role: &str) -> Result<Node<Ipc>, ShmError> {
    server_node_of::<Ipc>(instance, role)
}

/// [`server_node`] of any of iceoryx2's service variants.
pub fn server_node_of<S: iceoryx2::service::Service>(
    instance: &str,
    role: &str,
) -> Result<Node<S>, ShmError> {
    let n = format!("{}/{role}", control::server_node_name(instance));
    let node_name = NodeName::new(&n).map_err(|e| err(instance, format!("node name {n}"), e))?;
    NodeBuilder::new()
        .name(&node_name)
        .config(super::iox2_config())
        .signal_handling_mode(iceoryx2::prelude::SignalHandlingMode::Disabled)
        .create::<S>()
        .map_err(|e| match super::dir::foreign_directory() {
            Some(problem) => ShmError::ForeignDirectory {
                instance: instance.to_string(),
                problem,
            },
            None => err(instance, "node", e),
        })
}
