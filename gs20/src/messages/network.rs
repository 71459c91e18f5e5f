// SPDX-License-Identifier: MIT OR Apache-2.0
//! Set Network Configuration (0x10): how the module gets its address, and its host name,
//! which is the PROFINET station name (reference §1.5, error bit 3 in §1.6).

use std::net::Ipv4Addr;

use super::{Message, ParseError, Reader, Writer};
use crate::frame::{EmitError, FrameId};

/// The longest host name (reference §1.5).
pub const MAX_HOST_NAME: usize = 63;

coded_enum! {
    /// How the module gets its IP settings (0x10 byte 2, and the Network Up event).
    pub enum AddressMode(u8) display "unknown value {}" {
        /// 0: the addresses of the frame.
        Static = 0 => "static",
        /// 1: from a DHCP server (the module waits in Pending).
        Dhcp = 1 => "DHCP",
    }
}

/// Set Network Configuration (0x10, LEN 21 + N): address mode, IP, mask, gateway, two DNS
/// servers and a host name of N bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SetNetworkConfig<'a> {
    /// Byte 2.
    pub mode: AddressMode,
    /// Bytes 3–6.
    pub ip: Ipv4Addr,
    /// Bytes 7–10.
    pub mask: Ipv4Addr,
    /// Bytes 11–14.
    pub gateway: Ipv4Addr,
    /// Bytes 15–18.
    pub dns1: Ipv4Addr,
    /// Bytes 19–22.
    pub dns2: Ipv4Addr,
    /// Bytes 23 on: the host name as sent (see [`SetNetworkConfig::validate`]).
    pub host_name: &'a [u8],
}

/// Why a network configuration is invalid (error bit 3; reference §1.6 lists address mode,
/// IP, gateway, DNS and host name).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, thiserror::Error)]
pub enum NetworkConfigError {
    /// The address mode is neither static nor DHCP.
    #[error("address mode {0} is unknown: send 0 (static addresses) or 1 (DHCP)")]
    AddressMode(u8),
    /// The IP address is no usable host address in its subnet.
    #[error(
        "IP address {0} is no usable host address (not 0.0.0.0, loopback, multicast, \
         broadcast or the subnet's first or last address); send the station's own address"
    )]
    Ip(Ipv4Addr),
    /// The subnet mask is not a prefix of 1 to 30 bits.
    #[error("subnet mask {0} is not a mask of 1 to 30 leading one bits (e.g. 255.255.255.0)")]
    Mask(Ipv4Addr),
    /// The gateway is neither none nor an address in the station's subnet.
    #[error(
        "gateway {0} is not in the station's subnet; send 0.0.0.0 (or the station's own \
         address) for none"
    )]
    Gateway(Ipv4Addr),
    /// A DNS server is neither none nor a usable unicast address.
    #[error("DNS server {0} is no unicast address; send 0.0.0.0 for none")]
    Dns(Ipv4Addr),
    /// No host name.
    #[error("the host name is empty; it is the PROFINET station name, e.g. \"io-device-1\"")]
    HostNameEmpty,
    /// The host name is longer than 63 bytes.
    #[error("the host name has {0} bytes; it may have at most 63")]
    HostNameTooLong(usize),
    /// A byte that a host name may not hold.
    #[error(
        "the host name holds byte 0x{byte:02X} at {at}; use letters, digits, '-' and '.' \
         (it is the PROFINET station name)"
    )]
    HostNameChar {
        /// The byte.
        byte: u8,
        /// Its index.
        at: usize,
    },
    /// A label (between dots) is empty or starts or ends with '-'.
    #[error(
        "the host name has an empty label or one starting or ending with '-'; write labels \
         of letters, digits and '-' separated by single dots"
    )]
    HostNameLabel,
    /// The host name has a form PROFINET reserves: `port-xyz`, `port-xyz-abcde`, or an
    /// IPv4 address.
    #[error(
        "the host name has a form PROFINET reserves for port names or IP addresses \
         (\"port-001\", \"192.168.0.1\"); choose another, e.g. \"io-device-1\""
    )]
    HostNameReserved,
}

impl<'a> SetNetworkConfig<'a> {
    /// Static addresses without a gateway or DNS servers, as a host on a plant network
    /// without routing sends them.
    pub const fn static_ip(ip: Ipv4Addr, mask: Ipv4Addr, host_name: &'a [u8]) -> Self {
        SetNetworkConfig {
            mode: AddressMode::Static,
            ip,
            mask,
            gateway: Ipv4Addr::UNSPECIFIED,
            dns1: Ipv4Addr::UNSPECIFIED,
            dns2: Ipv4Addr::UNSPECIFIED,
            host_name,
        }
    }
}

