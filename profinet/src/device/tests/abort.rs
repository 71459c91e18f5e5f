// SPDX-License-Identifier: MIT OR Apache-2.0
//! How an AR ends before its Release, and that the station takes the next Connect each time:
//! the application ends it (IO-Base's `PNIO_device_ar_abort`: that AR only, with an ERR-RTA
//! AbortRequest to the controller), the controller aborts it with an ERR-RTA, or the
//! controller goes silent in start-up and its CMI activity timeout ends it.

use super::*;
use crate::rta::{RtaChannel, RtaEvent};

#[test]
fn the_application_ends_its_ar_and_the_station_takes_the_next_connect() {
    let (mut dev, connect) = counter_device();
    let t = to_data(&mut dev, &connect, 0);
    let mut out = Vec::new();
    let other = Uuid::from_fields(0x1234_5678, 0x9abc, 0x4def, [9; 8]);
    assert!(
        !dev.abort_ar_on_request(other, t, &mut out),
        "not the current AR: nothing ends"
    );
    assert!(out.is_empty());
    assert_eq!(dev.ar().state(), ArState::Data);

    assert!(dev.abort_ar_on_request(AR_UUID, t, &mut out));
    assert_eq!(dev.ar().state(), ArState::Idle);
    assert_eq!(dev.ar().last_abort(), Some(AbortCode::AbortRequest));
    assert_eq!(dev.ar().aborted_ars(), 1);
    let err = frames(&out)
        .into_iter()
        .find(|f| f[18..20] == [0xfe, 0x01])
        .expect("an ERR-RTA to the controller");
    let pdu = RtaPdu::parse(&rta_pdu::Packet::new_checked(&err[18..]).unwrap()).unwrap();
    assert_eq!(
        pdu.body,
        RtaBody::Err(ErrRta::abort(AbortCode::AbortRequest))
    );

    // The controller connects again (a new activity): accepted.
    let again = Uuid::from_fields(0xaaaa_0002, 1, 0x4000, [8, 7, 6, 5, 4, 3, 2, 1]);
    let blocks = connect.to_vec().unwrap();
    let r = call(
        &mut dev,
        &request(opnum::CONNECT, again, 0, &blocks, false),
        t + 100 * MS,
    );
    assert_eq!(status(&r), PnioStatus::OK);
    assert_eq!(dev.ar().state(), ArState::Connected);
}

/// The ERR-RTA a controller sends when it gives up the AR `connect` set up: on the
/// low-priority channel, from its alarm endpoint to ours, as its own channel emits it.
fn controllers_abort(connect: &ConnectRequest, code: AbortCode) -> RtaPdu {
    let mut ch = RtaChannel::new(
        Priority::Low,
        connect.alarm_cr.local_alarm_reference,
        connect::DEVICE_ALARM_REFERENCE,
        1,
        3,
    );
    let mut events = Vec::new();
    ch.abort(code, &mut events);
    match events.into_iter().next() {
        Some(RtaEvent::Send(pdu)) => pdu,
        other => panic!("no ERR-RTA: {other:?}"),
    }
}

/// The alarm frame carrying `pdu` from `src` to the counter device.
fn alarm_frame(src: MacAddress, pdu: &RtaPdu) -> Vec<u8> {
    ethernet_frame(PNET_MAC, src, Some(0xa000), &pdu.to_vec().unwrap())
}

/// A controller whose parameter write failed gives the AR up before PrmEnd: its ERR-RTA
/// ends the AR, which is only Connected, so that its next Connect is not refused for want
/// of AR resources.
#[test]
fn the_controllers_err_rta_ends_an_ar_before_prm_end() {
    let (mut dev, connect) = counter_device();
    assert_eq!(
        status(&call(&mut dev, &connect_request(&connect), 0)),
        PnioStatus::OK
    );
    assert_eq!(dev.ar().state(), ArState::Connected);
    let err = controllers_abort(&connect, AbortCode::ProtocolViolation);
    let mut out = Vec::new();
    // Not the AR's: from another station, or from another alarm endpoint.
    dev.on_frame(
        &alarm_frame(MacAddress([2, 0, 0, 0, 0, 9]), &err),
        MS,
        &mut out,
    );
    let mut other = err.clone();
    other.header.src_endpoint = other.header.src_endpoint.wrapping_add(1);
    dev.on_frame(&alarm_frame(S7_MAC, &other), MS, &mut out);
    assert_eq!(dev.ar().state(), ArState::Connected);

    // The AR's: it ends at once, without an ERR-RTA back.
    dev.on_frame(&alarm_frame(S7_MAC, &err), 2 * MS, &mut out);
    assert!(out.is_empty(), "{out:?}");
    assert_eq!(dev.ar().state(), ArState::Idle);
    assert_eq!(dev.ar().last_abort(), Some(AbortCode::ProtocolViolation));
    assert_eq!(dev.ar().aborted_ars(), 1);

    // The controller's next attempt (a new activity) is taken.
    let again = Uuid::from_fields(0xaaaa_0003, 1, 0x4000, [8, 7, 6, 5, 4, 3, 2, 1]);
    let r = call(
        &mut dev,
        &request(opnum::CONNECT, again, 0, &connect.to_vec().unwrap(), false),
        3 * MS,
    );
    assert_eq!(status(&r), PnioStatus::OK);
    assert_eq!(dev.ar().state(), ArState::Connected);
}

