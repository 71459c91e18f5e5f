// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimgd's library: the cycle engine, the shared-memory services, and the
//! daemon side of the PROFINET roles.
//!
//! ```text
//!  config ──▶ image::Tables ──▶ shm (iceoryx2 services) ◀── clients
//!                 │                    ▲
//!                 ▼                    │
//!   cycle::thread ─ cycle::Engine ─────┘   (SCHED_FIFO, no allocation)
//!                 │
//!                 ▼
//!        io::pnio (cyclic frames) ◀── procimg_nic (AF_PACKET, simulated link, replay)
//!                 ▲
//!                 │ channel
//!   acyclic (thread) ── roles::Role (controller: DCP, RPC, alarms)
//!   server::Control (requests, claims, liveness, status) ── roles::RoleServices
//! ```
pub mod acyclic;
/// The configuration file, from its own crate (`procimg-config`), which the command line
/// reads too.
pub use procimg_config as config;
pub mod cycle;
pub mod image;
pub mod io;
pub mod phy;
pub mod roles;
pub mod server;
pub mod shm;
pub mod stats;
// System calls. Besides them, unsafe code in the runtime is the input image built in place in
// shared memory (`image`, the cycle's publication), allowed item by item.
#[allow(unsafe_code)]
pub mod sys;
