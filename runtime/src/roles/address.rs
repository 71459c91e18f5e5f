// SPDX-License-Identifier: MIT OR Apache-2.0
//! A station's IPv4 address on its network interface, for the device role's station and for
//! the controller's own station where programs and DCP may change it (`[interface]
//! address_by_program`). A PROFINET device's address is the PLC's to give: the engineering
//! tool or the PLC sets it by DCP (for now or for good), resets it to factory (none), and
//! then connects to it. On a real interface procimgd carries that out on the Linux
//! interface, so that the PLC's Connect arrives:
//!
//! - At start the interface gets the station's address (configured, or kept in the state
//!   file), prefix from its netmask, unless it carries it already. A station without an
//!   address starts without one and waits for DCP.
//! - Any other IPv4 address on the interface stops the start, naming it. The interface is
//!   the station's, as a PROFINET device's port is: an address the PLC did not give could be
//!   the source of the station's answers, answer ARP beside the station, and stay when the
//!   PLC changes or clears the station's; and `network` naming the host's own LAN interface
//!   is a mistake that must not hand that interface's address to whoever speaks DCP there.
//!   Addresses procimgd added in an earlier run (marked, see
//!   [`PROCIMG_PROTOCOL`](crate::sys::netlink::PROCIMG_PROTOCOL)) are its
//!   own leftovers and are removed; the station's address with another netmask gets the
//!   station's.
//! - When DCP changes the station's IP suite, its old address goes and the new one comes
//!   (none for 0.0.0.0), with a default route through the gateway unless there is none
//!   (0.0.0.0, or the station's own address: DCP's "no router"). The route has a high metric
//!   ([`ROUTE_METRIC`]): it serves a host whose only way out is the PROFINET network, and
//!   never takes over a default route the host already has.
//! - At a clean stop procimgd removes what it added, as a device switched off no longer
//!   answers; an address it found (the administrator's, equal to the station's) stays.
//!
//! The changes happen on the acyclic thread, before the DCP answer goes out: a PLC connects
//! as soon as it has the answer. A change that fails is logged with the interface named;
//! the station goes on with the address DCP gave it.

use crate::sys::netlink::{self, IfAddress, Netlink};
use std::net::Ipv4Addr;

/// The metric of the station's default route: higher than any a distribution or DHCP client
/// gives (0 to a few thousand), so an existing default route stays in use.
pub const ROUTE_METRIC: u32 = 34964;

/// The station's IPv4 address as the interface carries it, and its router.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Suite {
    /// The address.
    pub ip: Ipv4Addr,
    /// The prefix length of its netmask.
    pub prefix: u8,
    /// The default gateway, if there is one.
    pub gateway: Option<Ipv4Addr>,
}

/// A netmask that is not ones followed by zeros: no prefix length.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NotANetmask(pub Ipv4Addr);

impl Suite {
    /// The suite of `ip` with `mask` and `gateway`; none for 0.0.0.0.
    pub fn new(
        ip: Ipv4Addr,
        mask: Ipv4Addr,
        gateway: Ipv4Addr,
    ) -> Result<Option<Suite>, NotANetmask> {
        if ip.is_unspecified() {
            return Ok(None);
        }
        let prefix = prefix_len(mask).ok_or(NotANetmask(mask))?;
        Ok(Some(Suite {
            ip,
            prefix,
            gateway: (!gateway.is_unspecified() && gateway != ip).then_some(gateway),
        }))
    }
}

/// The prefix length of `mask` (255.255.255.0: 24), if it is ones followed by zeros.
pub fn prefix_len(mask: Ipv4Addr) -> Option<u8> {
    let bits = u32::from(mask);
    let ones = bits.leading_ones();
    (ones + bits.trailing_zeros() == 32).then_some(ones as u8)
}

/// The station's address on the interface, as procimgd holds it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Held {
    ip: Ipv4Addr,
    /// As the interface carries it (an address found there keeps its own).
    prefix: u8,
    /// procimgd added it (and removes it at stop).
    added: bool,
    /// The gateway of the default route procimgd added.
    route: Option<Ipv4Addr>,
}

/// One change to the interface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Step {
    RemoveRoute,
    RemoveAddress(Ipv4Addr, u8),
    AddAddress(Ipv4Addr, u8),
    AddRoute(Ipv4Addr),
}

/// The changes from `held` to `want`, in order: the old route and address go before the
/// new ones come, so a route never points through an address about to go.
fn steps(held: Option<Held>, want: Option<Suite>) -> Vec<Step> {
    let same_address = held.map(|h| (h.ip, h.prefix)) == want.map(|w| (w.ip, w.prefix));
    let (route_now, route_want) = (held.and_then(|h| h.route), want.and_then(|w| w.gateway));
    // Removing the interface's last address flushes its routes: a kept gateway is added
    // again after a new address.
    let route_changes = route_now != route_want || !same_address;
    let mut out = Vec::new();
    if route_now.is_some() && route_changes {
        out.push(Step::RemoveRoute);
    }
    if !same_address {
        if let Some(h) = held {
            out.push(Step::RemoveAddress(h.ip, h.prefix));
        }
        if let Some(w) = want {
            out.push(Step::AddAddress(w.ip, w.prefix));
        }
    }
    if let Some(gw) = route_want.filter(|_| route_changes) {
        out.push(Step::AddRoute(gw));
    }
    out
}

