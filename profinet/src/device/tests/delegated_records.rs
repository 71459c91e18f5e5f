// SPDX-License-Identifier: MIT OR Apache-2.0
//! The application's check of a new AR, its records and its hold on the ApplicationReady: jobs, answers, stale
//! answers, timeouts, WriteMultiple with records of both, the configured parameter records,
//! and retransmissions and pings while a call waits.

use super::*;
use crate::device::CrInfo;
use crate::wire::record::{RecordErrorCode, join_write_multiple_to_vec};

/// The counter device in data exchange at `t`, slot 1's records given to the application.
fn delegating_device() -> (Device<TestApp>, u64) {
    let (mut dev, connect) = counter_device();
    dev.delegate_records(SubslotAddr::new(0, 1, 1), true);
    let t = to_data(&mut dev, &connect, 10 * MS);
    (dev, t)
}

/// A Write of `data` to `index` of (0, `slot`, 1) in the AR.
fn write_blocks(slot: u16, index: u16, data: &[u8]) -> Vec<u8> {
    let h = IodHeader::write_request(0, AR_UUID, 0, slot, 1, index, data.len() as u32);
    let mut b = h.to_bytes().to_vec();
    b.extend_from_slice(data);
    b
}

/// Sends `blocks` as call `op` with sequence number `seq`: what the device does.
fn send(
    dev: &mut Device<TestApp>,
    op: u16,
    seq: u32,
    blocks: &[u8],
    now: u64,
) -> Vec<DeviceAction> {
    let mut out = Vec::new();
    dev.on_datagram(
        S7_CLIENT,
        RPC_PORT,
        &request(op, ACTIVITY, seq, blocks, false),
        now,
        &mut out,
    );
    out
}

/// The record jobs among `out`.
fn jobs(out: &[DeviceAction]) -> Vec<RecordJob> {
    out.iter()
        .filter_map(|a| match a {
            DeviceAction::Record(r) => Some(r.clone()),
            _ => None,
        })
        .collect()
}

/// The one RPC response among `out`.
fn response(out: &[DeviceAction]) -> Reply {
    let d = datagrams(out);
    assert_eq!(d.len(), 1, "one response expected: {out:?}");
    parse_reply(&d[0].2)
}

#[test]
fn a_write_waits_for_the_application_and_a_second_answer_is_stale() {
    let (mut dev, t) = delegating_device();
    let out = send(
        &mut dev,
        opnum::WRITE,
        5,
        &write_blocks(1, 0x0042, &[7, 8, 9]),
        t,
    );
    assert!(
        datagrams(&out).is_empty(),
        "no answer before the application's: {out:?}"
    );
    let j = jobs(&out);
    assert_eq!(j.len(), 1);
    assert_eq!(
        (
            j[0].write,
            j[0].ar_uuid,
            j[0].slot,
            j[0].subslot,
            j[0].index
        ),
        (true, AR_UUID, 1, 1, 0x0042)
    );
    assert_eq!(j[0].data, [7, 8, 9]);

    let mut out = Vec::new();
    dev.answer_record(j[0].job, Ok(Vec::new()), &mut out)
        .unwrap();
    let r = response(&out);
    assert_eq!(status(&r), PnioStatus::OK);
    assert_eq!(IodHeader::parse(&r.blocks).unwrap().kind, IodKind::WriteRes);
    assert_eq!(
        dev.answer_record(j[0].job, Ok(Vec::new()), &mut out),
        Err(UnknownRecordJob(j[0].job))
    );
    // Slot 2 is not the application's: the device answers at once.
    let out = send(&mut dev, opnum::WRITE, 6, &write_blocks(2, 0x0042, &[1]), t);
    assert!(jobs(&out).is_empty());
    assert_eq!(status(&response(&out)), PnioStatus::OK);
}

#[test]
fn the_applications_error_reaches_the_controller() {
    let (mut dev, t) = delegating_device();
    let out = send(&mut dev, opnum::WRITE, 5, &write_blocks(1, 0x0042, &[7]), t);
    let job = jobs(&out)[0].job;
    let mut out = Vec::new();
    dev.answer_record(job, Err((RecordErrorCode::InvalidParameter, 3)), &mut out)
        .unwrap();
    assert_eq!(
        status(&response(&out)),
        PnioStatus::from_bytes([0xdf, 0x80, 0xb8, 3])
    );
}

