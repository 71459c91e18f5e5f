// SPDX-License-Identifier: MIT OR Apache-2.0
//! net-snmp's snmpd as the AgentX master of a test (Debian packages `snmpd` and `snmp`):
//! its configuration, AgentX socket, persistent state and log in a directory of the test,
//! listening on UDP on loopback, in the test's own network namespace if it names one; and
//! net-snmp's tools run against it with numeric OIDs.

use std::fs;
use std::net::UdpSocket;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Fails the test, saying what to install, unless net-snmp's agent and tools are there.
pub fn require_net_snmp() {
    for tool in ["/usr/sbin/snmpd", "/usr/bin/snmpwalk", "/usr/bin/snmpget"] {
        assert!(
            Path::new(tool).exists(),
            "{tool} is missing: install net-snmp with `apt-get install -y snmpd snmp`"
        );
    }
}

/// snmpd as AgentX master; ended (by its pid) when dropped, also when the test fails. The
/// directory it was given must outlive it.
pub struct Snmpd {
    child: Child,
    port: u16,
    log: PathBuf,
    netns: Option<String>,
}

impl Snmpd {
    /// Starts snmpd with its files in `dir`, the master socket `socket` and UDP on
    /// 127.0.0.1 (in network namespace `netns` if given, whose loopback it brings up), and
    /// waits until the socket is there.
    pub fn start(dir: &Path, socket: &Path, netns: Option<&str>) -> Snmpd {
        require_net_snmp();
        let port = match netns {
            // A namespace of the test's own: any port is free.
            Some(ns) => {
                crate::netns::ip(&["-n", ns, "link", "set", "lo", "up"]);
                16161
            }
            None => free_udp_port(),
        };
        let conf = dir.join("snmpd.conf");
        let log = dir.join("snmpd.log");
        fs::write(
            &conf,
            format!(
                "master agentx\n\
                 agentXSocket {}\n\
                 agentXTimeout 5\n\
                 agentaddress udp:127.0.0.1:{port}\n\
                 rocommunity public 127.0.0.1\n\
                 rwcommunity private 127.0.0.1\n",
                socket.display()
            ),
        )
        .expect("write snmpd.conf");
        let mut command = match netns {
            // `ip netns exec` becomes snmpd (it executes it in place): the pid is snmpd's.
            Some(ns) => {
                let mut c = Command::new("ip");
                c.args(["netns", "exec", ns, "/usr/sbin/snmpd"]);
                c
            }
            None => Command::new("/usr/sbin/snmpd"),
        };
        let child = command
            .args(["-f", "-Lo", "-C", "-c"])
            .arg(&conf)
            // Its persistent state goes to the test's directory, not /var/lib/snmp.
            .env("SNMP_PERSISTENT_DIR", dir)
            .stdin(Stdio::null())
            .stdout(fs::File::create(&log).expect("create snmpd.log"))
            .stderr(Stdio::inherit())
            .spawn()
            .expect("snmpd starts");
        let snmpd = Snmpd {
            child,
            port,
            log,
            netns: netns.map(str::to_owned),
        };
        let deadline = Instant::now() + Duration::from_secs(10);
        while !socket.exists() {
            assert!(
                Instant::now() < deadline,
                "snmpd made no AgentX socket in 10 s; its log:\n{}",
                snmpd.log()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        snmpd
    }

    /// What snmpd logged so far.
    pub fn log(&self) -> String {
        fs::read_to_string(&self.log).unwrap_or_default()
    }

    /// `127.0.0.1:PORT`, where it answers SNMP.
    pub fn target(&self) -> String {
        format!("127.0.0.1:{}", self.port)
    }

    /// Runs net-snmp tool `tool` (e.g. `/usr/bin/snmpwalk`) with SNMPv2c, community
    /// `public`, numeric OIDs and enums against this snmpd, in its namespace; its standard
    /// output. Fails the test, with snmpd's log, if the tool fails.
    pub fn tool(&self, tool: &str, args: &[&str]) -> String {
        let mut command = match &self.netns {
            Some(ns) => {
                let mut c = Command::new("ip");
                c.args(["netns", "exec", ns, tool]);
                c
            }
            None => Command::new(tool),
        };
        let out = command
            .args(["-v2c", "-c", "public", "-On", "-Oe", "-t", "2", "-r", "1"])
            .arg(self.target())
            .args(args)
            .output()
            .expect("the net-snmp tool runs");
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(
            out.status.success(),
            "{tool} {args:?} failed: {}{stdout}\nsnmpd's log:\n{}",
            String::from_utf8_lossy(&out.stderr),
            self.log()
        );
        stdout
    }
}

impl Drop for Snmpd {
    fn drop(&mut self) {
        // Child::kill signals this child's own pid (SIGKILL); wait reaps it.
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn free_udp_port() -> u16 {
    UdpSocket::bind("127.0.0.1:0")
        .and_then(|s| s.local_addr())
        .map(|a| a.port())
        .expect("a free UDP port on loopback")
}
