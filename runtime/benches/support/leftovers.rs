// SPDX-License-Identifier: MIT OR Apache-2.0
//! Unique instance names, and the check that a benchmark left no iceoryx2 node or service of
//! its instances behind (their files are in /dev/shm and iceoryx2's directory, named by hash, so
//! iceoryx2's own listings are asked by name instead).

use iceoryx2::node::{Node, NodeState, NodeView};
use iceoryx2::prelude::CallbackProgression;
use iceoryx2::service::Service;
use procimg_runtime::shm::{Ipc, iox2_config};
use std::sync::atomic::{AtomicU32, Ordering};

static NEXT: AtomicU32 = AtomicU32::new(0);

/// What every instance name of this process starts with.
pub fn prefix(bench: &str) -> String {
    format!("b{}{bench}", std::process::id())
}

/// A fresh instance name (at most 32 characters of A-Za-z0-9_-).
pub fn instance(bench: &str) -> String {
    let name = format!("{}-{}", prefix(bench), NEXT.fetch_add(1, Ordering::Relaxed));
    assert!(name.len() <= 32, "instance name {name} too long");
    name
}

/// The names of nodes and services whose name contains `prefix`.
pub fn find(prefix: &str) -> Vec<String> {
    let mut found = Vec::new();
    let _ = Node::<Ipc>::list(iox2_config(), |state| {
        let details = match &state {
            NodeState::Alive(v) => v.details().clone(),
            NodeState::Dead(v) => v.details().clone(),
            _ => None,
        };
        if let Some(d) = details
            && d.name().as_str().contains(prefix)
        {
            found.push(format!("node {}", d.name().as_str()));
        }
        CallbackProgression::Continue
    });
    let _ = Ipc::list(iox2_config(), |s| {
        let name = s.static_details.name().as_str();
        if name.contains(prefix) {
            found.push(format!("service {name}"));
        }
        CallbackProgression::Continue
    });
    found
}

/// Panics if anything of `bench`'s instances is left.
pub fn assert_none(bench: &str) {
    let left = find(&prefix(bench));
    assert!(left.is_empty(), "left behind in shared memory: {left:?}");
}
