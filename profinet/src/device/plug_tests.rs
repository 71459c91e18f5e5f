// SPDX-License-Identifier: MIT OR Apache-2.0
//! Pull, plug and return of submodules: the alarms the controller gets, the plug sub-cycle
//! (PlugPrmEnd, PlugApplicationReady), the submodule's status in the cyclic data, and what
//! is refused.

use super::tests::{
    ACTIVITY, AR_UUID, MS, PNET_MAC, S7_MAC, TestApp, alarms, built_connect, call, connect_request,
    counter_device, datagrams, frames, parse_reply, request, status, to_data, to_prm_end,
};
use super::*;
use crate::wire::PnioStatus;
use crate::wire::alarm::{AlarmType, Priority};
use crate::wire::connect::ConnectRequest;
use crate::wire::rpc::{RPC_PORT, opnum};
use crate::wire::rta_pdu::Packet;

/// The counter device's input submodule (4 bytes in).
const INPUT: SubslotAddr = SubslotAddr::new(0, 1, 1);

/// The IOPS the input CR frame among `out` gives the input submodule.
fn input_iops(out: &[DeviceAction], connect: &ConnectRequest) -> Option<u8> {
    let input = &connect.iocrs[0];
    let at = 20 + usize::from(input.apis[0].data_objects[1].frame_offset) + 4;
    frames(out)
        .iter()
        .find(|f| f.get(18..20) == Some(&input.frame_id.to_be_bytes()[..]))
        .map(|f| f[at])
}

/// Polls the device until `t`.
fn run(dev: &mut Device<TestApp>, from: u64, until: u64) -> Vec<DeviceAction> {
    let mut out = Vec::new();
    let mut t = from;
    while let Some(d) = dev.next_deadline_ns().filter(|d| *d <= until) {
        t = d.max(t);
        dev.poll(t, &mut out);
    }
    out
}

/// The controller's answer to the PlugApplicationReady among `out`, if there is one.
fn plug_ready_done(out: &[DeviceAction]) -> Option<(SocketAddrV4, Vec<u8>, u16)> {
    datagrams(out).into_iter().find_map(|(to, _, payload)| {
        let req = parse_reply(&payload);
        let c = ControlBlock::parse(&req.blocks).ok()?;
        (c.block_type == crate::wire::BlockType::PlugApplicationReadyReq).then(|| {
            let done = ControlBlock::done_response_for(&c).unwrap();
            let res = wire_rpc::emit_response(
                &req.header.reply(7),
                PnioStatus::OK,
                req.ndr.maximum_count(),
                &done.to_bytes(),
            )
            .unwrap();
            (to, res, c.alarm_sequence_number)
        })
    })
}

/// The controller's transport acknowledgement (ACK-RTA) of the alarm `n` went out in.
fn ack_transport(dev: &mut Device<TestApp>, out: &[DeviceAction], t: u64) -> Vec<DeviceAction> {
    let f = frames(out);
    let pdu = f
        .iter()
        .filter_map(|f| RtaPdu::parse(&Packet::new_checked(f.get(18..)?).ok()?).ok())
        .find(|p| p.notification().is_some())
        .expect("an alarm went out");
    let h = pdu.header;
    let ack = RtaPdu::first_ack_of(Priority::Low, &h);
    let mut next = Vec::new();
    dev.on_frame(
        &ethernet_frame(PNET_MAC, S7_MAC, Some(0xa000), &ack.to_vec().unwrap()),
        t,
        &mut next,
    );
    next
}

/// The exchanges handed out among `out`, and whether one was stopped.
fn handed_out(out: &[DeviceAction]) -> (Vec<CyclicAr>, bool) {
    let started = out
        .iter()
        .filter_map(|a| match a {
            DeviceAction::StartCyclic(ar) => Some((**ar).clone()),
            _ => None,
        })
        .collect();
    let stopped = out
        .iter()
        .any(|a| matches!(a, DeviceAction::StopCyclic { .. }));
    (started, stopped)
}

