// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimgd's library: configuration, the cycle engine, the shared-memory services and the
//! IO systems behind the image.
//!
//! ```text
//!  config ──▶ image::Tables ──▶ shm (iceoryx2 services) ◀── clients
//!                 │                    ▲
//!                 ▼                    │
//!   cycle::thread ─ cycle::Engine ─────┘   (SCHED_FIFO, no allocation)
//!                 │
//!                 ▼
//!           io::IoSystem (sim; PROFINET)
//!   server::Control (acyclic: requests, claims, liveness, status)
//! ```
pub mod acyclic;
pub mod config;
pub mod cycle;
pub mod image;
pub mod io;
pub mod network;
pub mod phy;
pub mod server;
pub mod shm;
pub mod sim_behaviour;
pub mod simnet;
pub mod stats;
// System calls: the only module of the runtime that may use unsafe.
#[allow(unsafe_code)]
pub mod sys;