/// What start finds on the interface and does about it.
#[derive(Debug, PartialEq, Eq)]
struct Takeover {
    /// To remove: procimgd's leftovers from an earlier run, and the station's address with
    /// another prefix than its netmask's.
    stale: Vec<IfAddress>,
    /// The station's address, found there.
    found: Option<Held>,
}

/// Sorts the interface's addresses `on` for a station that wants `want`; `Err` with the
/// addresses that are neither the station's nor procimgd's.
fn take_over(on: &[IfAddress], want: Option<Suite>) -> Result<Takeover, Vec<IfAddress>> {
    let wanted = |a: &IfAddress| want.is_some_and(|w| w.ip == a.ip);
    let foreign: Vec<IfAddress> = on
        .iter()
        .filter(|a| !a.ours && !wanted(a))
        .copied()
        .collect();
    if !foreign.is_empty() {
        return Err(foreign);
    }
    // The station's address is the station's whoever put it there, so it gets the station's
    // netmask too.
    let keep = |a: &IfAddress| want.is_some_and(|w| (w.ip, w.prefix) == (a.ip, a.prefix));
    Ok(Takeover {
        stale: on.iter().filter(|a| !keep(a)).copied().collect(),
        found: on.iter().find(|a| keep(a)).map(|a| Held {
            ip: a.ip,
            prefix: a.prefix,
            added: a.ours,
            route: None,
        }),
    })
}

/// `addresses` for a message: `10.0.0.1/24, 192.168.1.2/16`.
fn listed(addresses: &[IfAddress]) -> String {
    addresses
        .iter()
        .map(|a| format!("{}/{}", a.ip, a.prefix))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Why the station could not take its interface's address at start.
#[derive(Debug, thiserror::Error)]
pub enum AddressStartError {
    /// The interface's addresses could not be read or changed.
    // Not a `source`: the message already holds it, and error chains would repeat it.
    #[error(
        "network interface \"{interface}\": cannot {doing}: {error}; procimgd gives the \
         interface the station's address (the device role's station, or a controller whose \
         [interface] has address_by_program), which needs root (or CAP_NET_ADMIN)"
    )]
    Netlink {
        /// The interface.
        interface: String,
        /// What procimgd was doing.
        doing: String,
        /// What the system said.
        error: std::io::Error,
    },
    /// The interface carries addresses that are not the station's.
    #[error(
        "network interface \"{interface}\" carries {found}, not the station's address \
         ({station}): the station owns its interface's IPv4 address (the device role's, which \
         the PLC sets by DCP, or a controller's with [interface] address_by_program) and \
         procimgd shares the interface with no other; remove them (ip -4 addr flush dev \
         {interface}), make one the station's, or give the station a network interface of \
         its own"
    )]
    Foreign {
        /// The interface.
        interface: String,
        /// Its other addresses.
        found: String,
        /// The station's address, or "none".
        station: String,
    },
    /// The station's netmask has no prefix length.
    #[error(
        "the station's netmask {0} is not ones followed by zeros; correct `netmask` in \
         [station] (or the state file's)"
    )]
    Netmask(Ipv4Addr),
}

/// Why a change of the station's address could not be carried out on the interface.
#[derive(Debug, thiserror::Error)]
pub enum AddressChangeError {
    /// A netlink request failed.
    // Not a `source`: the message already holds it, and error chains would repeat it.
    #[error(
        "network interface \"{interface}\": cannot {doing}: {error}; the station keeps the \
         address DCP gave it, but the interface does not carry it: check the interface \
         (ip -4 addr show dev {interface}) and set the address again"
    )]
    Netlink {
        /// The interface.
        interface: String,
        /// What procimgd was doing.
        doing: String,
        /// What the system said.
        error: std::io::Error,
    },
    /// DCP gave a netmask without a prefix length (the engine refuses those).
    #[error(
        "network interface \"{interface}\": the station's new netmask {mask} is not ones \
         followed by zeros; its address stays as it was on the interface"
    )]
    Netmask {
        /// The interface.
        interface: String,
        /// The netmask.
        mask: Ipv4Addr,
    },
}

/// The station's hold on its interface's address.
pub struct InterfaceAddress {
    interface: String,
    index: u32,
    netlink: Netlink,
    held: Option<Held>,
}

