// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimg's process image over OPC UA: an ordinary asynchronous client of procimgd that
//! serves the image, states, alarms and records to the plant, off the real-time path.
//!
//! - [`snapshot`]: one cycle of the image, whole, taken by a thread of its own;
//! - [`tree`]: the browsable address space under `Objects/procimg/<instance>`, with typed
//!   variables where the devices' GSDML files describe the bytes ([`typed`]);
//! - [`pnio_nodes`]: the PNIO item names of the SIMATIC NET OPC server ([`items`]) as string
//!   NodeIds, resolved from the snapshot when read or monitored;
//! - [`server`]: the server put together: endpoints, security, the PKI folder;
//! - [`users`], [`auth`]: the users file and what a session may do;
//! - [`writer`]: writes of outputs, claimed as `procimg io write` claims them;
//! - [`records`]: record jobs of the record items and the methods ([`methods`]);
//! - [`events`]: procimgd's notifications as OPC UA events of procimg's types
//!   ([`event_types`]).

pub mod auth;
pub mod event_types;
pub mod events;
pub mod items;
pub mod methods;
pub mod pnio_nodes;
pub mod records;
pub mod server;
pub mod snapshot;
pub mod tree;
pub mod typed;
pub mod users;
pub mod writer;