#[test]
fn an_unanswered_job_times_out_as_resource_busy_and_retransmissions_wait() {
    let (mut dev, t) = delegating_device();
    let blocks = write_blocks(1, 0x0042, &[7]);
    let out = send(&mut dev, opnum::WRITE, 5, &blocks, t);
    let job = jobs(&out)[0].job;
    // The controller repeats its call and pings: dropped, and "working".
    let again = send(&mut dev, opnum::WRITE, 5, &blocks, t + MS);
    assert!(again.is_empty(), "{again:?}");
    let call = request(opnum::WRITE, ACTIVITY, 5, &blocks, false);
    let h = Header {
        packet_type: PacketType::Ping,
        ..wire_rpc::Packet::new_checked(&call[..])
            .map(|p| Header::parse(&p))
            .unwrap()
            .unwrap()
    };
    let mut out = Vec::new();
    dev.on_datagram(
        S7_CLIENT,
        RPC_PORT,
        &rpc::pdu(&h, &[]).unwrap(),
        t + 2 * MS,
        &mut out,
    );
    let d = datagrams(&out);
    assert_eq!(d.len(), 1);
    assert_eq!(
        wire_rpc::Packet::new_checked(&d[0].2[..])
            .unwrap()
            .packet_type(),
        PacketType::Working
    );

    let sent = run_until(&mut dev, t + RECORD_ANSWER_TIMEOUT_NS);
    let out: Vec<DeviceAction> = sent
        .into_iter()
        .map(|(_, a)| a)
        .filter(|a| matches!(a, DeviceAction::Datagram { to, .. } if *to == S7_CLIENT))
        .collect();
    assert_eq!(
        status(&response(&out)),
        PnioStatus::from_bytes([0xdf, 0x80, 0xc2, 0])
    );
    assert_eq!(dev.records().timeouts(), 1);
    assert_eq!(
        dev.answer_record(job, Ok(Vec::new()), &mut Vec::new()),
        Err(UnknownRecordJob(job))
    );
    // A retransmission now gets the response from the cache, the call is not run again.
    let again = send(
        &mut dev,
        opnum::WRITE,
        5,
        &blocks,
        t + RECORD_ANSWER_TIMEOUT_NS + MS,
    );
    assert!(jobs(&again).is_empty());
    assert_eq!(
        status(&response(&again)),
        PnioStatus::from_bytes([0xdf, 0x80, 0xc2, 0])
    );
}

#[test]
fn a_write_multiple_answers_when_the_applications_part_is_answered() {
    let (mut dev, t) = delegating_device();
    let app = IodHeader::write_request(0, AR_UUID, 0, 1, 1, 0x10, 2);
    let own = IodHeader::write_request(1, AR_UUID, 0, 2, 1, 0x11, 1);
    let data = join_write_multiple_to_vec(&[(app, &[1, 2]), (own, &[3])]).unwrap();
    let mut blocks = IodHeader::write_multiple(2, AR_UUID, data.len() as u32)
        .to_bytes()
        .to_vec();
    blocks.extend_from_slice(&data);
    let out = send(&mut dev, opnum::WRITE, 5, &blocks, t);
    let j = jobs(&out);
    assert_eq!(j.len(), 1, "only slot 1's write is the application's");
    assert!(datagrams(&out).is_empty());
    let mut out = Vec::new();
    dev.answer_record(j[0].job, Err((RecordErrorCode::InvalidRange, 0)), &mut out)
        .unwrap();
    let r = response(&out);
    assert_eq!(status(&r), PnioStatus::from_bytes([0xdf, 0x80, 0xb7, 0]));
    let (_, parts) = split_write_multiple_response(&r.blocks).unwrap();
    let statuses: Vec<PnioStatus> = parts.iter().map(|h| h.status).collect();
    assert_eq!(
        statuses,
        [
            PnioStatus::from_bytes([0xdf, 0x80, 0xb7, 0]),
            PnioStatus::OK
        ]
    );
}

#[test]
fn a_read_gets_the_applications_data_cut_to_what_the_controller_takes() {
    let (mut dev, t) = delegating_device();
    let h = IodHeader::read_request(0, AR_UUID, 0, 1, 1, 0x0042, 3);
    let out = send(&mut dev, opnum::READ, 5, &h.to_bytes(), t);
    let j = jobs(&out);
    assert_eq!((j[0].write, j[0].max_len), (false, 3));
    let mut out = Vec::new();
    dev.answer_record(j[0].job, Ok(vec![1, 2, 3, 4, 5]), &mut out)
        .unwrap();
    let r = response(&out);
    let (h, data, _) = IodHeader::split(&r.blocks).unwrap();
    assert_eq!((h.kind, data), (IodKind::ReadRes, &[1u8, 2, 3][..]));
    // The device's own records of the submodule stay the device's.
    let h = IodHeader::read_request(0, AR_UUID, 0, 1, 1, 0x800a, 4096);
    let out = send(&mut dev, opnum::READ, 6, &h.to_bytes(), t);
    assert!(jobs(&out).is_empty());
    assert_eq!(status(&response(&out)), PnioStatus::OK);
}

