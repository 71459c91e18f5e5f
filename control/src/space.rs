// SPDX-License-Identifier: MIT OR Apache-2.0
//! The two address spaces of an IO system, as requests and reports name them.

use serde::{Deserialize, Serialize};

/// The two address spaces of an IO system.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Space {
    /// Inputs (I).
    Input,
    /// Outputs (Q).
    Output,
}

impl core::fmt::Display for Space {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Space::Input => "I",
            Space::Output => "Q",
        })
    }
}
