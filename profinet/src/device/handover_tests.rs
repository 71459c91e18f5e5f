// SPDX-License-Identifier: MIT OR Apache-2.0
//! The cyclic exchange handed over to a cycle: what the engine hands out at PrmEnd, that it
//! then produces no cyclic frame itself, and how the exchange ends.

use super::tests::{
    ACTIVITY, AR_UUID, MS, PNET_MAC, S7_MAC, built_connect, call, connect_request, counter_device,
    datagrams, frames, request, run_until, status, to_data,
};
use super::*;
use crate::wire::PnioStatus;
use crate::wire::rpc::opnum;
use crate::wire::rt::FrameIdClass;

/// The exchanges started and stopped among `out`.
fn handovers(out: &[DeviceAction]) -> (Vec<CyclicAr>, Vec<u32>) {
    let mut started = Vec::new();
    let mut stopped = Vec::new();
    for a in out {
        match a {
            DeviceAction::StartCyclic(ar) => started.push((**ar).clone()),
            DeviceAction::StopCyclic { epoch } => stopped.push(*epoch),
            _ => {}
        }
    }
    (started, stopped)
}

/// Connect and PrmEnd of the counter device (DAP, 4 bytes in, 2 bytes out; a frame every
/// 2 ms) on a 1 ms cycle: everything the device did.
fn connect_and_prm_end(
    dev: &mut Device<super::tests::TestApp>,
    activity: Uuid,
) -> Vec<DeviceAction> {
    let (_, connect) = counter_device();
    let blocks = connect.to_vec().unwrap();
    let mut out = Vec::new();
    dev.on_datagram(
        SocketAddrV4::new([172, 16, 2, 100].into(), 54766),
        wire_rpc::RPC_PORT,
        &request(opnum::CONNECT, activity, 0, &blocks, false),
        0,
        &mut out,
    );
    let prm = ControlBlock::prm_end(AR_UUID, 1).to_bytes();
    dev.on_datagram(
        SocketAddrV4::new([172, 16, 2, 100].into(), 54766),
        wire_rpc::RPC_PORT,
        &request(opnum::CONTROL, activity, 1, &prm, false),
        MS,
        &mut out,
    );
    out
}

#[test]
fn prm_end_hands_out_the_exchange_mapped_onto_the_plugged_submodules() {
    let (mut dev, connect) = counter_device();
    dev.hand_over_cyclic(MS);
    let out = connect_and_prm_end(&mut dev, ACTIVITY);
    let (started, stopped) = handovers(&out);
    assert_eq!((started.len(), stopped.len()), (1, 0), "{out:?}");
    let ar = &started[0];
    assert_eq!((ar.device, ar.epoch, ar.peer), (0, 1, S7_MAC));
    // Consumed: the controller's output CR; produced: our input CR.
    assert_eq!(ar.input.frame_id, connect.iocrs[1].frame_id);
    assert!(FrameIdClass::of(ar.output.frame_id).is_cyclic());
    assert_eq!(
        ar.input.data_length,
        usize::from(connect.iocrs[1].data_length)
    );
    assert_eq!(
        ar.output.data_length,
        usize::from(connect.iocrs[0].data_length)
    );
    // Submodule 0 is the DAP (no data: an IOPS in the input CR, an IOCS in the output
    // CR), 1 has 4 input bytes, 2 has 2 output bytes: indexes in plugging order.
    let produced: Vec<(usize, usize)> = ar
        .output
        .objects
        .iter()
        .map(|o| (o.submodule, o.len))
        .collect();
    assert_eq!(produced, [(0, 0), (1, 4)]);
    let consumed: Vec<(usize, usize)> = ar
        .input
        .objects
        .iter()
        .map(|o| (o.submodule, o.len))
        .collect();
    assert_eq!(consumed, [(2, 2)]);
    let iocs_for_outputs: Vec<usize> = ar.output.iocs.iter().map(|c| c.submodule).collect();
    assert_eq!(iocs_for_outputs, [2]);
    let iocs_for_inputs: Vec<usize> = ar.input.iocs.iter().map(|c| c.submodule).collect();
    assert_eq!(iocs_for_inputs, [0, 1]);
    // Every second cycle of 1 ms, watchdog 3 frames.
    assert_eq!(ar.timing.every_cycles, 2);
    assert_eq!(ar.timing.watchdog_ns(), 6 * MS);
    assert_eq!(ar.submodules, 0..3);
    assert_eq!(&ar.frame[0..6], &S7_MAC.0);
    assert_eq!(&ar.frame[6..12], &PNET_MAC.0);
    // The engine itself sends no cyclic frame: only the ApplicationReady is due.
    let later = run_until(&mut dev, 50 * MS);
    let cyclic = later
        .iter()
        .filter(|(_, a)| matches!(a, DeviceAction::Frame(f) if f.len() > 18 && f[16..18] == [0x88, 0x92]))
        .count();
    assert_eq!(cyclic, 0, "{later:?}");
}

