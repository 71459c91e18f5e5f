// SPDX-License-Identifier: MIT OR Apache-2.0
//! Two network namespaces joined by a veth pair, made for a test and removed when it ends
//! (also when it fails). Shared by the runtime's and the tools' tests.
#![allow(dead_code)]

use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::ethernet;
use std::process::Command;

/// Whether the test runs as root (namespaces and raw sockets need it).
pub fn is_root() -> bool {
    // SAFETY: geteuid has no preconditions.
    unsafe { libc::geteuid() == 0 }
}

/// An untagged Ethernet frame around `payload`, padded to the Ethernet minimum.
pub fn frame(dst: MacAddress, src: MacAddress, ethertype: u16, payload: &[u8]) -> Vec<u8> {
    let eth = ethernet::Repr {
        dst,
        src,
        vlan: None,
        ethertype,
    };
    let mut f = vec![0u8; eth.buffer_len()];
    eth.emit(&mut f);
    f.extend_from_slice(payload);
    f.resize(f.len().max(60), 0);
    f
}

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
    pub ns: [String; 2],
    pub ifs: [String; 2],
}

impl TestNet {
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
        }
        net
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
            // SAFETY: setns(2) on a valid namespace descriptor; it changes this thread only.
            let rc =
                unsafe { libc::setns(std::os::fd::AsRawFd::as_raw_fd(&file), libc::CLONE_NEWNET) };
            assert_eq!(rc, 0, "setns: {}", std::io::Error::last_os_error());
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