/// Whether the exchange produces the data of submodule `index` of the device's table.
fn produces(ar: &CyclicAr, index: usize) -> bool {
    ar.output.objects.iter().any(|o| o.submodule == index)
}

#[test]
fn a_pulled_submodule_is_announced_and_bad_in_the_next_frame() {
    let (mut dev, connect) = counter_device();
    let t = to_data(&mut dev, &connect, 1_000 * MS);
    let out = run(&mut dev, t, t + 2 * MS);
    assert_eq!(input_iops(&out, &connect), Some(ar::IOXS_GOOD));
    let t = t + 2 * MS;
    let mut out = Vec::new();
    assert_eq!(
        dev.pull_submodule(INPUT, t, &mut out),
        Ok(Some(AlarmType::Pull))
    );
    assert!(!dev.plugging().is_plugged(INPUT));
    let a = alarms(&out);
    assert_eq!(a.len(), 1);
    assert_eq!(
        (a[0].priority, a[0].alarm_type, a[0].slot, a[0].subslot),
        (Priority::Low, AlarmType::Pull, 1, 1)
    );
    // Nothing is plugged in slot 1 any more: neither module nor submodule.
    assert_eq!((a[0].module_ident, a[0].submodule_ident), (0, 0));
    let out = run(&mut dev, t, t + 2 * MS);
    assert_eq!(input_iops(&out, &connect), Some(ar::IOXS_BAD));
    assert_eq!(
        dev.pull_submodule(INPUT, t, &mut Vec::new()),
        Err(PlugError::NotPlugged(INPUT))
    );
    assert_eq!(
        dev.pull_submodule(SubslotAddr::new(0, 9, 1), t, &mut Vec::new()),
        Err(PlugError::NotConfigured(SubslotAddr::new(0, 9, 1)))
    );
}

#[test]
fn a_plug_runs_the_sub_cycle_and_hands_the_exchange_out_again() {
    let (mut dev, connect) = counter_device();
    dev.hand_over_cyclic(MS);
    let t = to_data(&mut dev, &connect, 1_000 * MS);
    let (started, _) = handed_out(&run(&mut dev, t, t + MS));
    assert!(started.is_empty(), "handed out at PrmEnd already");

    // The pull hands out the exchange without the submodule, replacing the running one.
    let mut out = Vec::new();
    dev.pull_submodule(INPUT, t, &mut out).unwrap();
    dev.poll(t, &mut out);
    let (started, stopped) = handed_out(&out);
    assert!(!stopped);
    assert_eq!(started.len(), 1);
    assert!(!produces(&started[0], 1));
    assert!(ack_transport(&mut dev, &out, t + MS).is_empty());

    // The plug of the expected submodule: a Plug alarm with what is plugged.
    let t = t + 2 * MS;
    let mut out = Vec::new();
    assert_eq!(
        dev.plug_submodule(INPUT, 0x30, 0x1, t, &mut out),
        Ok(Some(AlarmType::Plug))
    );
    assert_eq!(
        dev.plug_submodule(INPUT, 0x30, 0x1, t, &mut Vec::new()),
        Err(PlugError::AlreadyPlugged(INPUT))
    );
    let a = alarms(&out);
    assert_eq!(a.len(), 1);
    assert_eq!(
        (a[0].alarm_type, a[0].module_ident, a[0].submodule_ident),
        (AlarmType::Plug, 0x30, 0x1)
    );
    let seq = a[0].specifier.sequence_number;
    dev.poll(t, &mut out);
    assert!(
        handed_out(&out).0.is_empty(),
        "not before the sub-cycle ends"
    );

    // A PlugPrmEnd for another alarm is refused; the right one is answered with its number.
    let wrong = ControlBlock::plug_prm_end(AR_UUID, 1, seq + 1).to_bytes();
    let r = call(
        &mut dev,
        &request(opnum::CONTROL, ACTIVITY, 5, &wrong, false),
        t,
    );
    assert_ne!(status(&r), PnioStatus::OK);
    let prm = ControlBlock::plug_prm_end(AR_UUID, 1, seq);
    let r = call(
        &mut dev,
        &request(opnum::CONTROL, ACTIVITY, 6, &prm.to_bytes(), false),
        t,
    );
    assert_eq!(status(&r), PnioStatus::OK);
    let res = ControlBlock::parse(&r.blocks).unwrap();
    assert!(res.answers(&prm));
    assert_eq!(res.block_type, crate::wire::BlockType::PlugPrmEndRes);

    // The PlugApplicationReady, repeated until answered; its answer ends the sub-cycle.
    let out = run(&mut dev, t, t + 2 * MS);
    let (to, answer, n) = plug_ready_done(&out).expect("a PlugApplicationReady");
    assert_eq!(n, seq);
    assert_eq!(to.port(), RPC_PORT);
    let mut out = Vec::new();
    dev.on_datagram(to, rpc::CLIENT_PORT, &answer, t + 3 * MS, &mut out);
    dev.poll(t + 3 * MS, &mut out);
    let (started, stopped) = handed_out(&out);
    assert!(!stopped);
    assert_eq!(started.len(), 1);
    assert!(produces(&started[0], 1));
    assert_eq!(dev.ar().state(), ArState::Data);
}

