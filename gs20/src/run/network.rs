// SPDX-License-Identifier: MIT OR Apache-2.0
//! The module's network side as the host sees it: the status word's flags and the Adapter
//! Events (reference §1.6), from procimgd's station and its notifications.
//!
//! What each means here, where the reference has only the names:
//! - **Ethernet link** (status bits 3–4): procimgd answers, so the station can go on the
//!   wire. Request Start needs it ("no network connection" otherwise).
//! - **Link up / link down** (events 1, 2): the host's station goes on the wire (it runs in
//!   procimgd, answers DCP and takes a PLC's Connect) / leaves it (Request Reset, or
//!   procimgd stopped).
//! - **Network up** (event 3; status bits 5–6): the station has an IP address: the host's
//!   static one once it is on the wire, or with DHCP the one the PLC (or an engineering
//!   tool) assigned by DCP, PROFINET's way of giving a device its address.
//! - **PLC connected / PLC lost** (events 4, 5; status bit 7): the PLC's AR reached data
//!   exchange / ended (released, aborted, its frames stopped).
//! - **PLC reset** (event 6): DCP's Reset to Factory, the one reset a PLC or an engineering
//!   tool commands of a PROFINET device, with reset type 1 (the reference gives types 0
//!   and 1 without saying what they are; 0 is not sent). The PLC's STOP is not a reset of
//!   the module: its outputs keep coming (their IOPS is the PLC's business), so it is no
//!   event; nor is the PLC's Release, which is "PLC lost".

use procimg_client::{ArState, Notification};
use procimg_gs20::messages::{AddressMode, Event, NetworkUp, StatusFlags};
use std::net::Ipv4Addr;

/// The reset type of "PLC reset" for DCP's Reset to Factory.
pub const RESET_TO_FACTORY: u8 = 1;

/// An IP suite: address, mask, gateway.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IpSuite {
    /// The address.
    pub ip: Ipv4Addr,
    /// The subnet mask.
    pub mask: Ipv4Addr,
    /// The gateway (0.0.0.0: none).
    pub gateway: Ipv4Addr,
}

/// The network side's state.
#[derive(Clone, Debug)]
pub struct NetState {
    /// procimgd answers.
    server: bool,
    /// The host's station is on the wire.
    on_wire: bool,
    /// The station's address, while it has one.
    suite: Option<IpSuite>,
    /// An AR is in data exchange.
    plc: bool,
    /// How the host asked for its address, and its DNS server, for Network Up.
    mode: AddressMode,
    dns: Ipv4Addr,
}

impl Default for NetState {
    fn default() -> NetState {
        NetState {
            server: false,
            on_wire: false,
            suite: None,
            plc: false,
            mode: AddressMode::Static,
            dns: Ipv4Addr::UNSPECIFIED,
        }
    }
}

impl NetState {
    /// The status word's flags (the link adds the mode and the error flag).
    pub fn flags(&self) -> StatusFlags {
        let mut f = StatusFlags::LINK_KNOWN;
        f.set(StatusFlags::LINK_UP, self.server);
        let addressed = self.server && self.on_wire && self.suite.is_some();
        f.set(StatusFlags::IP_OK | StatusFlags::NETWORK_OK, addressed);
        f.set(StatusFlags::PLC_CONNECTED, self.on_wire && self.plc);
        f
    }

    /// The broadcast address of the station's subnet, while it has an address.
    pub fn subnet_broadcast(&self) -> Option<Ipv4Addr> {
        self.suite
            .filter(|_| self.on_wire)
            .map(|s| Ipv4Addr::from(u32::from(s.ip) | !u32::from(s.mask)))
    }

    /// Whether procimgd answers.
    pub fn set_server(&mut self, up: bool) {
        self.server = up;
    }

    /// The station went on the wire with `suite` (none yet with DHCP) and the AR as the
    /// status has it: link up, network up with the address, PLC connected if an AR already
    /// is in data exchange.
    pub fn went_on_wire(
        &mut self,
        suite: Option<IpSuite>,
        plc: bool,
        mode: AddressMode,
        dns: Ipv4Addr,
    ) -> Vec<Event<'static>> {
        *self = NetState {
            server: true,
            on_wire: true,
            suite,
            plc,
            mode,
            dns,
        };
        let mut events = vec![Event::LinkUp];
        events.extend(self.network_up());
        if plc {
            events.push(Event::PlcConnected);
        }
        events
    }

    /// The station left the wire: PLC lost if one was connected, link down.
    pub fn went_off_wire(&mut self) -> Vec<Event<'static>> {
        let mut events = Vec::new();
        if self.on_wire && self.plc {
            events.push(Event::PlcLost);
        }
        if self.on_wire {
            events.push(Event::LinkDown);
        }
        *self = NetState {
            server: self.server,
            ..NetState::default()
        };
        events
    }

    /// What a notification of procimgd's station means for the host; events only while the
    /// station is on the wire.
    pub fn notification(&mut self, n: &Notification) -> Vec<Event<'static>> {
        if !self.on_wire {
            return Vec::new();
        }
        match n {
            Notification::StationAr {
                state: ArState::Data,
                ..
            } if !self.plc => {
                self.plc = true;
                vec![Event::PlcConnected]
            }
            Notification::StationArEnded { .. } if self.plc => {
                self.plc = false;
                vec![Event::PlcLost]
            }
            Notification::StationIdentity {
                ip,
                netmask,
                gateway,
                factory_reset,
                ..
            } => {
                let mut events = Vec::new();
                if *factory_reset {
                    events.push(Event::PlcReset {
                        reset_type: RESET_TO_FACTORY,
                    });
                }
                let suite = parse_suite(ip, netmask, gateway);
                if suite != self.suite {
                    self.suite = suite;
                    events.extend(self.network_up());
                }
                events
            }
            _ => Vec::new(),
        }
    }

    fn network_up(&self) -> Option<Event<'static>> {
        self.suite.map(|s| {
            Event::NetworkUp(NetworkUp {
                mode: self.mode,
                ip: s.ip,
                mask: s.mask,
                gateway: s.gateway,
                dns: self.dns,
            })
        })
    }
}