#[test]
fn im_records_go_to_the_application_only_when_handed_to_it() {
    let (mut dev, t) = delegating_device();
    // Slot 1's user records are the application's, its I&M not yet.
    let h = IodHeader::read_request(0, AR_UUID, 0, 1, 1, 0xaff1, 64);
    let out = send(&mut dev, opnum::READ, 5, &h.to_bytes(), t);
    assert!(jobs(&out).is_empty());
    dev.delegate_im_records(SubslotAddr::new(0, 1, 1), true);
    let out = send(&mut dev, opnum::READ, 6, &h.to_bytes(), t);
    let j = jobs(&out);
    assert_eq!((j.len(), j[0].index, j[0].write), (1, 0xaff1, false));
    dev.answer_record(j[0].job, Ok(vec![0; 4]), &mut Vec::new())
        .unwrap();
    let out = send(
        &mut dev,
        opnum::WRITE,
        7,
        &write_blocks(1, 0xaff0, &[0; 4]),
        t,
    );
    let j = jobs(&out);
    assert_eq!((j.len(), j[0].index, j[0].write), (1, 0xaff0, true));
    dev.answer_record(j[0].job, Ok(Vec::new()), &mut Vec::new())
        .unwrap();
    // I&M0FilterData stays the device's; so do I&M records once taken back.
    let f = IodHeader::read_request(0, AR_UUID, 0, 1, 1, 0xf840, 256);
    assert!(jobs(&send(&mut dev, opnum::READ, 8, &f.to_bytes(), t)).is_empty());
    dev.delegate_im_records(SubslotAddr::new(0, 1, 1), false);
    assert!(jobs(&send(&mut dev, opnum::READ, 9, &h.to_bytes(), t)).is_empty());
}

#[test]
fn configured_parameter_records_check_index_and_length_and_read_their_initial_data() {
    let (mut dev, connect) = counter_device();
    dev.set_parameter_records(&[ParameterRecord {
        at: SubslotAddr::new(0, 2, 1),
        index: 0x0100,
        length: 2,
        initial: vec![0xab],
    }]);
    let t = to_data(&mut dev, &connect, 10 * MS);
    let write = |dev: &mut Device<TestApp>, seq, index, data: &[u8]| {
        status(&response(&send(
            dev,
            opnum::WRITE,
            seq,
            &write_blocks(2, index, data),
            t,
        )))
    };
    let read = |dev: &mut Device<TestApp>, seq| {
        let h = IodHeader::read_request(0, AR_UUID, 0, 2, 1, 0x0100, 16);
        let r = response(&send(dev, opnum::READ, seq, &h.to_bytes(), t));
        IodHeader::split(&r.blocks).unwrap().1.to_vec()
    };
    assert_eq!(read(&mut dev, 2), [0xab, 0x00]);
    assert_eq!(
        write(&mut dev, 3, 0x0101, &[1, 2]),
        PnioStatus::from_bytes([0xdf, 0x80, 0xb0, 0])
    );
    assert_eq!(
        write(&mut dev, 4, 0x0100, &[1, 2, 3]),
        PnioStatus::from_bytes([0xdf, 0x80, 0xb1, 0])
    );
    assert_eq!(write(&mut dev, 5, 0x0100, &[1, 2]), PnioStatus::OK);
    assert_eq!(read(&mut dev, 6), [1, 2]);
}

#[test]
fn too_many_waiting_calls_get_resource_busy_at_once() {
    let (mut dev, t) = delegating_device();
    for seq in 0..MAX_WAITING_CALLS as u32 {
        let h = IodHeader::read_request(0, Uuid::NIL, 0, 1, 1, 0x0042, 8);
        let activity = Uuid::from_fields(seq, 2, 0x4000, [1; 8]);
        let mut out = Vec::new();
        dev.on_datagram(
            S7_CLIENT,
            RPC_PORT,
            &request(opnum::READ_IMPLICIT, activity, 0, &h.to_bytes(), false),
            t,
            &mut out,
        );
        assert_eq!(jobs(&out).len(), 1);
    }
    let out = send(&mut dev, opnum::WRITE, 9, &write_blocks(1, 0x0042, &[7]), t);
    assert!(jobs(&out).is_empty());
    assert_eq!(
        status(&response(&out)),
        PnioStatus::from_bytes([0xdf, 0x80, 0xc2, 0])
    );
}