#[test]
fn a_wrong_plug_is_announced_and_gets_no_sub_cycle() {
    let (mut dev, connect) = counter_device();
    let t = to_data(&mut dev, &connect, 1_000 * MS);
    let mut out = Vec::new();
    dev.pull_submodule(INPUT, t, &mut out).unwrap();
    ack_transport(&mut dev, &out, t);
    let mut out = Vec::new();
    assert_eq!(
        dev.plug_submodule(INPUT, 0x30, 0x99, t, &mut out),
        Ok(Some(AlarmType::PlugWrongSubmodule))
    );
    let a = alarms(&out);
    assert_eq!(
        (a[0].alarm_type, a[0].module_ident, a[0].submodule_ident),
        (AlarmType::PlugWrongSubmodule, 0x30, 0x99)
    );
    let prm = ControlBlock::plug_prm_end(AR_UUID, 1, a[0].specifier.sequence_number);
    let r = call(
        &mut dev,
        &request(opnum::CONTROL, ACTIVITY, 5, &prm.to_bytes(), false),
        t,
    );
    assert_ne!(status(&r), PnioStatus::OK);
    let out = run(&mut dev, t, t + 2 * MS);
    assert_eq!(input_iops(&out, &connect), Some(ar::IOXS_BAD));
}

#[test]
fn the_return_of_a_proper_submodule_is_announced() {
    let (mut dev, connect) = counter_device();
    let t = to_data(&mut dev, &connect, 1_000 * MS);
    let mut out = Vec::new();
    assert_eq!(
        dev.return_submodule(INPUT, t, &mut out),
        Ok(Some(AlarmType::ReturnOfSubmodule))
    );
    let a = alarms(&out);
    assert_eq!(
        (a[0].alarm_type, a[0].module_ident, a[0].submodule_ident),
        (AlarmType::ReturnOfSubmodule, 0x30, 0x1)
    );
}

#[test]
fn plug_and_pull_wait_for_data_exchange_and_before_an_ar_only_change_the_tree() {
    let (mut dev, connect) = counter_device();
    // Before any AR: no alarm; the Connect's ModuleDiffBlock shows the submodule missing.
    let mut out = Vec::new();
    assert_eq!(dev.pull_submodule(INPUT, 0, &mut out), Ok(None));
    assert!(out.is_empty());
    let r = call(&mut dev, &connect_request(&connect), MS);
    assert_eq!(status(&r), PnioStatus::OK);
    let res = crate::wire::connect::ConnectResponse::parse(&r.blocks).unwrap();
    let diff = res.module_diff.expect("a ModuleDiffBlock");
    let slot1 = diff.apis[0].modules.iter().find(|m| m.slot == 1).unwrap();
    assert_eq!(slot1.module_ident, 0);
    // Between the Connect and data exchange: refused.
    assert_eq!(
        dev.plug_submodule(INPUT, 0x30, 0x1, MS, &mut Vec::new()),
        Err(PlugError::ArStartingUp)
    );
    let (mut dev, connect) = counter_device();
    to_prm_end(&mut dev, &connect, MS);
    assert_eq!(
        dev.pull_submodule(INPUT, MS, &mut Vec::new()),
        Err(PlugError::ArStartingUp)
    );
}

