// SPDX-License-Identifier: MIT OR Apache-2.0
//! Two network namespaces joined by a veth pair, made for a test or a soak run and removed
//! when it ends (also when it fails).

use std::process::Command;

pub use crate::signal::is_root;

/// Runs `ip ARGS` (iproute2) and panics with its error output if it fails.
pub fn ip(args: &[&str]) {
    let out = Command::new("ip")
        .args(args)
        .output()
        .expect("the ip command (iproute2)");
    assert!(
        out.status.success(),
        "ip {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Two namespaces joined by a veth pair, ends up (or the second end left down).
pub struct TestNet {
    /// The namespaces' names.
    pub ns: [String; 2],
    /// The veth ends, `ifs[i]` in `ns[i]`.
    pub ifs: [String; 2],
}

impl TestNet {
    /// Makes the namespaces and the pair; `tag` (a few letters) keeps tests apart.
    pub fn new(tag: &str, second_up: bool) -> TestNet {
        let id = std::process::id() % 100_000;
        let net = TestNet {
            ns: [format!("pi{tag}{id}a"), format!("pi{tag}{id}b")],
            ifs: [format!("pi{tag}{id}a"), format!("pi{tag}{id}b")],
        };
        for ns in &net.ns {
            let _ = Command::new("ip").args(["netns", "del", ns]).output();
            ip(&["netns", "add", ns]);
        }
        ip(&[
            "link",
            "add",
            &net.ifs[0],
            "type",
            "veth",
            "peer",
            "name",
            &net.ifs[1],
        ]);
        for i in 0..2 {
            ip(&["link", "set", &net.ifs[i], "netns", &net.ns[i]]);
        }
        ip(&["-n", &net.ns[0], "link", "set", &net.ifs[0], "up"]);
        if second_up {
            ip(&["-n", &net.ns[1], "link", "set", &net.ifs[1], "up"]);
            for i in 0..2 {
                net.wait_until_running(i);
            }
        }
        net
    }

    /// Waits until end `i` carries frames. `ip link set up` returns before the kernel's link
    /// watch has given the veth its queue: until then a frame sent is dropped without an
    /// error, and a test that sends once (a DCP Identify) waits for an answer that never
    /// comes. The link watch runs from a work queue, late on a loaded machine.
    fn wait_until_running(&self, i: usize) {
        let until = std::time::Instant::now() + std::time::Duration::from_secs(10);
        loop {
            let out = Command::new("ip")
                .args(["-n", &self.ns[i], "link", "show", "dev", &self.ifs[i]])
                .output()
                .expect("the ip command (iproute2)");
            let line = String::from_utf8_lossy(&out.stdout);
            // `qdisc noop` is the placeholder that drops everything; `state UP` comes once the
            // carrier is on both ends.
            if line.contains("state UP") && !line.contains("qdisc noop") {
                return;
            }
            assert!(
                std::time::Instant::now() < until,
                "{} did not come up within 10 s: {line}",
                self.ifs[i]
            );
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
    }

    /// Puts the IPv4 address `cidr` (`A.B.C.D/N`) on end `i` of the pair.
    pub fn address(&self, i: usize, cidr: &str) {
        ip(&["-n", &self.ns[i], "addr", "add", cidr, "dev", &self.ifs[i]]);
    }

    /// Runs `f` on a thread that has entered namespace `i`.
    pub fn in_ns<T: Send + 'static>(
        &self,
        i: usize,
        f: impl FnOnce(String) -> T + Send + 'static,
    ) -> std::thread::JoinHandle<T> {
        let path = format!("/var/run/netns/{}", self.ns[i]);
        let ifname = self.ifs[i].clone();
        std::thread::spawn(move || {
            let file = std::fs::File::open(&path).unwrap();
            crate::signal::enter_netns(&file);
            f(ifname)
        })
    }
}

impl Drop for TestNet {
    fn drop(&mut self) {
        for ns in &self.ns {
            let _ = Command::new("ip").args(["netns", "del", ns]).output();
        }
    }
}

/// An untagged Ethernet frame around `payload`, padded to the Ethernet minimum of 60 bytes
/// (without FCS).
pub fn frame(dst: [u8; 6], src: [u8; 6], ethertype: u16, payload: &[u8]) -> Vec<u8> {
    let mut f = Vec::with_capacity(60.max(14 + payload.len()));
    f.extend_from_slice(&dst);
    f.extend_from_slice(&src);
    f.extend_from_slice(&ethertype.to_be_bytes());
    f.extend_from_slice(payload);
    f.resize(f.len().max(60), 0);
    f
}
