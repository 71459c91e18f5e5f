// SPDX-License-Identifier: MIT OR Apache-2.0
//! The cycle thread and what it runs.
pub mod engine;
pub mod force;
pub mod link;
pub mod publication;
pub mod shared;
pub mod thread;

pub use engine::{Engine, EngineSettings};
pub use force::{ForcePlan, ForceRun};
pub use link::{ClientLink, MemoryLink, Taken};
pub use publication::Publication;
pub use shared::{Command, Shared};
