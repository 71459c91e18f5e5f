// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimg-opcua serving the demo (`procimgd --demo`: three simulated devices) to an
//! independent OPC UA client, asyncua (PyPI), which runs `tests/asyncua_demo.py`: the PNIO
//! item names by NodeId with their qualities, one Read of one cycle, unknown items refused,
//! the browsable tree, a subscription as the counter device counts, an anonymous write
//! refused, and a secure channel (Basic256Sha256, SignAndEncrypt) once the client's
//! certificate, first refused and kept in the PKI folder's rejected/, is moved to trusted/;
//! over it, users of the users file (`procimg-opcua user add`): a writer's outputs come back
//! through the echo device, held against a second writer until the first session ends; a
//! reader's write and a write of the wrong type are refused.
//!
//! asyncua lives in a virtual environment: `ASYNCUA_PY` names its interpreter, by default
//! `target/asyncua-venv/bin/python`, which CI makes with `python3 -m venv
//! target/asyncua-venv && target/asyncua-venv/bin/pip install asyncua==2.1.0`.

use procimg_testkit::Launch;
use std::net::{Ipv4Addr, TcpListener, TcpStream};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
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

/// procimg-opcua as a child, ended (by its id) when dropped.
struct OpcUa(Child);

impl Drop for OpcUa {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
#[ignore = "needs asyncua (PyPI) in target/asyncua-venv (see the module's documentation)"]
fn an_independent_client_reads_browses_subscribes_and_connects_securely() {
    let python = asyncua_py();
    let demo = Launch::demo("opcua").until_cycling().start();
    demo.wait_devices_running(Duration::from_secs(60));
    let dir = procimg_testkit::files::temp_dir("opcua");
    let pki = dir.path().join("pki");
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
        use std::io::Write as _;
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
    let log_path = dir.path().join("procimg-opcua.log");
    let log = std::fs::File::create(&log_path).expect("the server's log file");
    let server = OpcUa(
        Command::new(env!("CARGO_BIN_EXE_procimg-opcua"))
            .args([
                "--instance",
                &demo.instance,
                "--endpoint",
                &url,
                "--insecure",
            ])
            .arg("--pki")
            .arg(&pki)
            .arg("--users")
            .arg(&users)
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
    let out = Command::new(&python)
        .arg(procimg_testkit::workspace_dir().join("opcua/tests/asyncua_demo.py"))
        .arg(format!("{url}/"))
        .arg(&demo.instance)
        .arg(&pki)
        .arg(dir.path())
        .output()
        .expect("run asyncua_demo.py");
    drop(server);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && stdout.contains("asyncua: all checks held"),
        "asyncua_demo.py ({}):\n{stdout}\n{}\nprocimg-opcua's log:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr),
        std::fs::read_to_string(&log_path).unwrap_or_default()
    );
    demo.assert_alive();
}
