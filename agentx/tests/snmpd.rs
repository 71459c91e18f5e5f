// SPDX-License-Identifier: MIT OR Apache-2.0
//! The subagent under net-snmp's snmpd (Debian packages `snmpd` and `snmp`): snmpd runs as
//! master agent on a socket and a UDP port of a temporary directory and loopback, the
//! runner serves [`Snapshot::example`], and net-snmp's own tools read it back.
//!
//! Ignored by default: run as root with `cargo test -p procimg-agentx -- --ignored`.

use std::fs;
use std::path::Path;
use std::process::Command;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};

use procimg_agentx::mib::{MibView, Snapshot};
use procimg_agentx::pdu::Value;
use procimg_agentx::runner::{self, MasterAddress, RunnerConfig, RunnerEvent};
use procimg_agentx::session::Event;
use procimg_testkit::snmpd::Snmpd;

const LLDP_MIB: &str = "1.0.8802.1.1.2";
const SYS_NAME: &str = "1.3.6.1.2.1.1.5.0";
const SYS_LOCATION: &str = "1.3.6.1.2.1.1.6.0";

/// Fails the test with what to do when it cannot run here.
fn require_root_and_net_snmp() {
    assert!(
        procimg_testkit::netns::is_root(),
        "run this test as root (it starts snmpd)"
    );
    procimg_testkit::snmpd::require_net_snmp();
}

/// The runner on a thread; stopped and joined when dropped.
struct Subagent {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
    events: Receiver<RunnerEvent>,
}

impl Subagent {
    fn start(socket: &Path, retry: Duration) -> Subagent {
        let config = RunnerConfig {
            master: MasterAddress::Unix(socket.to_owned()),
            retry_interval: retry,
            ..RunnerConfig::default()
        };
        let stop = Arc::new(AtomicBool::new(false));
        let (tx, events) = mpsc::channel();
        let thread_stop = Arc::clone(&stop);
        let thread = thread::spawn(move || {
            runner::run(&config, &thread_stop, Snapshot::example, |e| {
                let _ = tx.send(e);
            });
        });
        Subagent {
            stop,
            thread: Some(thread),
            events,
        }
    }

    /// Waits for an event that `wanted` accepts; returns every event seen on the way.
    fn wait_for(&self, what: &str, wanted: impl Fn(&RunnerEvent) -> bool) -> Vec<String> {
        let deadline = Instant::now() + Duration::from_secs(20);
        let mut seen = Vec::new();
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.events.recv_timeout(left) {
                Ok(e) => {
                    seen.push(format!("{e:?}"));
                    if wanted(&e) {
                        return seen;
                    }
                }
                Err(_) => panic!("no {what} in 20 s; events: {seen:#?}"),
            }
        }
    }
}

impl Drop for Subagent {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// `.1.2.3 = TYPE: value` lines as (OID without the leading dot, type, value).
fn parse_lines(output: &str) -> Vec<(String, String, String)> {
    output
        .lines()
        .filter_map(|line| {
            let (oid, rest) = line.split_once(" = ")?;
            let (ty, value) = rest.split_once(": ").unwrap_or((rest, ""));
            Some((
                oid.trim_start_matches('.').to_owned(),
                ty.to_owned(),
                value.to_owned(),
            ))
        })
        .collect()
}

/// The type net-snmp prints for a value.
fn net_snmp_type(v: &Value) -> &'static str {
    match v {
        Value::Integer(_) => "INTEGER",
        // Printable strings are STRING, others Hex-STRING.
        Value::OctetString(o) if o.iter().all(|b| b.is_ascii_graphic() || *b == b' ') => "STRING",
        Value::OctetString(_) => "Hex-STRING",
        Value::ObjectIdentifier(_) => "OID",
        Value::Gauge32(_) => "Gauge32",
        Value::Counter32(_) => "Counter32",
        Value::TimeTicks(_) => "Timeticks",
        other => panic!("the example serves no {other:?}"),
    }
}

/// What a walk of `root` should print: the example's instances under it.
fn expected_walk(root: &str) -> Vec<(String, &'static str)> {
    let root: procimg_agentx::pdu::Oid = root.parse().unwrap();
    MibView::new(&Snapshot::example())
        .instances()
        .iter()
        .filter(|v| v.name.starts_with(root.as_slice()))
        .map(|v| (v.name.to_string(), net_snmp_type(&v.value)))
        .collect()
}

