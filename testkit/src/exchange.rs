// SPDX-License-Identifier: MIT OR Apache-2.0
//! Data both ways between procimg as controller and procimg as device, through a client on
//! each side: the device's client echoes the PLC's Q data of a submodule into its I data,
//! the controller's client writes a pattern per cycle into that submodule's outputs and
//! checks that what comes back in its inputs is a whole pattern of a cycle gone by; and
//! what the controller's program hears of the device.

use procimg_client::{AttachOptions, Client, Ioxs, Notification, Services};
use std::time::{Duration, Instant};

/// How long a side waits for STARTOP: longer than any stall of a loaded machine, short
/// enough that a side whose server went away ends.
const STARTOP_WAIT: Duration = Duration::from_secs(5);

/// The index of the submodule at `slot`/`subslot` (of the first device).
pub fn at(client: &Client, slot: u16, subslot: u16) -> usize {
    client
        .layout()
        .submodules
        .iter()
        .position(|e| (e.slot, e.subslot) == (slot, subslot))
        .unwrap_or_else(|| panic!("no submodule at slot {slot} subslot {subslot}"))
}

/// The station's client side of the device demo's PLC program (each Q byte is its I byte
/// plus one): writes `written` as the I data of `submodule` every cycle until the PLC's Q
/// data of it answers so, with IOPS GOOD; fails the test after `within`.
pub fn until_the_plc_answers(
    client: &mut Client,
    submodule: usize,
    written: &[u8],
    within: Duration,
) {
    let wanted: Vec<u8> = written.iter().map(|b| b.wrapping_add(1)).collect();
    let until = Instant::now() + within;
    loop {
        let mut cycle = client.wait_startop(STARTOP_WAIT).expect("STARTOP");
        let last = cycle.q_data(submodule).expect("Q data").to_vec();
        let good = cycle.q_status(submodule).expect("Q status") == Ioxs::Good;
        cycle
            .i_data_mut(submodule)
            .expect("I data")
            .copy_from_slice(written);
        cycle.set_opdone().expect("OPDONE");
        if good && last == wanted {
            return;
        }
        assert!(
            Instant::now() < until,
            "the PLC's Q data never answered the I data: last Q {last:02x?}"
        );
    }
}

/// Runs the device's side for `cycles` in a thread of its own: the Q data of slot 1
/// (subslot 1) echoed into its I data. The thread's result is how many cycles the Q data
/// was GOOD. It ends early, without failing, when its server goes away (a test that kills
/// it joins the thread after).
pub fn device_echo(instance: String, cycles: u64) -> std::thread::JoinHandle<u64> {
    std::thread::spawn(move || {
        // The echo is the device's application: as a real one, it runs at a real-time
        // priority, so that the machine's other work does not make it miss cycles.
        let _ = procimg_client::realtime::make_current_thread_realtime(60);
        let mut client = Client::attach(&instance, AttachOptions::synchronous("dev-echo"))
            .expect("attach to the device");
        client.claim_i_data().expect("claim the I data");
        let s = at(&client, 1, 1);
        let mut echoed = 0;
        for _ in 0..cycles {
            let Ok(mut cycle) = client.wait_startop(STARTOP_WAIT) else {
                break;
            };
            let (Ok(q), Ok(st)) = (cycle.q_data(s).map(<[u8]>::to_vec), cycle.q_status(s)) else {
                break;
            };
            echoed += u64::from(st == Ioxs::Good);
            let Ok(i) = cycle.i_data_mut(s) else {
                break;
            };
            i.copy_from_slice(&q);
            if cycle.set_opdone().is_err() {
                break;
            }
        }
        echoed
    })
}

/// What the controller's client saw.
#[derive(Debug, Default)]
pub struct Seen {
    /// Cycles run.
    pub cycles: u64,
    /// Valid inputs that carried the whole pattern of this cycle or an earlier one.
    pub echoes: u64,
    /// Valid inputs that carried no such pattern: torn, or never written.
    pub wrong: u64,
}

/// The 8-byte pattern of cycle `k`: its low 32 bits and their complement, so that a torn
/// or made-up input shows.
fn pattern(k: u64) -> [u8; 8] {
    let k = k as u32;
    let mut p = [0; 8];
    p[..4].copy_from_slice(&k.to_be_bytes());
    p[4..].copy_from_slice(&(!k).to_be_bytes());
    p
}

/// Whether `input` is the pattern of cycle `now` or of an earlier one. Earlier rather than
/// one this client wrote: the controller's outputs hold what an earlier client wrote last
/// until this one's first cycle, and the device may echo that first.
fn is_pattern_by(input: &[u8], now: u64) -> bool {
    let Some(k) = input.get(..4).and_then(|b| <[u8; 4]>::try_from(b).ok()) else {
        return false;
    };
    let k = u32::from_be_bytes(k);
    k <= now as u32 && input == pattern(u64::from(k))
}

/// Runs the controller's side for `cycles`: a pattern per cycle into the outputs of slot 1
/// (subslot 1, 8 bytes) of device `device`, its inputs checked to be whole patterns of
/// cycles gone by.
pub fn controller_pattern(instance: &str, device: &str, cycles: u64) -> Seen {
    // Like the device's echo: the controller's application runs at a real-time priority.
    let _ = procimg_client::realtime::make_current_thread_realtime(60);
    let mut client = Client::attach(instance, AttachOptions::synchronous("ctl-pattern"))
        .expect("attach to the controller");
    client.claim_device(device).expect("claim the outputs");
    let s = at(&client, 1, 1);
    let mut seen = Seen::default();
    for _ in 0..cycles {
        let mut cycle = client.wait_startop(STARTOP_WAIT).expect("STARTOP");
        let k = cycle.number();
        let valid = cycle
            .status(s)
            .is_some_and(|st| st.input_remote == Ioxs::Good);
        let input = cycle.input(s).unwrap_or(&[]).to_vec();
        cycle
            .output_mut(s)
            .expect("outputs")
            .copy_from_slice(&pattern(k));
        cycle.set_opdone().expect("OPDONE");
        // All zeros: the device's client has not echoed anything yet.
        if valid && input != [0; 8] {
            if is_pattern_by(&input, k) {
                seen.echoes += 1;
            } else {
                seen.wrong += 1;
            }
        }
        seen.cycles += 1;
    }
    seen
}

/// The next device failure or return among a controller's notifications, skipping the
/// others; panics naming `what` after 30 s (a loaded machine is slow to connect).
pub fn next_device_event(services: &mut Services, what: &str) -> Notification {
    let within = Duration::from_secs(30);
    let until = Instant::now() + within;
    while Instant::now() < until {
        if let Some(n) = services.next(Duration::from_millis(100))
            && matches!(
                n,
                Notification::DeviceFailure { .. } | Notification::DeviceReturn { .. }
            )
        {
            return n;
        }
    }
    panic!("no device {what} within {within:?}");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pattern_counts_from_its_cycle_on_and_whole_only() {
        let p = pattern(1000);
        assert!(is_pattern_by(&p, 1000));
        assert!(is_pattern_by(&p, 5000));
        assert!(!is_pattern_by(&p, 999), "a cycle still to come");
        let mut torn = p;
        torn[7] ^= 1;
        assert!(!is_pattern_by(&torn, 5000));
        assert!(!is_pattern_by(&p[..3], 5000));
    }
}
