// SPDX-License-Identifier: MIT OR Apache-2.0
//! `pnio-interop-device` running in the device's namespace, its output lines collected as
//! they come. It is stopped when dropped, and when the test is failing, everything it printed
//! is shown.

use super::Net;
use std::io::{BufRead, BufReader, Read};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The device program.
pub const DEVICE: &str = env!("CARGO_BIN_EXE_pnio-interop-device");
/// The NameOfStation the tests give it.
pub const NAME: &str = "pnio-iop";

/// A running `pnio-interop-device`.
pub struct Device {
    child: Option<Child>,
    pid: u32,
    lines: mpsc::Receiver<String>,
    /// Every line it printed on standard output so far (as far as read).
    pub seen: Vec<String>,
    /// Where [`wait_for_new`](Self::wait_for_new) goes on looking.
    cursor: usize,
    /// Its standard error (pnio's log).
    stderr: Arc<Mutex<String>>,
    /// What to call it in messages.
    label: String,
}

impl Device {
    /// Starts the device in `net`'s device namespace and waits for its `READY`.
    pub fn start(net: &Net) -> Device {
        Device::start_labelled(net, "the device")
    }

    /// As [`start`](Self::start), called `label` in messages (to tell a restarted device from
    /// the first one).
    pub fn start_labelled(net: &Net, label: &str) -> Device {
        // `ip netns exec` execs the program in place (after mounting the namespace's sysfs,
        // where the device reads its MAC), so the child's pid is the device's.
        let mut child = Command::new("ip")
            .args(["netns", "exec", net.device_ns(), DEVICE])
            .args(["--iface", net.device_if(), "--name", NAME])
            .args(["--ip", &net.device_ip.to_string()])
            // The device stands for hardware of its own, so its cyclic thread gets a priority
            // above every other real-time thread of the tests (procimgd's cycle threads run at
            // 80, synchronous test clients at 60). At its default of 60 it was held up for
            // 20 ms and more while other tests ran, and it then let its watchdog expire before
            // reading the frames that had arrived meanwhile.
            .args(["--rt-priority", "90", "--lock-memory"])
            .env("RUST_LOG", "info")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start the device");
        let stdout = child.stdout.take().expect("the device's piped stdout");
        let (tx, lines) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        let stderr = Arc::new(Mutex::new(String::new()));
        let mut pipe = child.stderr.take().expect("the device's piped stderr");
        let sink = stderr.clone();
        std::thread::spawn(move || {
            let mut buf = [0u8; 4096];
            while let Ok(n) = pipe.read(&mut buf) {
                if n == 0 {
                    break;
                }
                if let Ok(mut s) = sink.lock() {
                    s.push_str(&String::from_utf8_lossy(&buf[..n]));
                }
            }
        });
        let mut dev = Device {
            pid: child.id(),
            child: Some(child),
            lines,
            seen: Vec::new(),
            cursor: 0,
            stderr,
            label: label.to_string(),
        };
        dev.wait_for("READY", Duration::from_secs(10));
        dev
    }

    /// The device's process id.
    pub fn pid(&self) -> u32 {
        self.pid
    }

    /// Takes the lines printed so far without waiting.
    pub fn drain(&mut self) {
        while let Ok(l) = self.lines.try_recv() {
            self.seen.push(l);
        }
    }

    /// Waits up to `until` for the next line; `false` on timeout or end of output.
    fn next_line(&mut self, until: Instant) -> bool {
        let left = until.saturating_duration_since(Instant::now());
        match self.lines.recv_timeout(left) {
            Ok(l) => {
                self.seen.push(l);
                true
            }
            Err(_) => false,
        }
    }

    /// Waits until the device has printed `line` (at any time since it started).
    pub fn wait_for(&mut self, line: &str, timeout: Duration) {
        let until = Instant::now() + timeout;
        while !self.seen.iter().any(|l| l == line) {
            if !self.next_line(until) {
                panic!(
                    "{} did not print {line:?} within {timeout:?}; it printed {:?}",
                    self.label, self.seen
                );
            }
        }
    }

    /// Waits until the device prints `line` after the last line an earlier call found (or
    /// after [`skip_seen`](Self::skip_seen)); the time it took.
    pub fn wait_for_new(&mut self, line: &str, timeout: Duration) -> Duration {
        let start = Instant::now();
        let until = start + timeout;
        loop {
            if let Some(i) = self.seen[self.cursor..].iter().position(|l| l == line) {
                self.cursor += i + 1;
                return start.elapsed();
            }
            if !self.next_line(until) {
                panic!(
                    "{} did not print {line:?} within {timeout:?}; since the last match it \
                     printed {:?}",
                    self.label,
                    &self.seen[self.cursor..]
                );
            }
        }
    }

    /// Makes [`wait_for_new`](Self::wait_for_new) look only at lines printed from now on;
    /// the index of the first of them in [`seen`](Self::seen).
    pub fn skip_seen(&mut self) -> usize {
        self.drain();
        self.cursor = self.seen.len();
        self.cursor
    }

    /// Sends SIGKILL: no ERR-RTA, no goodbye, as if the device lost power. Returns at once;
    /// [`wait_exit`](Self::wait_exit) reaps it (closing its raw sockets takes the kernel
    /// tens of milliseconds, which a caller timing what follows does not want to wait for).
    pub fn kill(&mut self) {
        if self.child.is_some() {
            // Our own child, not reaped yet: the pid cannot belong to another process.
            procimg_testkit::signal::send(self.pid, libc::SIGKILL);
        }
    }

    /// Sends SIGTERM and waits (10 s at most) for the exit status; the rest of its output
    /// lands in `seen`.
    pub fn terminate(&mut self) -> ExitStatus {
        if self.child.is_some() {
            procimg_testkit::signal::send(self.pid, libc::SIGTERM);
        }
        self.wait_exit(Duration::from_secs(10))
    }

    /// Waits up to `timeout` for the device to end and reaps it; the rest of its output lands
    /// in `seen`.
    pub fn wait_exit(&mut self, timeout: Duration) -> ExitStatus {
        let mut c = self.child.take().expect("the device was not reaped yet");
        let until = Instant::now() + timeout;
        let status = loop {
            if let Some(st) = c.try_wait().expect("wait for the device") {
                break st;
            }
            if Instant::now() > until {
                let _ = c.kill();
                let _ = c.wait();
                panic!("{} did not end within {timeout:?}", self.label);
            }
            std::thread::sleep(Duration::from_millis(10));
        };
        while let Ok(l) = self.lines.recv_timeout(Duration::from_millis(500)) {
            self.seen.push(l);
        }
        status
    }

    /// Everything the device printed, for a failure message.
    pub fn report(&mut self) -> String {
        self.drain();
        let stderr = self.stderr.lock().map(|s| s.clone()).unwrap_or_default();
        format!(
            "--- {} (pid {}), standard output:\n{}\n--- standard error:\n{stderr}",
            self.label,
            self.pid,
            self.seen.join("\n")
        )
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        if let Some(mut c) = self.child.take() {
            procimg_testkit::signal::send(self.pid, libc::SIGTERM);
            let until = Instant::now() + Duration::from_secs(3);
            loop {
                if let Ok(Some(_)) = c.try_wait() {
                    break;
                }
                if Instant::now() > until {
                    let _ = c.kill();
                    let _ = c.wait();
                    break;
                }
                std::thread::sleep(Duration::from_millis(10));
            }
        }
        if std::thread::panicking() {
            // Give the reader threads a moment for the last lines of a device that just ended.
            std::thread::sleep(Duration::from_millis(100));
            eprintln!("{}", self.report());
        }
    }
}