fn is_ready(e: &RunnerEvent) -> bool {
    matches!(e, RunnerEvent::Session(Event::Ready))
}

fn check_walk_and_get(snmpd: &Snmpd) {
    for tool in ["/usr/bin/snmpwalk", "/usr/bin/snmpbulkwalk"] {
        let walk = parse_lines(&snmpd.tool(tool, &[LLDP_MIB]));
        let got: Vec<(String, &str)> = walk
            .iter()
            .map(|(o, t, _)| (o.clone(), t.as_str()))
            .collect();
        let expected = expected_walk(LLDP_MIB);
        let expected: Vec<(String, &str)> = expected.iter().map(|(o, t)| (o.clone(), *t)).collect();
        assert_eq!(got, expected, "{tool} of the LLDP-MIB");
        let value = |oid: &str| {
            walk.iter()
                .find(|(o, _, _)| o == oid)
                .map(|(_, _, v)| v.clone())
                .unwrap_or_default()
        };
        assert_eq!(value("1.0.8802.1.1.2.1.3.3.0"), "\"plc-station\"");
        assert_eq!(
            value("1.0.8802.1.1.2.1.4.1.1.7.300.1.1"),
            "\"port-001.io-device-1\""
        );
        assert_eq!(value("1.0.8802.1.1.2.1.3.8.1.3.1.4.192.168.0.50"), "5");
        assert_eq!(value("1.0.8802.1.1.2.1.5.3791.1.3.1.1.3.300.1.1"), "240");
    }
    let get = parse_lines(&snmpd.tool("/usr/bin/snmpget", &[SYS_NAME, SYS_LOCATION]));
    assert_eq!(
        get,
        [
            (SYS_NAME.into(), "STRING".into(), "\"plc-station\"".into()),
            (SYS_LOCATION.into(), "STRING".into(), "\"hall 3\"".into()),
        ],
        "snmpd's log:\n{}",
        snmpd.log()
    );
}

#[test]
#[ignore = "needs root: snmpd"]
fn snmpd_serves_the_lldp_mib_and_the_system_group_from_the_subagent() {
    require_root_and_net_snmp();
    let dir = tempfile::tempdir().unwrap();
    let socket = dir.path().join("master");
    let snmpd = Snmpd::start(dir.path(), &socket, None);
    let subagent = Subagent::start(&socket, Duration::from_millis(200));
    let events = subagent.wait_for("registration", is_ready);
    assert!(
        !events.iter().any(|e| e.contains("Refused")),
        "{events:#?}\nsnmpd's log:\n{}",
        snmpd.log()
    );
    check_walk_and_get(&snmpd);
    // A set by a community that may write is refused by the subagent: the MIB is
    // read-only.
    let set = Command::new("/usr/bin/snmpset")
        .args(["-v2c", "-c", "private", "-t", "2", "-r", "0"])
        .arg(snmpd.target())
        .args([SYS_NAME, "s", "renamed"])
        .output()
        .expect("snmpset runs");
    let stderr = String::from_utf8_lossy(&set.stderr);
    assert!(
        !set.status.success() && stderr.contains("notWritable"),
        "{stderr}"
    );
    drop(subagent);
}

#[test]
#[ignore = "needs root: snmpd"]
fn a_subagent_started_before_snmpd_attaches_when_snmpd_comes_up() {
    require_root_and_net_snmp();
    let dir = tempfile::tempdir().unwrap();
    let socket = dir.path().join("master");
    let subagent = Subagent::start(&socket, Duration::from_millis(200));
    subagent.wait_for("failed connection", |e| {
        matches!(e, RunnerEvent::ConnectFailed(..))
    });
    let snmpd = Snmpd::start(dir.path(), &socket, None);
    subagent.wait_for("registration", is_ready);
    check_walk_and_get(&snmpd);
    // snmpd goes away and comes back: the subagent attaches again.
    drop(snmpd);
    subagent.wait_for("disconnection", |e| {
        matches!(e, RunnerEvent::Disconnected(_))
    });
    let _ = fs::remove_file(&socket);
    let snmpd = Snmpd::start(dir.path(), &socket, None);
    subagent.wait_for("registration", is_ready);
    check_walk_and_get(&snmpd);
}
