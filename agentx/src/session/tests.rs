// SPDX-License-Identifier: MIT OR Apache-2.0
//! The session against a recorded snmpd and against a scripted master: opening,
//! registering, answering, refusals, timeouts, closing, and input in any pieces.

use std::time::{Duration, Instant};

use super::*;
use crate::mib::Snapshot;
use crate::pdu::{Oid, Response, SearchRange, Value, VarBind};

/// The recorded session with net-snmp's snmpd (see the file's header).
const SNMPD_SESSION: &str = include_str!("../../tests/fixtures/snmpd-5.9.3-session.txt");

fn unhex(s: &str) -> Vec<u8> {
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
        .collect()
}

/// The fixture's lines: (whether the subagent wrote them, the bytes).
fn transcript() -> Vec<(bool, Vec<u8>)> {
    SNMPD_SESSION
        .lines()
        .filter_map(|l| {
            let (dir, hex) = l.split_once(' ')?;
            match dir {
                ">" => Some((true, unhex(hex))),
                "<" => Some((false, unhex(hex))),
                _ => None,
            }
        })
        .collect()
}

/// Splits bytes into PDUs.
fn pdus(mut bytes: &[u8]) -> Vec<PduRepr> {
    let mut out = Vec::new();
    while let Some(len) = pdu::frame_len(bytes).unwrap() {
        out.push(PduRepr::parse(&bytes[..len]).unwrap());
        bytes = &bytes[len..];
    }
    assert!(bytes.is_empty());
    out
}

fn events(s: &mut Session) -> Vec<Event> {
    std::iter::from_fn(|| s.poll_event()).collect()
}

#[test]
fn replays_the_recorded_snmpd_session_byte_for_byte() {
    let t0 = Instant::now();
    let mut session = Session::new(SessionConfig::procimgd(), t0);
    let mut snapshots = 0;
    for (i, (ours, bytes)) in transcript().into_iter().enumerate() {
        if ours {
            assert_eq!(
                session.poll_transmit(),
                Some(bytes),
                "line {i} of the transcript"
            );
        } else {
            session
                .handle_input(t0, &bytes, || {
                    snapshots += 1;
                    Snapshot::example()
                })
                .unwrap();
        }
    }
    assert_eq!(session.poll_transmit(), None, "CleanupSet is not answered");
    assert_eq!(session.state(), SessionState::Ready);
    assert_eq!(session.session_id(), 5);
    let procimgd = SessionConfig::procimgd();
    assert_eq!(
        events(&mut session),
        [
            Event::Opened { session_id: 5 },
            Event::Registered {
                subtree: procimgd.registrations[0].subtree.clone(),
                priority: SYSTEM_PRIORITY,
            },
            Event::Registered {
                subtree: Oid::from(crate::mib::lldp::LLDP_MIB),
                priority: DEFAULT_PRIORITY,
            },
            Event::Ready,
        ]
    );
    // One snapshot for each Get or GetNext (each came in a read of its own); none for
    // TestSet and CleanupSet.
    assert_eq!(snapshots, 5);
}

#[test]
fn the_recorded_master_pdus_parse_as_expected() {
    let master: Vec<PduRepr> = transcript()
        .into_iter()
        .filter(|(ours, _)| !ours)
        .flat_map(|(_, b)| pdus(&b))
        .collect();
    let types: Vec<PduType> = master.iter().map(|p| p.pdu.pdu_type()).collect();
    use PduType::*;
    assert_eq!(
        types,
        // snmpgetnext's GetNext, then snmpbulkget's three.
        [
            Response, Response, Response, Get, GetNext, GetNext, GetNext, GetNext, TestSet,
            CleanupSet
        ]
    );
    assert!(master.iter().all(|p| p.byte_order == pdu::ByteOrder::Big));
    let Pdu::Get(ranges) = &master[3].pdu else {
        panic!("{:?}", master[3]);
    };
    assert_eq!(
        ranges
            .iter()
            .map(|r| r.start.to_string())
            .collect::<Vec<_>>(),
        ["1.3.6.1.2.1.1.5.0", "1.0.8802.1.1.2.1.3.3.0"]
    );
    let Pdu::GetNext(ranges) = &master[4].pdu else {
        panic!("{:?}", master[4]);
    };
    assert_eq!(
        ranges[0],
        SearchRange {
            start: "1.0.8802.1.1.2.1.3.7.1.3".parse().unwrap(),
            include: false,
            end: "1.0.8802.1.1.3".parse().unwrap(),
        }
    );
}