/// The counter device up to PrmEnd with the ApplicationReady held; the time of the PrmEnd.
fn held_at_prm_end() -> (Device<TestApp>, u64) {
    let (mut dev, connect) = counter_device();
    dev.hold_application_ready(true);
    let t = 10 * MS;
    to_prm_end(&mut dev, &connect, t);
    (dev, t)
}

/// The ApplicationReady calls among what was sent.
fn app_readies(sent: &[(u64, DeviceAction)]) -> Vec<u64> {
    sent.iter()
        .filter(|(_, a)| matches!(a, DeviceAction::Datagram { from_port, .. } if *from_port == rpc::CLIENT_PORT))
        .map(|(t, _)| *t)
        .collect()
}

#[test]
fn a_held_application_ready_goes_out_when_released() {
    let (mut dev, t) = held_at_prm_end();
    let sent = run_until(&mut dev, t + 100 * MS);
    assert!(app_readies(&sent).is_empty());
    assert!(dev.ar().application_ready_held());
    assert_eq!(dev.ar().state(), ArState::Parameterized);
    assert!(dev.release_application_ready(t + 100 * MS));
    assert!(
        !dev.release_application_ready(t + 100 * MS),
        "released once"
    );
    let sent = run_until(&mut dev, t + 100 * MS);
    assert_eq!(app_readies(&sent), [t + 100 * MS]);
    assert_eq!(dev.ar().state(), ArState::WaitAppReadyConfirm);
    assert_eq!(dev.ar().app_ready_hold_timeouts(), 0);
}

#[test]
fn submodules_the_application_is_not_ready_for_are_pending_in_the_application_ready() {
    use crate::wire::connect::{ArInfo, ModuleDiffBlock};
    let (mut dev, t) = held_at_prm_end();
    let input = SubslotAddr::new(0, 1, 1);
    dev.application_ready_pending([input, input]);
    assert!(dev.release_application_ready(t + MS));
    let sent = run_until(&mut dev, t + MS);
    let payload = sent
        .iter()
        .find_map(|(_, a)| match a {
            DeviceAction::Datagram {
                from_port, payload, ..
            } if *from_port == rpc::CLIENT_PORT => Some(payload.clone()),
            _ => None,
        })
        .expect("the ApplicationReady");
    let blocks = parse_reply(&payload).blocks;
    // The ControlBlock first (BlockLength after the BlockType), then the ModuleDiffBlock.
    let control_len = 4 + usize::from(u16::from_be_bytes([blocks[2], blocks[3]]));
    let diff = ModuleDiffBlock::parse(&blocks[control_len..]).expect("a ModuleDiffBlock");
    let listed: Vec<_> = diff.submodules().collect();
    assert_eq!(listed.len(), 1, "{listed:?}");
    let (api, slot, subslot, state) = listed[0];
    assert_eq!((api, slot, subslot), (0, 1, 1));
    assert_eq!(state.ar_info(), ArInfo::ApplicationReadyPending);
    assert!(!state.is_usable());
    // The AR's ModuleDiff record says the same.
    let h = IodHeader::read_request(0, AR_UUID, 0, 0, 1, 0xe002, 4096);
    let out = send(&mut dev, opnum::READ, 9, &h.to_bytes(), t + MS);
    let r = response(&out);
    let (_, data, _) = IodHeader::split(&r.blocks).unwrap();
    let record = ModuleDiffBlock::parse(data).expect("record 0xE002");
    assert_eq!(record, diff);
}

#[test]
fn a_held_application_ready_goes_out_by_itself_before_the_cmi_timeout() {
    let (mut dev, t) = held_at_prm_end();
    // The Connect's CMI activity timeout is 200 × 100 ms = 20 s, beyond the hold's limit.
    let sent = run_until(&mut dev, t + APP_READY_HOLD_TIMEOUT_NS);
    assert_eq!(app_readies(&sent), [t + APP_READY_HOLD_TIMEOUT_NS]);
    assert_eq!(dev.ar().app_ready_hold_timeouts(), 1);
    assert!(!dev.ar().application_ready_held());
}

