// SPDX-License-Identifier: MIT OR Apache-2.0
//! Where the workspace and its build are, and its binaries built up to date: a test must
//! never start a stale build of another package.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Mutex, OnceLock};

/// The workspace root.
pub fn workspace_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("testkit/ lies in the workspace")
        .to_path_buf()
}

/// The cargo profile directory the running test or bench comes from (`target/debug`).
pub fn profile_dir() -> PathBuf {
    let me = std::env::current_exe().expect("the test's own path");
    // <target>/<profile>/deps/<test>: the binaries are in <target>/<profile>.
    me.parent()
        .and_then(Path::parent)
        .expect("the test runs from <target>/<profile>/deps")
        .to_path_buf()
}

/// Runs `cargo build ARGS` once per test process for each distinct `args`, in this test's
/// profile.
pub fn cargo_build_once(args: &[&str]) {
    static BUILT: OnceLock<Mutex<Vec<String>>> = OnceLock::new();
    let key = args.join(" ");
    let mut built = BUILT
        .get_or_init(|| Mutex::new(Vec::new()))
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    if built.contains(&key) {
        return;
    }
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.current_dir(workspace_dir()).arg("build").args(args);
    if profile_dir().ends_with("release") {
        cmd.arg("--release");
    }
    let st = cmd.status().expect("run cargo build");
    assert!(st.success(), "cargo build {key} failed");
    built.push(key);
}

/// The `procimgd` of this build: `PROCIMGD_BIN` if set, else built up to date in this
/// test's profile.
pub fn procimgd_bin() -> PathBuf {
    if let Some(p) = std::env::var_os("PROCIMGD_BIN") {
        return PathBuf::from(p);
    }
    cargo_build_once(&["-p", "procimg-runtime", "--bin", "procimgd"]);
    profile_dir().join("procimgd")
}

/// Binary `name` of workspace package `package`: the path in environment variable `env` if
/// set, else built up to date in this test's profile.
pub fn workspace_bin(name: &str, env: &str, package: &str) -> PathBuf {
    if let Some(p) = std::env::var_os(env) {
        return PathBuf::from(p);
    }
    cargo_build_once(&["-p", package, "--bin", name]);
    let path = profile_dir().join(name);
    assert!(
        path.exists(),
        "{} does not exist after cargo build -p {package}: set {env}",
        path.display()
    );
    path
}

/// Runs the `procimg` tool with `args` inside network namespace `ns`: whether it succeeded,
/// and its standard output and error together.
pub fn procimg_in_netns(ns: &str, args: &[&str]) -> (bool, String) {
    let procimg = workspace_bin("procimg", "PROCIMG_BIN", "procimg-tools");
    let out = std::process::Command::new("ip")
        .args(["netns", "exec", ns])
        .arg(procimg)
        .args(args)
        .output()
        .expect("run procimg");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr),
    )
}
