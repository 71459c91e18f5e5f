// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimgd running in a network namespace with a configuration file, under its own instance
//! name, logging at debug level into a file of its own temporary directory. Dropped, it gets
//! SIGTERM (on which it removes its shared memory) and is waited for, and the directory is
//! removed; when the test is failing, its log is shown first.

use super::workspace_bin;
use procimg_client::{ControlHandle, StatusReport};
use std::path::PathBuf;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// How much of the log a failure shows.
const LOG_TAIL_LINES: usize = 300;

/// A running procimgd.
pub struct Procimgd {
    child: Option<Child>,
    pid: u32,
    /// Its instance name.
    pub instance: String,
    /// Configuration, standard output and log.
    dir: PathBuf,
}

impl Procimgd {
    /// Starts procimgd (`PROCIMGD_BIN`, or beside this test's target directory) in namespace
    /// `ns` with configuration `config` under instance name `instance`, at niceness `nice`
    /// (which concerns its normal-priority threads only: the cycle thread is SCHED_FIFO).
    pub fn start(ns: &str, instance: &str, config: &str, nice: i32) -> Procimgd {
        let bin = workspace_bin("procimgd", "PROCIMGD_BIN", "procimg-runtime");
        let dir = std::env::temp_dir().join(format!("procimg-iop-{instance}"));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create the test's temporary directory");
        let config_path = dir.join("procimgd.toml");
        std::fs::write(&config_path, config).expect("write the procimgd configuration");
        let open = |name: &str| std::fs::File::create(dir.join(name)).expect("create a log file");
        // `ip netns exec` and `nice` exec procimgd in place: the child's pid is procimgd's.
        let child = Command::new("ip")
            .args(["netns", "exec", ns])
            .args(["nice", "-n", &nice.to_string()])
            .arg(&bin)
            .arg("--config")
            .arg(&config_path)
            .args(["--instance", instance])
            .env("RUST_LOG", "debug")
            .env("NO_COLOR", "1")
            .stdin(Stdio::null())
            .stdout(open("stdout.log"))
            .stderr(open("procimgd.log"))
            .spawn()
            .unwrap_or_else(|e| panic!("start {}: {e}", bin.display()));
        Procimgd {
            pid: child.id(),
            child: Some(child),
            instance: instance.to_string(),
            dir,
        }
    }

    /// The process id.
    pub fn pid(&self) -> u32 {
        self.pid
    }

    /// Its log so far (standard error, then standard output).
    pub fn log(&self) -> String {
        let read = |name: &str| std::fs::read_to_string(self.dir.join(name)).unwrap_or_default();
        let log = read("procimgd.log");
        let lines: Vec<&str> = log.lines().collect();
        let from = lines.len().saturating_sub(LOG_TAIL_LINES);
        format!(
            "--- procimgd (pid {}, instance {}), last {} lines of its log:\n{}\n--- standard \
             output:\n{}",
            self.pid,
            self.instance,
            lines.len() - from,
            lines[from..].join("\n"),
            read("stdout.log")
        )
    }

    /// Panics with the log if procimgd has exited.
    pub fn assert_alive(&mut self) {
        let Some(c) = self.child.as_mut() else {
            panic!("procimgd was stopped already");
        };
        if let Ok(Some(st)) = c.try_wait() {
            self.child = None;
            panic!("procimgd exited ({st})");
        }
    }

    /// Waits until the control service answers and the cycle runs; a handle to it.
    pub fn control(&mut self, timeout: Duration) -> ControlHandle {
        let until = Instant::now() + timeout;
        loop {
            self.assert_alive();
            if let Ok(c) = ControlHandle::open(&self.instance, "interop-test")
                && let Ok(s) = c.status()
                && s.cycle_count > 5
            {
                return c;
            }
            assert!(
                Instant::now() < until,
                "procimgd did not answer within {timeout:?}"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Polls the status until `done` holds for it (and returns that status); panics naming
    /// `what` and the last status after `timeout`.
    pub fn wait_status(
        &mut self,
        control: &ControlHandle,
        what: &str,
        timeout: Duration,
        mut done: impl FnMut(&StatusReport) -> bool,
    ) -> StatusReport {
        let until = Instant::now() + timeout;
        let mut last = None;
        loop {
            self.assert_alive();
            match control.status() {
                Ok(s) if done(&s) => return s,
                Ok(s) => last = Some(s),
                Err(e) => eprintln!("status: {e}"),
            }
            assert!(
                Instant::now() < until,
                "{what}: not within {timeout:?}; last status: {last:#?}"
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Sends SIGTERM and waits (10 s at most) for the exit status.
    pub fn terminate(&mut self) -> ExitStatus {
        let mut c = self.child.take().expect("procimgd running");
        // SAFETY: kill(2) on the pid of our own child, not reaped yet.
        unsafe { libc::kill(self.pid as i32, libc::SIGTERM) };
        let until = Instant::now() + Duration::from_secs(10);
        loop {
            if let Some(st) = c.try_wait().expect("wait for procimgd") {
                return st;
            }
            if Instant::now() > until {
                let _ = c.kill();
                let _ = c.wait();
                panic!("procimgd did not stop within 10 s of SIGTERM");
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

impl Drop for Procimgd {
    fn drop(&mut self) {
        if let Some(mut c) = self.child.take() {
            // SIGTERM, not SIGKILL: procimgd removes its shared memory on the way out.
            // SAFETY: kill(2) on the pid of our own child, not reaped yet.
            unsafe { libc::kill(self.pid as i32, libc::SIGTERM) };
            let until = Instant::now() + Duration::from_secs(10);
            loop {
                if let Ok(Some(_)) = c.try_wait() {
                    break;
                }
                if Instant::now() > until {
                    eprintln!("procimgd did not stop within 10 s of SIGTERM; killed");
                    let _ = c.kill();
                    let _ = c.wait();
                    break;
                }
                std::thread::sleep(Duration::from_millis(10));
            }
        }
        if std::thread::panicking() {
            eprintln!("{}", self.log());
        }
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}
