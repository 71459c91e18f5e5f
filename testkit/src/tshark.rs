// SPDX-License-Identifier: MIT OR Apache-2.0
//! Every frame procimg emits must decode in Wireshark's PROFINET dissectors without malformed
//! packets or error-level expert items: this writes frames to a pcap file and asks tshark.

use pcap_file::pcap::{PcapPacket, PcapWriter};
use std::process::Command;
use std::time::Duration;

/// One dissected frame: protocol column and info column.
#[derive(Debug)]
pub struct Dissected {
    /// Wireshark's protocol column.
    pub protocol: String,
    /// Wireshark's info column.
    pub info: String,
}

/// Writes `frames` to a pcap, checks tshark finds nothing malformed and no error-level expert
/// item, and returns what it made of each frame. Panics with tshark's full dissection of the
/// offending frames otherwise.
pub fn dissect_clean(name: &str, frames: &[Vec<u8>]) -> Vec<Dissected> {
    clean_fields(name, frames, &["_ws.col.Protocol", "_ws.col.Info"])
        .into_iter()
        .map(|mut f| {
            let info = f.pop().unwrap_or_default();
            let protocol = f.pop().unwrap_or_default();
            Dissected { protocol, info }
        })
        .collect()
}

/// Like [`dissect_clean`], then the values tshark reads for `fields` (display filter field
/// names such as `lldp.chassis.id`) in each frame: one string per field, empty where the
/// frame has none, several occurrences joined by commas.
pub fn clean_fields(name: &str, frames: &[Vec<u8>], fields: &[&str]) -> Vec<Vec<String>> {
    // Removed when this returns or panics: a failure prints what tshark said.
    let dir = crate::files::temp_dir("tshark");
    let path = dir.path().join("frames.pcap");
    let file = std::fs::File::create(&path).expect("create the pcap file");
    let mut w = PcapWriter::new(std::io::BufWriter::new(file)).expect("write the pcap header");
    for (i, f) in frames.iter().enumerate() {
        let at = Duration::from_millis(1_700_000_000_000 + i as u64);
        w.write_packet(&PcapPacket::new(at, f.len() as u32, f))
            .expect("write a frame to the pcap file");
    }
    drop(w);
    let tshark = |args: &[&str]| read(&path, args);
    // Error-level expert items have severity PI_ERROR = 0x00800000.
    let bad = tshark(&[
        "-Y",
        "_ws.malformed || _ws.expert.severity >= 8388608",
        "-T",
        "fields",
        "-e",
        "frame.number",
    ]);
    if !bad.trim().is_empty() {
        let numbers: Vec<&str> = bad.split_whitespace().collect();
        let filter = format!("frame.number in {{{}}}", numbers.join(" "));
        let detail = tshark(&["-Y", &filter, "-V"]);
        panic!("tshark finds frames {numbers:?} of {name} malformed or in error:\n{detail}");
    }
    let mut args = vec!["-T", "fields"];
    for f in fields {
        args.extend(["-e", f]);
    }
    let values: Vec<Vec<String>> = tshark(&args)
        .lines()
        .map(|l| {
            // The last field keeps any tab of its own (an info column may hold one).
            let mut v: Vec<String> = l
                .splitn(fields.len().max(1), '\t')
                .map(str::to_string)
                .collect();
            v.resize(fields.len(), String::new());
            v
        })
        .collect();
    assert_eq!(
        values.len(),
        frames.len(),
        "tshark read a different number of frames"
    );
    values
}

/// tshark recording an interface of a network namespace (not promiscuous: the frames it sends
/// and those addressed to it) into a file, from before the test's traffic until [`LiveCapture::stop`] (or until dropped, also when the test fails).
pub struct LiveCapture {
    child: Option<std::process::Child>,
    path: std::path::PathBuf,
}

impl LiveCapture {
    /// Starts tshark on `interface` of namespace `ns`, writing to `path`; returns once it
    /// captures.
    pub fn start(ns: &str, interface: &str, path: &std::path::Path) -> LiveCapture {
        let child = Command::new("ip")
            // -p: the interface's promiscuity stays what the test set up (some tests check it).
            .args([
                "netns", "exec", ns, "tshark", "-q", "-p", "-i", interface, "-w",
            ])
            .arg(path)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot run tshark ({e}): apt-get install tshark"));
        // tshark writes the file's header once it captures.
        let until = std::time::Instant::now() + Duration::from_secs(20);
        while !path.exists() && std::time::Instant::now() < until {
            std::thread::sleep(Duration::from_millis(50));
        }
        std::thread::sleep(Duration::from_millis(500));
        LiveCapture {
            child: Some(child),
            path: path.to_path_buf(),
        }
    }

    /// Stops tshark (SIGINT: it finishes the file) and returns the file.
    pub fn stop(mut self) -> std::path::PathBuf {
        self.end();
        self.path.clone()
    }

    fn end(&mut self) {
        if let Some(mut child) = self.child.take() {
            crate::signal::send(child.id(), libc::SIGINT);
            let _ = child.wait();
        }
    }
}

impl Drop for LiveCapture {
    fn drop(&mut self) {
        self.end();
    }
}

/// What tshark prints (one line per frame) for the frames of `pcap` that match display filter
/// `filter`; empty when none does.
pub fn frames_matching(pcap: &std::path::Path, filter: &str) -> String {
    let out = Command::new("tshark")
        .arg("-r")
        .arg(pcap)
        .args(["-Y", filter])
        .output()
        .unwrap_or_else(|e| panic!("cannot run tshark ({e}): apt-get install tshark"));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The values of `fields` (display filter field names such as `dcerpc.dg_act_id`) in each
/// frame of `pcap` that matches display filter `filter`, in capture order: one string per
/// field, empty where the frame has none, several occurrences joined by commas.
pub fn fields_matching(pcap: &std::path::Path, filter: &str, fields: &[&str]) -> Vec<Vec<String>> {
    let mut args = vec!["-Y", filter, "-T", "fields"];
    for f in fields {
        args.extend(["-e", f]);
    }
    read(pcap, &args)
        .lines()
        .map(|l| l.split('\t').map(str::to_owned).collect())
        .collect()
}

/// What tshark prints reading `pcap` with `args`; panics with its complaint if it fails.
fn read(pcap: &std::path::Path, args: &[&str]) -> String {
    let out = Command::new("tshark")
        .arg("-r")
        .arg(pcap)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run tshark ({e}): apt-get install tshark"));
    assert!(
        out.status.success(),
        "tshark failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The frames of `pcap` that tshark flags: malformed, or an expert item of error level.
pub fn flagged(pcap: &std::path::Path) -> String {
    frames_matching(pcap, "_ws.malformed || _ws.expert.severity >= error")
}