/// The suite of a notification's strings; `None` for no address (0.0.0.0) or what does not
/// parse.
pub fn parse_suite(ip: &str, mask: &str, gateway: &str) -> Option<IpSuite> {
    let ip: Ipv4Addr = ip.parse().ok()?;
    if ip.is_unspecified() {
        return None;
    }
    Some(IpSuite {
        ip,
        mask: mask.parse().unwrap_or(Ipv4Addr::UNSPECIFIED),
        gateway: gateway.parse().unwrap_or(Ipv4Addr::UNSPECIFIED),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn suite() -> IpSuite {
        IpSuite {
            ip: Ipv4Addr::new(192, 168, 0, 50),
            mask: Ipv4Addr::new(255, 255, 255, 0),
            gateway: Ipv4Addr::UNSPECIFIED,
        }
    }

    fn ar(state: ArState) -> Notification {
        Notification::StationAr {
            state,
            ar_uuid: "u".into(),
            controller_mac: "m".into(),
            controller_name: "plc".into(),
        }
    }

    fn ended() -> Notification {
        Notification::StationArEnded {
            ar_uuid: "u".into(),
            reason: "released by the PLC".into(),
            aborted: false,
            planned: false,
            abort_code: None,
        }
    }

    fn identity(ip: &str, factory_reset: bool) -> Notification {
        Notification::StationIdentity {
            name: "gs20-host".into(),
            ip: ip.into(),
            netmask: "255.255.255.0".into(),
            gateway: "0.0.0.0".into(),
            permanent: false,
            factory_reset,
        }
    }

    #[test]
    fn the_station_on_the_wire_reports_link_network_and_plc() {
        let mut n = NetState::default();
        n.set_server(true);
        assert_eq!(
            n.flags(),
            StatusFlags::LINK_KNOWN | StatusFlags::LINK_UP,
            "Config: procimgd answers, nothing on the wire"
        );
        assert!(n.notification(&ar(ArState::Data)).is_empty(), "not ours");
        let up = n.went_on_wire(
            Some(suite()),
            false,
            AddressMode::Static,
            Ipv4Addr::UNSPECIFIED,
        );
        assert_eq!(up.len(), 2);
        assert_eq!(up[0], Event::LinkUp);
        assert!(matches!(up[1], Event::NetworkUp(u) if u.ip == suite().ip));
        assert!(
            n.flags()
                .contains(StatusFlags::IP_OK | StatusFlags::NETWORK_OK)
        );
        assert!(n.notification(&ar(ArState::Connected)).is_empty());
        assert_eq!(n.notification(&ar(ArState::Data)), [Event::PlcConnected]);
        assert!(n.notification(&ar(ArState::Data)).is_empty(), "once");
        assert!(n.flags().contains(StatusFlags::PLC_CONNECTED));
        assert_eq!(n.notification(&ended()), [Event::PlcLost]);
        assert!(n.notification(&ended()).is_empty(), "once");
        assert_eq!(n.notification(&ar(ArState::Data)), [Event::PlcConnected]);
        assert_eq!(n.went_off_wire(), [Event::PlcLost, Event::LinkDown]);
        assert!(n.went_off_wire().is_empty());
        assert_eq!(n.flags(), StatusFlags::LINK_KNOWN | StatusFlags::LINK_UP);
    }

    #[test]
    fn dhcp_gets_its_address_by_dcp_and_a_reset_to_factory_is_the_plcs_reset() {
        let mut n = NetState::default();
        let up = n.went_on_wire(None, false, AddressMode::Dhcp, Ipv4Addr::new(10, 0, 0, 53));
        assert_eq!(up, [Event::LinkUp]);
        assert!(!n.flags().contains(StatusFlags::IP_OK));
        let got = n.notification(&identity("192.168.0.50", false));
        assert!(matches!(
            got[..],
            [Event::NetworkUp(u)] if u.mode == AddressMode::Dhcp && u.dns == Ipv4Addr::new(10, 0, 0, 53)
        ));
        assert!(n.notification(&identity("192.168.0.50", false)).is_empty());
        assert_eq!(
            n.notification(&identity("0.0.0.0", true)),
            [Event::PlcReset {
                reset_type: RESET_TO_FACTORY
            }]
        );
        assert!(!n.flags().contains(StatusFlags::IP_OK));
    }
}