/// A scripted master: PDUs in network byte order.
fn from_master(session_id: u32, packet_id: u32, pdu: Pdu) -> Vec<u8> {
    PduRepr::new(session_id, 7, packet_id, pdu)
        .to_bytes()
        .unwrap()
}

fn answer(error: ResponseError) -> Pdu {
    Pdu::Response(Response {
        sys_up_time: 1,
        error,
        index: 0,
        varbinds: Vec::new(),
    })
}

/// A session that the scripted master opened as session 9 and whose registrations it
/// answered with `errors` (in order).
fn opened(t0: Instant, errors: &[ResponseError]) -> Session {
    let mut s = Session::new(SessionConfig::procimgd(), t0);
    let open = pdus(&s.poll_transmit().unwrap());
    assert!(matches!(open[0].pdu, Pdu::Open(_)));
    s.handle_input(
        t0,
        &from_master(9, open[0].packet_id, answer(ResponseError::NoError)),
        Snapshot::default,
    )
    .unwrap();
    let registers = pdus(&s.poll_transmit().unwrap());
    assert_eq!(registers.len(), errors.len());
    for (r, e) in registers.iter().zip(errors) {
        assert_eq!(r.session_id, 9);
        s.handle_input(
            t0,
            &from_master(9, r.packet_id, answer(*e)),
            Snapshot::default,
        )
        .unwrap();
    }
    s
}

#[test]
fn a_refused_registration_is_reported_and_the_rest_is_served() {
    let t0 = Instant::now();
    let mut s = opened(
        t0,
        &[ResponseError::DuplicateRegistration, ResponseError::NoError],
    );
    let ev = events(&mut s);
    assert!(matches!(
        &ev[1],
        Event::RegistrationRefused {
            error: ResponseError::DuplicateRegistration,
            priority: 1,
            ..
        }
    ));
    assert!(matches!(ev[2], Event::Registered { priority: 127, .. }));
    assert_eq!(ev[3], Event::Ready);
    assert_eq!(s.state(), SessionState::Ready);
    assert_eq!(s.poll_timeout(), None);
}

#[test]
fn a_refused_open_closes_the_session() {
    let t0 = Instant::now();
    let mut s = Session::new(SessionConfig::procimgd(), t0);
    let open = pdus(&s.poll_transmit().unwrap());
    s.handle_input(
        t0,
        &from_master(0, open[0].packet_id, answer(ResponseError::OpenFailed)),
        Snapshot::default,
    )
    .unwrap();
    assert_eq!(
        events(&mut s),
        [Event::OpenRefused {
            error: ResponseError::OpenFailed
        }]
    );
    assert_eq!(s.state(), SessionState::Closed);
    assert_eq!(
        s.handle_input(t0, &[1], Snapshot::default),
        Err(InputError::Closed)
    );
}

#[test]
fn an_unanswered_open_times_out() {
    let t0 = Instant::now();
    let mut s = Session::new(SessionConfig::procimgd(), t0);
    s.poll_transmit();
    let deadline = s.poll_timeout().unwrap();
    assert_eq!(deadline, t0 + Duration::from_secs(5));
    s.handle_timeout(deadline - Duration::from_millis(1));
    assert_eq!(s.state(), SessionState::Opening);
    s.handle_timeout(deadline);
    assert_eq!(
        events(&mut s),
        [Event::MasterTimeout {
            request: PduType::Open
        }]
    );
    assert_eq!(s.state(), SessionState::Closed);
    // Not open yet: nothing to close on the wire.
    assert_eq!(s.poll_transmit(), None);
}

