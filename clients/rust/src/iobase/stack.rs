// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimgd as a program's own stack, the way PN Driver starts its stack inside the program
//! (`SERV_CP_startup` … `SERV_CP_shutdown`): the program hands over a configuration and an
//! adapter, and a procimgd is started for it, serves it, and ends with it.
//!
//! The procimgd started is an ordinary one (`PROCIMGD`, else `procimgd` on `PATH`), run as
//! `procimgd -c - --instance NAME --adapter IFACE --exit-with-stdin`: the configuration goes
//! over its standard input, and the pipe stays open for the stack's life, so procimgd stops
//! when the program ends however it ends (a crash included). Its log lines come back to the
//! program, which passes them on (PN Driver's trace) or lets them go to its own standard
//! error.

use crate::control::ControlHandle;
use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How long procimgd may take to serve its first clients: its start includes the real-time
/// set-up and, on a busy machine, more than a quiet one needs.
pub const START_TIMEOUT: Duration = Duration::from_secs(60);
/// How long procimgd may take to stop once told to (outputs to their safe state, shared
/// memory released) before it is killed.
pub const STOP_TIMEOUT: Duration = Duration::from_secs(15);
/// sysexits.h's EX_CONFIG, procimgd's exit status for a configuration it cannot use.
const EXIT_CONFIGURATION: i32 = 78;
/// How many of procimgd's last log lines an error quotes.
const LAST_LINES: usize = 4;

/// What becomes of procimgd's log lines.
pub type LogSink = Box<dyn FnMut(&str) + Send>;

/// What to start.
pub struct StackStart<'a> {
    /// The configuration, procimgd's TOML (`procimgd --print-demo-config` shows one).
    pub config: &'a [u8],
    /// The network interface the program chose; a configuration with `network = "sim"`
    /// keeps its simulated network.
    pub adapter: Option<&'a str>,
    /// The instance name the program's clients attach to.
    pub instance: &'a str,
    /// Where procimgd's log lines go; `None`: to this process's standard error.
    pub log: Option<LogSink>,
    /// procimgd's log filter (`RUST_LOG`); `None`: procimgd's default.
    pub log_filter: Option<&'a str>,
    /// The procimgd program; `None`: [`procimgd_program`].
    pub program: Option<PathBuf>,
}

impl<'a> StackStart<'a> {
    /// A start of `config` for `instance`, on the configuration's own network, with the log
    /// to standard error.
    pub fn new(config: &'a [u8], instance: &'a str) -> StackStart<'a> {
        StackStart {
            config,
            adapter: None,
            instance,
            log: None,
            log_filter: None,
            program: None,
        }
    }
}

/// Why a stack did not start.
#[derive(Debug, thiserror::Error)]
pub enum StackStartError {
    /// The procimgd program could not be started.
    #[error(
        "cannot start {}: {source}; set PROCIMGD to procimgd's path or put procimgd on PATH",
        program.display()
    )]
    Spawn {
        /// The program tried.
        program: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Another procimgd serves the instance already.
    #[error(
        "a procimgd already serves instance \"{instance}\": stop it, or name another instance \
         for this program's CP (PROCIMG_CP1)"
    )]
    AlreadyRunning {
        /// The instance.
        instance: String,
    },
    /// procimgd refused the configuration.
    #[error("procimgd cannot use the configuration: {reason}")]
    Configuration {
        /// procimgd's words (file, line and key).
        reason: String,
    },
    /// procimgd ended before it served.
    #[error("procimgd for instance \"{instance}\" ended at start ({status}): {reason}")]
    Exited {
        /// The instance.
        instance: String,
        /// Its exit status.
        status: ExitStatus,
        /// Its last log lines.
        reason: String,
    },
    /// procimgd did not serve within [`START_TIMEOUT`]; it was stopped.
    #[error(
        "procimgd for instance \"{instance}\" did not serve within {waited:?} and was stopped; \
         its last lines: {reason}"
    )]
    NotReady {
        /// The instance.
        instance: String,
        /// How long it was given.
        waited: Duration,
        /// Its last log lines.
        reason: String,
    },
    /// The configuration could not be handed over.
    #[error("cannot hand the configuration to procimgd: {0}")]
    Handover(std::io::Error),
}