impl SetNetworkConfig<'_> {
    /// Checks the configuration as the module would (error bit 3).
    ///
    /// The reference names the faults (address mode, IP, gateway, DNS, host name length
    /// and characters) but not the rules. Chosen:
    /// - with DHCP, the addresses are not looked at (the DHCP server's count);
    /// - with static addresses, the mask is 1 to 30 leading one bits; the IP is a host
    ///   address of its subnet (not 0.0.0.0/8, loopback, multicast, 240.0.0.0/4 or
    ///   broadcast, nor the subnet's first or last address); the gateway is 0.0.0.0 or
    ///   the IP itself (both: none, as PROFINET writes it) or a host address of the subnet;
    ///   each DNS server is 0.0.0.0 (none) or a unicast address;
    /// - the host name becomes the PROFINET station name, so it follows NameOfStation's
    ///   rules within the module's 63 bytes: letters (either case: the bridge writes it in
    ///   lower case, DNS names do not care), digits, '-' and '.'; labels not empty and not
    ///   starting or ending with '-'; not `port-xyz`, `port-xyz-abcde` or an IPv4 address.
    pub fn validate(&self) -> Result<(), NetworkConfigError> {
        match self.mode {
            AddressMode::Static => self.validate_addresses()?,
            AddressMode::Dhcp => {}
            AddressMode::Unknown(v) => return Err(NetworkConfigError::AddressMode(v)),
        }
        validate_host_name(self.host_name)
    }

    /// The station name: the host name, checked, in lower case.
    pub fn station_name(&self) -> Result<String, NetworkConfigError> {
        validate_host_name(self.host_name)?;
        Ok(self
            .host_name
            .iter()
            .map(|b| char::from(b.to_ascii_lowercase()))
            .collect())
    }

    fn validate_addresses(&self) -> Result<(), NetworkConfigError> {
        let mask = u32::from(self.mask);
        let prefix = mask.leading_ones();
        if mask.count_ones() != prefix || !(1..=30).contains(&prefix) {
            return Err(NetworkConfigError::Mask(self.mask));
        }
        let in_subnet_host = |a: Ipv4Addr| {
            let a32 = u32::from(a);
            let host = a32 & !mask;
            usable_unicast(a) && host != 0 && host != !mask
        };
        if !in_subnet_host(self.ip) {
            return Err(NetworkConfigError::Ip(self.ip));
        }
        let same_subnet = |a: Ipv4Addr| u32::from(a) & mask == u32::from(self.ip) & mask;
        let gw = self.gateway;
        if !(gw.is_unspecified() || gw == self.ip || (same_subnet(gw) && in_subnet_host(gw))) {
            return Err(NetworkConfigError::Gateway(gw));
        }
        for dns in [self.dns1, self.dns2] {
            if !(dns.is_unspecified() || usable_unicast(dns)) {
                return Err(NetworkConfigError::Dns(dns));
            }
        }
        Ok(())
    }
}

/// Not in 0.0.0.0/8, loopback, multicast or 240.0.0.0/4 (which holds the broadcast).
fn usable_unicast(a: Ipv4Addr) -> bool {
    let first = a.octets()[0];
    first != 0 && !a.is_loopback() && !a.is_multicast() && first < 240
}

fn validate_host_name(name: &[u8]) -> Result<(), NetworkConfigError> {
    if name.is_empty() {
        return Err(NetworkConfigError::HostNameEmpty);
    }
    if name.len() > MAX_HOST_NAME {
        return Err(NetworkConfigError::HostNameTooLong(name.len()));
    }
    if let Some((at, &byte)) = name
        .iter()
        .enumerate()
        .find(|(_, b)| !(b.is_ascii_alphanumeric() || **b == b'-' || **b == b'.'))
    {
        return Err(NetworkConfigError::HostNameChar { byte, at });
    }
    let labels = || name.split(|&b| b == b'.');
    if labels().any(|l| l.is_empty() || l.starts_with(b"-") || l.ends_with(b"-")) {
        return Err(NetworkConfigError::HostNameLabel);
    }
    let numeric = |l: &[u8]| (1..=3).contains(&l.len()) && l.iter().all(u8::is_ascii_digit);
    let first = labels().next().unwrap_or_default();
    if is_port_name(first) || (labels().count() == 4 && labels().all(numeric)) {
        return Err(NetworkConfigError::HostNameReserved);
    }
    Ok(())
}

/// `port-xyz` or `port-xyz-abcde`, x…e digits (IEC 61158-6-10's port names).
fn is_port_name(label: &[u8]) -> bool {
    let digits = |s: &[u8]| s.iter().all(u8::is_ascii_digit);
    let lower = label.to_ascii_lowercase();
    let Some(rest) = lower.strip_prefix(b"port-") else {
        return false;
    };
    match rest.len() {
        3 => digits(rest),
        9 => digits(&rest[..3]) && rest[3] == b'-' && digits(&rest[4..]),
        _ => false,
    }
}

impl<'a> Message<'a> for SetNetworkConfig<'a> {
    const ID: FrameId = FrameId::SetNetworkConfig;

    fn parse_payload(payload: &'a [u8]) -> Result<SetNetworkConfig<'a>, ParseError> {
        let mut r = Reader::new(Self::ID, payload)?;
        Ok(SetNetworkConfig {
            mode: AddressMode::from_raw(r.u8()?),
            ip: r.ipv4()?,
            mask: r.ipv4()?,
            gateway: r.ipv4()?,
            dns1: r.ipv4()?,
            dns2: r.ipv4()?,
            host_name: r.rest(),
        })
    }

    fn payload_len(&self) -> usize {
        21 + self.host_name.len()
    }

    fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
        Writer::new(out)
            .u8(self.mode.raw())
            .ipv4(self.ip)
            .ipv4(self.mask)
            .ipv4(self.gateway)
            .ipv4(self.dns1)
            .ipv4(self.dns2)
            .bytes(self.host_name)
            .finish()
    }
}
