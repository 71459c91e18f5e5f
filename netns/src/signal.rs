// SPDX-License-Identifier: MIT OR Apache-2.0
//! The system calls around procimg's child processes (in tests and the soak run): signals to
//! the caller's own children, who it runs as, and entering a network namespace.

use std::process::Child;

/// Sends SIGTERM to `child`, which has not been reaped yet.
pub fn terminate(child: &Child) {
    send(child.id(), libc::SIGTERM);
}

/// Sends `signal` to process `pid`, a child of this process that has not been reaped yet (so
/// the pid still names it).
pub fn send(pid: u32, signal: libc::c_int) {
    if let Ok(pid) = libc::pid_t::try_from(pid) {
        // SAFETY: kill(2) takes a pid and a signal number and touches no memory of ours; the
        // pid is our own unreaped child's.
        unsafe { libc::kill(pid, signal) };
    }
}

/// Sends `signal` to `child` and waits up to `grace` for it to end; then SIGKILL. Returns its
/// exit status (`None` if it could not be had).
pub fn stop(
    child: &mut Child,
    signal: libc::c_int,
    grace: std::time::Duration,
) -> Option<std::process::ExitStatus> {
    if let Ok(Some(status)) = child.try_wait() {
        return Some(status);
    }
    send(child.id(), signal);
    let until = std::time::Instant::now() + grace;
    while std::time::Instant::now() < until {
        if let Ok(Some(status)) = child.try_wait() {
            return Some(status);
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let _ = child.kill();
    child.wait().ok()
}

/// Whether this process runs as root (namespaces, raw sockets and SCHED_FIFO need it).
pub fn is_root() -> bool {
    // SAFETY: geteuid has no preconditions and cannot fail.
    unsafe { libc::geteuid() == 0 }
}

/// Moves the calling thread into the network namespace `file` (`/var/run/netns/NAME`).
pub fn enter_netns(file: &std::fs::File) {
    // SAFETY: setns(2) on a descriptor that `file` keeps open; it changes this thread only.
    let rc = unsafe { libc::setns(std::os::fd::AsRawFd::as_raw_fd(file), libc::CLONE_NEWNET) };
    assert_eq!(rc, 0, "setns: {}", std::io::Error::last_os_error());
}
