// SPDX-License-Identifier: MIT OR Apache-2.0
//! The machine's Ethernet adapters, as PN Driver's `SERV_CP_get_network_adapters` lists them
//! for a program to choose from: each with its interface name, MAC address and, for a PCI
//! card, its PCI location. Read from sysfs (`/sys/class/net`), which needs no rights.

use std::path::Path;

/// Where Linux lists its network interfaces.
const SYS_CLASS_NET: &str = "/sys/class/net";
/// `ARPHRD_ETHER`: the interface type of Ethernet (and of veth, bridges and the like).
const ARPHRD_ETHER: u32 = 1;

/// A card's place on the PCI bus (PN Driver's `PNIO_PCI_LOCATION_TYPE`; the domain is not
/// part of it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PciLocation {
    /// The bus number.
    pub bus: u16,
    /// The device number on the bus.
    pub device: u16,
    /// The function number of the device.
    pub function: u16,
}

impl PciLocation {
    /// Parses sysfs's name of a PCI function, `DDDD:BB:dd.f` (all hexadecimal).
    pub fn from_sysfs_name(name: &str) -> Option<PciLocation> {
        let (_domain, rest) = name.split_once(':')?;
        let (bus, rest) = rest.split_once(':')?;
        let (device, function) = rest.split_once('.')?;
        Some(PciLocation {
            bus: u16::from_str_radix(bus, 16).ok()?,
            device: u16::from_str_radix(device, 16).ok()?,
            function: u16::from_str_radix(function, 16).ok()?,
        })
    }
}

/// One Ethernet adapter of this machine.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NetworkAdapter {
    /// The interface name (`enp3s0`), what procimgd's configuration calls `network`.
    pub name: String,
    /// The interface's MAC address.
    pub mac: [u8; 6],
    /// The PCI location of a PCI card; `None` for a virtual interface (veth, a bridge) or a
    /// card on another bus.
    pub pci: Option<PciLocation>,
}

/// The Ethernet adapters of this machine (of the network namespace the caller runs in), in
/// interface index order; the loopback interface is not one. Interfaces sysfs cannot
/// describe are left out.
pub fn network_adapters() -> std::io::Result<Vec<NetworkAdapter>> {
    adapters_under(Path::new(SYS_CLASS_NET))
}

/// [`network_adapters`] from a sysfs-like directory (tests give one of their own).
pub fn adapters_under(dir: &Path) -> std::io::Result<Vec<NetworkAdapter>> {
    let mut found: Vec<(u32, NetworkAdapter)> = Vec::new();
    for entry in std::fs::read_dir(dir)? {
        let Ok(entry) = entry else { continue };
        let Some(name) = entry.file_name().to_str().map(str::to_string) else {
            continue;
        };
        let path = entry.path();
        let read = |file: &str| std::fs::read_to_string(path.join(file)).ok();
        let number = |file: &str| read(file).and_then(|t| t.trim().parse::<u32>().ok());
        if number("type") != Some(ARPHRD_ETHER) {
            continue;
        }
        let Some(mac) = read("address").and_then(|t| parse_mac(t.trim())) else {
            continue;
        };
        if mac == [0; 6] {
            // Loopback has type 772, but an interface with no address is not one to drive.
            continue;
        }
        let pci = std::fs::read_link(path.join("device"))
            .ok()
            .filter(|target| is_pci(target))
            .and_then(|target| {
                target
                    .file_name()
                    .and_then(|n| n.to_str())
                    .and_then(PciLocation::from_sysfs_name)
            });
        let index = number("ifindex").unwrap_or(u32::MAX);
        found.push((index, NetworkAdapter { name, mac, pci }));
    }
    found.sort_by(|a, b| a.0.cmp(&b.0).then_with(|| a.1.name.cmp(&b.1.name)));
    Ok(found.into_iter().map(|(_, a)| a).collect())
}

/// Whether a `device` link leads to a PCI function (`../../../0000:03:00.0`, under some
/// `pciDDDD:BB` root).
fn is_pci(target: &Path) -> bool {
    target
        .components()
        .any(|c| c.as_os_str().to_str().is_some_and(|s| s.starts_with("pci")))
}

/// `aa:bb:cc:dd:ee:ff` to bytes.
pub fn parse_mac(text: &str) -> Option<[u8; 6]> {
    let mut mac = [0u8; 6];
    let mut parts = text.split(':');
    for byte in &mut mac {
        *byte = u8::from_str_radix(parts.next()?, 16).ok()?;
    }
    parts.next().is_none().then_some(mac)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pci_names_and_macs_parse() {
        assert_eq!(
            PciLocation::from_sysfs_name("0000:03:1f.2"),
            Some(PciLocation {
                bus: 3,
                device: 0x1f,
                function: 2
            })
        );
        assert_eq!(PciLocation::from_sysfs_name("virtio0"), None);
        assert_eq!(
            parse_mac("02:00:5e:10:00:0a"),
            Some([2, 0, 0x5e, 0x10, 0, 0x0a])
        );
        assert_eq!(parse_mac("02:00:5e:10:00"), None);
        assert_eq!(parse_mac("02:00:5e:10:00:0a:01"), None);
    }

    #[test]
    fn a_sysfs_tree_gives_its_ethernet_adapters_in_index_order() {
        let dir = std::env::temp_dir().join(format!("procimg-adapters-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let iface = |name: &str, ty: u32, index: u32, mac: &str| {
            let d = dir.join(name);
            std::fs::create_dir_all(&d).unwrap();
            std::fs::write(d.join("type"), format!("{ty}\n")).unwrap();
            std::fs::write(d.join("ifindex"), format!("{index}\n")).unwrap();
            std::fs::write(d.join("address"), format!("{mac}\n")).unwrap();
            d
        };
        iface("lo", 772, 1, "00:00:00:00:00:00");
        iface("veth0", 1, 7, "02:00:00:00:00:07");
        let card = iface("enp3s0", 1, 2, "00:1b:1b:00:00:02");
        let pci = dir.join("pci0000:00/0000:00:1c.0/0000:03:00.0");
        std::fs::create_dir_all(&pci).unwrap();
        std::os::unix::fs::symlink(&pci, card.join("device")).unwrap();
        let adapters = adapters_under(&dir).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(
            adapters,
            vec![
                NetworkAdapter {
                    name: "enp3s0".into(),
                    mac: [0, 0x1b, 0x1b, 0, 0, 2],
                    pci: Some(PciLocation {
                        bus: 3,
                        device: 0,
                        function: 0
                    }),
                },
                NetworkAdapter {
                    name: "veth0".into(),
                    mac: [2, 0, 0, 0, 0, 7],
                    pci: None,
                },
            ]
        );
    }
}