#[test]
fn an_unanswered_ping_times_out_with_a_close() {
    let t0 = Instant::now();
    let mut s = opened(t0, &[ResponseError::NoError; 2]);
    s.ping(t0);
    let ping = pdus(&s.poll_transmit().unwrap());
    assert!(matches!(ping[0].pdu, Pdu::Ping));
    s.handle_timeout(t0 + Duration::from_secs(5));
    assert!(events(&mut s).contains(&Event::MasterTimeout {
        request: PduType::Ping
    }));
    let close = pdus(&s.poll_transmit().unwrap());
    assert_eq!(
        close[0].pdu,
        Pdu::Close(Close {
            reason: CloseReason::Timeouts
        })
    );
}

#[test]
fn get_get_next_and_sets_are_answered_from_the_snapshot() {
    let t0 = Instant::now();
    let mut s = opened(t0, &[ResponseError::NoError; 2]);
    let sys_name: Oid = "1.3.6.1.2.1.1.5.0".parse().unwrap();
    let mut input = from_master(
        9,
        100,
        Pdu::Get(vec![SearchRange {
            start: sys_name.clone(),
            ..SearchRange::default()
        }]),
    );
    input.extend(from_master(
        9,
        101,
        Pdu::GetNext(vec![SearchRange {
            start: sys_name.clone(),
            include: false,
            end: "1.3.6.1.2.1.1.6".parse().unwrap(),
        }]),
    ));
    input.extend(from_master(
        9,
        102,
        Pdu::TestSet(vec![VarBind::new(sys_name.clone(), Value::string("x"))]),
    ));
    input.extend(from_master(9, 103, Pdu::CleanupSet));
    input.extend(from_master(9, 104, Pdu::Ping));
    let mut snapshots = 0;
    s.handle_input(t0, &input, || {
        snapshots += 1;
        Snapshot::example()
    })
    .unwrap();
    assert_eq!(snapshots, 1, "one snapshot for the whole batch");
    let answers = pdus(&s.poll_transmit().unwrap());
    let responses: Vec<(u32, &Response)> = answers
        .iter()
        .map(|a| match &a.pdu {
            Pdu::Response(r) => (a.packet_id, r),
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(responses.len(), 4, "CleanupSet gets no answer");
    assert_eq!(responses[0].0, 100);
    assert_eq!(
        responses[0].1.varbinds,
        [VarBind::new(sys_name.clone(), Value::string("plc-station"))]
    );
    assert_eq!(
        responses[1].1.varbinds,
        [VarBind::new(sys_name, Value::EndOfMibView)]
    );
    assert_eq!(
        (responses[2].1.error, responses[2].1.index),
        (ResponseError::NotWritable, 1)
    );
    assert_eq!(
        (responses[3].0, responses[3].1.error),
        (104, ResponseError::NoError)
    );
    assert!(
        answers
            .iter()
            .all(|a| a.session_id == 9 && a.transaction_id == 7)
    );
}

#[test]
fn input_in_single_bytes_gives_the_same_answers() {
    let t0 = Instant::now();
    let mut whole = Session::new(SessionConfig::procimgd(), t0);
    let mut bytewise = Session::new(SessionConfig::procimgd(), t0);
    for (ours, bytes) in transcript() {
        if ours {
            assert_eq!(whole.poll_transmit().as_deref(), Some(&bytes[..]));
            let mut out = Vec::new();
            while let Some(b) = bytewise.poll_transmit() {
                out.extend(b);
            }
            assert_eq!(out, bytes);
        } else {
            whole.handle_input(t0, &bytes, Snapshot::example).unwrap();
            for b in &bytes {
                bytewise.handle_input(t0, &[*b], Snapshot::example).unwrap();
            }
        }
    }
}

#[test]
fn requests_of_another_session_are_answered_not_open() {
    let t0 = Instant::now();
    let mut s = opened(t0, &[ResponseError::NoError; 2]);
    s.handle_input(t0, &from_master(8, 50, Pdu::Ping), Snapshot::example)
        .unwrap();
    let answer = pdus(&s.poll_transmit().unwrap());
    assert!(matches!(&answer[0].pdu, Pdu::Response(r) if r.error == ResponseError::NotOpen));
}

#[test]
fn a_malformed_payload_is_answered_parse_error_and_the_session_goes_on() {
    let t0 = Instant::now();
    let mut s = opened(t0, &[ResponseError::NoError; 2]);
    // A GetNext whose OID says 3 subidentifiers and has 1: framed, but unparsable.
    let mut bad = vec![
        1, 6, 0x10, 0, 0, 0, 0, 9, 0, 0, 0, 7, 0, 0, 0, 60, 0, 0, 0, 8,
    ];
    bad.extend([3, 0, 0, 0, 0, 0, 0, 1]);
    s.handle_input(t0, &bad, Snapshot::example).unwrap();
    let answer = pdus(&s.poll_transmit().unwrap());
    assert_eq!(answer[0].packet_id, 60);
    assert!(matches!(&answer[0].pdu, Pdu::Response(r) if r.error == ResponseError::ParseError));
    assert_eq!(s.state(), SessionState::Ready);
}

#[test]
fn a_stream_out_of_step_closes_with_parse_error() {
    let t0 = Instant::now();
    let mut s = opened(t0, &[ResponseError::NoError; 2]);
    events(&mut s);
    let garbage = [2u8; 20];
    assert_eq!(
        s.handle_input(t0, &garbage, Snapshot::example),
        Err(InputError::Framing(ParseError::Version(2)))
    );
    let close = pdus(&s.poll_transmit().unwrap());
    assert_eq!(
        close[0].pdu,
        Pdu::Close(Close {
            reason: CloseReason::ParseError
        })
    );
    assert_eq!(s.state(), SessionState::Closed);
}

#[test]
fn closing_by_either_side() {
    let t0 = Instant::now();
    // The master closes.
    let mut s = opened(t0, &[ResponseError::NoError; 2]);
    events(&mut s);
    let close = Pdu::Close(Close {
        reason: CloseReason::Shutdown,
    });
    s.handle_input(t0, &from_master(9, 70, close), Snapshot::example)
        .unwrap();
    assert_eq!(
        events(&mut s),
        [Event::Closed {
            reason: CloseReason::Shutdown,
            by_master: true
        }]
    );
    assert_eq!(s.poll_transmit(), None);
    // This side closes; the master answers.
    let mut s = opened(t0, &[ResponseError::NoError; 2]);
    events(&mut s);
    s.close(t0, CloseReason::Shutdown);
    assert_eq!(s.state(), SessionState::Closing);
    let close = pdus(&s.poll_transmit().unwrap());
    assert_eq!(
        close[0].pdu,
        Pdu::Close(Close {
            reason: CloseReason::Shutdown
        })
    );
    s.handle_input(
        t0,
        &from_master(9, close[0].packet_id, answer(ResponseError::NoError)),
        Snapshot::example,
    )
    .unwrap();
    assert_eq!(
        events(&mut s),
        [Event::Closed {
            reason: CloseReason::Shutdown,
            by_master: false
        }]
    );
    assert_eq!(s.state(), SessionState::Closed);
}

#[test]
fn a_notification_goes_out_once_open() {
    let t0 = Instant::now();
    let trap_oid: Oid = "1.3.6.1.6.3.1.1.4.1.0".parse().unwrap();
    // lldpNotificationPrefix.1: lldpRemTablesChange.
    let change = Value::ObjectIdentifier("1.0.8802.1.1.2.0.0.1".parse().unwrap());
    let varbinds = vec![VarBind::new(trap_oid, change)];
    let mut s = Session::new(SessionConfig::procimgd(), t0);
    s.poll_transmit();
    s.notify(t0, varbinds.clone());
    assert_eq!(s.poll_transmit(), None, "not open yet");
    let mut s = opened(t0, &[ResponseError::NoError; 2]);
    s.notify(t0, varbinds.clone());
    let notify = pdus(&s.poll_transmit().unwrap());
    assert_eq!(notify[0].pdu, Pdu::Notify(varbinds));
    assert_eq!(notify[0].session_id, 9);
    s.handle_input(
        t0,
        &from_master(9, notify[0].packet_id, answer(ResponseError::NoError)),
        Snapshot::example,
    )
    .unwrap();
    assert_eq!(s.poll_timeout(), None);
}
