// SPDX-License-Identifier: MIT OR Apache-2.0
//! Every frame on the wire, checked by Wireshark's dissectors: dumpcap records the device's
//! end of the veth pair into files of a minute each, and every finished file is read by
//! tshark (at the lowest priority) and removed, so that an hour needs no more disk than a
//! few minutes of frames.

use crate::process::Running;
use anyhow::Context as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

/// Error-level expert items have severity PI_ERROR = 0x00800000.
const BAD_FRAMES: &str = "_ws.malformed || _ws.expert.severity >= 8388608";

/// What tshark found so far.
#[derive(Clone, Debug, Default)]
pub struct Verdict {
    /// Frames read.
    pub frames: u64,
    /// Malformed or in error, sent by procimgd.
    pub bad_from_procimgd: u64,
    /// Malformed or in error, sent by the device.
    pub bad_from_device: u64,
}

/// The running capture.
pub struct Capture {
    dumpcap: Running,
    dir: PathBuf,
    procimgd_mac: String,
    log: PathBuf,
    /// What was found so far.
    pub verdict: Verdict,
}

impl Capture {
    /// Starts dumpcap on `iface` in namespace `ns`; frames sent by `procimgd_mac` are
    /// procimgd's.
    pub fn start(ns: &str, iface: &str, procimgd_mac: &str, out: &Path) -> anyhow::Result<Capture> {
        let dir = out.join("capture");
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        let mut cmd = Command::new("ip");
        cmd.args(["netns", "exec", ns, "dumpcap", "-q", "-i", iface])
            .args(["-b", "duration:60", "-w"])
            .arg(dir.join("soak.pcapng"));
        let log = out.join("capture.log");
        let dumpcap =
            Running::spawn(cmd, &log).context("starting dumpcap (apt-get install tshark)")?;
        Ok(Capture {
            dumpcap,
            dir,
            procimgd_mac: procimgd_mac.to_ascii_lowercase(),
            log,
            verdict: Verdict::default(),
        })
    }

    /// The capture files, oldest first.
    fn files(&self) -> Vec<PathBuf> {
        let mut files: Vec<PathBuf> = std::fs::read_dir(&self.dir)
            .map(|d| {
                d.filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| p.extension().is_some_and(|x| x == "pcapng"))
                    .collect()
            })
            .unwrap_or_default();
        files.sort();
        files
    }

    /// Checks and removes the files dumpcap has finished (all but the newest).
    pub fn check_finished(&mut self) -> anyhow::Result<()> {
        let mut files = self.files();
        files.pop();
        for f in files {
            self.check(&f)?;
        }
        Ok(())
    }

    /// Stops dumpcap and checks what is left.
    pub fn finish(mut self) -> anyhow::Result<Verdict> {
        self.dumpcap.stop(libc::SIGTERM, Duration::from_secs(10));
        for f in self.files() {
            self.check(&f)?;
        }
        // Kept when it holds the files of bad frames.
        let _ = std::fs::remove_dir(&self.dir);
        Ok(self.verdict)
    }

    fn tshark(&self, file: &Path, args: &[&str]) -> anyhow::Result<String> {
        let out = Command::new("nice")
            .args(["-n", "19", "tshark", "-r"])
            .arg(file)
            .args(args)
            .output()
            .context("running tshark (apt-get install tshark)")?;
        if !out.status.success() {
            anyhow::bail!(
                "tshark -r {} failed: {}",
                file.display(),
                String::from_utf8_lossy(&out.stderr)
            );
        }
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    }

    fn check(&mut self, file: &Path) -> anyhow::Result<()> {
        let count = Command::new("capinfos")
            .args(["-c", "-M", "-T", "-r"])
            .arg(file)
            .output()
            .context("running capinfos (apt-get install tshark)")?;
        let frames: u64 = String::from_utf8_lossy(&count.stdout)
            .split_whitespace()
            .last()
            .and_then(|n| n.parse().ok())
            .unwrap_or(0);
        self.verdict.frames += frames;
        let bad = self.tshark(
            file,
            &[
                "-Y",
                BAD_FRAMES,
                "-T",
                "fields",
                "-e",
                "frame.number",
                "-e",
                "eth.src",
            ],
        )?;
        let mut numbers = Vec::new();
        for line in bad.lines().filter(|l| !l.trim().is_empty()) {
            let mut fields = line.split('\t');
            let number = fields.next().unwrap_or_default().to_string();
            if fields
                .next()
                .is_some_and(|src| src.eq_ignore_ascii_case(&self.procimgd_mac))
            {
                self.verdict.bad_from_procimgd += 1;
            } else {
                self.verdict.bad_from_device += 1;
            }
            numbers.push(number);
        }
        if numbers.is_empty() {
            let _ = std::fs::remove_file(file);
        } else {
            // Kept with tshark's dissection of the offending frames beside it.
            let filter = format!("frame.number in {{{}}}", numbers.join(" "));
            let detail = self.tshark(file, &["-Y", &filter, "-V"])?;
            let report = file.with_extension("bad.txt");
            std::fs::write(&report, detail)
                .with_context(|| format!("writing {}", report.display()))?;
            eprintln!(
                "procimg-soak: {} frames of {} malformed or in error: see {} (dumpcap log {})",
                numbers.len(),
                file.display(),
                report.display(),
                self.log.display()
            );
        }
        Ok(())
    }
}
