// SPDX-License-Identifier: MIT OR Apache-2.0
//! The application ends its AR (IO-Base's `PNIO_device_ar_abort`): that AR only, with an
//! ERR-RTA AbortRequest to the controller; the station keeps taking Connects.

use super::*;

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
