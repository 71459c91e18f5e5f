// SPDX-License-Identifier: MIT OR Apache-2.0
//! A child process of the soak: its standard output as lines on a channel, its standard error
//! appended to a log file, killed by its pid when dropped.

use std::fs::OpenOptions;
use std::io::{BufRead as _, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// A running child.
pub struct Running {
    child: Child,
    /// When it was started.
    pub started: Instant,
    lines: mpsc::Receiver<String>,
}

impl Running {
    /// Starts `cmd` with its standard error appended to `log`.
    pub fn spawn(mut cmd: Command, log: &Path) -> std::io::Result<Running> {
        let stderr = OpenOptions::new().create(true).append(true).open(log)?;
        let mut child = cmd
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(stderr)
            .spawn()?;
        let started = Instant::now();
        let (tx, lines) = mpsc::channel();
        if let Some(out) = child.stdout.take() {
            std::thread::spawn(move || {
                for line in BufReader::new(out).lines() {
                    let Ok(line) = line else { break };
                    if tx.send(line).is_err() {
                        break;
                    }
                }
            });
        }
        Ok(Running {
            child,
            started,
            lines,
        })
    }

    /// Its process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// The lines it printed since the last call.
    pub fn take_lines(&self) -> Vec<String> {
        self.lines.try_iter().collect()
    }

    /// Waits up to `timeout` for a line `pick` accepts; the lines before it are given to
    /// `also`.
    pub fn wait_line(
        &self,
        timeout: Duration,
        pick: impl Fn(&str) -> bool,
        mut also: impl FnMut(&str),
    ) -> Option<String> {
        let until = Instant::now() + timeout;
        loop {
            let left = until.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) if pick(&line) => return Some(line),
                Ok(line) => also(&line),
                Err(_) => return None,
            }
        }
    }

    /// Sends `signal` and waits up to `grace` for the process to end; then SIGKILL.
    pub fn stop(&mut self, signal: i32, grace: Duration) {
        procimg_netns::signal::stop(&mut self.child, signal, grace);
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        self.stop(libc::SIGKILL, Duration::from_secs(5));
    }
}
