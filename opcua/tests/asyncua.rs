// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimg-opcua serving procimgd to an independent OPC UA client, asyncua (PyPI), which
//! runs the scripts beside this file (`asyncua_common.py` holds what they share):
//!
//! - `asyncua_demo.py` against the demo (three simulated devices): the PNIO item names by
//!   NodeId with their qualities, one Read of one cycle, unknown items refused, the
//!   browsable tree, a subscription as the counter device counts, an anonymous write
//!   refused, and a secure channel (Basic256Sha256, SignAndEncrypt) once the client's
//!   certificate, first refused and kept in the PKI folder's rejected/, is moved to
//!   trusted/; over it, users of the users file (`procimg-opcua user add`): a writer's
//!   outputs come back through the echo device, held against a second writer until the
//!   first session ends; a reader's write and a write of the wrong type are refused; the
//!   devices' failure and return as events of procimg's DeviceEventType, around OFFLINE and
//!   a deactivation of one device by the ActivateDevice method.
//! - `asyncua_device.py` against the device demo: the station's I data written by a writer
//!   and the PLC's answer read back, the AR's life as events, wrong writes refused, a
//!   client that vanishes while subscribed.
//! - `asyncua_relayout.py`, subscribed while procimgd starts anew with another layout.
//!
//! asyncua lives in a virtual environment: `ASYNCUA_PY` names its interpreter, by default
//! `target/asyncua-venv/bin/python`, which CI makes with `python3 -m venv
//! target/asyncua-venv && target/asyncua-venv/bin/pip install asyncua==2.1.0`.

use procimg_testkit::Launch;
use std::io::{BufRead, BufReader, Write as _};
use std::net::{Ipv4Addr, TcpListener, TcpStream};
use std::path::PathBuf;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

fn asyncua_py() -> PathBuf {
    procimg_testkit::pypi::venv_python("ASYNCUA_PY", "asyncua-venv", "asyncua==2.1.0")
}

/// A port nobody listens on now.
fn free_port() -> u16 {
    TcpListener::bind((Ipv4Addr::LOCALHOST, 0))
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free TCP port on 127.0.0.1")
}

/// A child process, ended when dropped: SIGTERM, so that procimg-opcua closes its
/// sessions and lets go of procimgd's shared memory; SIGKILL after 10 s.
struct Ended(Child);

impl Drop for Ended {
    fn drop(&mut self) {
        procimg_testkit::signal::stop(&mut self.0, libc::SIGTERM, Duration::from_secs(10));
    }
}

/// procimg-opcua serving an instance, with the users the scripts know, its PKI and log in
/// a directory of its own.
struct Served {
    dir: procimg_testkit::files::TempDir,
    instance: String,
    url: String,
    _server: Ended,
}

impl Served {
    /// procimg-opcua for `instance`, with `extra` arguments.
    fn start(instance: &str, extra: &[&str]) -> Served {
        let dir = procimg_testkit::files::temp_dir("opcua");
        let port = free_port();
        let url = format!("opc.tcp://127.0.0.1:{port}");
        let users = dir.path().join("users.toml");
        for (name, role, password) in [
            ("operator", "writer", "op-pw"),
            ("second", "writer", "second-pw"),
            ("viewer", "reader", "viewer-pw"),
        ] {
            let mut add = Command::new(env!("CARGO_BIN_EXE_procimg-opcua"))
                .args(["user", "add"])
                .arg(&users)
                .args([name, "--role", role])
                .stdin(Stdio::piped())
                .spawn()
                .expect("procimg-opcua user add");
            let mut stdin = add.stdin.take().expect("its standard input");
            writeln!(stdin, "{password}").expect("the password");
            drop(stdin);
            assert!(
                add.wait().expect("user add ends").success(),
                "user add {name}"
            );
        }
        assert!(
            !std::fs::read_to_string(&users).unwrap().contains("op-pw"),
            "passwords are stored hashed"
        );
        let log = std::fs::File::create(dir.path().join("procimg-opcua.log"))
            .expect("the server's log file");
        let server = Ended(
            Command::new(env!("CARGO_BIN_EXE_procimg-opcua"))
                .args(["--instance", instance, "--endpoint", &url, "--insecure"])
                .arg("--pki")
                .arg(dir.path().join("pki"))
                .arg("--users")
                .arg(&users)
                .args(extra)
                .stdout(Stdio::null())
                .stderr(log)
                .spawn()
                .expect("start procimg-opcua"),
        );
        // It serves once it listens (its certificate is made first).
        let until = Instant::now() + Duration::from_secs(120);
        while TcpStream::connect((Ipv4Addr::LOCALHOST, port)).is_err() {
            assert!(
                Instant::now() < until,
                "procimg-opcua does not listen on {url}"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
        Served {
            dir,
            instance: instance.to_owned(),
            url,
            _server: server,
        }
    }

    /// `script` (beside this file) run by asyncua against the server.
    fn script(&self, script: &str) -> Command {
        let mut c = Command::new(asyncua_py());
        c.arg(
            procimg_testkit::workspace_dir()
                .join("opcua/tests")
                .join(script),
        )
        .arg(format!("{}/", self.url))
        .arg(&self.instance)
        .arg(self.dir.path().join("pki"))
        .arg(self.dir.path());
        c
    }

    /// Asserts that a script's run held all its checks.
    fn assert_held(&self, script: &str, out: &Output) {
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success() && stdout.contains("asyncua: all checks held"),
            "{script} ({}):\n{stdout}\n{}\nprocimg-opcua's log:\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr),
            std::fs::read_to_string(self.dir.path().join("procimg-opcua.log")).unwrap_or_default()
        );
    }

    fn run(&self, script: &str) {
        let out = self.script(script).output().expect("run an asyncua script");
        self.assert_held(script, &out);
    }
}

#[test]
#[ignore = "needs asyncua (PyPI) in target/asyncua-venv (see the module's documentation)"]
fn an_independent_client_reads_browses_subscribes_and_connects_securely() {
    let demo = Launch::demo("opcua").until_cycling().start();
    demo.wait_devices_running(Duration::from_secs(60));
    // The demo devices' own GSDML files type their data.
    let gsdml = procimg_testkit::workspace_dir().join("config/gsdml");
    let served = Served::start(&demo.instance, &["--gsdml", gsdml.to_str().unwrap()]);
    served.run("asyncua_demo.py");
    demo.assert_alive();
}

#[test]
#[ignore = "needs asyncua (PyPI) in target/asyncua-venv (see the module's documentation)"]
fn the_station_is_served_and_a_new_layout_replaces_its_nodes() {
    let mut station = Launch::demo_device("opcua-dev").start();
    let served = Served::start(&station.instance, &[]);
    served.run("asyncua_device.py");
    station.assert_alive();

    // A client subscribed while procimgd starts anew, as the controller demo.
    let mut watcher = served
        .script("asyncua_relayout.py")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run asyncua_relayout.py");
    let mut first = String::new();
    BufReader::new(watcher.stdout.as_mut().expect("its standard output"))
        .read_line(&mut first)
        .expect("a line of asyncua_relayout.py");
    assert!(first.contains("subscribed"), "asyncua_relayout.py: {first}");
    station.terminate();
    let controller = Launch::demo("opcua-relayout")
        .instance(&station.instance)
        .start();
    let mut out = watcher
        .wait_with_output()
        .expect("asyncua_relayout.py ends");
    out.stdout.splice(0..0, first.into_bytes());
    served.assert_held("asyncua_relayout.py", &out);
    controller.assert_alive();
}
