// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the interop tests share beyond the test kit: the network namespaces with the device's
//! subnet, and the device program as a child process.
#![allow(dead_code)]

pub mod device;

use procimg_testkit::netns::TestNet;
use std::net::Ipv4Addr;
use std::process::Command;

/// The two namespaces, the device's address and the controller side's address.
pub struct Net {
    pub net: TestNet,
    pub device_ip: Ipv4Addr,
    pub controller_ip: Ipv4Addr,
}

impl Net {
    /// Two namespaces, the controller in the first one and the device in the second; both
    /// ends get an address of 10.213.`subnet`.0/24, a subnet that exists only on this veth
    /// pair.
    pub fn new(tag: &str, subnet: u8) -> Net {
        let net = TestNet::new(tag, true);
        let device_ip = Ipv4Addr::new(10, 213, subnet, 2);
        let controller_ip = Ipv4Addr::new(10, 213, subnet, 1);
        net.address(0, &format!("{controller_ip}/24"));
        net.address(1, &format!("{device_ip}/24"));
        Net {
            net,
            device_ip,
            controller_ip,
        }
    }

    /// The controller's namespace.
    pub fn controller_ns(&self) -> &str {
        &self.net.ns[0]
    }

    /// The controller's end of the veth pair.
    pub fn controller_if(&self) -> &str {
        &self.net.ifs[0]
    }

    /// The device's namespace.
    pub fn device_ns(&self) -> &str {
        &self.net.ns[1]
    }

    /// The device's end of the veth pair.
    pub fn device_if(&self) -> &str {
        &self.net.ifs[1]
    }

    /// How many sockets hold the controller's end of the veth pair in promiscuous mode.
    pub fn controller_promiscuity(&self) -> u32 {
        let out = Command::new("ip")
            .args(["-d", "-n", self.controller_ns(), "link", "show"])
            .arg(self.controller_if())
            .output()
            .expect("the ip command (iproute2)");
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        let mut words = text.split_whitespace();
        words
            .find(|w| *w == "promiscuity")
            .and_then(|_| words.next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no promiscuity in {text:?}"))
    }

    /// The MAC address of procimgd's interface, as `aa:bb:cc:dd:ee:ff`.
    pub fn controller_mac(&self) -> String {
        mac_of(self.controller_ns(), self.controller_if())
    }

    /// The MAC address of the device's interface, as `aa:bb:cc:dd:ee:ff`.
    pub fn device_mac(&self) -> String {
        mac_of(self.device_ns(), self.device_if())
    }
}

/// The MAC address of `interface` in namespace `ns`.
fn mac_of(ns: &str, interface: &str) -> String {
    let out = Command::new("ip")
        .args(["-n", ns, "-o", "link", "show", interface])
        .output()
        .expect("the ip command (iproute2)");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let mut words = text.split_whitespace();
    words
        .find(|w| *w == "link/ether")
        .and_then(|_| words.next())
        .unwrap_or_else(|| panic!("no MAC address in {text:?}"))
        .to_string()
}