/// Why a stack did not stop cleanly.
#[derive(Debug, thiserror::Error)]
pub enum StackStopError {
    /// procimgd did not stop within [`STOP_TIMEOUT`] and was killed.
    #[error("procimgd for instance \"{instance}\" did not stop within {waited:?}; it was killed")]
    Killed {
        /// The instance.
        instance: String,
        /// How long it was given.
        waited: Duration,
    },
    /// procimgd stopped with a failure.
    #[error("procimgd for instance \"{instance}\" stopped with {status}: {reason}")]
    Failed {
        /// The instance.
        instance: String,
        /// Its exit status.
        status: ExitStatus,
        /// Its last log lines.
        reason: String,
    },
    /// Waiting for procimgd failed.
    #[error("cannot wait for procimgd of instance \"{instance}\": {source}")]
    Wait {
        /// The instance.
        instance: String,
        /// Why.
        source: std::io::Error,
    },
}

/// A procimgd started for this program; it stops when this is shut down or dropped, or when
/// the program ends.
pub struct Stack {
    instance: String,
    child: Option<Child>,
    lifeline: Option<ChildStdin>,
    log: Option<JoinHandle<()>>,
    last_lines: Arc<Mutex<Vec<String>>>,
}

impl std::fmt::Debug for Stack {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Stack")
            .field("instance", &self.instance)
            .field("pid", &self.pid())
            .finish_non_exhaustive()
    }
}

/// The procimgd program to start: `PROCIMGD`, else `procimgd` on `PATH`.
pub fn procimgd_program() -> PathBuf {
    std::env::var_os("PROCIMGD")
        .filter(|p| !p.is_empty())
        .map_or_else(|| PathBuf::from("procimgd"), PathBuf::from)
}

/// Whether a procimgd serves `instance` now (its control service answers).
pub fn instance_serves(instance: &str) -> bool {
    ControlHandle::open(instance, "stack-probe").is_ok_and(|c| c.status().is_ok())
}

impl Stack {
    /// Starts procimgd with `start`'s configuration and waits until it serves clients.
    pub fn start(start: StackStart<'_>) -> Result<Stack, StackStartError> {
        let instance = start.instance.to_string();
        if instance_serves(&instance) {
            return Err(StackStartError::AlreadyRunning { instance });
        }
        let program = start.program.unwrap_or_else(procimgd_program);
        let mut command = Command::new(&program);
        command
            .args(["-c", "-", "--quiet", "--exit-with-stdin", "--instance"])
            .arg(&instance)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        if let Some(adapter) = start.adapter {
            command.args(["--adapter", adapter]);
        }
        if let Some(filter) = start.log_filter {
            command.env("RUST_LOG", filter);
        }
        // The lines carry no colour codes: they go to a program, not a terminal.
        command.env("NO_COLOR", "1");
        let mut child = command
            .spawn()
            .map_err(|source| StackStartError::Spawn { program, source })?;
        let last_lines = Arc::new(Mutex::new(Vec::new()));
        let log = child
            .stderr
            .take()
            .map(|stderr| forward_log(stderr, start.log, last_lines.clone()));
        let mut stack = Stack {
            instance,
            lifeline: child.stdin.take(),
            child: Some(child),
            log,
            last_lines,
        };
        stack.hand_over(start.config)?;
        stack.wait_serving()?;
        Ok(stack)
    }

    /// The instance the stack serves.
    pub fn instance(&self) -> &str {
        &self.instance
    }

    /// procimgd's process id, while it runs.
    pub fn pid(&self) -> Option<u32> {
        self.child.as_ref().map(Child::id)
    }

    /// Stops procimgd (its outputs go to their safe state first) and waits for it.
    pub fn shutdown(mut self) -> Result<ExitStatus, StackStopError> {
        self.stop()
    }