/// The AR checks among `out`.
fn checks(out: &[DeviceAction]) -> Vec<ArCheck> {
    out.iter()
        .filter_map(|a| match a {
            DeviceAction::ArCheck(c) => Some(c.clone()),
            _ => None,
        })
        .collect()
}

/// The counter device checking its Connects, the Connect sent: the check.
fn connect_waiting() -> (Device<TestApp>, ConnectRequest, ArCheck) {
    let (mut dev, connect) = counter_device();
    dev.check_connects(true);
    let out = send(&mut dev, opnum::CONNECT, 0, &connect.to_vec().unwrap(), 0);
    assert!(
        datagrams(&out).is_empty(),
        "no answer before the check's: {out:?}"
    );
    let c = checks(&out);
    assert_eq!(c.len(), 1);
    assert_eq!(dev.ar().state(), ArState::Idle);
    (dev, connect, c[0].clone())
}

#[test]
fn a_new_ar_waits_for_the_applications_check_and_is_accepted() {
    let (mut dev, _, check) = connect_waiting();
    assert_eq!((check.ar_uuid, check.session_key), (AR_UUID, 1));
    assert_eq!(check.controller_name, "procimgd");
    assert_eq!(check.expected.len(), 3);
    let slot1 = check.expected[1];
    assert_eq!(
        (slot1.at, slot1.module_ident, slot1.input_length),
        (SubslotAddr::new(0, 1, 1), 0x30, 4)
    );
    assert_eq!(slot1.plugged.map(|p| p.module_ident), Some(0x30));
    // The CRs as the Connect asks for them (1 ms send clock, a frame every 2, data hold
    // factor 3), with the FrameIDs the AR will use and each submodule's data object.
    let [input, output] = &check.crs[..] else {
        panic!("two CRs: {:?}", check.crs);
    };
    assert!(input.input && !output.input);
    assert_eq!((input.frame_id, output.frame_id), (0x8000, 0x8001));
    for cr in [input, output] {
        assert_eq!(
            (
                cr.send_clock_factor,
                cr.reduction_ratio,
                cr.data_hold_factor
            ),
            (32, 2, 3)
        );
        assert!(cr.data_objects.iter().all(|&(_, at)| at < cr.data_length));
    }
    let holds = |cr: &CrInfo, slot| cr.data_objects.iter().any(|(a, _)| a.slot == slot);
    assert!(holds(input, 1) && !holds(input, 2), "{input:?}");
    assert!(holds(output, 2) && !holds(output, 1), "{output:?}");
    // Its retransmission waits too.
    let again = send(&mut dev, opnum::CONNECT, 0, &[], MS);
    assert!(again.is_empty(), "{again:?}");
    let mut out = Vec::new();
    dev.answer_connect(check.job, Ok(()), 2 * MS, &mut out)
        .unwrap();
    assert_eq!(status(&response(&out)), PnioStatus::OK);
    assert_eq!(dev.ar().state(), ArState::Connected);
    assert_eq!(
        dev.answer_connect(check.job, Ok(()), 2 * MS, &mut out),
        Err(UnknownArCheck(check.job))
    );
}

#[test]
fn a_refused_ar_gets_the_applications_error_and_an_unanswered_one_is_accepted() {
    let (mut dev, connect, check) = connect_waiting();
    let mut out = Vec::new();
    dev.answer_connect(check.job, Err((0x40, 0x04)), MS, &mut out)
        .unwrap();
    assert_eq!(
        status(&response(&out)),
        PnioStatus::from_bytes([0xdb, 0x81, 0x40, 0x04])
    );
    assert_eq!(dev.ar().state(), ArState::Idle);
    // The controller tries again (a new call): nobody answers, the AR is accepted.
    let out = send(
        &mut dev,
        opnum::CONNECT,
        1,
        &connect.to_vec().unwrap(),
        10 * MS,
    );
    assert_eq!(checks(&out).len(), 1);
    let sent = run_until(&mut dev, 10 * MS + AR_CHECK_TIMEOUT_NS);
    let answers: Vec<DeviceAction> = sent
        .into_iter()
        .map(|(_, a)| a)
        .filter(|a| matches!(a, DeviceAction::Datagram { to, .. } if *to == S7_CLIENT))
        .collect();
    assert_eq!(status(&response(&answers)), PnioStatus::OK);
    assert_eq!(dev.ar().state(), ArState::Connected);
    assert_eq!(dev.ar_checks().timeouts(), 1);
}
