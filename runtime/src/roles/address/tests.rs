// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the station does to its interface's addresses, without an interface.

use super::*;

fn ip(s: &str) -> Ipv4Addr {
    s.parse().unwrap()
}

fn suite(a: &str, prefix: u8, gateway: Option<&str>) -> Option<Suite> {
    Some(Suite {
        ip: ip(a),
        prefix,
        gateway: gateway.map(ip),
    })
}

fn held(a: &str, prefix: u8, route: Option<&str>) -> Option<Held> {
    Some(Held {
        ip: ip(a),
        prefix,
        added: true,
        route: route.map(ip),
    })
}

fn on(a: &str, prefix: u8, ours: bool) -> IfAddress {
    IfAddress {
        ip: ip(a),
        prefix,
        ours,
    }
}

#[test]
fn prefixes_come_from_netmasks_of_ones_then_zeros() {
    assert_eq!(prefix_len(ip("255.255.255.0")), Some(24));
    assert_eq!(prefix_len(ip("255.255.240.0")), Some(20));
    assert_eq!(prefix_len(ip("255.255.255.255")), Some(32));
    assert_eq!(prefix_len(ip("0.0.0.0")), Some(0));
    assert_eq!(prefix_len(ip("255.0.255.0")), None);
    assert_eq!(prefix_len(ip("0.0.0.255")), None);
}

#[test]
fn a_suite_has_no_gateway_when_dcp_says_none() {
    let mask = ip("255.255.255.0");
    assert_eq!(
        Suite::new(ip("0.0.0.0"), ip("0.0.0.0"), ip("0.0.0.0")),
        Ok(None)
    );
    // DCP's "no router": the gateway is the station's own address (as an S7 sets it).
    assert_eq!(
        Suite::new(ip("10.0.0.5"), mask, ip("10.0.0.5")),
        Ok(suite("10.0.0.5", 24, None))
    );
    assert_eq!(
        Suite::new(ip("10.0.0.5"), mask, ip("0.0.0.0")),
        Ok(suite("10.0.0.5", 24, None))
    );
    assert_eq!(
        Suite::new(ip("10.0.0.5"), mask, ip("10.0.0.1")),
        Ok(suite("10.0.0.5", 24, Some("10.0.0.1")))
    );
    assert_eq!(
        Suite::new(ip("10.0.0.5"), ip("255.0.255.0"), ip("0.0.0.0")),
        Err(NotANetmask(ip("255.0.255.0")))
    );
}

#[test]
fn nothing_changes_when_the_suite_stays() {
    assert_eq!(steps(None, None), []);
    let h = held("10.0.0.5", 24, Some("10.0.0.1"));
    assert_eq!(steps(h, suite("10.0.0.5", 24, Some("10.0.0.1"))), []);
}

#[test]
fn a_first_address_is_added_with_its_route() {
    assert_eq!(
        steps(None, suite("10.0.0.5", 24, Some("10.0.0.1"))),
        [
            Step::AddAddress(ip("10.0.0.5"), 24),
            Step::AddRoute(ip("10.0.0.1"))
        ]
    );
    assert_eq!(
        steps(None, suite("10.0.0.5", 24, None)),
        [Step::AddAddress(ip("10.0.0.5"), 24)]
    );
}

#[test]
fn a_new_address_replaces_the_old_and_brings_the_route_back() {
    assert_eq!(
        steps(
            held("10.0.0.5", 24, Some("10.0.0.1")),
            suite("10.0.0.6", 24, Some("10.0.0.1"))
        ),
        [
            Step::RemoveRoute,
            Step::RemoveAddress(ip("10.0.0.5"), 24),
            Step::AddAddress(ip("10.0.0.6"), 24),
            Step::AddRoute(ip("10.0.0.1")),
        ]
    );
    // Only the netmask changes: the address goes and comes with the new prefix.
    assert_eq!(
        steps(held("10.0.0.5", 24, None), suite("10.0.0.5", 16, None)),
        [
            Step::RemoveAddress(ip("10.0.0.5"), 24),
            Step::AddAddress(ip("10.0.0.5"), 16),
        ]
    );
}

#[test]
fn a_new_gateway_changes_only_the_route() {
    assert_eq!(
        steps(
            held("10.0.0.5", 24, Some("10.0.0.1")),
            suite("10.0.0.5", 24, Some("10.0.0.2"))
        ),
        [Step::RemoveRoute, Step::AddRoute(ip("10.0.0.2"))]
    );
    assert_eq!(
        steps(
            held("10.0.0.5", 24, Some("10.0.0.1")),
            suite("10.0.0.5", 24, None)
        ),
        [Step::RemoveRoute]
    );
}

#[test]
fn a_reset_to_factory_removes_route_and_address() {
    assert_eq!(
        steps(held("10.0.0.5", 24, Some("10.0.0.1")), None),
        [Step::RemoveRoute, Step::RemoveAddress(ip("10.0.0.5"), 24)]
    );
}

#[test]
fn other_addresses_stop_the_start() {
    let found = [on("192.168.1.7", 24, false), on("10.0.0.5", 24, false)];
    assert_eq!(
        take_over(&found, suite("10.0.0.5", 24, None)),
        Err(vec![on("192.168.1.7", 24, false)])
    );
    // A station without an address shares the interface with none.
    assert_eq!(
        take_over(&[on("10.0.0.5", 24, false)], None),
        Err(vec![on("10.0.0.5", 24, false)])
    );
    assert_eq!(listed(&found), "192.168.1.7/24, 10.0.0.5/24");
}

#[test]
fn the_stations_address_found_there_is_kept_and_leftovers_go() {
    let found = [on("10.0.0.9", 24, true), on("10.0.0.5", 24, false)];
    assert_eq!(
        take_over(&found, suite("10.0.0.5", 24, None)),
        Ok(Takeover {
            stale: vec![on("10.0.0.9", 24, true)],
            found: Some(Held {
                ip: ip("10.0.0.5"),
                prefix: 24,
                added: false,
                route: None,
            }),
        })
    );
    // Ours from an earlier run, the station's: kept, and removed again at stop.
    assert_eq!(
        take_over(&[on("10.0.0.5", 24, true)], suite("10.0.0.5", 24, None)),
        Ok(Takeover {
            stale: vec![],
            found: held("10.0.0.5", 24, None),
        })
    );
    // With another netmask than the station's: replaced.
    assert_eq!(
        take_over(&[on("10.0.0.5", 16, false)], suite("10.0.0.5", 24, None)),
        Ok(Takeover {
            stale: vec![on("10.0.0.5", 16, false)],
            found: None,
        })
    );
    assert_eq!(
        take_over(&[], None),
        Ok(Takeover {
            stale: vec![],
            found: None
        })
    );
}
