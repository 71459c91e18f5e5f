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
    assert_eq!(dev.kept_identity(), &KeptIdentity::default());
    assert_eq!(
        set(&mut dev, &wire_dcp::Repr::set_name(1, "temporary", false)),
        [0]
    );
    assert_eq!(dev.name(), "temporary");
    assert_eq!(dev.kept_identity().changes, 0);

    assert_eq!(
        set(&mut dev, &wire_dcp::Repr::set_name(2, "station-7", true)),
        [0]
    );
    let kept = dev.kept_identity();
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
    assert_eq!(dev.kept_identity().changes, 2);

    let ip = wire_dcp::Repr::set_ip(4, [10, 0, 0, 7], [255, 255, 0, 0], [10, 0, 0, 1], true);
    assert_eq!(set(&mut dev, &ip), [0]);
    assert_eq!(
        dev.kept_identity().ip_suite,
        Some([[10, 0, 0, 7], [255, 255, 0, 0], [10, 0, 0, 1]])
    );
    assert_eq!(dev.mask_and_gateway(), ([255, 255, 0, 0], [10, 0, 0, 1]));
    let temporary = wire_dcp::Repr::set_ip(5, [10, 0, 0, 8], [255, 255, 0, 0], [0; 4], false);
    assert_eq!(set(&mut dev, &temporary), [0]);
    assert_eq!(dev.ip(), [10, 0, 0, 8]);
    assert_eq!(
        dev.kept_identity().ip_suite.map(|s| s[0]),
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
    let kept = dev.kept_identity();
    assert_eq!(kept.name.as_deref(), Some(""));
    assert_eq!(kept.ip_suite, Some([[0; 4]; 3]));
    assert_eq!((dev.name(), dev.ip()), ("", [0; 4]));
}

#[test]
fn the_caller_sets_the_kept_identity_back_at_start() {
    let mut dev = pnet_device(TestApp::None);
    dev.set_name("from-last-time");
    dev.set_ip_suite([10, 1, 2, 3], [255, 0, 0, 0], [10, 0, 0, 1]);
    assert_eq!(dev.name(), "from-last-time");
    assert_eq!(dev.ip(), [10, 1, 2, 3]);
    assert_eq!(dev.mask_and_gateway(), ([255, 0, 0, 0], [10, 0, 0, 1]));
    assert_eq!(
        dev.kept_identity().changes,
        0,
        "setting it back is no change"
    );
}
