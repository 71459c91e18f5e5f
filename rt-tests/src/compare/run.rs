// SPDX-License-Identifier: MIT OR Apache-2.0
//! Running one measuring tool as a child process: found beside this program (or in PATH for
//! the real cyclictest), its output into a log file, a time limit, and a short reason when
//! it could not measure.

use std::os::unix::process::CommandExt as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Where a tool comes from.
#[derive(Clone, Debug)]
pub enum Program {
    /// One of this crate's binaries, next to procimg-compare.
    Sibling(&'static str),
    /// A program in PATH, with what to install when it is missing.
    InPath {
        /// Program name.
        name: &'static str,
        /// The install hint.
        install: &'static str,
    },
}

impl Program {
    /// The program's path, or why it cannot be run.
    pub fn locate(&self) -> Result<PathBuf, String> {
        match self {
            Program::Sibling(name) => {
                let me = std::env::current_exe()
                    .map_err(|e| format!("cannot find procimg-compare's own path ({e})"))?;
                let path = me.with_file_name(name);
                if path.is_file() {
                    Ok(path)
                } else {
                    Err(format!(
                        "{name} is not built beside procimg-compare ({}): cargo build --bins",
                        path.display()
                    ))
                }
            }
            Program::InPath { name, install } => {
                let path = std::env::var_os("PATH").unwrap_or_default();
                std::env::split_paths(&path)
                    .map(|dir| dir.join(name))
                    .find(|p| is_executable(p))
                    .ok_or_else(|| format!("{name} is not installed: {install}"))
            }
        }
    }
}

fn is_executable(path: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt as _;
    std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
}

/// One run of one tool.
#[derive(Clone, Debug)]
pub struct Invocation {
    /// The tool.
    pub program: Program,
    /// Its arguments.
    pub args: Vec<String>,
    /// Its stdout and stderr go here.
    pub log: PathBuf,
    /// Longest it may take before it is killed.
    pub limit: Duration,
}

/// Runs `inv` to its end. `Err` is a one-line reason fit for the table's footnotes.
pub fn run(inv: &Invocation) -> Result<Duration, String> {
    let path = inv.program.locate()?;
    let log = std::fs::File::create(&inv.log)
        .map_err(|e| format!("cannot create {} ({e})", inv.log.display()))?;
    let log2 = log
        .try_clone()
        .map_err(|e| format!("cannot share {} ({e})", inv.log.display()))?;
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let start = Instant::now();
    let mut child = Command::new(&path)
        .args(&inv.args)
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(log2)
        // A group of its own: on a time-out the tool and whatever it started (procimgd, client
        // processes) are ended together, by this group's id.
        .process_group(0)
        .spawn()
        .map_err(|e| format!("cannot start {} ({e})", path.display()))?;
    let pid = child.id();
    let (tx, rx) = mpsc::channel();
    // Wait on a thread so that this one can sleep with a time limit instead of polling
    // while the tool measures.
    std::thread::spawn(move || {
        let _ = tx.send(child.wait());
    });
    let status = match rx.recv_timeout(inv.limit) {
        Ok(status) => status,
        Err(_) => {
            kill_group(pid);
            let _ = rx.recv();
            return Err(format!(
                "{name} took longer than {} s and was stopped (see {})",
                inv.limit.as_secs(),
                inv.log.display()
            ));
        }
    };
    let status = status.map_err(|e| format!("cannot wait for {name} ({e})"))?;
    if status.success() {
        Ok(start.elapsed())
    } else {
        Err(failure(&name, status, &inv.log))
    }
}

/// Ends the process group `pgid` (a child of ours that leads its own group).
fn kill_group(pgid: u32) {
    if let Ok(pgid) = libc::pid_t::try_from(pgid) {
        // SAFETY: kill takes a pid and a signal; a negative pid names the process group we
        // created for our own child, so nothing else is signalled.
        #[allow(unsafe_code)]
        unsafe {
            libc::kill(-pgid, libc::SIGKILL);
        }
    }
}

/// `"NAME failed (exit status: 1): <its last line of output>"`.
fn failure(name: &str, status: ExitStatus, log: &Path) -> String {
    let text = std::fs::read_to_string(log).unwrap_or_default();
    let last = text
        .lines()
        .rev()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("no output");
    let last: String = if last.chars().count() > 200 {
        last.chars().take(200).chain("…".chars()).collect()
    } else {
        last.to_string()
    };
    format!("{name} failed ({status}): {last}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_program_says_how_to_install_it() {
        let p = Program::InPath {
            name: "procimg-no-such-program",
            install: "apt-get install nothing",
        };
        assert!(p.locate().unwrap_err().contains("apt-get install nothing"));
    }

    #[test]
    fn a_failing_tool_is_reported_with_its_last_line() {
        let dir = std::env::temp_dir().join(format!("procimg-compare-run-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let inv = Invocation {
            program: Program::InPath {
                name: "sh",
                install: "",
            },
            args: vec![
                "-c".into(),
                "echo first; echo 'it broke' >&2; exit 3".into(),
            ],
            log: dir.join("log"),
            limit: Duration::from_secs(30),
        };
        let e = run(&inv).unwrap_err();
        assert!(e.contains("it broke") && e.contains('3'), "{e}");
        let slow = Invocation {
            args: vec!["-c".into(), "sleep 30".into()],
            limit: Duration::from_millis(200),
            ..inv
        };
        assert!(run(&slow).unwrap_err().contains("stopped"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
