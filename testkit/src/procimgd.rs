// SPDX-License-Identifier: MIT OR Apache-2.0
//! The real `procimgd` as a child process of a test, each under its own instance name: the
//! demo or a configuration text, optionally inside a network namespace, at a niceness, with
//! its log kept in a file of its own. Dropped, it gets SIGTERM (on which it releases its
//! devices and removes its shared memory), is waited for and, if it does not stop, killed;
//! its temporary directory is removed, and when the test is failing its log is shown first.

use crate::build::procimgd_bin;
use crate::signal;
use procimg_client::{ArState, ControlHandle, DeviceState, Mode, StatusReport};
use std::path::PathBuf;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// How long waits for the server take at most: a loaded machine is slow, not wrong.
const GENEROUS: Duration = Duration::from_secs(30);
/// How much of the log a failure shows.
const LOG_TAIL_LINES: usize = 300;

/// A unique instance name for this test process.
pub fn unique_instance(tag: &str) -> String {
    static NEXT: AtomicU32 = AtomicU32::new(0);
    format!(
        "t{}-{}-{}",
        std::process::id(),
        tag,
        NEXT.fetch_add(1, Ordering::Relaxed)
    )
}

/// What to wait for after the start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ready {
    /// The control service answers and cycles run, and every device is in data exchange.
    DevicesRunning,
    /// The control service answers and cycles run.
    Cycling,
    /// Nothing: the caller waits itself.
    Started,
}

/// How to start procimgd; [`Launch::start`] starts it.
#[derive(Debug, Clone)]
pub struct Launch {
    instance: String,
    config: Option<String>,
    /// Without a configuration: `--demo` or `--demo-device`.
    demo: &'static str,
    netns: Option<String>,
    nice: Option<i32>,
    log_file: bool,
    rust_log: String,
    ready: Ready,
}

impl Launch {
    /// `procimgd --demo` under a fresh instance name.
    pub fn demo(tag: &str) -> Launch {
        Launch {
            instance: unique_instance(tag),
            config: None,
            demo: "--demo",
            netns: None,
            nice: None,
            log_file: false,
            rust_log: "warn".into(),
            ready: Ready::DevicesRunning,
        }
    }

    /// `procimgd --demo-device` (the IO device role, procimg's controller as the PLC) under
    /// a fresh instance name; by default it waits until the AR is in data exchange.
    pub fn demo_device(tag: &str) -> Launch {
        Launch {
            demo: "--demo-device",
            ..Launch::demo(tag)
        }
    }

    /// `procimgd --demo-device-program` (the device demo's station, defined by its program)
    /// under a fresh instance name; it waits until cycles run (the station waits for its
    /// program).
    pub fn demo_device_program(tag: &str) -> Launch {
        Launch {
            demo: "--demo-device-program",
            ready: Ready::Cycling,
            ..Launch::demo(tag)
        }
    }

    /// procimgd with configuration `toml` under a fresh instance name.
    pub fn config(tag: &str, toml: &str) -> Launch {
        Launch {
            config: Some(toml.to_string()),
            ..Launch::demo(tag)
        }
    }

    /// Under instance name `instance` instead of a fresh one.
    pub fn instance(mut self, instance: &str) -> Launch {
        self.instance = instance.to_string();
        self
    }

    /// Inside network namespace `ns` (`ip netns exec`, which needs root).
    pub fn netns(mut self, ns: &str) -> Launch {
        self.netns = Some(ns.to_string());
        self
    }

    /// At niceness `nice` (its normal-priority threads only: the cycle thread is SCHED_FIFO
    /// when allowed).
    pub fn nice(mut self, nice: i32) -> Launch {
        self.nice = Some(nice);
        self
    }

    /// Logging at debug level into a file, shown when the test fails.
    pub fn debug_log(mut self) -> Launch {
        self.log_file = true;
        self.rust_log = "debug".into();
        self
    }

    /// Returns once the control service answers and cycles run, without waiting for the
    /// devices.
    pub fn until_cycling(mut self) -> Launch {
        self.ready = Ready::Cycling;
        self
    }

    /// Returns at once after the process started.
    pub fn without_waiting(mut self) -> Launch {
        self.ready = Ready::Started;
        self
    }

