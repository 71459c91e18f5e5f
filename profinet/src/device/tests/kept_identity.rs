// SPDX-License-Identifier: MIT OR Apache-2.0
//! What a restart keeps: the name and address DCP set permanently, the factory state after
//! a reset; not what was set temporarily.

use super::*;

/// Sends a DCP request to the device; the one response's Set results.
fn set(dev: &mut Device<TestApp>, repr: &wire_dcp::Repr) -> Vec<u8> {
    let mut out = Vec::new();
    dev.on_frame(
        &dcp_client::frame(PNET_MAC, S7_MAC, repr).unwrap(),
        0,
        &mut out,
    );
    parse_dcp(&frames(&out)[0])
        .set_result()
        .map(|(_, _, e)| e)
        .collect()
}

#[test]
fn a_permanent_set_is_kept_and_a_temporary_one_is_not() {
    let mut dev = pnet_device(TestApp::None);
    assert_eq!(dev.station().kept_identity(), &KeptIdentity::default());
    assert_eq!(
        set(&mut dev, &wire_dcp::Repr::set_name(1, "temporary", false)),
        [0]
    );
    assert_eq!(dev.station().name(), "temporary");
    assert_eq!(dev.station().kept_identity().changes, 0);

    assert_eq!(
        set(&mut dev, &wire_dcp::Repr::set_name(2, "station-7", true)),
        [0]
    );
    let kept = dev.station().kept_identity();
    assert_eq!(
        (kept.name.as_deref(), kept.ip_suite, kept.changes),
        (Some("station-7"), None, 1)
    );
    // The same value again, permanently: kept again (an engineering tool makes a name
    // permanent that way).
    assert_eq!(
        set(&mut dev, &wire_dcp::Repr::set_name(3, "station-7", true)),
        [0]
    );
    assert_eq!(dev.station().kept_identity().changes, 2);

    let ip = wire_dcp::Repr::set_ip(4, [10, 0, 0, 7], [255, 255, 0, 0], [10, 0, 0, 1], true);
    assert_eq!(set(&mut dev, &ip), [0]);
    assert_eq!(
        dev.station().kept_identity().ip_suite,
        Some([[10, 0, 0, 7], [255, 255, 0, 0], [10, 0, 0, 1]])
    );
    assert_eq!(
        dev.station().mask_and_gateway(),
        ([255, 255, 0, 0], [10, 0, 0, 1])
    );
    let temporary = wire_dcp::Repr::set_ip(5, [10, 0, 0, 8], [255, 255, 0, 0], [0; 4], false);
    assert_eq!(set(&mut dev, &temporary), [0]);
    assert_eq!(dev.station().ip(), [10, 0, 0, 8]);
    assert_eq!(
        dev.station().kept_identity().ip_suite.map(|s| s[0]),
        Some([10, 0, 0, 7])
    );
}

#[test]
fn a_reset_to_factory_keeps_the_factory_state() {
    let mut dev = pnet_device(TestApp::None);
    assert_eq!(
        set(&mut dev, &wire_dcp::Repr::set_name(1, "station-7", true)),
        [0]
    );
    let reset = wire_dcp::Repr::reset_to_factory(2, 2);
    set(&mut dev, &reset);
    let kept = dev.station().kept_identity();
    assert_eq!(kept.name.as_deref(), Some(""));
    assert_eq!(kept.ip_suite, Some([[0; 4]; 3]));
    assert_eq!((dev.station().name(), dev.station().ip()), ("", [0; 4]));
}

#[test]
fn the_caller_sets_the_kept_identity_back_at_start() {
    let mut dev = pnet_device(TestApp::None);
    dev.station_mut().set_name("from-last-time");
    dev.station_mut()
        .set_ip_suite([10, 1, 2, 3], [255, 0, 0, 0], [10, 0, 0, 1]);
    assert_eq!(dev.station().name(), "from-last-time");
    assert_eq!(dev.station().ip(), [10, 1, 2, 3]);
    assert_eq!(
        dev.station().mask_and_gateway(),
        ([255, 0, 0, 0], [10, 0, 0, 1])
    );
    assert_eq!(
        dev.station().kept_identity().changes,
        0,
        "setting it back is no change"
    );
}

