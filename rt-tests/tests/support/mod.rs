// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the tools' integration tests share: running a tool and judging how it ended.

// Each test file uses the part it needs; the rest is dead code there.
#![allow(dead_code)]

use std::fmt::Debug;
use std::path::PathBuf;
use std::process::Command;

/// A file in the temporary directory for `tool`'s tests, unique to this test process.
pub fn temp(tool: &str, name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("{tool}-test-{}-{name}", std::process::id()))
}

/// Runs `cmd` and fails the test unless it succeeded, naming `what` with the tool's status,
/// stdout and stderr. Returns its stdout.
pub fn stdout_of_success(cmd: &mut Command, what: &dyn Debug) -> String {
    let out = cmd.output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{what:?}: {}\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// Runs `tool` with `args` and fails the test if it succeeds. Returns its stderr: the reason
/// it gave.
pub fn refusal(tool: &str, args: &[&str]) -> String {
    let out = Command::new(tool).args(args).output().unwrap();
    assert!(!out.status.success(), "{args:?} was not refused");
    String::from_utf8_lossy(&out.stderr).into_owned()
}
