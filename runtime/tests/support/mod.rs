// SPDX-License-Identifier: MIT OR Apache-2.0
//! Starting the real procimgd for integration tests, each under its own instance name, and
//! stopping it again even when a test fails.
#![allow(dead_code)]

use procimg_client::{ControlHandle, StatusReport};
use std::io::Write as _;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

static NEXT: AtomicU32 = AtomicU32::new(0);

/// A unique instance name for this test process.
pub fn unique_instance(tag: &str) -> String {
    format!(
        "t{}-{}-{}",
        std::process::id(),
        tag,
        NEXT.fetch_add(1, Ordering::Relaxed)
    )
}

/// A running procimgd, killed on drop.
pub struct Server {
    pub instance: String,
    pub child: Option<Child>,
    config: Option<PathBuf>,
}

impl Server {
    /// Starts `procimgd --demo` under a fresh instance name and waits until it cycles.
    pub fn demo(tag: &str) -> Server {
        Server::start_with(&unique_instance(tag), None)
    }

    /// Starts procimgd with a configuration text (TOML) under a fresh instance name.
    pub fn with_config(tag: &str, toml: &str) -> Server {
        let instance = unique_instance(tag);
        let path = std::env::temp_dir().join(format!("{instance}.toml"));
        let mut f = std::fs::File::create(&path).expect("write the test configuration");
        f.write_all(toml.as_bytes()).unwrap();
        Server::start_with(&instance, Some(path))
    }

    /// Starts (or restarts) procimgd for `instance`.
    pub fn start_with(instance: &str, config: Option<PathBuf>) -> Server {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_procimgd"));
        match &config {
            Some(path) => cmd.arg("--config").arg(path),
            None => cmd.arg("--demo").arg("--quiet"),
        };
        cmd.arg("--instance")
            .arg(instance)
            .env("RUST_LOG", "warn")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::inherit());
        let child = cmd.spawn().expect("start procimgd");
        let server = Server {
            instance: instance.to_string(),
            child: Some(child),
            config,
        };
        // Generous: on a loaded machine the simulated devices' threads (normal priority) may
        // need a few tries to come up.
        server.wait_cycling(Duration::from_secs(30));
        server.wait_devices_running(Duration::from_secs(30));
        server
    }

    /// Restarts a server for the same instance and configuration (after it was killed).
    pub fn restart(&mut self) {
        let again = Server::start_with(&self.instance, self.config.clone());
        let mut again = again;
        self.child = again.child.take();
    }

    /// Status over the control service.
    pub fn status(&self) -> StatusReport {
        ControlHandle::open(&self.instance, "test-status")
            .expect("open the control service")
            .status()
            .expect("status")
    }

    /// Waits (30 s at most: a loaded machine is slow, not wrong) until a status report
    /// satisfies `done`, and returns it.
    pub fn wait_status(&self, what: &str, done: impl Fn(&StatusReport) -> bool) -> StatusReport {
        let until = Instant::now() + Duration::from_secs(30);
        loop {
            let s = self.status();
            if done(&s) {
                return s;
            }
            assert!(
                Instant::now() < until,
                "{}: waited 30 s for {what}; last status: mode {}, cycle {}",
                self.instance,
                s.mode,
                s.cycle_count
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Waits until the server answers and has run a few cycles.
    pub fn wait_cycling(&self, timeout: Duration) {
        let until = Instant::now() + timeout;
        loop {
            if let Ok(c) = ControlHandle::open(&self.instance, "test-wait")
                && let Ok(s) = c.status()
                && s.cycle_count > 5
            {
                return;
            }
            assert!(
                Instant::now() < until,
                "procimgd for {} did not start",
                self.instance
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Waits until every device is in data exchange (the simulated ones come up through
    /// DCP, Connect, PrmEnd and ApplicationReady like real ones).
    pub fn wait_devices_running(&self, timeout: Duration) {
        let until = Instant::now() + timeout;
        loop {
            if let Ok(c) = ControlHandle::open(&self.instance, "test-wait")
                && let Ok(s) = c.status()
                && s.devices.iter().all(|d| d.state == "running")
            {
                return;
            }
            assert!(
                Instant::now() < until,
                "the devices of {} did not come up",
                self.instance
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// SIGKILLs the server.
    pub fn kill(&mut self) {
        if let Some(mut c) = self.child.take() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }

    /// Sends SIGTERM and waits for the exit status.
    pub fn terminate(&mut self) -> std::process::ExitStatus {
        let mut c = self.child.take().expect("server running");
        // SAFETY: kill(2) on our own child's pid.
        unsafe { libc::kill(c.id() as i32, libc::SIGTERM) };
        let until = Instant::now() + Duration::from_secs(10);
        loop {
            if let Some(st) = c.try_wait().unwrap() {
                return st;
            }
            if Instant::now() > until {
                let _ = c.kill();
                panic!("procimgd did not stop within 10 s of SIGTERM");
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        if let Some(mut c) = self.child.take() {
            // SAFETY: kill(2) on our own child's pid.
            unsafe { libc::kill(c.id() as i32, libc::SIGTERM) };
            let until = Instant::now() + Duration::from_secs(3);
            while Instant::now() < until {
                if let Ok(Some(_)) = c.try_wait() {
                    break;
                }
                std::thread::sleep(Duration::from_millis(10));
            }
            let _ = c.kill();
            let _ = c.wait();
        }
        if let Some(p) = &self.config {
            let _ = std::fs::remove_file(p);
        }
    }
}

/// The pattern of cycle k for a buffer of `len` bytes: k little-endian, then its complement,
/// repeated. Any mix of two writes breaks the relation between the halves.
pub fn pattern(k: u64, len: usize) -> Vec<u8> {
    let mut block = k.to_le_bytes().to_vec();
    block.extend_from_slice(&(!k).to_le_bytes());
    block.iter().copied().cycle().take(len).collect()
}

/// The k a buffer was written with, if it is an untorn pattern.
pub fn pattern_value(b: &[u8]) -> Option<u64> {
    if b.len() < 16 {
        return None;
    }
    let k = u64::from_le_bytes(b[..8].try_into().ok()?);
    (pattern(k, b.len()) == b).then_some(k)
}
