// SPDX-License-Identifier: MIT OR Apache-2.0
use super::*;
use crate::services::RecordTarget;
use crate::{decode, encode};

fn json(r: &Request) -> String {
    String::from_utf8(encode(r)).unwrap()
}

#[test]
fn each_group_keeps_the_one_tagged_wire_shape_and_comes_back_in_its_group() {
    let all = [
        (
            Request::from(CoreRequest::Status),
            r#"{"request":"status"}"#,
        ),
        (
            Request::from(CoreRequest::Unsubscribe { subscriber: 7 }),
            r#"{"request":"unsubscribe","subscriber":7}"#,
        ),
        (
            Request::from(ControllerRequest::Diagnosis),
            r#"{"request":"diagnosis"}"#,
        ),
        (
            Request::from(ControllerRequest::AcknowledgeAlarm {
                subscriber: 7,
                alarm: 3,
            }),
            r#"{"request":"acknowledge_alarm","subscriber":7,"alarm":3}"#,
        ),
        (
            Request::from(DeviceRequest::StationProblem { problem: true }),
            r#"{"request":"station_problem","problem":true}"#,
        ),
    ];
    for (request, wire) in all {
        assert_eq!(json(&request), wire);
        assert_eq!(decode::<Request>(wire.as_bytes()), Ok(request));
    }
}

#[test]
fn a_request_with_a_wrong_field_is_refused_with_what_is_wrong() {
    let e = decode::<Request>(br#"{"request":"record_read","reply_to":1}"#).unwrap_err();
    assert!(e.contains("missing field `reference`"), "{e}");
    let target = RecordTarget {
        device: 0,
        api: 0,
        slot: 1,
        subslot: 1,
        index: 0xAFF0,
    };
    let ok = Request::from(ControllerRequest::RecordRead {
        reply_to: 1,
        reference: 2,
        target,
        max_len: 4,
    });
    assert_eq!(decode::<Request>(&encode(&ok)), Ok(ok));
}

#[test]
fn a_request_no_group_knows_is_named_in_the_refusal() {
    let e = decode::<Request>(br#"{"request":"make_coffee"}"#).unwrap_err();
    assert!(e.contains("unknown request \"make_coffee\""), "{e}");
}