#[test]
fn during_the_ar_check_the_application_plugs_what_the_plc_expects() {
    // The PLC expects submodule 0x99 in slot 1, where 0x1 is plugged.
    let (mut dev, _) = counter_device();
    let connect = built_connect(
        &[
            (0, 1, 0x1, 0x1, 0, 0),
            (1, 1, 0x30, 0x99, 4, 0),
            (2, 1, 0x31, 0x1, 0, 2),
        ],
        AR_UUID,
        (32, 2, 3),
    );
    dev.check_connects(true);
    let mut out = Vec::new();
    dev.on_datagram(
        SocketAddrV4::new([172, 16, 2, 100].into(), 54766),
        RPC_PORT,
        &connect_request(&connect),
        MS,
        &mut out,
    );
    let check = out
        .iter()
        .find_map(|a| match a {
            DeviceAction::ArCheck(c) => Some(c.clone()),
            _ => None,
        })
        .expect("an AR check");
    let slot1 = check.expected[1];
    assert_eq!(slot1.at, INPUT);
    assert_eq!(slot1.plugged.map(|p| p.submodule_ident), Some(0x1));
    // EXP_SUBMOD: the application plugs what is expected, then accepts.
    assert_eq!(dev.pull_submodule(INPUT, MS, &mut Vec::new()), Ok(None));
    assert_eq!(
        dev.plug_submodule(INPUT, 0x30, 0x99, MS, &mut Vec::new()),
        Ok(None)
    );
    let mut out = Vec::new();
    dev.answer_connect(check.job, Ok(()), 2 * MS, &mut out)
        .unwrap();
    let (_, _, payload) = datagrams(&out).remove(0);
    let r = parse_reply(&payload);
    assert_eq!(status(&r), PnioStatus::OK);
    let res = crate::wire::connect::ConnectResponse::parse(&r.blocks).unwrap();
    assert_eq!(res.module_diff, None, "everything as expected");
}

#[test]
fn a_held_application_ready_holds_the_plug_application_ready_too() {
    let (mut dev, connect) = counter_device();
    // The caller's cycle runs the exchange: no watchdog of the PLC's frames here.
    dev.hand_over_cyclic(MS);
    let t = to_data(&mut dev, &connect, 1_000 * MS);
    dev.hold_application_ready(true);
    let mut out = Vec::new();
    dev.pull_submodule(INPUT, t, &mut out).unwrap();
    ack_transport(&mut dev, &out, t + MS);
    let t = t + 2 * MS;
    let mut out = Vec::new();
    dev.plug_submodule(INPUT, 0x30, 0x1, t, &mut out).unwrap();
    let seq = alarms(&out)[0].specifier.sequence_number;
    assert!(dev.take_plug_parameterized().is_empty());
    let prm = ControlBlock::plug_prm_end(AR_UUID, 1, seq);
    let r = call(
        &mut dev,
        &request(opnum::CONTROL, ACTIVITY, 6, &prm.to_bytes(), false),
        t,
    );
    assert_eq!(status(&r), PnioStatus::OK);
    assert_eq!(dev.take_plug_parameterized(), [INPUT]);
    assert!(dev.take_plug_parameterized().is_empty());
    // Held: nothing goes out until the application releases it.
    assert!(plug_ready_done(&run(&mut dev, t, t + 5 * MS)).is_none());
    assert!(dev.release_application_ready(t + 5 * MS));
    let out = run(&mut dev, t + 5 * MS, t + 7 * MS);
    let (_, _, n) = plug_ready_done(&out).expect("the PlugApplicationReady once released");
    assert_eq!(n, seq);
}