#[test]
fn the_exchange_stops_with_the_ar_and_the_cycles_watchdog_ends_it() {
    let (mut dev, connect) = counter_device();
    dev.hand_over_cyclic(MS);
    let t = to_data(&mut dev, &connect, 0);
    assert_eq!(dev.ar().state(), ArState::Data);
    // Without cyclic frames the engine's own watchdog does not run: only the cycle's.
    let quiet = run_until(&mut dev, t + 100 * MS);
    assert!(
        handovers(&quiet.into_iter().map(|(_, a)| a).collect::<Vec<_>>())
            .1
            .is_empty()
    );
    assert_eq!(dev.ar().state(), ArState::Data);
    assert!(dev.cyclic_started(1, t));
    let mut out = Vec::new();
    dev.cyclic_expired(7, t + 200 * MS, &mut out);
    assert_eq!(
        dev.ar().state(),
        ArState::Data,
        "another epoch's report is stale"
    );
    dev.cyclic_expired(1, t + 200 * MS, &mut out);
    assert_eq!(dev.ar().state(), ArState::Idle);
    assert_eq!(dev.ar().last_abort(), Some(AbortCode::ConsumerDhtExpired));
    assert_eq!(handovers(&out).1, [1]);
    assert_eq!(frames(&out).len(), 1, "the ERR-RTA: {out:?}");

    // A new AR gets a new epoch, and its Release stops it.
    // Another activity: the RPC layer would take the same one's calls as duplicates.
    let second = Uuid::from_fields(0xaaaa_0002, 1, 0x4000, [8, 7, 6, 5, 4, 3, 2, 1]);
    let mut out = connect_and_prm_end(&mut dev, second);
    assert_eq!(handovers(&out).0[0].epoch, 2);
    out.clear();
    let release = ControlBlock::release(AR_UUID, 1).to_bytes();
    dev.on_datagram(
        SocketAddrV4::new([172, 16, 2, 100].into(), 54766),
        wire_rpc::RPC_PORT,
        &request(opnum::RELEASE, second, 2, &release, false),
        t + 300 * MS,
        &mut out,
    );
    assert_eq!(
        status(&super::tests::parse_reply(&datagrams(&out)[0].2)),
        PnioStatus::OK
    );
    assert_eq!(dev.ar().state(), ArState::Idle);
    assert_eq!(handovers(&out).1, [2], "{out:?}");
}

#[test]
fn a_period_the_cycle_cannot_keep_is_refused() {
    let (mut dev, _) = counter_device();
    // A frame every 2 ms does not fit a 3 ms cycle, nor a 4 ms one.
    for cycle in [3 * MS, 4 * MS] {
        dev.hand_over_cyclic(cycle);
        let subs = [
            (0, 1, 0x1, 0x1, 0, 0),
            (1, 1, 0x30, 0x1, 4, 0),
            (2, 1, 0x31, 0x1, 0, 2),
        ];
        let connect = built_connect(&subs, AR_UUID, (32, 2, 3));
        let r = call(&mut dev, &connect_request(&connect), 0);
        let s = status(&r);
        assert_eq!((s.error_code1, s.error_code2), (0x02, 11), "{s:?}");
        assert_eq!(dev.ar().state(), ArState::Idle);
        assert!(datagrams(&[]).is_empty());
    }
}