/// The ERR-RTAs among `sent`.
fn err_rtas(sent: &[(u64, DeviceAction)]) -> Vec<(u64, RtaPdu)> {
    sent.iter()
        .filter_map(|(t, a)| match a {
            DeviceAction::Frame(f) => {
                let pdu = RtaPdu::parse(&rta_pdu::Packet::new_checked(&f[18..]).ok()?).ok()?;
                matches!(pdu.body, RtaBody::Err(_)).then_some((*t, pdu))
            }
            _ => None,
        })
        .collect()
}

/// A controller that goes silent after its Connect loses the AR after its
/// CMInitiatorActivityTimeoutFactor × 100 ms, told with an ERR-RTA; the device then takes the
/// next Connect.
#[test]
fn a_controller_silent_in_start_up_loses_the_ar_after_its_cmi_timeout() {
    let (mut dev, connect) = counter_device();
    let timeout = u64::from(connect.ar.activity_timeout_factor) * 100 * MS;
    assert_eq!(
        status(&call(&mut dev, &connect_request(&connect), 0)),
        PnioStatus::OK
    );
    let sent = run_until(&mut dev, timeout - 1);
    assert!(err_rtas(&sent).is_empty());
    assert_eq!(dev.ar().state(), ArState::Connected);

    let sent = run_until(&mut dev, timeout);
    let errs = err_rtas(&sent);
    assert_eq!(errs.len(), 1, "{sent:?}");
    assert_eq!(
        errs[0].1.body,
        RtaBody::Err(ErrRta::abort(AbortCode::CmiTimeout))
    );
    assert_eq!(
        errs[0].1.header.dst_endpoint,
        connect.alarm_cr.local_alarm_reference
    );
    assert_eq!(dev.ar().state(), ArState::Idle);
    assert_eq!(dev.ar().last_abort(), Some(AbortCode::CmiTimeout));

    let again = Uuid::from_fields(0xaaaa_0004, 1, 0x4000, [8, 7, 6, 5, 4, 3, 2, 1]);
    let r = call(
        &mut dev,
        &request(opnum::CONNECT, again, 0, &connect.to_vec().unwrap(), false),
        timeout + MS,
    );
    assert_eq!(status(&r), PnioStatus::OK);
}

/// Each record call of the AR in start-up is the controller's activity: the CMI timeout
/// counts from the last one, not from the Connect.
#[test]
fn a_record_call_in_start_up_starts_the_cmi_timeout_again() {
    let (mut dev, connect) = counter_device();
    let timeout = u64::from(connect.ar.activity_timeout_factor) * 100 * MS;
    assert_eq!(
        status(&call(&mut dev, &connect_request(&connect), 0)),
        PnioStatus::OK
    );
    let at = timeout / 2;
    let h = IodHeader::write_request(1, AR_UUID, 0, 1, 1, 0x10, 2);
    let mut blocks = h.to_bytes().to_vec();
    blocks.extend_from_slice(&[1, 2]);
    let r = call(
        &mut dev,
        &request(opnum::WRITE, ACTIVITY, 1, &blocks, false),
        at,
    );
    assert_eq!(status(&r), PnioStatus::OK);
    // An implicit read names no AR: it is not the AR's controller at work.
    let implicit = IodHeader::read_request(2, Uuid::NIL, 0, 1, 1, 0x10, 2);
    let r = call(
        &mut dev,
        &request(
            opnum::READ_IMPLICIT,
            Uuid::from_fields(0xbbbb_0001, 1, 0x4000, [1; 8]),
            0,
            &implicit.to_bytes(),
            false,
        ),
        at + MS,
    );
    assert!(r.ndr.status().is_some(), "the implicit read is answered");

    let sent = run_until(&mut dev, at + timeout - 1);
    assert!(err_rtas(&sent).is_empty());
    assert_eq!(dev.ar().state(), ArState::Connected);
    run_until(&mut dev, at + timeout);
    assert_eq!(dev.ar().state(), ArState::Idle);
    assert_eq!(dev.ar().last_abort(), Some(AbortCode::CmiTimeout));
}
