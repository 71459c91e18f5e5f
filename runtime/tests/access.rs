// SPDX-License-Identifier: MIT OR Apache-2.0
//! A process of another user cannot attach, and is told why. The other-user process is this
//! test binary run again as uid/gid 65534 (nobody); the test needs root to start it.

use procimg_client::{AttachError, AttachOptions, Client};
use procimg_testkit::Procimgd;
use std::os::unix::process::CommandExt as _;
use std::process::Command;

const CHILD_ENV: &str = "PROCIMG_TEST_ACCESS_CHILD";

/// Run as a child process only: tries to attach and prints what happened.
#[test]
fn child_attach_as_another_user() {
    let Ok(instance) = std::env::var(CHILD_ENV) else {
        return;
    };
    match Client::attach(&instance, AttachOptions::asynchronous("intruder")) {
        Ok(_) => println!("RESULT attached"),
        // Denied at the services (owner-only), or already at iceoryx2's directory, which the
        // server's user created.
        Err(e @ (AttachError::AccessDenied { .. } | AttachError::ForeignDirectory { .. })) => {
            println!("RESULT access-denied: {e}")
        }
        Err(e) => println!("RESULT other: {e}"),
    }
}

#[test]
#[ignore = "needs root (starts a process as another user): run as root with --ignored"]
fn another_user_is_denied_with_a_clear_error() {
    let root = procimg_testkit::signal::is_root();
    assert!(
        root,
        "this test starts a process as another user, which needs root: run it as root"
    );
    let server = Procimgd::demo("access");
    let out = Command::new(std::env::current_exe().unwrap())
        .args(["--exact", "child_attach_as_another_user", "--nocapture"])
        .env(CHILD_ENV, &server.instance)
        .uid(65534)
        .gid(65534)
        .output();
    let out = match out {
        Ok(o) => o,
        Err(e) if e.kind() == std::io::ErrorKind::PermissionDenied => {
            eprintln!("skipped: the test binary is not executable by uid 65534 ({e})");
            return;
        }
        Err(e) => panic!("cannot start the child: {e}"),
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    let line = stdout
        .lines()
        .find(|l| l.starts_with("RESULT"))
        .unwrap_or("no result");
    assert!(line.starts_with("RESULT access-denied"), "{line}\n{stdout}");
    assert!(
        line.contains("run this client as the server's user") || line.contains("run as root too"),
        "the message says what to do: {line}"
    );
    // The server did not register it.
    assert!(server.status().clients.is_empty());
}