    /// Starts procimgd and waits as asked (by default until every device is in data
    /// exchange: the simulated ones come up through DCP, Connect, PrmEnd and
    /// ApplicationReady like real ones).
    pub fn start(self) -> Procimgd {
        let bin = procimgd_bin();
        // One directory per start: a restart's new process keeps its files apart.
        static STARTS: AtomicU32 = AtomicU32::new(0);
        let dir = std::env::temp_dir().join(format!(
            "procimg-test-{}-{}",
            self.instance,
            STARTS.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create the test's temporary directory");
        // `ip netns exec` and `nice` exec procimgd in place: the child's pid is procimgd's.
        let mut argv: Vec<std::ffi::OsString> = Vec::new();
        if let Some(ns) = &self.netns {
            argv.extend(["ip", "netns", "exec", ns.as_str()].map(Into::into));
        }
        if let Some(n) = self.nice {
            argv.extend(["nice".into(), "-n".into(), n.to_string().into()]);
        }
        argv.push(bin.clone().into());
        let mut cmd = Command::new(&argv[0]);
        cmd.args(&argv[1..]);
        match &self.config {
            Some(toml) => {
                let path = dir.join("procimgd.toml");
                std::fs::write(&path, toml).expect("write the test configuration");
                cmd.arg("--config").arg(path);
            }
            None => {
                cmd.args([self.demo, "--quiet"]);
            }
        }
        cmd.args(["--instance", &self.instance])
            .env("RUST_LOG", &self.rust_log)
            .env("NO_COLOR", "1")
            .stdin(Stdio::null());
        if self.log_file {
            let open = |name: &str| std::fs::File::create(dir.join(name)).expect("a log file");
            cmd.stdout(open("stdout.log")).stderr(open("procimgd.log"));
        } else {
            cmd.stdout(Stdio::null()).stderr(Stdio::inherit());
        }
        let child = cmd
            .spawn()
            .unwrap_or_else(|e| panic!("start {}: {e}", bin.display()));
        let server = Procimgd {
            instance: self.instance.clone(),
            pid: child.id(),
            child: Mutex::new(Some(child)),
            dir,
            launch: self,
            owns_instance_files: true,
        };
        match server.launch.ready {
            Ready::DevicesRunning => {
                server.wait_cycling(GENEROUS);
                server.wait_devices_running(GENEROUS);
            }
            Ready::Cycling => server.wait_cycling(GENEROUS),
            Ready::Started => {}
        }
        server
    }
}

/// A running procimgd, stopped on drop.
pub struct Procimgd {
    /// Its instance name.
    pub instance: String,
    pid: u32,
    /// `None` once stopped or killed. Behind a lock so that a shared server can be checked.
    child: Mutex<Option<Child>>,
    /// The configuration file and the logs.
    dir: PathBuf,
    launch: Launch,
    /// Whether dropping it removes the instance's files in `/dev/shm` (not when a restarted
    /// server of the same instance took over).
    owns_instance_files: bool,
}

impl Procimgd {
    /// `procimgd --demo` under a fresh instance name, cycling, its devices in data exchange.
    pub fn demo(tag: &str) -> Procimgd {
        Launch::demo(tag).start()
    }

    /// procimgd with a configuration text (TOML) under a fresh instance name, cycling, its
    /// devices in data exchange.
    pub fn with_config(tag: &str, toml: &str) -> Procimgd {
        Launch::config(tag, toml).start()
    }

    /// The configuration file it was started with (`-c FILE`; none for a demo).
    pub fn config_path(&self) -> PathBuf {
        self.dir.join("procimgd.toml")
    }

    /// The process id (procimgd's own, also inside a namespace).
    pub fn pid(&self) -> u32 {
        self.pid
    }

    /// Starts procimgd again as it was started, under the same instance (after a kill).
    pub fn restart(&mut self) {
        self.stop_child();
        let again = self.launch.clone().start();
        self.owns_instance_files = false;
        drop(std::mem::replace(self, again));
    }

    /// A handle to the control service, opened once the server answers and cycles run.
    pub fn control(&self, timeout: Duration) -> ControlHandle {
        self.wait_cycling(timeout);
        ControlHandle::open(&self.instance, "test-control").expect("open the control service")
    }

    /// Status over the control service. A server between two generations (a station its
    /// program defines runs anew) has no control service for a moment: asked again then,
    /// for a few seconds.
    pub fn status(&self) -> StatusReport {
        let until = Instant::now() + Duration::from_secs(5);
        loop {
            let asked = ControlHandle::open(&self.instance, "test-status")
                .map_err(|e| e.to_string())
                .and_then(|c| c.status().map_err(|e| e.to_string()));
            match asked {
                Ok(s) => return s,
                Err(e) if Instant::now() >= until => panic!("{}: status: {e}", self.instance),
                Err(_) => {
                    self.assert_alive();
                    std::thread::sleep(Duration::from_millis(10));
                }
            }
        }
    }

    /// The server's mode now.
    pub fn mode(&self) -> Mode {
        self.status().mode
    }

    /// Asks for `mode` and waits until the server is there.
    pub fn set_mode(&self, mode: Mode) {
        ControlHandle::open(&self.instance, "test-mode")
            .expect("open the control service")
            .set_mode(mode)
            .expect("set the mode");
        self.wait_status(&format!("mode {mode:?}"), |s| s.mode == mode);
    }

    /// Waits (30 s at most) until a status report satisfies `done`, and returns it.
    pub fn wait_status(&self, what: &str, done: impl FnMut(&StatusReport) -> bool) -> StatusReport {
        self.wait_status_within(what, GENEROUS, done)
    }

    /// Waits until a status report satisfies `done` and returns it; panics naming `what` and
    /// the last status after `timeout`, or at once if procimgd exited.
    pub fn wait_status_within(
        &self,
        what: &str,
        timeout: Duration,
        mut done: impl FnMut(&StatusReport) -> bool,
    ) -> StatusReport {
        let until = Instant::now() + timeout;
        let mut control = None;
        let mut last = None;
        loop {
            self.assert_alive();
            // Between two generations (a station its program defines runs anew) the control
            // service is briefly not there: it is opened again, until the wait runs out.
            if control.is_none() {
                match ControlHandle::open(&self.instance, "test-wait") {
                    Ok(c) => control = Some(c),
                    Err(e) => eprintln!("{}: control service: {e}", self.instance),
                }
            }
            match control.as_ref().map(ControlHandle::status) {
                Some(Ok(s)) if done(&s) => return s,
                Some(Ok(s)) => last = Some(s),
                Some(Err(e)) => eprintln!("{}: status: {e}", self.instance),
                None => {}
            }
            assert!(
                Instant::now() < until,
                "{}: {what}: not within {timeout:?}; last status: {last:#?}",
                self.instance
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Waits until the server cycles and every device is in data exchange.
    pub fn wait_ready(&self, timeout: Duration) {
        self.wait_cycling(timeout);
        self.wait_devices_running(timeout);
    }

    /// Waits until the control service answers and the server has run a few cycles.
    pub fn wait_cycling(&self, timeout: Duration) {
        self.wait_until(timeout, "did not start cycling", |s| s.cycle_count > 5);
    }

    /// Waits until every device is in data exchange; in the device role, until the station's
    /// AR is.
    pub fn wait_devices_running(&self, timeout: Duration) {
        self.wait_until(
            timeout,
            "did not bring its devices (or its station's AR) into data exchange",
            |s| match &s.station {
                Some(station) => station
                    .ar
                    .as_ref()
                    .is_some_and(|a| a.state == ArState::Data),
                None => s.devices.iter().all(|d| d.state == DeviceState::Running),
            },
        );
    }

    fn wait_until(&self, timeout: Duration, failed: &str, done: fn(&StatusReport) -> bool) {
        let until = Instant::now() + timeout;
        loop {
            self.assert_alive();
            if let Ok(c) = ControlHandle::open(&self.instance, "test-wait")
                && let Ok(s) = c.status()
                && done(&s)
            {
                return;
            }
            assert!(
                Instant::now() < until,
                "procimgd for {} {failed} within {timeout:?}",
                self.instance
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Panics (with its log, if kept) if procimgd has exited.
    pub fn assert_alive(&self) {
        let mut child = self.child();
        let Some(c) = child.as_mut() else {
            panic!("procimgd for {} was stopped already", self.instance);
        };
        if let Ok(Some(st)) = c.try_wait() {
            *child = None;
            drop(child);
            panic!("procimgd for {} exited ({st})", self.instance);
        }
    }

    fn child(&self) -> MutexGuard<'_, Option<Child>> {
        self.child.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The lines of its whole log so far that contain `needle` (started with
    /// [`Launch::debug_log`]).
    pub fn log_lines(&self, needle: &str) -> Vec<String> {
        std::fs::read_to_string(self.dir.join("procimgd.log"))
            .unwrap_or_default()
            .lines()
            .filter(|l| l.contains(needle))
            .map(str::to_owned)
            .collect()
    }

    /// Its log so far, when it was started with [`Launch::debug_log`].
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

    /// SIGKILLs the server (it leaves its shared memory behind, as a crash would).
    pub fn kill(&mut self) {
        if let Some(mut c) = self.child().take() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }

    /// Sends SIGTERM and waits (10 s at most) for the exit status.
    pub fn terminate(&mut self) -> ExitStatus {
        let mut c = self.child().take().expect("procimgd running");
        signal::terminate(&c);
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

    /// SIGTERM (procimgd removes its shared memory on the way out), then SIGKILL after 10 s.
    fn stop_child(&mut self) {
        let Some(mut c) = self.child().take() else {
            return;
        };
        signal::terminate(&c);
        let until = Instant::now() + Duration::from_secs(10);
        loop {
            if let Ok(Some(_)) = c.try_wait() {
                return;
            }
            if Instant::now() > until {
                eprintln!("procimgd did not stop within 10 s of SIGTERM; killed");
                let _ = c.kill();
                let _ = c.wait();
                return;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

impl Drop for Procimgd {
    fn drop(&mut self) {
        self.stop_child();
        if std::thread::panicking() && self.launch.log_file {
            eprintln!("{}", self.log());
        }
        let _ = std::fs::remove_dir_all(&self.dir);
        if self.owns_instance_files {
            // What a killed server could not remove (a stopped one removed it already); the
            // next server of the instance would, but a test starts none.
            procimg_shm_layout::handshake_map::remove_stale_blocks(&self.instance);
            let _ = std::fs::remove_file(procimg_control::doorbell::doorbell_path(&self.instance));
        }
    }
}