impl InterfaceAddress {
    /// Gives `interface` the station's address `station` (none: no address) and removes
    /// procimgd's leftovers; refuses an interface with addresses of others.
    pub fn take(
        interface: &str,
        ip: Option<Ipv4Addr>,
        mask: Ipv4Addr,
        gateway: Ipv4Addr,
    ) -> Result<InterfaceAddress, AddressStartError> {
        let want = Suite::new(ip.unwrap_or(Ipv4Addr::UNSPECIFIED), mask, gateway)
            .map_err(|NotANetmask(m)| AddressStartError::Netmask(m))?;
        let failed = |doing: String| {
            move |error| AddressStartError::Netlink {
                interface: interface.to_owned(),
                doing,
                error,
            }
        };
        let index =
            netlink::interface_index(interface).map_err(failed("find its index".to_owned()))?;
        let mut netlink = Netlink::open().map_err(failed("open a netlink socket".to_owned()))?;
        let on = netlink
            .addresses(index)
            .map_err(failed("read its IPv4 addresses".to_owned()))?;
        let plan = take_over(&on, want).map_err(|foreign| AddressStartError::Foreign {
            interface: interface.to_owned(),
            found: listed(&foreign),
            station: ip.map_or_else(|| "none".to_owned(), |ip| ip.to_string()),
        })?;
        for a in &plan.stale {
            netlink
                .remove_address(index, a.ip, a.prefix)
                .map_err(failed(format!("remove {}/{}", a.ip, a.prefix)))?;
            tracing::info!(
                "network interface \"{interface}\": removed {}/{} (left by an earlier \
                 procimgd, or the station's address with another netmask)",
                a.ip,
                a.prefix
            );
        }
        // A route an earlier run left stays when its address was kept.
        netlink
            .remove_default_route(index, ROUTE_METRIC)
            .map_err(failed(
                "remove the default route an earlier procimgd left".to_owned(),
            ))?;
        let mut me = InterfaceAddress {
            interface: interface.to_owned(),
            index,
            netlink,
            held: plan.found,
        };
        for step in steps(plan.found, want) {
            me.apply(step).map_err(|e| match e {
                AddressChangeError::Netlink {
                    interface,
                    doing,
                    error,
                } => AddressStartError::Netlink {
                    interface,
                    doing,
                    error,
                },
                AddressChangeError::Netmask { mask, .. } => AddressStartError::Netmask(mask),
            })?;
        }
        Ok(me)
    }

    /// Carries out on the interface the station's IP suite `ip`, `netmask`, `gateway` (ip
    /// 0.0.0.0: none), if it changed.
    pub fn follow(
        &mut self,
        ip: Ipv4Addr,
        netmask: Ipv4Addr,
        gateway: Ipv4Addr,
    ) -> Result<(), AddressChangeError> {
        let want = Suite::new(ip, netmask, gateway).map_err(|NotANetmask(mask)| {
            AddressChangeError::Netmask {
                interface: self.interface.clone(),
                mask,
            }
        })?;
        for step in steps(self.held, want) {
            self.apply(step)?;
        }
        Ok(())
    }

    /// One step, and what procimgd holds after it.
    fn apply(&mut self, step: Step) -> Result<(), AddressChangeError> {
        let (index, interface) = (self.index, &self.interface);
        let failed = |doing: String| {
            move |error| AddressChangeError::Netlink {
                interface: interface.clone(),
                doing,
                error,
            }
        };
        match step {
            Step::RemoveRoute => {
                self.netlink
                    .remove_default_route(index, ROUTE_METRIC)
                    .map_err(failed("remove the station's default route".into()))?;
                if let Some(h) = self.held.as_mut() {
                    h.route = None;
                }
            }
            Step::RemoveAddress(ip, prefix) => {
                self.netlink
                    .remove_address(index, ip, prefix)
                    .map_err(failed(format!(
                        "remove the station's old address {ip}/{prefix}"
                    )))?;
                self.held = None;
                tracing::info!("network interface \"{interface}\": removed {ip}/{prefix}");
            }
            Step::AddAddress(ip, prefix) => {
                self.netlink
                    .add_address(index, ip, prefix)
                    .map_err(failed(format!("add the station's address {ip}/{prefix}")))?;
                self.held = Some(Held {
                    ip,
                    prefix,
                    added: true,
                    route: None,
                });
                tracing::info!("network interface \"{interface}\": added {ip}/{prefix}");
            }
            Step::AddRoute(gateway) => {
                self.netlink
                    .add_default_route(index, gateway, ROUTE_METRIC)
                    .map_err(failed(format!("add a default route through {gateway}")))?;
                if let Some(h) = self.held.as_mut() {
                    h.route = Some(gateway);
                }
                tracing::info!(
                    "network interface \"{interface}\": default route through {gateway} \
                     (metric {ROUTE_METRIC})"
                );
            }
        }
        Ok(())
    }
}

impl Drop for InterfaceAddress {
    /// A clean stop: what procimgd added goes; an address it found stays.
    fn drop(&mut self) {
        let Some(held) = self.held else {
            return;
        };
        let route = held.route.map(|_| Step::RemoveRoute);
        let address = held
            .added
            .then_some(Step::RemoveAddress(held.ip, held.prefix));
        for step in route.into_iter().chain(address) {
            if let Err(e) = self.apply(step) {
                tracing::warn!("{e}");
            }
        }
    }
}

#[cfg(test)]
mod tests;