    /// Writes the configuration and its terminating NUL; the pipe stays open.
    fn hand_over(&mut self, config: &[u8]) -> Result<(), StackStartError> {
        let text = config.split(|b| *b == 0).next().unwrap_or_default();
        let written = self.lifeline.as_mut().map(|pipe| {
            pipe.write_all(text)
                .and_then(|()| pipe.write_all(&[0]))
                .and_then(|()| pipe.flush())
        });
        match written {
            Some(Ok(())) | None => Ok(()),
            // A procimgd that ended at once closed the pipe: its exit says why.
            Some(Err(e)) => match self.exited_at_start() {
                Some(err) => Err(err),
                None => Err(StackStartError::Handover(e)),
            },
        }
    }

    /// Waits until procimgd's control service answers, procimgd ends, or the time is up.
    fn wait_serving(&mut self) -> Result<(), StackStartError> {
        let until = Instant::now() + START_TIMEOUT;
        loop {
            if let Some(err) = self.exited_at_start() {
                return Err(err);
            }
            if instance_serves(&self.instance) {
                return Ok(());
            }
            if Instant::now() >= until {
                let _ = self.stop();
                return Err(StackStartError::NotReady {
                    instance: self.instance.clone(),
                    waited: START_TIMEOUT,
                    reason: self.last_lines(),
                });
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// The error for a procimgd that has ended, if it has.
    fn exited_at_start(&mut self) -> Option<StackStartError> {
        let status = self.child.as_mut()?.try_wait().ok()??;
        self.child = None;
        self.finish_log();
        let reason = self.last_lines();
        Some(if status.code() == Some(EXIT_CONFIGURATION) {
            StackStartError::Configuration { reason }
        } else {
            StackStartError::Exited {
                instance: self.instance.clone(),
                status,
                reason,
            }
        })
    }

    fn stop(&mut self) -> Result<ExitStatus, StackStopError> {
        // Closing its standard input is procimgd's word to stop.
        self.lifeline = None;
        let Some(mut child) = self.child.take() else {
            return Err(StackStopError::Wait {
                instance: self.instance.clone(),
                source: std::io::Error::other("procimgd is not running"),
            });
        };
        let until = Instant::now() + STOP_TIMEOUT;
        let wait = |child: &mut Child| loop {
            match child.try_wait() {
                Ok(Some(status)) => return Ok(Some(status)),
                Ok(None) if Instant::now() >= until => return Ok(None),
                Ok(None) => std::thread::sleep(Duration::from_millis(10)),
                Err(e) => return Err(e),
            }
        };
        let waited = wait(&mut child).map_err(|source| StackStopError::Wait {
            instance: self.instance.clone(),
            source,
        });
        let outcome = match waited {
            Ok(Some(status)) if status.success() => Ok(status),
            Ok(Some(status)) => {
                self.finish_log();
                Err(StackStopError::Failed {
                    instance: self.instance.clone(),
                    status,
                    reason: self.last_lines(),
                })
            }
            Ok(None) => {
                let _ = child.kill();
                let _ = child.wait();
                Err(StackStopError::Killed {
                    instance: self.instance.clone(),
                    waited: STOP_TIMEOUT,
                })
            }
            Err(e) => Err(e),
        };
        self.finish_log();
        outcome
    }

    /// Waits until every log line procimgd wrote has been passed on.
    fn finish_log(&mut self) {
        if let Some(log) = self.log.take() {
            let _ = log.join();
        }
    }

    fn last_lines(&self) -> String {
        let lines = self.last_lines.lock().unwrap_or_else(|e| e.into_inner());
        if lines.is_empty() {
            "it said nothing".to_string()
        } else {
            lines.join(" / ")
        }
    }
}

impl Drop for Stack {
    fn drop(&mut self) {
        if self.child.is_some() {
            let _ = self.stop();
        }
    }
}

/// Passes procimgd's log lines on, keeping the last few for error messages.
fn forward_log(
    stderr: std::process::ChildStderr,
    sink: Option<LogSink>,
    last: Arc<Mutex<Vec<String>>>,
) -> JoinHandle<()> {
    let mut sink = sink.unwrap_or_else(|| Box::new(|line: &str| eprintln!("{line}")));
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines() {
            let Ok(line) = line else { break };
            sink(&line);
            let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
            if last.len() == LAST_LINES {
                last.remove(0);
            }
            last.push(line);
        }
    })
}
