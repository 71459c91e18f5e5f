// SPDX-License-Identifier: MIT OR Apache-2.0
//! An interface's link and counters as the kernel shows them in sysfs
//! (`/sys/class/net/<interface>/`): what the device role's physical records report. Plain
//! file reads, no `unsafe`; sysfs shows the network namespace of the process (as `ip netns
//! exec` mounts it).

use std::io;
use std::path::PathBuf;

/// What the kernel says of an interface now.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct InterfaceState {
    /// `operstate` is `up`.
    pub up: bool,
    /// `speed` in Mbit/s, when the driver knows it.
    pub speed_mbit: Option<u32>,
    /// `duplex` is `full`.
    pub full_duplex: bool,
    /// The `statistics` counters: rx/tx bytes, dropped, errors.
    pub counters: [u64; 6],
    /// The `statistics` frame counters: rx and tx packets, collisions.
    pub frames: [u64; 3],
}

/// Reads `interface`'s state. Files a driver does not provide (speed, duplex) read as
/// unknown; a missing interface is an error.
pub fn read(interface: &str) -> io::Result<InterfaceState> {
    let dir = PathBuf::from("/sys/class/net").join(interface);
    let text = |name: &str| std::fs::read_to_string(dir.join(name)).map(|s| s.trim().to_owned());
    let number = |name: &str| text(name).ok().and_then(|s| s.parse::<i64>().ok());
    let operstate = text("operstate")?;
    let mut counters = [0u64; 6];
    for (c, name) in counters.iter_mut().zip([
        "rx_bytes",
        "tx_bytes",
        "rx_dropped",
        "tx_dropped",
        "rx_errors",
        "tx_errors",
    ]) {
        *c = number(&format!("statistics/{name}")).map_or(0, |v| v.max(0) as u64);
    }
    let mut frames = [0u64; 3];
    for (c, name) in frames
        .iter_mut()
        .zip(["rx_packets", "tx_packets", "collisions"])
    {
        *c = number(&format!("statistics/{name}")).map_or(0, |v| v.max(0) as u64);
    }
    Ok(InterfaceState {
        frames,
        up: operstate == "up",
        speed_mbit: number("speed").and_then(|s| u32::try_from(s).ok()),
        full_duplex: text("duplex").is_ok_and(|d| d == "full"),
        counters,
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn loopback_reads() {
        let s = super::read("lo").expect("lo in sysfs");
        // Loopback's operstate is "unknown": it has no link to speak of.
        assert!(!s.up);
        assert!(super::read("no-such-interface-x").is_err());
    }
}
