// SPDX-License-Identifier: MIT OR Apache-2.0
//! The server's iceoryx2 services and ports.
//!
//! Per instance and server generation (see `procimg_control::names` for the names):
//! `layout` (publish-subscribe with history: the tables), `inputs` (publish-subscribe: one
//! input image per cycle), `outputs/<token>` (publish-subscribe, one per client, which
//! creates it and publishes: see [`outputs`]), `cycle-events`
//! (STARTOP, NEWCYCLE, MODE, OPFAULT) and `opdone` (clients notify). The `control`
//! request-response service is named after the instance only, so clients reach a restarted
//! server through the port they already hold.

pub mod access;
pub mod aside;
mod config;
pub mod dir;
mod node;
mod notices;
pub mod outputs;
mod ports;
pub mod reserve;

pub use config::iox2_config;
pub use notices::Notices;

pub use node::{ShmError, server_node, server_node_of};
pub use ports::{ControlPorts, CyclePorts, cleanup_dead_nodes};

/// The iceoryx2 service variant used for everything but the clients' output ports:
/// inter-process, one thread per port.
pub type Ipc = iceoryx2::service::ipc::Service;
