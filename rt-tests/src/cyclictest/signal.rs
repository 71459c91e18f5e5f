// SPDX-License-Identifier: MIT OR Apache-2.0
//! Ctrl-C (SIGINT) and SIGTERM end the run and still print the results, as in cyclictest,
//! whose endless runs (-l 0 without -D) are ended that way.

use std::sync::Arc;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

static INTERRUPTED: OnceLock<Arc<AtomicBool>> = OnceLock::new();

/// Installs the handler for SIGINT and SIGTERM. Returns a warning if it cannot.
pub fn install() -> Result<(), String> {
    let flag = INTERRUPTED.get_or_init(|| Arc::new(AtomicBool::new(false)));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(sig, flag.clone()).map_err(|e| {
            format!(
                "cannot catch signal {sig} ({e}): Ctrl-C ends the run without results; use -l or -D"
            )
        })?;
    }
    Ok(())
}

/// A SIGINT or SIGTERM arrived.
pub fn interrupted() -> bool {
    INTERRUPTED.get().is_some_and(|f| f.load(Ordering::Relaxed))
}