/// Sends DCP `repr` from the S7 to the device at `now`: what the device does.
fn dcp_set(dev: &mut Device<TestApp>, repr: &wire_dcp::Repr, now: u64) -> Vec<DeviceAction> {
    let mut out = Vec::new();
    dev.on_frame(
        &dcp_client::frame(PNET_MAC, S7_MAC, repr).unwrap(),
        now,
        &mut out,
    );
    out
}

/// The DCP Set checks among `out`.
fn set_checks(out: &[DeviceAction]) -> Vec<DcpSetCheck> {
    out.iter()
        .filter_map(|a| match a {
            DeviceAction::DcpSetCheck(c) => Some(c.clone()),
            _ => None,
        })
        .collect()
}

/// The BlockErrors of the one Set response among `out`.
fn set_errors(out: &[DeviceAction]) -> Vec<u8> {
    let f = frames(out);
    assert_eq!(f.len(), 1, "one response: {out:?}");
    parse_dcp(&f[0]).set_result().map(|(_, _, e)| e).collect()
}

#[test]
fn the_application_vetoes_or_allows_dcps_changes() {
    let mut dev = quiet_device(pnet_spec(TestApp::None));
    dev.verify_dcp_sets(true);
    let before = dev.station().name().to_owned();
    // A new name waits; the repeated request too; a vetoed one leaves the name alone.
    let out = dcp_set(&mut dev, &wire_dcp::Repr::set_name(5, "new-name", true), 0);
    assert!(frames(&out).is_empty(), "{out:?}");
    let c = set_checks(&out);
    assert_eq!(
        (c[0].name.as_deref(), c[0].permanent, c[0].reset, c[0].from),
        (Some("new-name"), true, false, S7_MAC)
    );
    assert!(dcp_set(&mut dev, &wire_dcp::Repr::set_name(5, "new-name", true), MS).is_empty());
    // Another Set meanwhile: resource error.
    let other = dcp_set(&mut dev, &wire_dcp::Repr::set_name(6, "third", false), MS);
    assert_eq!(set_errors(&other), [wire_dcp::block_error::RESOURCE_ERROR]);
    let mut out = Vec::new();
    dev.answer_dcp_set(c[0].job, false, 2 * MS, &mut out)
        .unwrap();
    assert_eq!(set_errors(&out), [wire_dcp::block_error::SET_NOT_POSSIBLE]);
    assert_eq!(dev.station().name(), before);
    assert_eq!(
        dev.answer_dcp_set(c[0].job, true, 2 * MS, &mut out),
        Err(UnknownDcpSetCheck(c[0].job))
    );
    // Allowed: carried out and kept.
    let out = dcp_set(
        &mut dev,
        &wire_dcp::Repr::set_ip(7, [10, 0, 0, 9], [255, 255, 255, 0], [0; 4], false),
        3 * MS,
    );
    let c = set_checks(&out);
    assert_eq!(
        c[0].ip_suite,
        Some([[10, 0, 0, 9], [255, 255, 255, 0], [0; 4]])
    );
    let mut out = Vec::new();
    dev.answer_dcp_set(c[0].job, true, 4 * MS, &mut out)
        .unwrap();
    assert_eq!(set_errors(&out), [wire_dcp::block_error::OK]);
    assert_eq!(dev.station().ip(), [10, 0, 0, 9]);
    // Signal does not wait.
    let out = dcp_set(&mut dev, &wire_dcp::Repr::signal(8), 5 * MS);
    assert!(set_checks(&out).is_empty());
    assert_eq!(set_errors(&out), [wire_dcp::block_error::OK]);
    // Unanswered: carried out after the timeout.
    let out = dcp_set(
        &mut dev,
        &wire_dcp::Repr::set_name(9, "late-name", false),
        6 * MS,
    );
    assert_eq!(set_checks(&out).len(), 1);
    let sent: Vec<DeviceAction> = run_until(&mut dev, 6 * MS + DCP_SET_CHECK_TIMEOUT_NS)
        .into_iter()
        .map(|(_, a)| a)
        .filter(|a| matches!(a, DeviceAction::Frame(f) if f.get(12..14) == Some(&[0x88, 0x92][..]) && f.get(14..16) == Some(&[0xfe, 0xfd][..])))
        .collect();
    assert_eq!(set_errors(&sent), [wire_dcp::block_error::OK]);
    assert_eq!(dev.station().name(), "late-name");
    assert_eq!(dev.dcp_set_checks().timeouts(), 1);
}
